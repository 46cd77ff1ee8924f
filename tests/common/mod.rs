//! Helpers shared by the integration tests: small terrains and scenes that read like the domain.

#![allow(
    dead_code,
    reason = "each test binary uses a different subset of the helpers"
)]

pub mod algorithms;
pub mod cli;
pub mod experiment;
pub mod patches;
pub mod scenes;

use glam::DVec3;
use roamsim::sim::algorithm::{BrokenBounds, FrameInput, LodAlgorithm};
use roamsim::sim::draw::DrawCounts;
use roamsim::sim::draw::check::check_buffers_draw_mesh;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::VertexSet;
use roamsim::sim::mesh::check::MeshChecker;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose, ViewSettings};
use std::fmt::Display;

/// One frame of `algorithm`: its update for frame `frame` seen from `camera` and the upkeep of
/// its GPU buffers (what the runner times), and the statistics it filled. `bounds_broken`: every motion bound broke since the
/// previous frame (a teleport, or the first frame), so whatever was deferred is revalidated.
pub fn step(
    algorithm: &mut dyn LodAlgorithm,
    frame: u64,
    camera: &Camera,
    bounds_broken: bool,
) -> FrameStats {
    step_breaking(
        algorithm,
        frame,
        camera,
        BrokenBounds::all_if(bounds_broken),
    )
}

/// [`step`], naming which motion bounds broke since the previous frame (a turn faster than
/// the rotation bound, say).
pub fn step_breaking(
    algorithm: &mut dyn LodAlgorithm,
    frame: u64,
    camera: &Camera,
    broken_bounds: BrokenBounds,
) -> FrameStats {
    let mut stats = FrameStats {
        frame,
        ..FrameStats::default()
    };
    algorithm.update(
        &FrameInput {
            frame,
            camera,
            broken_bounds,
        },
        &mut stats,
    );
    let draw = algorithm.prepare_draw();
    algorithm.draw_columns(&mut stats.extra);
    stats.upload_bytes = draw.upload_bytes;
    stats.draw_calls = draw.draw_calls;
    stats.triangles_submitted = draw.triangles_submitted;
    stats
}

/// What a stepped frame uploaded into its GPU buffers and issued ([`step`] made them drawable).
pub fn draw_counts(stats: &FrameStats) -> DrawCounts {
    DrawCounts {
        upload_bytes: stats.upload_bytes,
        draw_calls: stats.draw_calls,
        triangles_submitted: stats.triangles_submitted,
    }
}

/// [`step`], then what `roamsim run --check` runs after every frame: the mesh (either form)
/// and the algorithm's own triangle count against it, the statistics' count against both, and
/// the triangles its GPU buffers draw against the mesh.
/// Panics naming `context` and the frame.
pub fn checked_step(
    hierarchy: &Hierarchy,
    algorithm: &mut dyn LodAlgorithm,
    frame: u64,
    camera: &Camera,
    bounds_broken: bool,
    context: impl Display,
) -> FrameStats {
    let broken_bounds = BrokenBounds::all_if(bounds_broken);
    checked_step_breaking(hierarchy, algorithm, frame, camera, broken_bounds, context)
}

/// [`checked_step`], naming which motion bounds broke since the previous frame.
pub fn checked_step_breaking(
    hierarchy: &Hierarchy,
    algorithm: &mut dyn LodAlgorithm,
    frame: u64,
    camera: &Camera,
    broken_bounds: BrokenBounds,
    context: impl Display,
) -> FrameStats {
    let stats = step_breaking(algorithm, frame, camera, broken_bounds);
    if let Err(error) = MeshChecker::new().check(hierarchy, algorithm.mesh(), stats.triangles) {
        panic!("{context}, frame {frame}: {error}");
    }
    if let Err(error) = check_buffers_draw_mesh(algorithm.buffers(), algorithm.mesh(), hierarchy) {
        panic!("{context}, frame {frame}: {error}");
    }
    if let Err(error) = algorithm.check_own() {
        panic!("{context}, frame {frame}: {error}");
    }
    assert_eq!(
        algorithm.triangle_count(),
        stats.triangles,
        "{context}, frame {frame}: the algorithm's count and its statistics"
    );
    stats
}

/// Flies `algorithm` over `cameras`, frame k seen from `cameras[k]` with no motion bound
/// broken, each frame checked as [`checked_step`] checks it (panics naming `context` and the
/// frame); then `each_frame` gets the frame's number, camera and statistics and the algorithm,
/// for the suite's own checks. Returns what `each_frame` returned, frame by frame.
pub fn fly_checked<A: LodAlgorithm, T>(
    hierarchy: &Hierarchy,
    algorithm: &mut A,
    cameras: &[Camera],
    context: &str,
    mut each_frame: impl FnMut(usize, &Camera, FrameStats, &mut A) -> T,
) -> Vec<T> {
    cameras
        .iter()
        .enumerate()
        .map(|(frame, camera)| {
            let stats = checked_step(hierarchy, algorithm, frame as u64, camera, false, context);
            each_frame(frame, camera, stats, algorithm)
        })
        .collect()
}

/// The value of the algorithm-specific column `name` (a constant of
/// `roamsim::sim::algorithm::columns`) in `stats`. Panics when the algorithm does not declare it
/// (or it is no algorithm's column at all).
pub fn extra(algorithm: &dyn LodAlgorithm, stats: &FrameStats, name: &str) -> f64 {
    roamsim::sim::algorithm::columns::extra_value(algorithm.extra_columns(), stats, name)
        .unwrap_or_else(|| panic!("{} declares no column {name:?}", algorithm.name()))
}

/// The 4-8 mesh of an algorithm that draws one.
pub fn vertex_set(algorithm: &dyn LodAlgorithm) -> &VertexSet {
    algorithm
        .mesh()
        .lattice_vertices()
        .unwrap_or_else(|| panic!("{} draws a triangle list, not a 4-8 mesh", algorithm.name()))
}

/// A deterministic bumpy terrain of side 2^level + 1 with 10 m posts.
pub fn bumpy_terrain(level: u32) -> Hierarchy {
    let side = (1usize << level) + 1;
    let heights = (0..side * side)
        .map(|k| {
            let (i, j) = ((k % side) as f32, (k / side) as f32);
            20.0 * (0.9 * i).sin() * (0.7 * j).cos() + ((k * 2654435761) % 97) as f32 * 0.3
        })
        .collect();
    let field = Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap();
    Hierarchy::new(field)
}

pub fn view_600() -> ViewSettings {
    ViewSettings {
        width_px: 600,
        height_px: 600,
        fovy: 60f64.to_radians(),
        near: 1.0,
        far: 100_000.0,
    }
}

/// A camera at `eye` looking along +x, slightly down.
pub fn camera_at(eye: DVec3) -> Camera {
    Camera::new(
        &Pose {
            position: eye,
            yaw: 0.0,
            pitch: -0.3,
        },
        view_600(),
    )
}
