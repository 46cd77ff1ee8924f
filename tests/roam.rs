//! ROAM'97 (`roam`) and its split-only rebuild (`roam-rebuild`) on small bumpy terrains (SPEC
//! §6): valid meshes and bintrees every frame, the dual queue against the rebuild, deferral
//! (ROAM'97 §7.3) against full recomputation, speed-bound violations, and the oscillation guard.

mod common;

use common::{bumpy_terrain, vertex_set, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::{
    FrameInput, LodAlgorithm, MotionBound, PriorityCheck, QueueKind, ROAM_UPLOAD_BYTES_PER_CHANGE,
    Roam, RoamConfig, RoamGoal, RoamRebuild, ThicknessScope,
};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::validate::validate_reported;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::{Camera, Pose};
use roamsim::sim::zone::SpeedBound;

const SPEED: SpeedBound = SpeedBound {
    horizontal: 4.0,
    vertical: 2.0,
    rotation: SpeedBound::NO_ROTATION_BOUND,
};

fn tolerance(tau_px: f64) -> RoamConfig {
    RoamConfig {
        nesting: roamsim::sim::hierarchy::NestingRule::MaxPlusOwn,
        thickness: ThicknessScope::PerTriangle,
        queue: QueueKind::Buckets,
        goal: RoamGoal::TolerancePx(tau_px),
        deferral: false,
        culling_flags: false,
        strips: false,
    }
}

fn target(triangles: u64) -> RoamConfig {
    RoamConfig {
        goal: RoamGoal::TargetTriangles(triangles),
        ..tolerance(0.0)
    }
}

/// A straight flight at 3 m per frame over a 33×33 (320 m) terrain, looking along +x, slightly
/// down: the orientation never changes, so deferral can work.
fn straight_flight(frames: u64) -> Vec<Camera> {
    (0..frames)
        .map(|k| {
            Camera::new(
                &Pose {
                    position: DVec3::new(-40.0 + 3.0 * k as f64, 150.0 + 1.5 * k as f64, 70.0),
                    yaw: 0.2,
                    pitch: -0.35,
                },
                view_600(),
            )
        })
        .collect()
}

/// A turning flight: the camera circles the terrain's centre and looks ahead.
fn turning_flight(frames: u64) -> Vec<Camera> {
    (0..frames)
        .map(|k| {
            let angle = 0.05 * k as f64;
            Camera::new(
                &Pose {
                    position: DVec3::new(
                        160.0 + 120.0 * angle.cos(),
                        160.0 + 120.0 * angle.sin(),
                        60.0,
                    ),
                    yaw: angle + std::f64::consts::FRAC_PI_2,
                    pitch: -0.3,
                },
                view_600(),
            )
        })
        .collect()
}

/// One frame of any algorithm, checked with the shared mesh validator.
fn step(
    algorithm: &mut dyn LodAlgorithm,
    hierarchy: &Hierarchy,
    frame: u64,
    camera: &Camera,
    speed_bound_broken: bool,
) -> FrameStats {
    let mut stats = FrameStats {
        frame,
        ..FrameStats::default()
    };
    algorithm.update(
        &FrameInput {
            frame,
            camera,
            broken_bounds: if speed_bound_broken {
                roamsim::sim::algorithm::BrokenBounds::ALL
            } else {
                roamsim::sim::algorithm::BrokenBounds::NONE
            },
        },
        &mut stats,
    );
    if let Err(error) = validate_reported(
        hierarchy.lattice(),
        vertex_set(algorithm),
        algorithm.triangle_count(),
    ) {
        panic!("{} frame {frame}: {error}", algorithm.name());
    }
    assert_eq!(stats.triangles, algorithm.triangle_count());
    assert_eq!(stats.extra.len(), algorithm.extra_columns().len());
    stats
}

fn extra(algorithm: &dyn LodAlgorithm, stats: &FrameStats, column: &str) -> f64 {
    let k = algorithm
        .extra_columns()
        .iter()
        .position(|c| *c == column)
        .unwrap_or_else(|| panic!("no column {column}"));
    stats.extra[k]
}

/// Flies `roam`, checking the mesh and the whole bintree (exact priorities) every frame.
fn fly_checked(config: RoamConfig, cameras: &[Camera]) -> Vec<FrameStats> {
    let hierarchy = bumpy_terrain(5);
    let mut roam = Roam::new(&hierarchy, config, SPEED);
    let mut frames = Vec::new();
    for (frame, camera) in cameras.iter().enumerate() {
        frames.push(step(&mut roam, &hierarchy, frame as u64, camera, false));
        let check = if config.deferral {
            PriorityCheck::Deferred
        } else {
            PriorityCheck::Exact
        };
        if let Err(error) = roam.validate(camera, check) {
            panic!("frame {frame}: {error}");
        }
    }
    frames
}

#[test]
fn a_tolerance_flight_keeps_a_valid_bintree_and_splits_and_merges() {
    let frames = fly_checked(tolerance(1.0), &turning_flight(40));
    assert!(frames[0].splits > 10);
    assert!(frames.iter().skip(1).map(|f| f.merges).sum::<u64>() > 0);
    assert!(frames.iter().skip(1).map(|f| f.splits).sum::<u64>() > 0);
}

#[test]
fn a_target_flight_with_every_effect_stays_valid_and_within_budget() {
    let config = RoamConfig {
        culling_flags: true,
        strips: true,
        ..target(300)
    };
    let cameras = turning_flight(40);
    let frames = fly_checked(config, &cameras);
    for stats in &frames {
        assert!(
            stats.triangles <= 300,
            "frame {}: {}",
            stats.frame,
            stats.triangles
        );
        assert!(
            stats.triangles >= 250,
            "frame {}: {}",
            stats.frame,
            stats.triangles
        );
    }
    let hierarchy = bumpy_terrain(5);
    let roam = Roam::new(&hierarchy, config, SPEED);
    let strips = &frames[10];
    let per_strip = extra(&roam, strips, "triangles_per_strip");
    assert!((1.0..=10.0).contains(&per_strip), "{per_strip}");
}

#[test]
fn culling_flags_leave_outside_triangles_coarse() {
    let cameras = straight_flight(5);
    let plain = fly_checked(tolerance(1.0), &cameras);
    let culled = fly_checked(
        RoamConfig {
            culling_flags: true,
            ..tolerance(1.0)
        },
        &cameras,
    );
    assert!(culled[4].triangles < plain[4].triangles);
}

#[test]
fn at_a_fixed_target_the_dual_queue_and_the_rebuild_reach_the_same_crossover_within_one_split() {
    let hierarchy = bumpy_terrain(5);
    for (k, camera) in turning_flight(30).iter().enumerate().step_by(6) {
        let mut roam = Roam::new(&hierarchy, target(200), SPEED);
        let mut rebuild = RoamRebuild::new(&hierarchy, target(200), SPEED);
        // The incremental mesh converges over a few frames of the same view.
        for frame in 0..4 {
            step(&mut roam, &hierarchy, frame, camera, false);
        }
        step(&mut rebuild, &hierarchy, 0, camera, false);
        roam.validate(camera, PriorityCheck::Exact).unwrap();
        let incremental_top = roam.max_split_priority();
        let rebuild_top = rebuild.max_split_priority();
        let rebuild_last = rebuild.last_split_priority().unwrap();
        // Each is no worse than the other one split earlier.
        assert!(
            incremental_top <= rebuild_last,
            "view {k}: incremental leaves {incremental_top} px, the rebuild's last split was {rebuild_last} px"
        );
        let incremental_bottom = roam.min_merge_priority().unwrap();
        assert!(
            rebuild_top <= incremental_bottom,
            "view {k}: rebuild leaves {rebuild_top} px, the incremental keeps a diamond of {incremental_bottom} px"
        );
    }
}

#[test]
fn deferral_never_lets_a_priority_cross_tau_unseen_and_gives_the_same_meshes() {
    let hierarchy = bumpy_terrain(5);
    for culling_flags in [false, true] {
        let full_config = RoamConfig {
            culling_flags,
            ..tolerance(1.0)
        };
        let deferred_config = RoamConfig {
            deferral: true,
            ..full_config
        };
        let mut deferred = Roam::new(&hierarchy, deferred_config, SPEED);
        let mut full = Roam::new(&hierarchy, full_config, SPEED);
        let mut total_deferred = 0.0;
        let mut recomputations = (0, 0);
        for (frame, camera) in straight_flight(60).iter().enumerate() {
            let frame = frame as u64;
            let stats = step(&mut deferred, &hierarchy, frame, camera, false);
            let reference = step(&mut full, &hierarchy, frame, camera, false);
            if let Err(error) = deferred.validate(camera, PriorityCheck::Deferred) {
                panic!("flags {culling_flags}, frame {frame}: {error}");
            }
            assert_eq!(
                vertex_set(&deferred),
                vertex_set(&full),
                "flags {culling_flags}, frame {frame}"
            );
            total_deferred += extra(&deferred, &stats, "deferred");
            recomputations.0 += stats.metric_evaluations;
            recomputations.1 += reference.metric_evaluations;
        }
        assert!(total_deferred > 0.0, "flags {culling_flags}");
        assert!(
            recomputations.0 < recomputations.1,
            "flags {culling_flags}: deferral recomputed {} priorities, full recomputation {}",
            recomputations.0,
            recomputations.1
        );
    }
}

#[test]
fn a_speed_bound_violation_forces_a_revalidation() {
    let hierarchy = bumpy_terrain(5);
    let config = RoamConfig {
        deferral: true,
        ..tolerance(1.0)
    };
    let far = straight_flight(1)[0];
    let near = Camera::new(
        &Pose {
            position: DVec3::new(150.0, 160.0, 40.0),
            yaw: 0.2,
            pitch: -0.35,
        },
        view_600(),
    );
    // Honest: the runner reports the teleport.
    let mut roam = Roam::new(&hierarchy, config, SPEED);
    for frame in 0..3 {
        step(&mut roam, &hierarchy, frame, &far, false);
    }
    let quiet = step(&mut roam, &hierarchy, 3, &far, false);
    assert_eq!(extra(&roam, &quiet, "revalidations"), 0.0);
    let jump = step(&mut roam, &hierarchy, 4, &near, true);
    assert_eq!(extra(&roam, &jump, "revalidations"), 1.0);
    assert_eq!(extra(&roam, &jump, "deferred"), 0.0);
    roam.validate(&near, PriorityCheck::Deferred).unwrap();

    // Without the report, deferred priorities go stale: that is what the revalidation prevents.
    let mut unaware = Roam::new(&hierarchy, config, SPEED);
    for frame in 0..4 {
        step(&mut unaware, &hierarchy, frame, &far, false);
    }
    step(&mut unaware, &hierarchy, 4, &near, false);
    assert!(unaware.validate(&near, PriorityCheck::Deferred).is_err());
}

#[test]
fn an_unreachable_budget_does_not_make_the_mesh_oscillate() {
    // Every split adds at least two triangles, so an odd budget cannot be met exactly: a loop
    // that splits when too small and merges when too large would flip between two meshes
    // forever (within a frame, or from frame to frame).
    let hierarchy = bumpy_terrain(5);
    let camera = turning_flight(1)[0];
    for budget in [3, 5, 41, 101, 257] {
        let mut roam = Roam::new(&hierarchy, target(budget), SPEED);
        let first = step(&mut roam, &hierarchy, 0, &camera, false);
        assert!(first.triangles <= budget && first.triangles + 8 >= budget.min(100));
        let mesh = vertex_set(&roam).clone();
        for frame in 1..5 {
            let stats = step(&mut roam, &hierarchy, frame, &camera, false);
            assert_eq!(
                (stats.splits, stats.merges),
                (0, 0),
                "budget {budget}, frame {frame}: the mesh changed under a still camera"
            );
            assert_eq!(vertex_set(&roam), &mesh);
        }
        roam.validate(&camera, PriorityCheck::Exact).unwrap();
    }
}

#[test]
fn the_guard_refuses_to_undo_a_frame_s_swaps_while_turning() {
    // A turning camera makes the dual queue swap (merge to make room, then split) every frame.
    // Each frame must end within budget with bounded work, and the guard is what refuses to
    // re-split a diamond merged in the same frame (or merge one just split).
    // Culling flags on: the priorities are finite (no +∞ behind the eye to tie with).
    let hierarchy = bumpy_terrain(5);
    let config = RoamConfig {
        culling_flags: true,
        ..target(151)
    };
    let mut roam = Roam::new(&hierarchy, config, SPEED);
    let mut guard_stops = 0.0;
    for (frame, camera) in turning_flight(60).iter().enumerate() {
        let stats = step(&mut roam, &hierarchy, frame as u64, camera, false);
        assert!(stats.triangles <= 151);
        if frame > 0 {
            assert!(
                stats.splits + stats.merges <= 151,
                "frame {frame}: {stats:?}"
            );
        }
        guard_stops += extra(&roam, &stats, "oscillation_guard_stops");
        roam.validate(camera, PriorityCheck::Exact).unwrap();
    }
    assert!(guard_stops > 0.0, "the guard never had to act");
}

#[test]
fn the_rebuild_matches_the_incremental_mesh_at_a_fixed_tolerance() {
    // At a fixed τ both end with every leaf at or below τ; the incremental mesh may keep forced
    // diamonds a little longer, so it is a superset.
    let hierarchy = bumpy_terrain(5);
    let mut roam = Roam::new(&hierarchy, tolerance(1.5), SPEED);
    let mut rebuild = RoamRebuild::new(&hierarchy, tolerance(1.5), SPEED);
    for (frame, camera) in turning_flight(20).iter().enumerate() {
        step(&mut roam, &hierarchy, frame as u64, camera, false);
        step(&mut rebuild, &hierarchy, frame as u64, camera, false);
        assert!(
            vertex_set(&rebuild).is_subset(vertex_set(&roam)),
            "frame {frame}"
        );
        assert!(roam.max_split_priority() <= 1.5);
        assert!(rebuild.max_split_priority() <= 1.5);
    }
}

mod experiment_entries {
    use super::common::experiment::{quickstart, save};
    use roamsim::edge::experiment::{ExperimentError, load};
    use serde_json::{Value, json};

    /// The problems of a small synthetic experiment running only `entry`.
    fn problems_of(entry: Value) -> Vec<String> {
        let dir = tempfile::tempdir().unwrap();
        let mut experiment = quickstart();
        experiment["terrain"] = json!({"synthetic": {"level": 5, "seed": 3, "amplitude_m": 50,
            "roughness": 0.7, "spacing_m": {"dx": 10, "dy": 10}}});
        experiment["algorithms"] = json!([entry]);
        let path = save(dir.path(), "roam", &experiment);
        match load(&path) {
            Ok(_) => Vec::new(),
            Err(ExperimentError { problems, .. }) => problems
                .iter()
                .map(|p| format!("{}: {}", p.field, p.problem))
                .collect(),
        }
    }

    #[test]
    fn roam_entries_with_a_target_or_a_tolerance_are_accepted() {
        let entries = [
            json!({"name": "roam", "target_triangles": 3000, "culling_flags": true, "strips": true}),
            json!({"name": "roam", "tau_px": 2, "deferral": true}),
            json!({"name": "roam", "tau_px": 2, "thickness": "per_vertex", "queue": "heap"}),
            json!({"name": "roam", "tau_px": 2, "thickness": "per_triangle", "queue": "buckets"}),
            json!({"name": "roam-rebuild", "target_triangles": 3000}),
        ];
        for entry in entries {
            assert_eq!(problems_of(entry.clone()), Vec::<String>::new(), "{entry}");
        }
    }

    #[test]
    fn a_roam_entry_needs_exactly_one_goal() {
        for entry in [
            json!({"name": "roam"}),
            json!({"name": "roam", "tau_px": 2, "target_triangles": 100}),
        ] {
            let problems = problems_of(entry);
            assert_eq!(problems.len(), 1, "{problems:?}");
            assert!(problems[0].starts_with("algorithms[0]: expected exactly one of"));
        }
    }

    #[test]
    fn deferral_works_with_a_target_and_is_refused_for_the_rebuild() {
        let problems =
            problems_of(json!({"name": "roam", "target_triangles": 100, "deferral": true}));
        assert_eq!(problems, Vec::<String>::new());
        let problems = problems_of(json!({"name": "roam-rebuild", "tau_px": 1, "deferral": true}));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].contains("roam-rebuild starts from scratch"));
    }

    #[test]
    fn an_unknown_thickness_or_queue_names_the_field() {
        let problems = problems_of(json!({"name": "roam", "tau_px": 1, "thickness": "per_edge"}));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(
            problems[0].starts_with("algorithms[0].thickness: unknown variant `per_edge`"),
            "{problems:?}"
        );
        let problems = problems_of(json!({"name": "roam", "tau_px": 1, "queue": "fibonacci"}));
        assert!(problems[0].starts_with("algorithms[0].queue: unknown variant"));
    }

    #[test]
    fn a_misspelt_roam_parameter_is_an_error() {
        let problems = problems_of(json!({"name": "roam", "tau_px": 1, "strip": true}));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(
            problems[0].contains("unknown field `strip`"),
            "{problems:?}"
        );
    }
}

#[test]
fn a_turning_camera_revalidates_every_frame_under_deferral() {
    // Eq. 3 depends on the view direction, and this experiment declares no rotation bound.
    let hierarchy = bumpy_terrain(5);
    let config = RoamConfig {
        deferral: true,
        ..tolerance(1.0)
    };
    let mut roam = Roam::new(&hierarchy, config, SPEED);
    for (frame, camera) in turning_flight(10).iter().enumerate() {
        let stats = step(&mut roam, &hierarchy, frame as u64, camera, false);
        assert_eq!(extra(&roam, &stats, "revalidations"), 1.0, "frame {frame}");
        assert_eq!(extra(&roam, &stats, "deferred"), 0.0, "frame {frame}");
        roam.validate(camera, PriorityCheck::Exact).unwrap();
    }
}

#[test]
fn the_experiments_rotation_bound_lets_a_turning_camera_defer_with_the_same_meshes() {
    let hierarchy = bumpy_terrain(5);
    let bounded = SpeedBound {
        rotation: 0.02,
        ..SPEED
    };
    let config = RoamConfig {
        culling_flags: true,
        ..tolerance(1.0)
    };
    let mut deferred = Roam::new(
        &hierarchy,
        RoamConfig {
            deferral: true,
            ..config
        },
        bounded,
    );
    let mut full = Roam::new(&hierarchy, config, bounded);
    let (mut evaluations, mut full_evaluations) = (0, 0);
    // 0.015 rad per frame: within the bound, and 1.4 m per frame along the circle.
    for (frame, camera) in circle(40, 0.015).iter().enumerate() {
        let frame = frame as u64;
        let stats = step(&mut deferred, &hierarchy, frame, camera, false);
        let reference = step(&mut full, &hierarchy, frame, camera, false);
        deferred.validate(camera, PriorityCheck::Deferred).unwrap();
        assert!(
            vertex_set(&deferred) == vertex_set(&full),
            "frame {frame}: the meshes differ"
        );
        let revalidated = extra(&deferred, &stats, "revalidations");
        assert_eq!(
            revalidated,
            f64::from(u8::from(frame == 0)),
            "frame {frame}"
        );
        if frame > 0 {
            evaluations += stats.metric_evaluations;
            full_evaluations += reference.metric_evaluations;
        }
    }
    assert!(
        2 * evaluations < full_evaluations,
        "{evaluations} evaluations deferred against {full_evaluations}"
    );
}

/// A circle around the terrain's centre at `radians_per_frame`, the camera looking along the
/// path: it turns by exactly that angle every frame.
fn circle(frames: u64, radians_per_frame: f64) -> Vec<Camera> {
    (0..frames)
        .map(|k| {
            let angle = radians_per_frame * k as f64;
            Camera::new(
                &Pose {
                    position: DVec3::new(
                        160.0 + 110.0 * angle.cos(),
                        160.0 + 110.0 * angle.sin(),
                        60.0,
                    ),
                    yaw: angle + std::f64::consts::FRAC_PI_2,
                    pitch: -0.3,
                },
                view_600(),
            )
        })
        .collect()
}

/// Flies `config` with and without deferral (the deferred one under `motion`), checking after
/// every frame that the meshes are identical and that the deferred queues are stale only where
/// the schedule allows. Returns the priority evaluations (deferred, full) and the deferred run's
/// revalidations.
fn deferral_against_full(
    config: RoamConfig,
    motion: MotionBound,
    cameras: &[Camera],
) -> (u64, u64, f64) {
    let hierarchy = bumpy_terrain(5);
    let mut deferred = Roam::with_motion_bound(
        &hierarchy,
        RoamConfig {
            deferral: true,
            ..config
        },
        motion,
    );
    let mut full = Roam::new(&hierarchy, config, SPEED);
    let (mut evaluations, mut revalidations) = ((0, 0), 0.0);
    for (frame, camera) in cameras.iter().enumerate() {
        let frame = frame as u64;
        let stats = step(&mut deferred, &hierarchy, frame, camera, false);
        let reference = step(&mut full, &hierarchy, frame, camera, false);
        if let Err(error) = deferred.validate(camera, PriorityCheck::Deferred) {
            panic!("{config:?}, frame {frame}: {error}");
        }
        assert!(
            vertex_set(&deferred) == vertex_set(&full),
            "{config:?}, frame {frame}: the meshes differ"
        );
        assert_eq!(
            (stats.splits, stats.merges),
            (reference.splits, reference.merges)
        );
        if frame > 0 {
            evaluations.0 += stats.metric_evaluations;
            evaluations.1 += reference.metric_evaluations;
            revalidations += extra(&deferred, &stats, "revalidations");
        }
    }
    (evaluations.0, evaluations.1, revalidations)
}

const NO_TURN: MotionBound = MotionBound {
    metres_per_frame: 4.47213595499958,
    radians_per_frame: None,
};

#[test]
fn deferral_with_a_triangle_target_gives_the_meshes_of_full_recomputation_for_less() {
    // Culling flags on: without them the triangles behind the eye take priority +∞ and the
    // crossover with them, and nothing can be deferred against an infinite crossover.
    for strips in [false, true] {
        let config = RoamConfig {
            culling_flags: true,
            strips,
            ..target(240)
        };
        let (deferred, full, revalidations) =
            deferral_against_full(config, NO_TURN, &straight_flight(60));
        assert!(
            3 * deferred < 2 * full,
            "strips {strips}: {deferred} evaluations against {full}"
        );
        assert!(revalidations < 10.0, "{revalidations} revalidations");
    }
}

#[test]
fn with_a_rotation_bound_a_turning_camera_defers_and_keeps_the_meshes() {
    // 0.03 rad a frame, bound 0.035: never beyond the bound.
    let turning = MotionBound {
        metres_per_frame: 4.0,
        radians_per_frame: Some(0.035),
    };
    let cameras = circle(60, 0.03);
    for goal in [RoamGoal::TolerancePx(1.0), RoamGoal::TargetTriangles(240)] {
        let config = RoamConfig {
            goal,
            culling_flags: true,
            strips: true,
            ..tolerance(1.0)
        };
        let (deferred, full, revalidations) = deferral_against_full(config, turning, &cameras);
        assert!(
            deferred < full,
            "{goal:?}: {deferred} evaluations against {full}"
        );
        if matches!(goal, RoamGoal::TolerancePx(_)) {
            assert_eq!(
                revalidations, 0.0,
                "{goal:?}: a turn within the bound revalidated"
            );
        }
        // Without the rotation bound the same flight revalidates every frame.
        let (_, _, unbounded) = deferral_against_full(config, NO_TURN, &cameras);
        assert_eq!(unbounded, 59.0);
    }
}

#[test]
fn a_turn_beyond_the_rotation_bound_revalidates() {
    let hierarchy = bumpy_terrain(5);
    let motion = MotionBound {
        metres_per_frame: 4.0,
        radians_per_frame: Some(0.01),
    };
    let config = RoamConfig {
        deferral: true,
        ..tolerance(1.0)
    };
    let mut roam = Roam::with_motion_bound(&hierarchy, config, motion);
    let slow = circle(10, 0.009);
    for (frame, camera) in slow.iter().enumerate() {
        let stats = step(&mut roam, &hierarchy, frame as u64, camera, false);
        let expected = if frame == 0 { 1.0 } else { 0.0 };
        assert_eq!(
            extra(&roam, &stats, "revalidations"),
            expected,
            "frame {frame}"
        );
    }
    let next = circle(11, 0.009)[10];
    let stats = step(&mut roam, &hierarchy, 10, &next, false);
    assert_eq!(extra(&roam, &stats, "revalidations"), 0.0);
    let fast = circle(13, 0.009)[12];
    let stats = step(&mut roam, &hierarchy, 11, &fast, false);
    assert_eq!(
        extra(&roam, &stats, "revalidations"),
        1.0,
        "0.018 rad in one frame"
    );
    let beyond = Camera::new(
        &Pose {
            yaw: 0.5,
            ..Pose {
                position: fast.eye,
                yaw: 0.0,
                pitch: -0.3,
            }
        },
        view_600(),
    );
    let stats = step(&mut roam, &hierarchy, 12, &beyond, false);
    assert_eq!(extra(&roam, &stats, "revalidations"), 1.0);
    roam.validate(&beyond, PriorityCheck::Deferred).unwrap();
}

#[test]
fn culling_flags_are_kept_without_walking_the_whole_tree() {
    // A straight flight: the labels of most of the tree stay, and the traversal stops at the
    // top of every unchanged OUT or ALL-IN subtree (the validator checks every label).
    let config = RoamConfig {
        culling_flags: true,
        ..tolerance(0.5)
    };
    let hierarchy = bumpy_terrain(5);
    let mut roam = Roam::new(&hierarchy, config, SPEED);
    let mut tested = 0.0;
    let mut tree = 0.0;
    for (frame, camera) in straight_flight(30).iter().enumerate() {
        let stats = step(&mut roam, &hierarchy, frame as u64, camera, false);
        roam.validate(camera, PriorityCheck::Exact).unwrap();
        if frame > 0 {
            tested += extra(&roam, &stats, "flag_tests");
            // Leaves plus interior triangles: 2·leaves − 2.
            tree += 2.0 * stats.triangles as f64 - 2.0;
        }
    }
    assert!(
        tested < 0.5 * tree,
        "{tested} flag tests for {tree} triangles"
    );
}

#[test]
fn strips_glue_new_triangles_to_their_neighbours() {
    let config = RoamConfig {
        culling_flags: true,
        strips: true,
        ..target(300)
    };
    let frames = fly_checked(config, &turning_flight(40));
    let hierarchy = bumpy_terrain(5);
    let roam = Roam::new(&hierarchy, config, SPEED);
    let mean: f64 = frames
        .iter()
        .map(|f| extra(&roam, f, "triangles_per_strip"))
        .sum::<f64>()
        / frames.len() as f64;
    assert!(mean > 3.0, "{mean} triangles per strip");
}

#[test]
fn per_vertex_thickness_refines_a_superset_of_the_papers_per_triangle_mesh_on_the_real_tile() {
    // Per vertex, every triangle's thickness is at least eq. (1)'s, so every priority is at least
    // as large: at a fixed τ the rebuild splits a superset, and on real terrain a larger one.
    let experiment = roamsim::edge::experiment::load(
        &common::experiment::repository().join("experiments/quickstart.json"),
    )
    .unwrap();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let per_triangle = RoamConfig {
        culling_flags: true,
        ..tolerance(4.0)
    };
    let per_vertex = RoamConfig {
        thickness: ThicknessScope::PerVertex,
        ..per_triangle
    };
    let mut paper = RoamRebuild::new(&hierarchy, per_triangle, experiment.speed);
    let mut loose = RoamRebuild::new(&hierarchy, per_vertex, experiment.speed);
    for frame in [0u64, 150, 300] {
        let camera = Camera::new(
            &experiment.field.local_pose(experiment.flight.pose(frame)),
            experiment.view,
        );
        let a = step(&mut paper, &hierarchy, frame, &camera, false);
        let b = step(&mut loose, &hierarchy, frame, &camera, false);
        assert!(
            vertex_set(&paper).is_subset(vertex_set(&loose)),
            "frame {frame}"
        );
        assert!(
            b.triangles > a.triangles + a.triangles / 20,
            "frame {frame}: {} triangles per vertex, {} per triangle",
            b.triangles,
            a.triangles
        );
    }
}

/// Issues the frame's draw and checks that the buffers draw exactly the mesh; what it uploaded.
fn draw_checked(algorithm: &mut dyn LodAlgorithm, hierarchy: &Hierarchy, frame: u64) -> u64 {
    let counts = algorithm.prepare_draw();
    if let Err(error) = roamsim::sim::draw::check::check_buffers_draw_mesh(
        algorithm.buffers(),
        algorithm.mesh(),
        hierarchy,
    ) {
        panic!("{} frame {frame}: {error}", algorithm.name());
    }
    assert_eq!(counts.draw_calls, 1, "one triangle list");
    assert_eq!(counts.triangles_submitted, algorithm.triangle_count());
    counts.upload_bytes
}

/// A flight that splits, merges, defers, stands still and teleports: the straight flight, three
/// frames standing at its end, then a jump back to its start (a broken speed bound).
fn flight_with_a_stop_and_a_teleport() -> Vec<(Camera, bool)> {
    let mut cameras: Vec<(Camera, bool)> = straight_flight(30)
        .into_iter()
        .map(|c| (c, false))
        .collect();
    let last = cameras[cameras.len() - 1].0;
    cameras.extend([(last, false), (last, false), (last, false)]);
    let first = straight_flight(1)[0];
    cameras.extend([(first, true), (first, false)]);
    cameras
}

#[test]
fn roam_s_buffers_are_its_leaves_every_frame_and_cost_only_its_splits_and_merges() {
    let hierarchy = bumpy_terrain(5);
    for config in [
        tolerance(1.0),
        RoamConfig {
            deferral: true,
            culling_flags: true,
            strips: true,
            ..tolerance(1.0)
        },
        RoamConfig {
            deferral: true,
            culling_flags: true,
            ..target(300)
        },
    ] {
        let mut roam = Roam::new(&hierarchy, config, SPEED);
        let (mut splits, mut merges, mut still_frames) = (0, 0, 0);
        for (frame, (camera, teleport)) in flight_with_a_stop_and_a_teleport().iter().enumerate() {
            let frame = frame as u64;
            let stats = step(&mut roam, &hierarchy, frame, camera, *teleport);
            let upload = draw_checked(&mut roam, &hierarchy, frame);
            let changes = stats.splits + stats.merges;
            if frame > 0 {
                assert!(
                    upload <= ROAM_UPLOAD_BYTES_PER_CHANGE * changes,
                    "{config:?} frame {frame}: {upload} bytes for {changes} splits and merges"
                );
            }
            if frame > 0 && changes == 0 {
                assert_eq!(
                    upload, 0,
                    "frame {frame}: nothing changed, nothing uploaded"
                );
                still_frames += 1;
            }
            splits += stats.splits;
            merges += stats.merges;
        }
        assert!(
            splits > 0 && merges > 0 && still_frames > 0,
            "{config:?}: the flight must split ({splits}), merge ({merges}) and stand still \
             ({still_frames} frames)"
        );
    }
}

#[test]
fn roam_rebuild_s_buffers_are_its_mesh_every_frame() {
    let hierarchy = bumpy_terrain(5);
    let config = RoamConfig {
        culling_flags: true,
        ..target(300)
    };
    let mut rebuild = RoamRebuild::new(&hierarchy, config, SPEED);
    for (frame, (camera, teleport)) in flight_with_a_stop_and_a_teleport().iter().enumerate() {
        let frame = frame as u64;
        step(&mut rebuild, &hierarchy, frame, camera, *teleport);
        let upload = draw_checked(&mut rebuild, &hierarchy, frame);
        // Rebuilt every frame: at least one index per corner of every triangle.
        assert!(upload >= 12 * rebuild.triangle_count(), "frame {frame}");
    }
}
