//! Wu's algorithm (Wu et al. 2001 §3, §5; SPEC §5) against the from-scratch reference of its
//! criterion (SPEC §6), and its queues against their validator.
//!
//! The central property (fixed τ, no budget, motion bounds honoured, traversal options off):
//! after every frame,
//!   from-scratch(split iff ℓ ≤ 0)  ⊆  wu's mesh  ⊆  from-scratch(split iff ℓ < 1),
//! and with in-view refinement (`refine: in_view`)
//!   from-scratch(ℓ ≤ 0 and in view)  ⊆  wu's mesh  ⊆  from-scratch(ℓ < 1 and in view),
//! checked on exhaustive small cases and on random terrains and flights, the camera turning.
//! The upper bound needs nested zones (a block's zone contains its sub-blocks'), which only the
//! conservative variant guarantees: with the paper's boxes, centred on different vertices, a
//! block can have ℓ ≥ 1 while a sub-block that keeps it active has ℓ < 1. So the upper bound is
//! checked for the conservative zone, the lower bound for both. (Spheres nest for every zone
//! variant; a node out of view merges whatever the bounds, issue #30 item 3.) The queue validator, which also recounts the in-view triangles and
//! retests every in-view flag, runs after every frame.

mod common;

use common::algorithms::{reference, wu, wu_budget};
use common::{
    bumpy_terrain, camera_at, checked_step, checked_step_breaking, extra, step, step_breaking,
    view_600,
};
use glam::DVec3;
use proptest::prelude::*;
use roamsim::sim::algorithm::columns::wu::BASE_CLAMPED;
use roamsim::sim::algorithm::{
    BrokenBounds, BudgetConfig, LodAlgorithm, Reference, ReferenceConfig, Refinement,
    SplitThreshold, ViewThreshold, Wu, WuConfig,
};
use roamsim::sim::audit::{AuditSettings, Auditor};
use roamsim::sim::draw::check::check_buffers_draw_mesh;
use roamsim::sim::hierarchy::{Hierarchy, VertexClass};
use roamsim::sim::mesh::MeshOutput;
use roamsim::sim::metrics::view_angle_error_px;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose};
use roamsim::sim::zone::{SpeedBound, ZoneVariant};

const SPEED: SpeedBound = SpeedBound {
    horizontal: 10.0,
    vertical: 5.0,
    rotation: SpeedBound::NO_ROTATION_BOUND,
};

/// The speed bounds with a rotation bound of 0.05 rad (2.9°) a frame.
const TURNING: SpeedBound = SpeedBound {
    rotation: 0.05,
    ..SPEED
};

/// Wu at a fixed τ with small wheels (16 links), so that overflow links are exercised.
fn fixed_tau(tau_px: f64, zone: ZoneVariant) -> WuConfig {
    WuConfig {
        wheel_links: 16,
        ..wu(tau_px, zone)
    }
}

/// Wu refining only what the view cone needs and keeping the in-view count (which the queue
/// validator recounts every frame). The count is kept only for a budget; a fixed-τ config gets
/// one that cannot move b from 0 (`base_limit` 0), so its τ stays fixed.
fn in_view(config: WuConfig) -> WuConfig {
    let frozen = BudgetConfig {
        triangles: 1,
        dead_band: 0,
        base_limit: 0,
        initial_tau_k: 1.5,
        tau_recentring: None,
    };
    WuConfig {
        cone_culling: true,
        refine: Refinement::InView,
        budget: config.budget.or(Some(frozen)),
        ..config
    }
}

/// One frame of Wu with the eye at `eye` looking along +x (within the speed bounds), checked as
/// `--check` checks it.
fn wu_step(hierarchy: &Hierarchy, wu: &mut Wu, frame: u64, eye: DVec3) -> FrameStats {
    checked_step(hierarchy, wu, frame, &camera_at(eye), false, "wu")
}

/// One frame of Wu at `pose` (within the motion bounds), checked as `--check` checks it.
fn wu_step_to(hierarchy: &Hierarchy, wu: &mut Wu, frame: u64, pose: &Pose) -> FrameStats {
    let camera = Camera::new(pose, view_600());
    checked_step(hierarchy, wu, frame, &camera, false, "wu")
}

/// One frame of `algorithm` at `pose` (within the motion bounds), unchecked.
fn step_to(algorithm: &mut dyn LodAlgorithm, frame: u64, pose: &Pose) -> FrameStats {
    step(algorithm, frame, &Camera::new(pose, view_600()), false)
}

/// The terrain of a random scene: side 2^level + 1, 10 m posts.
fn random_terrain(level: u32, heights: Vec<f32>) -> Hierarchy {
    let side = (1usize << level) + 1;
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

/// A pose at `eye` looking towards `yaw`, slightly down.
fn looking(eye: DVec3, yaw: f64) -> Pose {
    Pose {
        position: eye,
        yaw,
        pitch: -0.3,
    }
}

/// A scene: one terrain, the reference pair that sandwiches Wu, and Wu itself.
struct Sandwich<'h> {
    hierarchy: &'h Hierarchy,
    wu: Wu<'h>,
    lower: Reference<'h>,
    upper: Reference<'h>,
    zone: ZoneVariant,
    frame: u64,
}

impl<'h> Sandwich<'h> {
    fn new(hierarchy: &'h Hierarchy, tau_px: f64, zone: ZoneVariant, speed: SpeedBound) -> Self {
        Sandwich::refining(hierarchy, tau_px, zone, speed, Refinement::Everywhere)
    }

    fn refining(
        hierarchy: &'h Hierarchy,
        tau_px: f64,
        zone: ZoneVariant,
        speed: SpeedBound,
        refine: Refinement,
    ) -> Self {
        let from_scratch = |threshold, view_threshold| {
            Reference::new(
                hierarchy,
                ReferenceConfig {
                    threshold,
                    refine,
                    view_threshold,
                    ..reference(tau_px, zone)
                },
                &view_600(),
                speed,
            )
        };
        let config = match refine {
            Refinement::Everywhere => fixed_tau(tau_px, zone),
            Refinement::InView => in_view(fixed_tau(tau_px, zone)),
        };
        Sandwich {
            hierarchy,
            wu: Wu::new(hierarchy, config, &view_600(), speed),
            lower: from_scratch(SplitThreshold::LifeAtMost(0.0), ViewThreshold::InView),
            upper: from_scratch(SplitThreshold::LifeBelow(1.0), ViewThreshold::InView),
            zone,
            frame: 0,
        }
    }

    /// Flies to `eye` looking along +x and checks everything; `broken` says the move broke the
    /// motion bounds.
    fn fly_to(&mut self, eye: DVec3, broken: bool) -> FrameStats {
        self.fly(&looking(eye, 0.0), BrokenBounds::all_if(broken))
    }

    /// Flies to `pose` and checks everything.
    fn fly(&mut self, pose: &Pose, broken_bounds: BrokenBounds) -> FrameStats {
        let zones_nest = self.zone == ZoneVariant::Conservative;
        let camera = Camera::new(pose, view_600());
        let eye = pose.position;
        let frame = self.frame;
        self.frame += 1;
        let context = format!("{pose:?}");
        let stats = checked_step_breaking(
            self.hierarchy,
            &mut self.wu,
            frame,
            &camera,
            broken_bounds,
            &context,
        );
        step_breaking(&mut self.lower, frame, &camera, broken_bounds);
        step_breaking(&mut self.upper, frame, &camera, broken_bounds);
        if let Err(error) = self.wu.validate_queues(true) {
            panic!("frame {frame}, {pose:?}: {error}");
        }
        assert!(
            self.lower.vertex_set().is_subset(self.wu.vertex_set()),
            "frame {frame}, eye {eye:?}: a vertex the eye is inside the zone of (and in view) is \
             missing"
        );
        assert!(
            !zones_nest || self.wu.vertex_set().is_subset(self.upper.vertex_set()),
            "frame {frame}, eye {eye:?}: a vertex whose life is ≥ 1 (or out of view) is still \
             active"
        );
        stats
    }
}

/// A serpentine sweep over the terrain at `altitude`, in steps no longer than the speed bound.
fn serpentine(hierarchy: &Hierarchy, altitude: f64, step: f64) -> Vec<DVec3> {
    let (width, height) = hierarchy.field().extent();
    let mut eyes = Vec::new();
    let rows = (height / step).ceil() as usize;
    let columns = (width / step).ceil() as usize;
    for row in 0..=rows {
        for k in 0..=columns {
            let column = if row % 2 == 0 { k } else { columns - k };
            eyes.push(DVec3::new(
                (column as f64 * step).min(width),
                (row as f64 * step).min(height),
                altitude,
            ));
        }
    }
    eyes
}

#[test]
fn wu_is_sandwiched_between_the_references_over_every_eye_of_a_9_by_9_terrain() {
    let hierarchy = bumpy_terrain(3);
    for zone in [ZoneVariant::Conservative, ZoneVariant::Paper] {
        for tau_px in [0.5, 3.0, 40.0] {
            for altitude in [-10.0, 30.0, 300.0] {
                let mut scene = Sandwich::new(&hierarchy, tau_px, zone, SPEED);
                for eye in serpentine(&hierarchy, altitude, 10.0) {
                    scene.fly_to(eye, false);
                }
            }
        }
    }
}

#[test]
fn wu_is_sandwiched_between_the_references_over_every_eye_of_a_17_by_17_terrain() {
    let hierarchy = bumpy_terrain(4);
    for altitude in [5.0, 60.0, 2000.0] {
        let mut scene = Sandwich::new(&hierarchy, 2.0, ZoneVariant::Conservative, SPEED);
        let mut total_ops = 0;
        for eye in serpentine(&hierarchy, altitude, 10.0) {
            let stats = scene.fly_to(eye, false);
            total_ops += stats.splits + stats.merges;
        }
        assert!(total_ops > 0, "the flight at {altitude} m changed nothing");
    }
}

#[test]
fn a_teleport_is_revalidated_not_kept_stale() {
    let hierarchy = bumpy_terrain(5);
    let mut scene = Sandwich::new(&hierarchy, 1.0, ZoneVariant::Conservative, SPEED);
    scene.fly_to(DVec3::new(5000.0, 5000.0, 3000.0), false);
    // Far away, the mesh is coarse; then the eye jumps onto the terrain: the runner flags the
    // frame and Wu must recompute every queued life, or the lower sandwich bound fails.
    let coarse = scene.wu.triangle_count();
    let stats = scene.fly_to(DVec3::new(100.0, 100.0, 20.0), true);
    assert!(scene.wu.triangle_count() > coarse, "{stats:?}");
    for step in 1..20 {
        scene.fly_to(DVec3::new(100.0 + 8.0 * step as f64, 100.0, 20.0), false);
    }
}

#[test]
fn without_the_violation_flag_a_teleport_would_leave_stale_lives() {
    // The same teleport unflagged: the queues keep lives computed for the far eye, so Wu's mesh
    // misses vertices the reference has. This is what the flag exists for.
    let hierarchy = bumpy_terrain(5);
    let view = view_600();
    let mut wu = Wu::new(
        &hierarchy,
        fixed_tau(1.0, ZoneVariant::Conservative),
        &view,
        SPEED,
    );
    let mut reference = Reference::new(
        &hierarchy,
        reference(1.0, ZoneVariant::Conservative),
        &view,
        SPEED,
    );
    for (frame, eye) in [
        DVec3::new(5000.0, 5000.0, 3000.0),
        DVec3::new(100.0, 100.0, 20.0),
    ]
    .into_iter()
    .enumerate()
    {
        let camera = camera_at(eye);
        step(&mut wu, frame as u64, &camera, false);
        step(&mut reference, frame as u64, &camera, false);
    }
    assert!(!reference.vertex_set().is_subset(wu.vertex_set()));
}

/// Terrain level, heights, walk steps, τ and whether to use the paper's zone.
type RandomScene = (u32, Vec<f32>, Vec<(f64, f64, f64)>, f64, bool);

/// Random terrains of side 9, 17 or 33 and random walks that honour the speed bounds.
fn terrain_and_walk() -> impl Strategy<Value = RandomScene> {
    (3u32..=5).prop_flat_map(|level| {
        let side = (1usize << level) + 1;
        (
            Just(level),
            prop::collection::vec(-30.0f32..30.0, side * side),
            prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0), 1..40),
            prop_oneof![Just(0.0), 0.3f64..20.0],
            any::<bool>(),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn wu_is_sandwiched_on_random_terrains_and_flights(
        (level, heights, walk, tau_px, paper_zone) in terrain_and_walk()
    ) {
        let hierarchy = random_terrain(level, heights);
        let zone = if paper_zone { ZoneVariant::Paper } else { ZoneVariant::Conservative };
        let mut scene = Sandwich::new(&hierarchy, tau_px, zone, SPEED);
        let mut eye = DVec3::new(40.0, 40.0, 50.0);
        for (dx, dy, dz) in walk {
            // Steps within the bounds: |Δxy| ≤ 10/√2·√2 = 10, |Δz| ≤ 5.
            eye += DVec3::new(dx * 7.0, dy * 7.0, dz * 5.0);
            scene.fly_to(eye, false);
        }
    }
}

#[test]
fn with_the_conservative_zone_every_removed_vertex_error_subtends_at_most_tau() {
    // What Wu's max-nesting guarantees, with the conservative zone and the speed bounds
    // honoured: each inactive vertex's own error ε (the vertical segment from its height to the
    // midpoint of the edge it bisects) subtends at most τ from the eye. It does not bound the
    // mesh's distance from the surface, where removed vertices' errors add up: see
    // `max_nesting_does_not_bound_the_audited_surface_error_on_a_real_tile`.
    let hierarchy = bumpy_terrain(5);
    let tau_px = 8.0;
    let mut scene = Sandwich::new(&hierarchy, tau_px, ZoneVariant::Conservative, SPEED);
    let lattice = hierarchy.lattice();
    let pixel_angle = view_600().pixel_angle();
    let mut removed_checked = 0;
    for eye in serpentine(&hierarchy, 150.0, 10.0) {
        scene.fly_to(eye, false);
        let mesh = scene.wu.vertex_set();
        for id in 0..lattice.n_vertices() as u32 {
            let p = lattice.point(id);
            if mesh.contains(id) || lattice.classify(p) == VertexClass::Corner {
                continue;
            }
            let position = hierarchy.field().position(p.i as usize, p.j as usize);
            let epsilon = hierarchy.vertex_error(p);
            let base = DVec3::new(position.x, position.y, position.z.min(position.z - epsilon));
            let px = view_angle_error_px(eye, base, epsilon.abs(), pixel_angle);
            assert!(px <= tau_px, "vertex {p:?} from {eye:?}: {px} px > τ");
            removed_checked += 1;
        }
    }
    assert!(
        removed_checked > 10_000,
        "only {removed_checked} removed vertices checked"
    );
}

#[test]
fn max_nesting_does_not_bound_the_audited_surface_error_on_a_real_tile() {
    // The quickstart's first pose over the real SRTM crop, τ = 2 px, conservative zone: the
    // audit finds the mesh more than τ away from the terrain somewhere, although every removed
    // vertex's own error is within τ. Accumulated errors are what ROAM's max-plus-own bounds.
    let experiment = roamsim::edge::experiment::load(
        &common::experiment::repository().join("experiments/quickstart.json"),
    )
    .unwrap();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let mut wu = Wu::new(
        &hierarchy,
        fixed_tau(2.0, ZoneVariant::Conservative),
        &experiment.view,
        experiment.speed,
    );
    let camera = roamsim::sim::view::Camera::new(experiment.flight.pose(0), experiment.view);
    step(&mut wu, 0, &camera, false);
    let mut auditor = roamsim::sim::audit::Auditor::new(
        &hierarchy,
        roamsim::sim::audit::AuditSettings {
            stride: 4,
            popping: false,
            detail_stride: None,
        },
    );
    let audit = auditor.audit(&hierarchy, MeshOutput::lattice(wu.vertex_set()), &camera);
    let worst = audit.view_angle.unwrap().max;
    assert!(worst > 2.0, "worst audited view-angle error {worst} px");
}

#[test]
fn an_unreachable_budget_keeps_b_clamped_and_reports_it() {
    let hierarchy = bumpy_terrain(4);
    let config = WuConfig {
        wheel_links: 16,
        ..wu_budget(1.0, 1_000_000, 20)
    };
    let mut wu = Wu::new(&hierarchy, config, &view_600(), SPEED);
    let mut stats = FrameStats::default();
    for frame in 0..60 {
        stats = wu_step(&hierarchy, &mut wu, frame, DVec3::new(80.0, 80.0, 400.0));
        wu.validate_queues(false).unwrap();
    }
    assert_eq!(wu.base(), 20);
    assert_eq!(extra(&wu, &stats, BASE_CLAMPED), 1.0);
    assert_eq!(
        stats.triangles,
        2 * 16 * 16,
        "the whole mesh, short of the budget"
    );
}

/// Flies Wu along a line over a 65×65 terrain; returns the total life recomputations and the
/// final mesh size, validating every frame.
fn fly_line(config: WuConfig, frames: u64, altitude: f64) -> (u64, u64, Vec<u64>) {
    let hierarchy = bumpy_terrain(6);
    let mut wu = Wu::new(&hierarchy, config, &view_600(), SPEED);
    let mut lives = 0;
    let mut counts = Vec::new();
    for frame in 0..frames {
        let eye = DVec3::new(20.0 + 5.0 * frame as f64, 300.0, altitude);
        let stats = wu_step(&hierarchy, &mut wu, frame, eye);
        wu.validate_queues(false).unwrap();
        lives += stats.metric_evaluations;
        counts.push(stats.triangles);
    }
    (lives, wu.triangle_count(), counts)
}

#[test]
fn block_priority_traversal_computes_fewer_lives() {
    let plain = fixed_tau(6.0, ZoneVariant::Conservative);
    let (lives_plain, _, _) = fly_line(plain, 80, 400.0);
    let (lives_priority, _, _) = fly_line(
        WuConfig {
            block_priority: true,
            ..plain
        },
        80,
        400.0,
    );
    assert!(
        lives_priority < lives_plain,
        "block priority {lives_priority} vs plain {lives_plain}"
    );
}

#[test]
fn a_depth_limit_spreads_the_first_refinement_over_several_frames() {
    let plain = fixed_tau(6.0, ZoneVariant::Conservative);
    let (_, _, unlimited) = fly_line(plain, 1, 150.0);
    let (_, _, limited) = fly_line(
        WuConfig {
            depth_limit: Some(2),
            ..plain
        },
        1,
        150.0,
    );
    assert!(
        limited[0] < unlimited[0],
        "limited {} vs unlimited {}",
        limited[0],
        unlimited[0]
    );
    // A hovering eye: the limited run catches up with the unlimited mesh within a few frames.
    let hierarchy = bumpy_terrain(6);
    let run = |config: WuConfig| {
        let mut wu = Wu::new(&hierarchy, config, &view_600(), SPEED);
        for frame in 0..20 {
            wu_step(&hierarchy, &mut wu, frame, DVec3::new(20.0, 300.0, 150.0));
        }
        wu.vertex_set().clone()
    };
    assert_eq!(
        run(WuConfig {
            depth_limit: Some(2),
            ..plain
        }),
        run(plain)
    );
}

#[test]
fn a_budget_holds_the_triangle_count_near_the_budget() {
    let config = WuConfig {
        tau_px: None,
        zone: ZoneVariant::Paper,
        wheel_links: 16,
        ..wu_budget(1.0, 1500, 1000)
    };
    let (_, _, counts) = fly_line(config, 200, 150.0);
    assert_settles_near(&counts[100..], 1500.0);
}

/// The mean of `counts` is within 10 % of `budget`.
fn assert_settles_near(counts: &[u64], budget: f64) {
    let mean = counts.iter().sum::<u64>() as f64 / counts.len() as f64;
    assert!(
        (mean - budget).abs() < 0.1 * budget,
        "mean {mean} over the last {} frames, budget {budget}",
        counts.len()
    );
}

#[test]
fn a_million_frames_keep_the_wheels_valid_and_b_bounded() {
    // A small terrain circled 250 times at a budget it reaches only near the terrain: b moves
    // both ways for 10^6 frames; the frame counter, the wheel heads and b must not overflow.
    // In view, the camera looks along the circle (turning 1.6 mrad a frame), so the view keys,
    // the in-view flags and count run for a million frames too.
    let hierarchy = bumpy_terrain(3);
    for refine in [Refinement::Everywhere, Refinement::InView] {
        let plain = WuConfig {
            wheel_links: 16,
            ..wu_budget(4.0, 40, 50)
        };
        let config = match refine {
            Refinement::Everywhere => plain,
            Refinement::InView => in_view(plain),
        };
        let mut wu = Wu::new(&hierarchy, config, &view_600(), TURNING);
        let (mut lowest, mut highest) = (i64::MAX, i64::MIN);
        let circle = |frame: u64| {
            let angle = frame as f64 * std::f64::consts::TAU / 4000.0;
            let eye = DVec3::new(40.0 + 60.0 * angle.cos(), 40.0 + 60.0 * angle.sin(), 30.0);
            looking(eye, angle + std::f64::consts::FRAC_PI_2)
        };
        for frame in 0..1_000_000u64 {
            step_to(&mut wu, frame, &circle(frame));
            lowest = lowest.min(wu.base());
            highest = highest.max(wu.base());
        }
        // One more frame, checked as `--check` checks it.
        wu_step_to(&hierarchy, &mut wu, 1_000_000, &circle(1_000_000));
        wu.validate_queues(false).unwrap();
        assert!(lowest < highest, "{refine:?}: b never moved ({lowest})");
        assert!((-50..=50).contains(&lowest) && (-50..=50).contains(&highest));
    }
}

/// The serpentine sweep with the look direction turning by `turn` radians a frame, looking
/// further down from higher up (so that the terrain enters the view).
fn turning_serpentine(hierarchy: &Hierarchy, altitude: f64, turn: f64) -> Vec<Pose> {
    let pitch = if altitude > 100.0 { -1.2 } else { -0.3 };
    serpentine(hierarchy, altitude, 10.0)
        .into_iter()
        .enumerate()
        .map(|(k, eye)| Pose {
            pitch,
            ..looking(eye, turn * k as f64)
        })
        .collect()
}

#[test]
fn in_view_wu_is_sandwiched_over_every_eye_of_a_9_by_9_terrain_while_turning() {
    let hierarchy = bumpy_terrain(3);
    for zone in [ZoneVariant::Conservative, ZoneVariant::Paper] {
        for tau_px in [0.5, 3.0, 40.0] {
            for altitude in [-10.0, 30.0, 300.0] {
                for turn in [0.0, 0.05, -0.049] {
                    let mut scene =
                        Sandwich::refining(&hierarchy, tau_px, zone, TURNING, Refinement::InView);
                    for pose in turning_serpentine(&hierarchy, altitude, turn) {
                        scene.fly(&pose, BrokenBounds::NONE);
                    }
                }
            }
        }
    }
}

#[test]
fn in_view_wu_is_sandwiched_over_every_eye_of_a_17_by_17_terrain_while_turning() {
    let hierarchy = bumpy_terrain(4);
    let mut outside = 0;
    for altitude in [5.0, 60.0, 2000.0] {
        let mut scene = Sandwich::refining(
            &hierarchy,
            2.0,
            ZoneVariant::Conservative,
            TURNING,
            Refinement::InView,
        );
        let mut total_ops = 0;
        for pose in turning_serpentine(&hierarchy, altitude, 0.05) {
            let stats = scene.fly(&pose, BrokenBounds::NONE);
            total_ops += stats.splits + stats.merges;
            let in_view = scene.wu.in_view_triangles().unwrap();
            assert!(in_view <= stats.triangles);
            outside += u64::from(in_view < stats.triangles);
        }
        assert!(total_ops > 0, "the flight at {altitude} m changed nothing");
    }
    assert!(outside > 0, "no flight ever left a triangle out of view");
}

#[test]
fn a_turn_faster_than_the_rotation_bound_is_revalidated_and_stays_sandwiched() {
    let hierarchy = bumpy_terrain(5);
    let mut scene = Sandwich::refining(
        &hierarchy,
        1.0,
        ZoneVariant::Conservative,
        TURNING,
        Refinement::InView,
    );
    let eye = DVec3::new(160.0, 160.0, 40.0);
    for frame in 0..30 {
        scene.fly(&looking(eye, 0.04 * frame as f64), BrokenBounds::NONE);
    }
    // Half a turn in one frame, flagged by the runner: the view keys are recomputed.
    let before = scene.wu.in_view_triangles();
    let turned = BrokenBounds {
        rotation: true,
        ..BrokenBounds::NONE
    };
    scene.fly(&looking(eye, 1.2 + std::f64::consts::PI), turned);
    assert_ne!(scene.wu.in_view_triangles(), before);
    for frame in 1..30 {
        let yaw = 1.2 + std::f64::consts::PI - 0.04 * frame as f64;
        scene.fly(&looking(eye, yaw), BrokenBounds::NONE);
    }
}

#[test]
fn without_the_rotation_flag_a_fast_turn_would_leave_stale_view_keys() {
    // The same half turn unflagged: the view keys promised the flags could not change yet, so the
    // validator finds a flag (or the count) that no longer matches the cone.
    let hierarchy = bumpy_terrain(5);
    let mut wu = Wu::new(
        &hierarchy,
        in_view(fixed_tau(1.0, ZoneVariant::Conservative)),
        &view_600(),
        TURNING,
    );
    let eye = DVec3::new(160.0, 160.0, 40.0);
    for (frame, yaw) in [0.0, 0.0, 0.0, std::f64::consts::PI]
        .into_iter()
        .enumerate()
    {
        step_to(&mut wu, frame as u64, &looking(eye, yaw));
    }
    let error = wu.validate_queues(false).unwrap_err();
    assert!(error.contains("in view"), "{error}");
}

#[test]
fn an_in_view_teleport_is_revalidated_not_kept_stale() {
    let hierarchy = bumpy_terrain(5);
    let mut scene = Sandwich::refining(
        &hierarchy,
        1.0,
        ZoneVariant::Conservative,
        TURNING,
        Refinement::InView,
    );
    scene.fly(
        &looking(DVec3::new(5000.0, 5000.0, 3000.0), 3.9),
        BrokenBounds::NONE,
    );
    let coarse = scene.wu.triangle_count();
    scene.fly(
        &looking(DVec3::new(100.0, 100.0, 20.0), 0.5),
        BrokenBounds::ALL,
    );
    assert!(scene.wu.triangle_count() > coarse);
    for step in 1..20 {
        let eye = DVec3::new(100.0 + 8.0 * step as f64, 100.0, 20.0);
        scene.fly(&looking(eye, 0.5 + 0.04 * step as f64), BrokenBounds::NONE);
    }
}

#[test]
fn in_view_refinement_leaves_what_is_behind_the_camera_coarse() {
    // Low over a 65² terrain, looking east from its west edge: everywhere-refinement splits the
    // terrain behind and beside the camera too; in-view refinement keeps it coarse.
    let hierarchy = bumpy_terrain(6);
    let run = |refine: Refinement| {
        let mut scene =
            Sandwich::refining(&hierarchy, 1.0, ZoneVariant::Conservative, TURNING, refine);
        let mut stats = FrameStats::default();
        for frame in 0..10 {
            let eye = DVec3::new(300.0 + 5.0 * frame as f64, 320.0, 40.0);
            stats = scene.fly(&looking(eye, 0.0), BrokenBounds::NONE);
        }
        stats.triangles
    };
    let everywhere = run(Refinement::Everywhere);
    let in_view = run(Refinement::InView);
    assert!(
        2 * in_view < everywhere,
        "in view {in_view} triangles, everywhere {everywhere}"
    );
}

#[test]
fn an_in_view_budget_holds_the_triangles_in_view_near_the_budget() {
    let config = in_view(WuConfig {
        tau_px: None,
        zone: ZoneVariant::Paper,
        wheel_links: 16,
        ..wu_budget(1.0, 1500, 1000)
    });
    let hierarchy = bumpy_terrain(6);
    let mut wu = Wu::new(&hierarchy, config, &view_600(), TURNING);
    let mut counted = Vec::new();
    for frame in 0..300u64 {
        let eye = DVec3::new(20.0 + 2.0 * frame as f64, 300.0, 150.0);
        wu_step_to(
            &hierarchy,
            &mut wu,
            frame,
            &looking(eye, 0.01 * frame as f64),
        );
        wu.validate_queues(false).unwrap();
        counted.push(wu.in_view_triangles().unwrap());
    }
    assert_settles_near(&counted[100..], 1500.0);
}

#[test]
fn tau_recentring_brings_the_mean_of_b_towards_zero() {
    // A τ far too coarse for the budget: b climbs to make up for it. Re-centring moves τ until b
    // hovers around 0. (Slow speed bounds, which the 0.84 m a frame of the circle honours: b then
    // grows the zones by little per frame, and climbs high.)
    const SLOW: SpeedBound = SpeedBound {
        horizontal: 1.0,
        vertical: 0.5,
        rotation: 0.05,
    };
    let hierarchy = bumpy_terrain(6);
    let budget = BudgetConfig {
        triangles: 1000,
        dead_band: 0,
        base_limit: 1000,
        initial_tau_k: 1.5,
        tau_recentring: None,
    };
    let run = |tau_recentring| {
        let config = in_view(WuConfig {
            tau_px: Some(300.0),
            budget: Some(BudgetConfig {
                tau_recentring,
                ..budget
            }),
            ..fixed_tau(300.0, ZoneVariant::Paper)
        });
        let mut wu = Wu::new(&hierarchy, config, &view_600(), SLOW);
        let mut bases = Vec::new();
        for frame in 0..3000u64 {
            let angle = frame as f64 * std::f64::consts::TAU / 1500.0;
            let eye = DVec3::new(
                320.0 + 200.0 * angle.cos(),
                320.0 + 200.0 * angle.sin(),
                60.0,
            );
            step_to(
                &mut wu,
                frame,
                &looking(eye, angle + std::f64::consts::FRAC_PI_2),
            );
            bases.push(wu.base() as f64);
            wu.validate_queues(false).unwrap();
        }
        let late = &bases[2000..];
        (late.iter().sum::<f64>() / late.len() as f64, wu.tau_px())
    };
    let (fixed_mean, fixed_tau) = run(None);
    let (recentred_mean, recentred_tau) = run(Some(roamsim::sim::algorithm::TauRecentring {
        window_frames: 16,
    }));
    assert_eq!(fixed_tau, 300.0);
    assert!(fixed_mean > 100.0, "b's mean {fixed_mean} with τ fixed");
    assert!(recentred_tau < 300.0, "τ {recentred_tau}");
    // Re-centring leaves a mean within its dead band (16 frames) alone.
    assert!(
        recentred_mean.abs() <= 16.0,
        "b's mean {recentred_mean} re-centred, {fixed_mean} fixed"
    );
}

/// A random walk's step: displacement within the speed bounds and a turn within the rotation
/// bound.
type WalkStep = (f64, f64, f64, f64);

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn in_view_wu_is_sandwiched_on_random_terrains_and_turning_flights(
        (level, heights, walk, tau_px, paper_zone) in terrain_and_turning_walk()
    ) {
        let hierarchy = random_terrain(level, heights);
        let zone = if paper_zone { ZoneVariant::Paper } else { ZoneVariant::Conservative };
        let mut scene =
            Sandwich::refining(&hierarchy, tau_px, zone, TURNING, Refinement::InView);
        let mut pose = looking(DVec3::new(40.0, 40.0, 50.0), 0.3);
        for (dx, dy, dz, turn) in walk {
            pose.position += DVec3::new(dx * 7.0, dy * 7.0, dz * 5.0);
            // Yaw and pitch turns whose combined angle stays within 0.05 rad.
            pose.yaw += turn * 0.035;
            pose.pitch = (pose.pitch + dz * 0.035).clamp(-1.5, 1.5);
            scene.fly(&pose, BrokenBounds::NONE);
        }
    }
}

fn terrain_and_turning_walk() -> impl Strategy<Value = (u32, Vec<f32>, Vec<WalkStep>, f64, bool)> {
    (3u32..=5).prop_flat_map(|level| {
        let side = (1usize << level) + 1;
        (
            Just(level),
            prop::collection::vec(-30.0f32..30.0, side * side),
            prop::collection::vec(
                (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0),
                1..40,
            ),
            prop_oneof![Just(0.0), 0.3f64..20.0],
            any::<bool>(),
        )
    })
}

/// Bytes one split or merge may upload: its centre and at most four boundary vertices change,
/// each insertion writing its vertex (12 bytes) and at most four triangles of indices (12 bytes
/// each), each deletion at most four triangles (`wu/draw.rs`). The base mesh (4 vertices, 2
/// triangles: 72 bytes) is the first frame's constant.
const UPLOAD_PER_OPERATION: u64 = 5 * (12 + 4 * 12);

/// Flies `config` over `poses` (`teleports`: frames whose pose jumps, flagged as a broken bound)
/// and after every frame checks, as `--check` does, that the buffers draw the mesh, and that the
/// frame uploaded no more than [`UPLOAD_PER_OPERATION`] per split or merge; returns each
/// frame's (splits + merges, upload bytes, draw calls).
fn fly_drawing(
    hierarchy: &Hierarchy,
    config: WuConfig,
    speed: SpeedBound,
    poses: &[Pose],
    teleports: &[usize],
) -> Vec<(u64, u64, u64)> {
    let mut wu = Wu::new(hierarchy, config, &view_600(), speed);
    let mut frames = Vec::new();
    for (frame, pose) in poses.iter().enumerate() {
        let camera = Camera::new(pose, view_600());
        let stats = checked_step(
            hierarchy,
            &mut wu,
            frame as u64,
            &camera,
            teleports.contains(&frame),
            "wu",
        );
        let counts = common::draw_counts(&stats);
        if let Err(error) = check_buffers_draw_mesh(wu.buffers(), wu.mesh(), hierarchy) {
            panic!("frame {frame}: {error}");
        }
        let operations = stats.splits + stats.merges;
        assert!(
            counts.upload_bytes <= UPLOAD_PER_OPERATION * (operations + 1),
            "frame {frame}: {} bytes for {operations} splits and merges",
            counts.upload_bytes
        );
        assert_eq!(
            counts.triangles_submitted,
            wu.triangle_count(),
            "frame {frame}"
        );
        frames.push((operations, counts.upload_bytes, counts.draw_calls));
    }
    frames
}

/// A turning flight over the terrain with a teleport at frame 120 and a hover (the same pose
/// three frames running) at the end.
fn drawing_flight() -> (Vec<Pose>, Vec<usize>) {
    let mut poses: Vec<Pose> = (0..120)
        .map(|k| {
            let t = k as f64;
            looking(DVec3::new(30.0 + 4.0 * t, 60.0 + 2.0 * t, 120.0), 0.02 * t)
        })
        .collect();
    poses.extend((0..80).map(|k| {
        let t = k as f64;
        looking(DVec3::new(600.0 - 3.0 * t, 500.0, 60.0), 3.5 - 0.03 * t)
    }));
    let last = *poses.last().unwrap();
    poses.extend([last, last, last]);
    (poses, vec![120])
}

#[test]
fn the_buffers_are_the_mesh_every_frame_and_cost_only_its_splits_and_merges() {
    let hierarchy = bumpy_terrain(6);
    let (poses, teleports) = drawing_flight();
    let configs = [
        (
            "fixed τ everywhere",
            fixed_tau(1.0, ZoneVariant::Paper),
            SPEED,
        ),
        (
            "fixed τ in the cone",
            WuConfig {
                cone_culling: true,
                refine: Refinement::InView,
                ..fixed_tau(1.0, ZoneVariant::Paper)
            },
            TURNING,
        ),
        (
            "budget in the cone",
            in_view(WuConfig {
                tau_px: None,
                zone: ZoneVariant::Paper,
                wheel_links: 16,
                ..wu_budget(1.0, 1500, 1000)
            }),
            TURNING,
        ),
    ];
    for (name, config, speed) in configs {
        let frames = fly_drawing(&hierarchy, config, speed, &poses, &teleports);
        let (operations, bytes): (u64, u64) = frames
            .iter()
            .fold((0, 0), |(o, b), &(ops, up, _)| (o + ops, b + up));
        assert!(operations > 500, "{name}: {operations} splits and merges");
        assert!(frames.iter().all(|&(_, _, calls)| calls == 1), "{name}");
        // Hovering: nothing splits or merges (a budget's b may still move), and a frame that
        // changes nothing uploads nothing.
        let hover = &frames[frames.len() - 2..];
        for &(ops, up, _) in hover {
            assert!(
                ops > 0 || up == 0,
                "{name}: {up} bytes with nothing changed"
            );
        }
        assert!(
            hover.iter().any(|&(ops, _, _)| ops == 0),
            "{name}: the hover changed the mesh every frame"
        );
        assert!(bytes > 0, "{name}");
    }
}

#[test]
fn a_budget_without_a_given_tau_meets_its_budget_from_the_first_frame() {
    let hierarchy = bumpy_terrain(6);
    let budget = 1500;
    for cone in [false, true] {
        let base = WuConfig {
            tau_px: None,
            zone: ZoneVariant::Paper,
            wheel_links: 16,
            ..wu_budget(1.0, budget, 1000)
        };
        let config = if cone { in_view(base) } else { base };
        let mut wu = Wu::new(&hierarchy, config, &view_600(), TURNING);
        let paper_tau = wu.tau_px();
        wu_step_to(
            &hierarchy,
            &mut wu,
            0,
            &looking(DVec3::new(20.0, 300.0, 150.0), 0.0),
        );
        wu.validate_queues(false).unwrap();
        let counted = wu.in_view_triangles().unwrap_or(wu.triangle_count());
        assert!(
            counted <= budget && counted as f64 >= 0.7 * budget as f64,
            "cone {cone}: {counted} triangles on the first frame for a budget of {budget}"
        );
        let facts = wu.run_facts();
        let fact = |name: &str| facts.iter().find(|(n, _)| *n == name).map(|&(_, v)| v);
        assert_eq!(fact("paper_initial_tau_px"), Some(paper_tau));
        assert_eq!(fact("initial_tau_px"), Some(wu.tau_px()));
    }
}

/// Wu §7's morphing (`morph_frames`): over a flight with splits and merges, the buffers draw the
/// morphed mesh every frame, the surface moves by a fraction of what it pops without morphing,
/// and the upload stays bounded per split and merge (each changed vertex writes its insertion
/// or deletion once and its height once a frame while it morphs).
#[test]
fn morphing_spreads_each_pop_over_frames_and_the_buffers_follow_it() {
    const FRAMES: u32 = 4;
    let hierarchy = bumpy_terrain(6);
    // Across the terrain low, then on beyond its edge climbing 4 m a frame: the first half
    // splits, the second merges.
    let poses: Vec<Pose> = (0..240)
        .map(|k| {
            let t = k as f64;
            let climb = 4.0 * (t - 120.0).max(0.0);
            looking(
                DVec3::new(30.0 + 4.0 * t, 60.0 + 2.0 * t, 120.0 + climb),
                0.02 * t,
            )
        })
        .collect();
    let fly = |morph_frames: Option<u32>| {
        let config = WuConfig {
            morph_frames,
            ..fixed_tau(2.0, ZoneVariant::Paper)
        };
        let mut wu = Wu::new(&hierarchy, config, &view_600(), SPEED);
        let mut auditor = Auditor::new(
            &hierarchy,
            AuditSettings {
                stride: 1,
                popping: true,
                detail_stride: None,
            },
        );
        let (mut largest_pop, mut operations, mut merges, mut uploaded, mut longer) =
            (0.0f64, 0, 0, 0, 0);
        for (frame, pose) in poses.iter().enumerate() {
            let camera = Camera::new(pose, view_600());
            let stats = checked_step(&hierarchy, &mut wu, frame as u64, &camera, false, "wu");
            if let Some(popping) = auditor.audit(&hierarchy, wu.mesh(), &camera).popping {
                largest_pop = largest_pop.max(popping.max_m);
            }
            let counts = common::draw_counts(&stats);
            assert_eq!(
                counts.triangles_submitted,
                wu.triangle_count(),
                "frame {frame}"
            );
            if frame > 0 {
                operations += stats.splits + stats.merges;
                merges += stats.merges;
                uploaded += counts.upload_bytes;
            }
            longer += u64::from(
                wu.triangle_count() > wu.vertex_set().triangle_count(hierarchy.lattice()),
            );
        }
        (largest_pop, operations, merges, uploaded, longer)
    };
    let (plain_pop, plain_operations, _, plain_upload, plain_longer) = fly(None);
    let (morphed_pop, operations, merges, upload, longer) = fly(Some(FRAMES));
    assert!(merges > 20, "the flight should merge ({merges} merges)");
    assert_eq!(
        plain_longer, 0,
        "without morphing the drawn mesh is the vertex set"
    );
    assert!(
        longer > 0,
        "sinking vertices stay drawn after their merge ({merges} merges)"
    );
    assert!(
        plain_pop > 0.5,
        "the flight should pop without morphing ({plain_pop} m)"
    );
    assert!(
        morphed_pop < plain_pop / 2.0,
        "largest pop {morphed_pop} m with morphing, {plain_pop} m without"
    );
    assert_eq!(
        operations, plain_operations,
        "morphing changes no refinement"
    );
    let per_operation = 5 * (12 + 4 * 12 + 12 * (u64::from(FRAMES) + 1));
    assert!(
        upload <= per_operation * operations,
        "{upload} bytes for {operations} splits and merges"
    );
    assert!(
        upload > plain_upload,
        "morphing rewrites heights ({upload} vs {plain_upload})"
    );
}
