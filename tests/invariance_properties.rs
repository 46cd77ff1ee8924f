//! Invariance properties (SPEC §9), for every algorithm, on random terrains and flights:
//!
//! - translating terrain and flight together by up to 10^6 m (the terrain's `f64` origin, the
//!   flight's world poses) changes no split or merge decision: the same mesh and the same
//!   counts (splits, merges, vertices inserted and deleted, triangles) at every frame;
//! - scaling terrain, flight, near/far planes and speed bounds together by a power of two changes
//!   no mesh and no count. Powers of two keep every stored `f32` height exact, so any difference
//!   would be an absolute length hidden in the arithmetic (an epsilon in metres, a clamp); other
//!   factors (0.001, 1000) are checked on a fixed scene in `tests/hard_cases.rs`.
//!
//! The block-based algorithms (triangle lists) are held to the same properties through their
//! drawn triangles: positions, roles, groups, levels and heights (scaled heights divided by the
//! power of two, exactly), and their counts.
//!
//! Röttger's configurations (`every_rottger`: it has no τ) run on every scene too, and so do
//! `vanek`'s (`every_vanek`: no τ either; its mindist and maxdist scale with the scene) and the
//! stitching strips' (`every_stitching`: a threshold in pixels, like τ).
//!
//! This file does not check that the meshes are right, only that they do not move;
//! `tests/hard_cases.rs` and the per-algorithm tests check the right answers.

mod common;

use common::algorithms::{
    every_algorithm, every_block_algorithm, every_rottger, every_stitching, every_vanek,
};
use common::{step, vertex_set, view_600};
use glam::DVec3;
use proptest::prelude::*;
use roamsim::sim::algorithm::AlgorithmConfig;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::VertexSet;
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose, ViewSettings};
use roamsim::sim::zone::SpeedBound;

const SIDE: usize = 17;
const POST_M: f64 = 10.0;

const SPEED: SpeedBound = SpeedBound {
    horizontal: 10.0,
    vertical: 5.0,
    rotation: SpeedBound::NO_ROTATION_BOUND,
};

/// What one frame decided: the mesh and the counts of what changed.
#[derive(Debug, PartialEq)]
struct Decisions {
    mesh: VertexSet,
    counts: [u64; 5],
}

/// A scene: terrain heights, a flight in the terrain's frame and a tolerance.
#[derive(Clone, Debug)]
struct Scene {
    heights: Vec<f32>,
    poses: Vec<Pose>,
    tau_px: f64,
}

fn scene() -> impl Strategy<Value = Scene> {
    let heights = prop::collection::vec(-40.0f32..40.0, SIDE * SIDE);
    let start = (-40.0..200.0f64, -40.0..200.0f64, 5.0..150.0f64);
    // Steps within the speed bounds: the flight never needs revalidating.
    let steps = prop::collection::vec((-7.0..7.0f64, -7.0..7.0f64, -3.0..3.0f64), 1..8);
    let look = (0.0..std::f64::consts::TAU, -1.4..0.2f64);
    let tau_px = prop_oneof![Just(0.5), Just(1.0), Just(2.0), Just(4.0), 0.25..16.0f64];
    (heights, start, steps, look, tau_px).prop_map(|(heights, start, steps, look, tau_px)| {
        let mut eye = DVec3::new(start.0, start.1, start.2);
        let mut poses = vec![eye];
        for (dx, dy, dz) in steps {
            eye += DVec3::new(dx, dy, dz);
            poses.push(eye);
        }
        let poses = poses
            .into_iter()
            .enumerate()
            .map(|(k, position)| Pose {
                position,
                yaw: look.0 + 0.05 * k as f64,
                pitch: look.1,
            })
            .collect();
        Scene {
            heights,
            poses,
            tau_px,
        }
    })
}

/// Every frame's decisions of `config` over the poses (world poses, moved into the terrain's
/// frame as the runner does).
fn decisions(
    hierarchy: &Hierarchy,
    config: &AlgorithmConfig,
    view: ViewSettings,
    speed: SpeedBound,
    poses: &[Pose],
) -> Vec<Decisions> {
    let mut algorithm = config.build(hierarchy, &view, speed);
    poses
        .iter()
        .enumerate()
        .map(|(frame, pose)| {
            let camera = Camera::new(&hierarchy.field().local_pose(pose), view);
            let stats = step(algorithm.as_mut(), frame as u64, &camera, frame == 0);
            Decisions {
                mesh: vertex_set(algorithm.as_ref()).clone(),
                counts: [
                    stats.triangles,
                    stats.splits,
                    stats.merges,
                    stats.vertices_inserted,
                    stats.vertices_deleted,
                ],
            }
        })
        .collect()
}

/// One triangle as a block algorithm drew it: corner positions (fixed point), role, group,
/// level — what it decided.
type DrawnSignature = ([(i64, i64); 3], usize, u32, u32);

/// What one frame of a block algorithm decided: its triangles and its counts, and the corner
/// heights it drew them at (divided by the scene's scale).
#[derive(Debug, PartialEq)]
struct BlockDecisions {
    triangles: Vec<DrawnSignature>,
    counts: [u64; 5],
    heights: Vec<[f64; 3]>,
}

impl BlockDecisions {
    /// The same triangles and counts, and heights within `tolerance_m` of each other.
    fn same_within(&self, other: &BlockDecisions, tolerance_m: f64) -> bool {
        self.triangles == other.triangles
            && self.counts == other.counts
            && self.heights.len() == other.heights.len()
            && self
                .heights
                .iter()
                .zip(&other.heights)
                .all(|(a, b)| a.iter().zip(b).all(|(a, b)| (a - b).abs() <= tolerance_m))
    }
}

/// How far a morphed height may move when the terrain and the flight are translated: the eye's
/// terrain-local position is `(p + offset) − offset`, which rounds at a million metres by up to
/// about 10⁻¹⁰ m, and a morph factor is a continuous function of that distance (a decision
/// is not: levels, positions, roles and counts must match exactly).
const TRANSLATED_MORPH_TOLERANCE_M: f64 = 1e-6;

/// Every frame's decisions of a block algorithm over the poses, heights divided by `scale`.
fn block_decisions(
    hierarchy: &Hierarchy,
    config: &AlgorithmConfig,
    view: ViewSettings,
    poses: &[Pose],
    scale: f64,
) -> Vec<BlockDecisions> {
    let mut algorithm = config.build(hierarchy, &view, SPEED);
    poses
        .iter()
        .enumerate()
        .map(|(frame, pose)| {
            let camera = Camera::new(&hierarchy.field().local_pose(pose), view);
            let stats = step(algorithm.as_mut(), frame as u64, &camera, frame == 0);
            let mut triangles = Vec::new();
            let mut heights = Vec::new();
            algorithm.mesh().for_each_triangle(hierarchy, |t| {
                triangles.push((
                    t.corners.map(|c| c.position.raw()),
                    t.info.role.index(),
                    t.info.group,
                    t.info.level,
                ));
                heights.push(t.corners.map(|c| f64::from(c.z) / scale));
            });
            BlockDecisions {
                triangles,
                counts: [
                    stats.triangles,
                    stats.splits,
                    stats.merges,
                    stats.vertices_inserted,
                    stats.vertices_deleted,
                ],
                heights,
            }
        })
        .collect()
}

fn hierarchy(heights: Vec<f32>, post_m: f64, origin: DVec3) -> Hierarchy {
    let spacing = Spacing {
        dx: post_m,
        dy: post_m,
    };
    Hierarchy::new(
        Heightfield::new(SIDE, heights, spacing)
            .unwrap()
            .with_origin(origin),
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn translating_terrain_and_flight_by_up_to_a_million_metres_changes_no_decision(
        scene in scene(),
        offset in (-1e6..1e6f64, -1e6..1e6f64, -1e6..1e6f64),
    ) {
        let offset = DVec3::new(offset.0, offset.1, offset.2);
        let here = hierarchy(scene.heights.clone(), POST_M, DVec3::ZERO);
        let there = hierarchy(scene.heights.clone(), POST_M, offset);
        let moved: Vec<Pose> = scene
            .poses
            .iter()
            .map(|p| Pose { position: p.position + offset, ..*p })
            .collect();
        for config in every_algorithm(scene.tau_px).into_iter().chain(every_rottger()) {
            let a = decisions(&here, &config, view_600(), SPEED, &scene.poses);
            let b = decisions(&there, &config, view_600(), SPEED, &moved);
            prop_assert_eq!(a, b, "{:?}, offset {:?}", config, offset);
        }
        for config in every_block_algorithm(scene.tau_px)
            .into_iter()
            .chain(every_vanek(1.0))
            .chain(every_stitching())
        {
            let a = block_decisions(&here, &config, view_600(), &scene.poses, 1.0);
            let b = block_decisions(&there, &config, view_600(), &moved, 1.0);
            let same = a
                .iter()
                .zip(&b)
                .all(|(a, b)| a.same_within(b, TRANSLATED_MORPH_TOLERANCE_M));
            prop_assert!(a.len() == b.len() && same, "{:?}, offset {:?}", config, offset);
        }
    }

    #[test]
    fn scaling_terrain_flight_and_speed_bounds_by_a_power_of_two_changes_no_decision(
        scene in scene(),
        exponent in -12..=12i32,
    ) {
        let scale = 2f64.powi(exponent);
        let original = hierarchy(scene.heights.clone(), POST_M, DVec3::ZERO);
        let scaled_heights = scene.heights.iter().map(|h| (f64::from(*h) * scale) as f32).collect();
        let scaled = hierarchy(scaled_heights, POST_M * scale, DVec3::ZERO);
        let scaled_poses: Vec<Pose> = scene
            .poses
            .iter()
            .map(|p| Pose { position: p.position * scale, ..*p })
            .collect();
        let view = view_600();
        let scaled_view = ViewSettings { near: view.near * scale, far: view.far * scale, ..view };
        let scaled_speed = SpeedBound {
            horizontal: SPEED.horizontal * scale,
            vertical: SPEED.vertical * scale,
            rotation: SPEED.rotation,
        };
        for config in every_algorithm(scene.tau_px).into_iter().chain(every_rottger()) {
            let a = decisions(&original, &config, view, SPEED, &scene.poses);
            let b = decisions(&scaled, &config, scaled_view, scaled_speed, &scaled_poses);
            prop_assert_eq!(a, b, "{:?} at scale 2^{}", config, exponent);
        }
        for config in every_block_algorithm(scene.tau_px).into_iter().chain(every_stitching()) {
            let a = block_decisions(&original, &config, view, &scene.poses, 1.0);
            let b = block_decisions(&scaled, &config, scaled_view, &scaled_poses, scale);
            prop_assert!(a == b, "{:?} at scale 2^{}", config, exponent);
        }
        // vanek's mindist and maxdist are lengths: scaled with the scene.
        for (one, many) in every_vanek(1.0).into_iter().zip(every_vanek(scale)) {
            let a = block_decisions(&original, &one, view, &scene.poses, 1.0);
            let b = block_decisions(&scaled, &many, scaled_view, &scaled_poses, scale);
            prop_assert!(a == b, "{:?} at scale 2^{}", one, exponent);
        }
    }
}
