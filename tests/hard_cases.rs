//! Hard cases of SPEC §9 for every algorithm: each test states the right answer (full
//! resolution, the base mesh, identical meshes) and checks it, besides the absence of panics.
//! Every mesh is also validated (closure and the triangle-count formula).

mod common;

use common::view_600;
use glam::DVec3;
use roamsim::sim::algorithm::{
    AlgorithmConfig, FrameInput, LindstromConfig, ReferenceConfig, RoamConfig, RoamGoal,
    SplitThreshold, WuConfig,
};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::VertexSet;
use roamsim::sim::mesh::validate::validate_reported;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose, ViewSettings};
use roamsim::sim::zone::{SpeedBound, ZoneVariant};

const SPEED: SpeedBound = SpeedBound {
    horizontal: 10.0,
    vertical: 5.0,
};

/// Every algorithm at tolerance `tau_px`, with the options that make it a pure function of the
/// view (no budget).
fn every_algorithm(tau_px: f64) -> Vec<AlgorithmConfig> {
    let mut configs = Vec::new();
    for zone in [ZoneVariant::Conservative, ZoneVariant::Paper] {
        configs.push(AlgorithmConfig::Reference(ReferenceConfig {
            nesting: roamsim::sim::hierarchy::NestingRule::Max,
            tau_px,
            zone,
            threshold: SplitThreshold::LifeAtMost(0.0),
        }));
        configs.push(AlgorithmConfig::Wu(WuConfig {
            nesting: roamsim::sim::hierarchy::NestingRule::Max,
            tau_px: Some(tau_px),
            budget: None,
            zone,
            block_priority: false,
            depth_limit: None,
            cone_culling: false,
            wheel_links: 64,
        }));
    }
    for block_level in [1, 3] {
        configs.push(AlgorithmConfig::Lindstrom(LindstromConfig {
            nesting: roamsim::sim::hierarchy::NestingRule::Max,
            tau_px,
            block_level,
        }));
    }
    let roam = RoamConfig {
        nesting: roamsim::sim::hierarchy::NestingRule::MaxPlusOwn,
        goal: RoamGoal::TolerancePx(tau_px),
        deferral: false,
        culling_flags: false,
        strips: false,
    };
    configs.push(AlgorithmConfig::Roam(roam));
    configs.push(AlgorithmConfig::Roam(RoamConfig {
        deferral: true,
        culling_flags: true,
        strips: true,
        ..roam
    }));
    configs.push(AlgorithmConfig::RoamRebuild(roam));
    configs
}

fn terrain(side: usize, spacing: f64, height: impl Fn(usize, usize) -> f32) -> Hierarchy {
    let heights = (0..side * side)
        .map(|k| height(k % side, k / side))
        .collect();
    let field = Heightfield::new(
        side,
        heights,
        Spacing {
            dx: spacing,
            dy: spacing,
        },
    )
    .unwrap();
    Hierarchy::new(field)
}

/// A pseudo-random number in [−1, 1] for a sample (SplitMix64's finaliser: well mixed).
fn noise(i: usize, j: usize) -> f64 {
    let mut x = ((i as u64) << 32 | j as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^= x >> 31;
    (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Pseudo-random relief in ±amplitude: every vertex has a non-zero error.
fn rough(side: usize, spacing: f64, amplitude: f32) -> Hierarchy {
    terrain(side, spacing, |i, j| amplitude * noise(i, j) as f32)
}

/// The pose the tests fly with: looking north-east and down.
fn pose(eye: DVec3) -> Pose {
    Pose {
        position: eye,
        yaw: 0.7,
        pitch: -0.4,
    }
}

/// Runs `config` over the eyes (one frame each, in order) and returns the final mesh; every
/// frame's mesh is validated.
fn final_mesh(
    hierarchy: &Hierarchy,
    config: &AlgorithmConfig,
    view: ViewSettings,
    speed: SpeedBound,
    eyes: &[DVec3],
) -> VertexSet {
    let poses: Vec<Pose> = eyes.iter().map(|&e| pose(e)).collect();
    final_mesh_from(hierarchy, config, view, speed, &poses)
}

/// [`final_mesh`] with explicit poses.
fn final_mesh_from(
    hierarchy: &Hierarchy,
    config: &AlgorithmConfig,
    view: ViewSettings,
    speed: SpeedBound,
    poses: &[Pose],
) -> VertexSet {
    let mut algorithm = config.build(hierarchy, &view, speed);
    for (frame, pose) in poses.iter().enumerate() {
        let eye = pose.position;
        // As the runner does: world pose into the terrain's local frame.
        let camera = Camera::new(&hierarchy.field().local_pose(pose), view);
        let mut stats = FrameStats::default();
        algorithm.update(
            &FrameInput {
                frame: frame as u64,
                camera: &camera,
                speed_bound_broken: frame == 0,
            },
            &mut stats,
        );
        if let Err(error) =
            validate_reported(hierarchy.lattice(), algorithm.mesh(), stats.triangles)
        {
            panic!("{config:?}, eye {eye:?}: {error}");
        }
    }
    algorithm.mesh().clone()
}

fn full_grid(hierarchy: &Hierarchy) -> VertexSet {
    let mut set = VertexSet::new(hierarchy.lattice());
    for id in 0..hierarchy.lattice().n_vertices() as u32 {
        set.insert(id);
    }
    set
}

#[test]
fn flat_terrain_gives_the_base_mesh_for_every_eye_and_tolerance() {
    let flat = terrain(17, 10.0, |_, _| 123.0);
    let base = VertexSet::base_mesh(flat.lattice());
    for tau_px in [0.0, 1.0, 1e9] {
        for config in every_algorithm(tau_px) {
            for eye in [
                DVec3::new(80.0, 80.0, 123.0),
                DVec3::new(-50.0, 30.0, 500.0),
            ] {
                let mesh = final_mesh(&flat, &config, view_600(), SPEED, &[eye]);
                assert_eq!(mesh, base, "{config:?} from {eye:?}");
            }
        }
    }
}

#[test]
fn tau_zero_gives_full_resolution_on_rough_terrain() {
    // Looking straight down from 1 km, the whole terrain is in view (culling flags cull nothing).
    let hierarchy = rough(17, 10.0, 50.0);
    let full = full_grid(&hierarchy);
    let above = Pose {
        position: DVec3::new(80.0, 80.0, 1000.0),
        yaw: 0.0,
        pitch: -std::f64::consts::FRAC_PI_2,
    };
    for config in every_algorithm(0.0) {
        let mesh = final_mesh_from(&hierarchy, &config, view_600(), SPEED, &[above]);
        assert_eq!(mesh, full, "{config:?}");
    }
}

#[test]
fn a_far_eye_gives_the_base_mesh_and_a_huge_tau_keeps_it_coarse() {
    let hierarchy = rough(33, 10.0, 50.0);
    let base = VertexSet::base_mesh(hierarchy.lattice());
    for config in every_algorithm(1.0) {
        let mesh = final_mesh(
            &hierarchy,
            &config,
            view_600(),
            SPEED,
            &[DVec3::new(0.0, 0.0, 1e9)],
        );
        assert_eq!(mesh, base, "{config:?}");
    }
    for config in every_algorithm(1e12) {
        let mesh = final_mesh(
            &hierarchy,
            &config,
            view_600(),
            SPEED,
            &[DVec3::new(-5e3, 160.0, 400.0)],
        );
        assert_eq!(mesh, base, "{config:?}");
    }
}

#[test]
fn eyes_on_a_vertex_on_a_block_centre_inside_and_below_the_terrain_keep_the_vertex_under_them() {
    let hierarchy = rough(17, 10.0, 50.0);
    let lattice = hierarchy.lattice();
    let field = hierarchy.field();
    // On the root's centre vertex, on an edge midpoint, inside the terrain, far below it.
    let cases = [(8, 8, 0.0), (4, 8, 0.0), (5, 11, -10.0), (12, 3, -1000.0)];
    for (i, j, below) in cases {
        let eye = field.position(i, j) + DVec3::new(0.0, 0.0, below);
        for config in every_algorithm(1.0) {
            let mesh = final_mesh(&hierarchy, &config, view_600(), SPEED, &[eye]);
            let p = roamsim::sim::hierarchy::GridPoint::new(i as u32, j as u32);
            if below > -100.0 {
                assert!(mesh.contains_point(lattice, p), "{config:?}: eye {eye:?}");
            }
        }
    }
}

#[test]
fn tiny_terrains_of_3_by_3_and_5_by_5_work_for_every_algorithm() {
    for side in [3, 5] {
        let hierarchy = rough(side, 1.0, 5.0);
        let full = full_grid(&hierarchy);
        for config in every_algorithm(0.0) {
            let mesh = final_mesh(
                &hierarchy,
                &config,
                view_600(),
                SPEED,
                &[DVec3::new(1.0, 1.0, 3.0)],
            );
            assert_eq!(mesh, full, "{config:?} on {side}×{side}");
        }
    }
}

#[test]
fn scaling_terrain_flight_and_speed_bounds_together_changes_no_mesh() {
    let eyes: Vec<DVec3> = (0..30)
        .map(|f| DVec3::new(20.0 + 4.0 * f as f64, 60.0 + 2.0 * f as f64, 90.0))
        .collect();
    for scale in [0.001, 1000.0] {
        let small = rough(33, 10.0, 20.0);
        let scaled = terrain(33, 10.0 * scale, |i, j| {
            (f64::from(20.0 * noise(i, j) as f32) * scale) as f32
        });
        let scaled_eyes: Vec<DVec3> = eyes.iter().map(|e| *e * scale).collect();
        let view = view_600();
        let scaled_view = ViewSettings {
            near: view.near * scale,
            far: view.far * scale,
            ..view
        };
        let scaled_speed = SpeedBound {
            horizontal: SPEED.horizontal * scale,
            vertical: SPEED.vertical * scale,
        };
        for config in every_algorithm(2.0) {
            let a = final_mesh(&small, &config, view, SPEED, &eyes);
            let b = final_mesh(&scaled, &config, scaled_view, scaled_speed, &scaled_eyes);
            assert_eq!(a, b, "{config:?} at scale {scale}");
        }
    }
}

#[test]
fn zero_and_huge_speed_bounds_change_no_fixed_tau_mesh() {
    // Lives are about when to look again, not what to show: with a fixed τ every algorithm's
    // mesh at a frame is the same whatever the bounds (the flight is revalidated when it breaks
    // a zero bound).
    let hierarchy = rough(33, 10.0, 20.0);
    let eyes: Vec<DVec3> = (0..25)
        .map(|f| DVec3::new(10.0 + 6.0 * f as f64, 100.0, 60.0))
        .collect();
    for config in every_algorithm(2.0) {
        let normal = final_mesh(&hierarchy, &config, view_600(), SPEED, &eyes);
        let huge = SpeedBound {
            horizontal: 1e12,
            vertical: 1e12,
        };
        assert_eq!(
            normal,
            final_mesh(&hierarchy, &config, view_600(), huge, &eyes),
            "{config:?}"
        );
    }
}

#[test]
fn extreme_views_keep_valid_meshes() {
    let hierarchy = rough(17, 10.0, 30.0);
    let eye = DVec3::new(30.0, 40.0, 80.0);
    for (width_px, height_px, fovy_deg) in [(1, 1, 60.0), (600, 600, 0.001), (600, 600, 179.9)] {
        let view = ViewSettings {
            width_px,
            height_px,
            fovy: f64::to_radians(fovy_deg),
            near: 0.1,
            far: 1e5,
        };
        for config in every_algorithm(1.0) {
            final_mesh(&hierarchy, &config, view, SPEED, &[eye, eye + DVec3::X]);
        }
    }
}

#[test]
fn translating_terrain_and_flight_by_a_million_metres_changes_no_mesh() {
    let heights: Vec<f32> = (0..33 * 33)
        .map(|k| 30.0 * noise(k % 33, k / 33) as f32)
        .collect();
    let field = |origin: DVec3| {
        Heightfield::new(33, heights.clone(), Spacing { dx: 10.0, dy: 10.0 })
            .unwrap()
            .with_origin(origin)
    };
    let near = Hierarchy::new(field(DVec3::ZERO));
    let far_away = DVec3::new(1.0e6, -1.0e6, 1.0e6);
    let far = Hierarchy::new(field(far_away));
    let eyes: Vec<DVec3> = (0..30)
        .map(|f| DVec3::new(20.0 + 7.0 * f as f64, 50.0 + 3.0 * f as f64, 70.0))
        .collect();
    let moved: Vec<DVec3> = eyes.iter().map(|e| *e + far_away).collect();
    for config in every_algorithm(2.0) {
        for frames in [1, eyes.len()] {
            let a = final_mesh(&near, &config, view_600(), SPEED, &eyes[..frames]);
            let b = final_mesh(&far, &config, view_600(), SPEED, &moved[..frames]);
            assert_eq!(a, b, "{config:?} after {frames} frames");
        }
    }
}
