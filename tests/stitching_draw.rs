//! What `stitching-strips` sends to the GPU (issue #31): the blocks as patches in a per-frame
//! instance buffer, tessellated on the GPU side, and the strips and P-blocks written by the CPU
//! every frame (the 2019 paper, §3.2 and §4.2). Over flights with splits, merges, factor
//! changes, culling and teleports, for every method: the buffers draw the mesh every frame,
//! every triangle of the mesh is submitted, and what is uploaded is the blocks' data and the
//! strips' geometry, never a tessellated triangle.

mod common;

use common::{bumpy_terrain, checked_step, draw_counts, extra, step, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::columns::stitching::{M_BLOCKS, M_BLOCKS_CULLED, STRIPS};
use roamsim::sim::algorithm::stitching::{PATCH_BYTES, frame_upload_bytes};
use roamsim::sim::algorithm::{
    BlockDistance, LodAlgorithm, PBlockShape, Stitching, StitchingConfig, StitchingMethod,
    ViewDirection,
};
use roamsim::sim::draw::{DrawCounts, GpuBuffers, Topology};
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::{Camera, Pose};

fn config(method: StitchingMethod, culling: bool, p_block: PBlockShape) -> StitchingConfig {
    StitchingConfig {
        threshold_px: 1.0,
        block_level: 5,
        strip_width_cells: 1.0,
        method,
        distance: BlockDistance::Centre,
        view_direction: ViewDirection::ToBlock,
        p_block,
        culling,
    }
}

fn every_method_culling_and_p_block() -> Vec<StitchingConfig> {
    let mut configs = Vec::new();
    for method in [
        StitchingMethod::Strips,
        StitchingMethod::PowerOfTwo,
        StitchingMethod::Uniform,
    ] {
        configs.push(config(method, false, PBlockShape::TwoTriangles));
        configs.push(config(method, true, PBlockShape::Fan));
    }
    configs
}

/// A flight over a 257² terrain of 10 m posts (2 560 m): down from high above to near the
/// ground, a low pass while turning (blocks leave and enter the view), then teleports to the
/// corners and back. Frames whose pose jumped are marked.
fn flight() -> Vec<(Camera, bool)> {
    let mut frames = Vec::new();
    let pose = |x: f64, y: f64, z: f64, yaw: f64, pitch: f64| Pose {
        position: DVec3::new(x, y, z),
        yaw,
        pitch,
    };
    for k in 0..20 {
        let t = f64::from(k) / 19.0;
        frames.push((
            pose(
                1_280.0,
                -1_500.0 + 1_750.0 * t,
                2_000.0 - 1_900.0 * t,
                1.5,
                -0.6,
            ),
            false,
        ));
    }
    for k in 0..20 {
        let t = f64::from(k) / 19.0;
        frames.push((
            pose(
                1_280.0 + 750.0 * t,
                250.0 + 1_500.0 * t,
                100.0,
                1.5 - 3.0 * t,
                -0.3,
            ),
            false,
        ));
    }
    for (x, y, yaw) in [
        (50.0, 50.0, 0.8),
        (2_500.0, 2_500.0, -2.4),
        (1_280.0, 1_280.0, 0.0),
    ] {
        for k in 0..4 {
            frames.push((pose(x, y, 120.0, yaw + 0.1 * f64::from(k), -0.4), k == 0));
        }
    }
    frames
        .into_iter()
        .map(|(p, jumped)| (Camera::new(&p, view_600()), jumped))
        .collect()
}

/// The blocks' patch draw and the strips' list draw of a frame, as issued.
struct Issued {
    patch_words: u64,
    strip_vertices: u64,
    strip_indices: u64,
    strip_triangles: u64,
}

fn issued(buffers: &GpuBuffers) -> Issued {
    let mut issued = Issued {
        patch_words: 0,
        strip_vertices: 0,
        strip_indices: 0,
        strip_triangles: 0,
    };
    for call in buffers.draws() {
        match call.topology {
            Topology::Patches => issued.patch_words += u64::from(call.index_count),
            Topology::TriangleList => {
                issued.strip_vertices += buffers.vertices(call.vertices).len() as u64;
                issued.strip_indices += u64::from(call.index_count);
                issued.strip_triangles += u64::from(call.index_count / 3);
            }
            other => panic!("stitching-strips draws patches and lists, not {other:?}"),
        }
    }
    issued
}

fn drawn_blocks(stitching: &Stitching, stats: &FrameStats) -> u64 {
    (extra(stitching, stats, M_BLOCKS) - extra(stitching, stats, M_BLOCKS_CULLED)) as u64
}

#[test]
fn over_flights_the_buffers_are_the_mesh_and_only_blocks_and_strips_are_uploaded() {
    let hierarchy = bumpy_terrain(8);
    let flight = flight();
    for config in every_method_culling_and_p_block() {
        let context = format!("{:?}, culling {}", config.method, config.culling);
        let mut stitching = Stitching::new(&hierarchy, config);
        let (mut splits, mut merges, mut culled, mut factor_changes) = (0, 0, 0, 0);
        let mut factors_before = Vec::new();
        for (frame, (camera, jumped)) in flight.iter().enumerate() {
            let frame = frame as u64;
            let stats = checked_step(
                &hierarchy,
                &mut stitching,
                frame,
                camera,
                frame == 0 || *jumped,
                &context,
            );
            let counts = draw_counts(&stats);
            let issued = issued(stitching.buffers());
            let blocks = drawn_blocks(&stitching, &stats);
            assert_eq!(
                issued.patch_words * 4,
                blocks * PATCH_BYTES,
                "{context}, frame {frame}: one patch a drawn block"
            );
            assert_eq!(
                counts.triangles_submitted, stats.triangles,
                "{context}, frame {frame}: every triangle of the mesh is submitted"
            );
            let tessellated = counts.triangles_submitted - issued.strip_triangles;
            assert!(
                tessellated > 0,
                "{context}, frame {frame}: blocks were tessellated"
            );
            assert_eq!(
                counts.upload_bytes,
                frame_upload_bytes(blocks, issued.strip_vertices, issued.strip_triangles),
                "{context}, frame {frame}: the blocks' data and the strips' geometry, nothing of \
                 the {tessellated} tessellated triangles"
            );
            if config.method != StitchingMethod::Strips {
                assert_eq!(
                    issued.strip_indices, 0,
                    "{context}, frame {frame}: no strips"
                );
            }
            splits += stats.splits;
            merges += stats.merges;
            culled += extra(&stitching, &stats, M_BLOCKS_CULLED) as u64;
            let factors: Vec<(_, f64)> = stitching.leaves().collect();
            factor_changes += u64::from(factors != factors_before);
            factors_before = factors;
        }
        if config.method != StitchingMethod::Uniform {
            assert!(splits > 0 && merges > 0, "{context}: {splits} / {merges}");
        }
        assert!(factor_changes > 5, "{context}: {factor_changes}");
        assert_eq!(culled > 0, config.culling, "{context}: {culled} culled");
    }
}

#[test]
fn a_still_camera_uploads_the_blocks_data_and_the_strips_the_paper_rebuilds_each_frame() {
    let hierarchy = bumpy_terrain(8);
    let camera = Camera::new(
        &Pose {
            position: DVec3::new(1_000.0, 900.0, 150.0),
            yaw: 0.7,
            pitch: -0.35,
        },
        view_600(),
    );
    for config in every_method_culling_and_p_block() {
        let context = format!("{:?}, culling {}", config.method, config.culling);
        let mut stitching = Stitching::new(&hierarchy, config);
        let first = draw_counts(&step(&mut stitching, 0, &camera, true));
        for frame in 1..4 {
            let stats = step(&mut stitching, frame, &camera, false);
            let counts = draw_counts(&stats);
            let issued = issued(stitching.buffers());
            let blocks = drawn_blocks(&stitching, &stats);
            let strips = extra(&stitching, &stats, STRIPS) as u64;
            assert_eq!(
                counts, first,
                "{context}, frame {frame}: the same frame again"
            );
            let strip_bytes = frame_upload_bytes(0, issued.strip_vertices, issued.strip_triangles);
            assert_eq!(
                counts.upload_bytes,
                blocks * PATCH_BYTES + strip_bytes,
                "{context}, frame {frame}"
            );
            if config.method == StitchingMethod::Strips {
                assert!(
                    strips > 0 && strip_bytes > 0,
                    "{context}: strips were drawn"
                );
                assert_eq!(counts.draw_calls, 2, "{context}: the patches, the strips");
            } else {
                assert_eq!(
                    counts.upload_bytes,
                    blocks * PATCH_BYTES,
                    "{context}, frame {frame}: only the blocks' data"
                );
                assert_eq!(counts.draw_calls, 1, "{context}: the patches");
            }
        }
    }
}

/// Method II keeps the same blocks at every eye (all at the deepest level): whatever their
/// factors, and so their triangles, it uploads the same bytes.
#[test]
fn finer_tessellation_submits_more_triangles_and_uploads_nothing_more() {
    let hierarchy = bumpy_terrain(8);
    let camera = Camera::new(
        &Pose {
            position: DVec3::new(1_280.0, -300.0, 400.0),
            yaw: 1.5,
            pitch: -0.3,
        },
        view_600(),
    );
    let counts: Vec<DrawCounts> = [8.0, 2.0, 0.5]
        .into_iter()
        .map(|threshold_px| {
            let config = StitchingConfig {
                threshold_px,
                ..config(StitchingMethod::Uniform, false, PBlockShape::TwoTriangles)
            };
            let mut stitching = Stitching::new(&hierarchy, config);
            draw_counts(&checked_step(
                &hierarchy,
                &mut stitching,
                0,
                &camera,
                true,
                threshold_px,
            ))
        })
        .collect();
    for pair in counts.windows(2) {
        assert!(
            pair[1].triangles_submitted > pair[0].triangles_submitted,
            "{counts:?}"
        );
        assert_eq!(pair[1].upload_bytes, pair[0].upload_bytes, "{counts:?}");
    }
}
