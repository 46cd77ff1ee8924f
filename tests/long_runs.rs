//! Very long runs (SPEC §9): 10^6 frames of every algorithm over a small terrain, circled so that
//! the mesh keeps changing. Nothing may overflow or drift: the frame counter, the wheels and b
//! (Wu's own million-frame test is in `tests/wu.rs`), the slotmap keys and queues (ROAM), the
//! double-buffered meshes and quadtree matrix (the from-scratch algorithms), Röttger's c under its
//! load controller. Each run checks that the mesh is valid,
//! that the inserted and deleted vertices summed over the run account exactly for the final mesh
//! (no counter wrapped or lost a change), that the algorithm's memory stays bounded (no leak
//! from frame to frame), and that the final mesh is the one a fresh instance builds for the
//! final view (no drift). The block-based algorithms (geomipmap, chunked, stitching-strips) are
//! held to the same, their vertices counted in their triangle lists (every chunk's, patch's,
//! block's or cross of strips' own).
//!
//! This file does not measure speed; `benches/` does.

mod common;

use common::algorithms::{
    chunked, chunked_with_everything, geomipmap, lindstrom, reference, roam_tolerance, stitching,
    vanek,
};
use common::{bumpy_terrain, camera_at, checked_step, extra, step, vertex_set};
use glam::DVec3;
use roamsim::sim::algorithm::RottgerConfig;
use roamsim::sim::algorithm::rottger::{LoadCount, LoadTarget};
use roamsim::sim::algorithm::{
    AlgorithmConfig, BlockGoal, ChunkedConfig, GeomipmapConfig, LevelDifference, LodAlgorithm,
    RoamConfig, VanekConfig,
};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::MeshOutput;
use roamsim::sim::mesh::VertexSet;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::zone::{SpeedBound, ZoneVariant};

const MILLION: u64 = 1_000_000;

/// Frames per lap of the circle: 250 laps in a million frames.
const FRAMES_PER_LAP: u64 = 4000;

const SPEED: SpeedBound = SpeedBound {
    horizontal: 10.0,
    vertical: 5.0,
    rotation: SpeedBound::NO_ROTATION_BOUND,
};

/// The eye at `frame`: a circle of 60 m around the middle of a 9×9 terrain, 30 m up (0.1 m a
/// frame, inside the speed bounds).
fn eye_at(frame: u64) -> DVec3 {
    let angle = (frame % FRAMES_PER_LAP) as f64 * std::f64::consts::TAU / FRAMES_PER_LAP as f64;
    DVec3::new(40.0 + 60.0 * angle.cos(), 40.0 + 60.0 * angle.sin(), 30.0)
}

/// What a long run leaves behind.
struct LongRun {
    final_mesh: VertexSet,
    /// Σ vertices inserted − Σ vertices deleted over the run.
    net_vertices: i128,
    total_changes: u128,
    memory_after_first_lap: usize,
    memory_at_end: usize,
}

fn fly(hierarchy: &Hierarchy, config: &AlgorithmConfig, frames: u64) -> LongRun {
    fly_observed(hierarchy, config, frames, &mut |_, _, _| {})
}

/// [`fly`], showing every frame's statistics (and the algorithm that filled them) to `observe`.
fn fly_observed(
    hierarchy: &Hierarchy,
    config: &AlgorithmConfig,
    frames: u64,
    observe: &mut dyn FnMut(u64, &dyn LodAlgorithm, &FrameStats),
) -> LongRun {
    let mut algorithm = config.build(hierarchy, &common::view_600(), SPEED);
    let (mut inserted, mut deleted) = (0u128, 0u128);
    let mut memory_after_first_lap = 0;
    for frame in 0..frames {
        let camera = camera_at(eye_at(frame));
        let checked = frame % 100_003 == 0 || frame + 1 == frames;
        let stats = if checked {
            let context = format!("{config:?}");
            checked_step(
                hierarchy,
                algorithm.as_mut(),
                frame,
                &camera,
                frame == 0,
                context,
            )
        } else {
            step(algorithm.as_mut(), frame, &camera, frame == 0)
        };
        inserted += u128::from(stats.vertices_inserted);
        deleted += u128::from(stats.vertices_deleted);
        observe(frame, algorithm.as_ref(), &stats);
        if frame + 1 == FRAMES_PER_LAP {
            memory_after_first_lap = algorithm.memory_bytes();
        }
    }
    LongRun {
        final_mesh: vertex_set(algorithm.as_ref()).clone(),
        net_vertices: inserted as i128 - deleted as i128,
        total_changes: inserted + deleted,
        memory_after_first_lap,
        memory_at_end: algorithm.memory_bytes(),
    }
}

/// The mesh a fresh instance builds for the view of `frame`.
fn fresh_mesh(hierarchy: &Hierarchy, config: &AlgorithmConfig, frame: u64) -> VertexSet {
    let mut algorithm = config.build(hierarchy, &common::view_600(), SPEED);
    step(algorithm.as_mut(), 0, &camera_at(eye_at(frame)), true);
    vertex_set(algorithm.as_ref()).clone()
}

fn check_million_frames(config: AlgorithmConfig) {
    let hierarchy = bumpy_terrain(3);
    let run = fly(&hierarchy, &config, MILLION);
    let base = VertexSet::base_mesh(hierarchy.lattice());
    assert_eq!(
        run.net_vertices,
        run.final_mesh.len() as i128 - base.len() as i128,
        "{config:?}: the inserted and deleted counts do not account for the final mesh"
    );
    assert!(
        run.total_changes > 1000,
        "{config:?}: the mesh hardly changed ({} changes), the flight tests nothing",
        run.total_changes
    );
    assert!(
        run.memory_at_end <= 2 * run.memory_after_first_lap.max(1),
        "{config:?}: memory grew from {} to {} bytes",
        run.memory_after_first_lap,
        run.memory_at_end
    );
    assert_eq!(
        run.final_mesh,
        fresh_mesh(&hierarchy, &config, MILLION - 1),
        "{config:?}: the mesh after 10^6 frames is not the one the final view calls for"
    );
}

#[test]
fn a_million_reference_frames_stay_exact() {
    // Wu's zones are large at small τ: at 4 px this flight stays inside all of them.
    check_million_frames(AlgorithmConfig::Reference(reference(
        64.0,
        ZoneVariant::Conservative,
    )));
}

#[test]
fn a_million_lindstrom_frames_stay_exact() {
    check_million_frames(AlgorithmConfig::Lindstrom(lindstrom(4.0, 1)));
}

#[test]
fn a_million_roam_frames_with_every_effect_stay_exact() {
    check_million_frames(AlgorithmConfig::Roam(RoamConfig {
        deferral: true,
        culling_flags: true,
        strips: true,
        ..roam_tolerance(4.0)
    }));
}

#[test]
fn a_million_roam_rebuild_frames_stay_exact() {
    // A coarser τ than roam's: the rebuild splits from the base mesh every frame, and its cost
    // grows with the mesh; the mesh still changes thousands of times.
    check_million_frames(AlgorithmConfig::RoamRebuild(roam_tolerance(16.0)));
}

/// One drawn triangle as comparable values: its corners (position and height bits), role, group
/// and level.
type TriangleSignature = ([(i64, i64, u32); 3], usize, u32, u32);

/// A block algorithm's triangle list as comparable values.
fn list_signature(hierarchy: &Hierarchy, algorithm: &dyn LodAlgorithm) -> Vec<TriangleSignature> {
    let mut triangles = Vec::new();
    algorithm.mesh().for_each_triangle(hierarchy, |t| {
        triangles.push((
            t.corners.map(|c| {
                let (x, y) = c.position.raw();
                (x, y, c.z.to_bits())
            }),
            t.info.role.index(),
            t.info.group,
            t.info.level,
        ));
    });
    triangles
}

/// A million frames of a block algorithm: the mesh valid at the checked frames, the vertices
/// inserted and deleted over the run adding up to the final list's, memory bounded, and the
/// final list the one a fresh instance draws for the final view.
fn check_million_block_frames(config: AlgorithmConfig) {
    let hierarchy = bumpy_terrain(3);
    let mut algorithm = config.build(&hierarchy, &common::view_600(), SPEED);
    let (mut inserted, mut deleted) = (0u128, 0u128);
    let mut memory_after_first_lap = 0;
    for frame in 0..MILLION {
        let camera = camera_at(eye_at(frame));
        let stats = if frame % 100_003 == 0 || frame + 1 == MILLION {
            let context = format!("{config:?}");
            checked_step(
                &hierarchy,
                algorithm.as_mut(),
                frame,
                &camera,
                frame == 0,
                context,
            )
        } else {
            step(algorithm.as_mut(), frame, &camera, frame == 0)
        };
        inserted += u128::from(stats.vertices_inserted);
        deleted += u128::from(stats.vertices_deleted);
        if frame + 1 == FRAMES_PER_LAP {
            memory_after_first_lap = algorithm.memory_bytes();
        }
    }
    let MeshOutput::Triangles(list) = algorithm.mesh() else {
        panic!("{config:?} draws a triangle list");
    };
    assert_eq!(
        inserted as i128 - deleted as i128,
        list.vertices().len() as i128,
        "{config:?}: the inserted and deleted counts do not account for the final mesh"
    );
    assert!(
        inserted + deleted > 1000,
        "{config:?}: the mesh hardly changed ({} changes), the flight tests nothing",
        inserted + deleted
    );
    let memory_at_end = algorithm.memory_bytes();
    assert!(
        memory_at_end <= 2 * memory_after_first_lap.max(1),
        "{config:?}: memory grew from {memory_after_first_lap} to {memory_at_end} bytes"
    );
    let mut fresh = config.build(&hierarchy, &common::view_600(), SPEED);
    step(fresh.as_mut(), 0, &camera_at(eye_at(MILLION - 1)), true);
    assert!(
        list_signature(&hierarchy, algorithm.as_ref())
            == list_signature(&hierarchy, fresh.as_ref()),
        "{config:?}: the mesh after 10^6 frames is not the one the final view calls for"
    );
}

#[test]
fn a_million_geomipmap_frames_with_morphing_stay_exact() {
    check_million_block_frames(AlgorithmConfig::Geomipmap(GeomipmapConfig {
        morph: true,
        level_difference: LevelDifference::Any,
        // 4 patches of 4×4 cells: 8 to 128 triangles; held at 40, they change level around
        // the circle.
        goal: BlockGoal::TargetTriangles(40),
        ..geomipmap(1.0, 2)
    }));
}

#[test]
fn a_million_chunked_frames_with_every_effect_and_a_target_stay_exact() {
    check_million_block_frames(AlgorithmConfig::Chunked(chunked_with_everything(4.0, 1)));
    check_million_block_frames(AlgorithmConfig::Chunked(ChunkedConfig {
        goal: BlockGoal::TargetTriangles(250),
        morph: true,
        ..chunked(4.0, 1)
    }));
}

#[test]
fn a_million_vanek_frames_with_culling_and_a_target_stay_exact() {
    // 4×4 patches of 3×3 samples; the eye 30 m up, 20 to 100 m from the patches' boxes around
    // the circle: the linear curve from 35 to 110 m moves every patch through its levels, and
    // the target (120 triangles, of 64 at the coarsest and 224 at the finest) moves the distance
    // multiplier every lap.
    check_million_block_frames(AlgorithmConfig::Vanek(VanekConfig {
        box_culling: true,
        ..vanek(1, 35.0, 110.0)
    }));
    check_million_block_frames(AlgorithmConfig::Vanek(VanekConfig {
        target_triangles: Some(120),
        ..vanek(1, 35.0, 110.0)
    }));
}

#[test]
fn a_million_stitching_strips_frames_with_culling_stay_exact() {
    // The 8-cell terrain is one block (blocks of at most 64 cells have no error at F = 64, so
    // they never split); at ρ_thr = 40 px its factor moves between 2 and a few tens around the
    // circle, fractional all the way.
    check_million_block_frames(AlgorithmConfig::Stitching(
        roamsim::sim::algorithm::StitchingConfig {
            culling: true,
            ..stitching(40.0, 1)
        },
    ));
}

#[test]
fn a_million_rottger_frames_with_clipping_and_geomorphing_stay_exact() {
    check_million_frames(AlgorithmConfig::Rottger(RottgerConfig {
        clipping: true,
        ..common::algorithms::rottger(4.0, 20.0)
    }));
}

#[test]
fn a_million_rottger_frames_under_the_load_controller_keep_c_bounded_and_exact() {
    // The controller's c changes every frame it misses the target: after 10^6 frames it must
    // still be a finite value inside its bounds that moved within the last lap, and the mesh must
    // be the one a fixed-c instance at the final c builds for the final view.
    use roamsim::sim::algorithm::columns::rottger::DESIRED_RESOLUTION_C;
    use roamsim::sim::algorithm::rottger::{DESIRED_RESOLUTION_MAX, DESIRED_RESOLUTION_MIN};
    let hierarchy = bumpy_terrain(3);
    let config = RottgerConfig {
        load: Some(LoadTarget {
            count: LoadCount::FanVertices,
            target: 150,
        }),
        ..common::algorithms::rottger(2.0, 1.0)
    };
    let mut c_in_last_lap = std::collections::BTreeSet::new();
    let mut last_c = 0.0;
    let run = fly_observed(
        &hierarchy,
        &AlgorithmConfig::Rottger(config),
        MILLION,
        &mut |frame, algorithm, stats| {
            last_c = extra(algorithm, stats, DESIRED_RESOLUTION_C);
            assert!(
                (DESIRED_RESOLUTION_MIN..=DESIRED_RESOLUTION_MAX).contains(&last_c),
                "frame {frame}: c = {last_c}"
            );
            if frame + FRAMES_PER_LAP >= MILLION {
                c_in_last_lap.insert(last_c.to_bits());
            }
        },
    );
    let base = VertexSet::base_mesh(hierarchy.lattice());
    assert_eq!(
        run.net_vertices,
        run.final_mesh.len() as i128 - base.len() as i128
    );
    assert!(run.memory_at_end <= 2 * run.memory_after_first_lap);
    assert!(c_in_last_lap.len() > 1, "c froze");
    let fixed = AlgorithmConfig::Rottger(RottgerConfig {
        load: None,
        desired_resolution: last_c,
        ..config
    });
    assert_eq!(run.final_mesh, fresh_mesh(&hierarchy, &fixed, MILLION - 1));
}
