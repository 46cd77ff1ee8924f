//! Chunked LOD's GPU-side data as Ulrich's chunked LOD keeps it (`chunked/buffers.rs`): over
//! flights with splits, merges, morphing, culling and a teleport, plain, with runtime detail,
//! with out-of-core loading and with both, every frame's buffers draw exactly its mesh
//! (`checked_step`), a chunk's vertex buffer is uploaded once when it first becomes drawable
//! and never again while it stays resident, the shared index buffer once, and otherwise a
//! frame uploads only its per-draw constants; a still camera uploads nothing else.

mod common;

use common::algorithms::{chunked, chunked_with_everything};
use common::{bumpy_terrain, checked_step, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::chunked::{ChunkId, DetailConfig, LoadingConfig};
use roamsim::sim::algorithm::{Chunked, ChunkedConfig, LodAlgorithm};
use roamsim::sim::hierarchy::{GridPoint, Hierarchy};
use roamsim::sim::view::{Camera, Pose};
use std::collections::BTreeSet;

/// Bytes of per-draw constants a drawn chunk uploads (its blend as an `f32`).
const CONSTANT_BYTES: u64 = 4;

fn detail(max_queued_chunks: u32, cache_chunks: u32) -> DetailConfig {
    DetailConfig {
        levels: 2,
        seed: 2005,
        amplitude_m: 4.0,
        roughness: 0.5,
        max_queued_chunks,
        max_speed_per_spacing: None,
        cache_chunks,
    }
}

fn loading(resident_chunks: u32) -> LoadingConfig {
    LoadingConfig {
        latency_frames: 3,
        bandwidth_chunks_per_frame: 8,
        resident_chunks,
    }
}

/// A camera `height` m above the ground at grid point (i, i), looking along the diagonal.
fn camera_at(hierarchy: &Hierarchy, i: u32, height: f64, yaw: f64) -> Camera {
    let field = hierarchy.field();
    let ground = f64::from(hierarchy.height(GridPoint::new(i, i)));
    let position = field.position(i as usize, i as usize);
    Camera::new(
        &Pose {
            position: DVec3::new(position.x, position.y, ground + height),
            yaw,
            pitch: -0.35,
        },
        view_600(),
    )
}

/// A low flight along the diagonal, turning, that jumps back to the start half way (a
/// teleport), then holds still for `still` frames.
fn flight(hierarchy: &Hierarchy, frames: u32, still: u32) -> Vec<Camera> {
    let last = hierarchy.field().side() as u32 - 1;
    let mut cameras: Vec<Camera> = (0..frames)
        .map(|k| {
            let t = if k < frames / 2 {
                0.1 + 0.8 * f64::from(k) / f64::from(frames)
            } else {
                0.05 + 0.5 * f64::from(k - frames / 2) / f64::from(frames)
            };
            let i = (t * f64::from(last)).round() as u32;
            let yaw = std::f64::consts::FRAC_PI_4 + 0.6 * (f64::from(k) * 0.15).sin();
            camera_at(hierarchy, i, 5.0 + 200.0 * t, yaw)
        })
        .collect();
    let held = *cameras.last().expect("a flight has frames");
    cameras.extend(std::iter::repeat_n(held, still as usize));
    cameras
}

/// What a flight showed, summed over its frames.
#[derive(Debug, Default)]
struct Seen {
    splits: u64,
    merges: u64,
    made: u64,
    released: u64,
    morphing_draws: u64,
    culled: u64,
    deepest: u32,
}

/// Flies `config` over `cameras`, every frame checked and its uploads accounted for.
fn fly(hierarchy: &Hierarchy, config: ChunkedConfig, cameras: &[Camera], name: &str) -> Seen {
    let mut algorithm = Chunked::new(hierarchy, config, &view_600());
    let cells = 1u64 << config.chunk_level;
    let index_bytes = (2 * cells * cells + 8 * cells) * 3 * 4;
    let mut previous: BTreeSet<ChunkId> = BTreeSet::new();
    let mut seen = Seen::default();
    for (frame, camera) in cameras.iter().enumerate() {
        let stats = checked_step(hierarchy, &mut algorithm, frame as u64, camera, true, name);
        let buffered: BTreeSet<ChunkId> = algorithm.buffered_chunks().into_iter().collect();
        let new = buffered.difference(&previous).count() as u64;
        let made = algorithm.chunk_buffers_made();
        assert_eq!(
            made, new,
            "{name}, frame {frame}: a buffer made for a chunk that already had one"
        );
        let expected = stats.draw_calls * CONSTANT_BYTES
            + made * algorithm.chunk_buffer_bytes()
            + if frame == 0 { index_bytes } else { 0 };
        assert_eq!(
            stats.upload_bytes, expected,
            "{name}, frame {frame}: {} draws, {made} chunks made",
            stats.draw_calls
        );
        assert_eq!(stats.draw_calls, algorithm.drawn().len() as u64);
        for chunk in algorithm.drawn() {
            assert!(buffered.contains(&chunk.id), "{name}, frame {frame}");
        }
        for &id in &buffered {
            assert!(
                algorithm.chunk(id).is_some(),
                "{name}, frame {frame}: {id:?} keeps a buffer though it is not available"
            );
        }
        seen.splits += stats.splits;
        seen.merges += stats.merges;
        seen.made += made;
        seen.released += previous.difference(&buffered).count() as u64;
        seen.morphing_draws += algorithm
            .buffers()
            .draws()
            .iter()
            .filter(|d| d.blend > 0.0 && d.blend < 1.0)
            .count() as u64;
        seen.culled += algorithm.culled().len() as u64;
        seen.deepest = seen.deepest.max(
            algorithm
                .drawn()
                .iter()
                .map(|c| c.id.level)
                .max()
                .unwrap_or(0),
        );
        previous = buffered;
    }
    seen
}

#[test]
fn each_chunk_is_uploaded_once_and_a_frame_otherwise_uploads_only_its_draws_constants() {
    // 65², chunks of 9²: source leaves at level 3, two synthesised levels below.
    let hierarchy = bumpy_terrain(6);
    let cameras = flight(&hierarchy, 80, 0);
    // τ 100 px: the source chunks split and merge; τ 20 px: the synthesised ones do.
    let base = chunked_with_everything(100.0, 3);
    let fine = chunked_with_everything(20.0, 3);
    for (name, config) in [
        ("plain", chunked(100.0, 3)),
        ("every effect", base),
        (
            "detail",
            ChunkedConfig {
                detail: Some(detail(8, 48)),
                ..fine
            },
        ),
        (
            "loading",
            ChunkedConfig {
                loading: Some(loading(24)),
                ..base
            },
        ),
        (
            "detail and loading",
            ChunkedConfig {
                detail: Some(detail(8, 48)),
                loading: Some(loading(24)),
                ..fine
            },
        ),
    ] {
        let seen = fly(&hierarchy, config, &cameras, name);
        assert!(seen.splits > 0 && seen.merges > 0, "{name}: {seen:?}");
        assert!(seen.made > 0, "{name}: {seen:?}");
        if config.morph {
            assert!(seen.morphing_draws > 0, "{name}: nothing morphed: {seen:?}");
        }
        if config.culling {
            assert!(seen.culled > 0, "{name}: nothing culled: {seen:?}");
        }
        if config.detail.is_some() {
            assert!(
                seen.deepest > 3,
                "{name}: nothing synthesised drawn: {seen:?}"
            );
        }
        if config.detail.is_some() || config.loading.is_some() {
            assert!(
                seen.released > 0,
                "{name}: no evicted chunk released its buffer: {seen:?}"
            );
        }
    }
}

#[test]
fn a_still_camera_uploads_only_the_per_draw_constants() {
    let hierarchy = bumpy_terrain(6);
    let cameras = flight(&hierarchy, 20, 100);
    for (name, config) in [
        ("every effect", chunked_with_everything(20.0, 3)),
        (
            "detail",
            ChunkedConfig {
                detail: Some(detail(8, 400)),
                ..chunked_with_everything(20.0, 3)
            },
        ),
    ] {
        let mut algorithm = Chunked::new(&hierarchy, config, &view_600());
        let mut uploads = Vec::new();
        for (frame, camera) in cameras.iter().enumerate() {
            let stats = checked_step(
                &hierarchy,
                &mut algorithm,
                frame as u64,
                camera,
                false,
                name,
            );
            uploads.push((stats.upload_bytes, stats.draw_calls));
        }
        // Once what the still camera wants has arrived, nothing but the constants.
        for (frame, &(bytes, draws)) in uploads.iter().enumerate().skip(110) {
            assert!(draws > 0, "{name}, frame {frame}");
            assert_eq!(bytes, draws * CONSTANT_BYTES, "{name}, frame {frame}");
        }
        assert!(
            uploads[..20]
                .iter()
                .any(|&(bytes, draws)| bytes > draws * CONSTANT_BYTES),
            "{name}: the moving frames made buffers"
        );
    }
}

#[test]
fn an_in_memory_chunk_idle_for_long_is_released_and_made_again_when_drawn() {
    let hierarchy = bumpy_terrain(6);
    let near = camera_at(&hierarchy, 8, 5.0, std::f64::consts::FRAC_PI_4);
    let far = camera_at(
        &hierarchy,
        56,
        5.0,
        std::f64::consts::FRAC_PI_4 + std::f64::consts::PI,
    );
    let config = chunked_with_everything(20.0, 3);
    let mut algorithm = Chunked::new(&hierarchy, config, &view_600());
    let step = |frame: u64, camera: &Camera, algorithm: &mut Chunked| {
        checked_step(&hierarchy, algorithm, frame, camera, true, "idle")
    };
    step(0, &near, &mut algorithm);
    let near_chunks: BTreeSet<ChunkId> = algorithm.drawn().iter().map(|c| c.id).collect();
    let mut frame = 1;
    while frame < 200 {
        step(frame, &far, &mut algorithm);
        frame += 1;
    }
    let far_chunks: BTreeSet<ChunkId> = algorithm.drawn().iter().map(|c| c.id).collect();
    let only_near: Vec<ChunkId> = near_chunks.difference(&far_chunks).copied().collect();
    assert!(!only_near.is_empty());
    let buffered: BTreeSet<ChunkId> = algorithm.buffered_chunks().into_iter().collect();
    assert!(
        only_near.iter().all(|id| !buffered.contains(id)),
        "chunks idle for 199 frames keep their buffers"
    );
    let stats = step(frame, &near, &mut algorithm);
    assert!(algorithm.chunk_buffers_made() >= only_near.len() as u64);
    assert!(stats.upload_bytes >= only_near.len() as u64 * algorithm.chunk_buffer_bytes());
}
