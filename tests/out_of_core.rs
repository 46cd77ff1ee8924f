//! Out-of-core loading with latency (the `chunked` entry's `loading` effect,
//! Lauritsen–Nielsen §3.2.14–3.2.15): no chunk is drawn before its latency has passed since it
//! was first requested, the bandwidth and the memory cap hold in every frame, the parent is
//! drawn while the children travel, and the same flight without the effect draws no chunk
//! coarser than it wants.

mod common;

use common::algorithms::{chunked, chunked_with_everything};
use common::scenes::{DiagonalFlight, diagonal_flight};
use common::{bumpy_terrain, checked_step, extra, fly_checked, view_600};
use roamsim::sim::algorithm::chunked::{ChunkId, DetailConfig, LoadingConfig};
use roamsim::sim::algorithm::columns::chunked::{
    CHUNKS_COARSER, CHUNKS_LOADED, DETAIL_SYNTHESISED, REQUESTS_IN_FLIGHT, RESIDENT_CHUNKS,
};
use roamsim::sim::algorithm::{Chunked, ChunkedConfig};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::view::Camera;
use std::collections::HashMap;

fn loading(latency_frames: u32, bandwidth: u32, resident_chunks: u32) -> LoadingConfig {
    LoadingConfig {
        latency_frames,
        bandwidth_chunks_per_frame: bandwidth,
        resident_chunks,
    }
}

/// A flight 8 m above the ground along the terrain's diagonal, looking ahead and down.
fn low_flight(hierarchy: &Hierarchy, frames: u32) -> Vec<Camera> {
    let flight = DiagonalFlight {
        frames,
        above_ground_m: 8.0,
        start: 0.05,
        span: 0.9,
        pitch: -0.3,
        yaw_swing: 0.0,
    };
    diagonal_flight(hierarchy, flight)
}

/// Flies `config`, every frame checked, asserting that every chunk's first appearance comes at
/// least `latency` frames after its parent's first request, that the bandwidth (4 per group,
/// `bandwidth` per frame) and the resident cap hold; the frames' `chunks_coarser`.
fn fly_checking_latency(
    hierarchy: &Hierarchy,
    config: ChunkedConfig,
    cameras: &[Camera],
    name: &str,
) -> Vec<f64> {
    let loading = config.loading.unwrap();
    let mut algorithm = Chunked::new(hierarchy, config, &view_600());
    let mut first_request: HashMap<ChunkId, u64> = HashMap::new();
    let mut first_drawn: HashMap<ChunkId, u64> = HashMap::new();
    let mut coarser = Vec::new();
    for (frame, camera) in cameras.iter().enumerate() {
        let frame = frame as u64;
        let stats = checked_step(hierarchy, &mut algorithm, frame, camera, false, name);
        algorithm
            .validate_frame(camera)
            .unwrap_or_else(|e| panic!("{name}, frame {frame}: {e}"));
        for chunk in algorithm.drawn() {
            first_drawn.entry(chunk.id).or_insert(frame);
            let Some(parent) = chunk.id.parent() else {
                continue;
            };
            let requested = first_request.get(&parent).unwrap_or_else(|| {
                panic!(
                    "{name}, frame {frame}: {:?} drawn, never requested",
                    chunk.id
                )
            });
            if first_drawn[&chunk.id] == frame {
                assert!(
                    frame >= requested + u64::from(loading.latency_frames),
                    "{name}: {:?} drawn at frame {frame}, requested at {requested}",
                    chunk.id
                );
            }
        }
        for &parent in algorithm.requested() {
            first_request.entry(parent).or_insert(frame);
        }
        let column = |name| extra(&algorithm, &stats, name);
        let issued = column(CHUNKS_LOADED)
            + if config.detail.is_some() {
                column(DETAIL_SYNTHESISED)
            } else {
                0.0
            };
        assert!(
            issued <= f64::from(loading.bandwidth_chunks_per_frame),
            "{name}, frame {frame}: {issued} chunks issued"
        );
        assert!(
            column(RESIDENT_CHUNKS) <= f64::from(loading.resident_chunks),
            "{name}, frame {frame}: {} resident",
            column(RESIDENT_CHUNKS)
        );
        // What is on its way was issued in the last `latency` frames.
        let in_flight_bound = loading.latency_frames * loading.bandwidth_chunks_per_frame;
        assert!(
            column(REQUESTS_IN_FLIGHT) <= f64::from(in_flight_bound),
            "{name}, frame {frame}: {} in flight",
            column(REQUESTS_IN_FLIGHT)
        );
        coarser.push(column(CHUNKS_COARSER));
    }
    assert!(
        first_drawn.keys().any(|id| id.level >= 2),
        "{name}: nothing deep drawn"
    );
    coarser
}

#[test]
fn no_chunk_is_drawn_before_its_latency_and_bandwidth_and_memory_hold_every_frame() {
    // 129², chunks of 9²: source leaves at level 4.
    let hierarchy = bumpy_terrain(7);
    let cameras = low_flight(&hierarchy, 50);
    for (name, base) in [
        ("plain", chunked(4.0, 3)),
        ("every effect", chunked_with_everything(4.0, 3)),
    ] {
        for (latency, bandwidth, cap) in [(1, 8, 400), (3, 8, 60), (6, 4, 32)] {
            let config = ChunkedConfig {
                loading: Some(loading(latency, bandwidth, cap)),
                ..base
            };
            let label = format!("{name}, latency {latency}, bandwidth {bandwidth}, cap {cap}");
            let coarser = fly_checking_latency(&hierarchy, config, &cameras, &label);
            assert!(coarser.iter().sum::<f64>() > 0.0, "{label}");
            // With detail as well: synthesised chunks travel the same way.
            let config = ChunkedConfig {
                detail: Some(DetailConfig {
                    levels: 2,
                    seed: 1,
                    amplitude_m: 3.0,
                    roughness: 0.5,
                    max_queued_chunks: 8,
                    max_speed_per_spacing: None,
                    cache_chunks: 64,
                }),
                ..config
            };
            fly_checking_latency(&hierarchy, config, &cameras, &format!("{label}, detail"));
        }
        // Without the effect every source chunk is there: nothing is drawn coarser.
        let mut algorithm = Chunked::new(&hierarchy, base, &view_600());
        fly_checked(
            &hierarchy,
            &mut algorithm,
            &cameras,
            name,
            |frame, _, _, algorithm| {
                assert!(algorithm.requested().is_empty(), "{name}, frame {frame}");
            },
        );
    }
}

#[test]
fn under_a_still_camera_each_level_arrives_one_latency_after_the_last() {
    // τ = 0 refines every chunk with an error: with room and bandwidth for everything, the
    // level drawn at frame f is ⌊f / latency⌋ until the leaves (level 4).
    let hierarchy = bumpy_terrain(7);
    let camera = low_flight(&hierarchy, 1)[0];
    for latency in [1u32, 2, 5] {
        let config = ChunkedConfig {
            loading: Some(loading(latency, 100_000, 100_000)),
            ..chunked(0.0, 3)
        };
        let mut algorithm = Chunked::new(&hierarchy, config, &view_600());
        for frame in 0..(6 * latency) {
            checked_step(
                &hierarchy,
                &mut algorithm,
                u64::from(frame),
                &camera,
                false,
                "still",
            );
            let expected = (frame / latency).min(4);
            let levels: Vec<u32> = algorithm.drawn().iter().map(|c| c.id.level).collect();
            assert!(
                levels.iter().all(|&l| l == expected),
                "latency {latency}, frame {frame}: levels {levels:?}, expected {expected}"
            );
        }
    }
}
