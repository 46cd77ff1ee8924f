//! ROAM'97 (`roam`) and its split-only rebuild (`roam-rebuild`) on small bumpy terrains:
//! valid meshes and bintrees every frame, the dual queue against the rebuild, deferral against
//! full recomputation, speed-bound violations, and the oscillation guard.

mod common;

use common::algorithms::{roam_target as target, roam_tolerance as tolerance};
use common::{bumpy_terrain, checked_step, extra, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::columns::roam::{
    DEFERRED, OSCILLATION_GUARD_STOPS, REVALIDATIONS, TRIANGLES_PER_STRIP,
};
use roamsim::sim::algorithm::{
    LodAlgorithm, PriorityCheck, Roam, RoamConfig, RoamGoal, RoamRebuild,
};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::{Camera, Pose};
use roamsim::sim::zone::SpeedBound;

const SPEED: SpeedBound = SpeedBound {
    horizontal: 4.0,
    vertical: 2.0,
};

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

/// One frame of any algorithm, checked as `--check` checks it.
fn step(
    algorithm: &mut dyn LodAlgorithm,
    hierarchy: &Hierarchy,
    frame: u64,
    camera: &Camera,
    speed_bound_broken: bool,
) -> FrameStats {
    let name = algorithm.name();
    let stats = checked_step(
        hierarchy,
        algorithm,
        frame,
        camera,
        speed_bound_broken,
        name,
    );
    assert_eq!(stats.extra.len(), algorithm.extra_columns().len());
    stats
}

/// Flies `roam`, checking the mesh and the whole bintree (exact priorities) every frame.
fn fly_checked(config: RoamConfig, cameras: &[Camera]) -> Vec<FrameStats> {
    let hierarchy = bumpy_terrain(5);
    let mut roam = Roam::new(&hierarchy, config, SPEED);
    let mut frames = Vec::new();
    for (frame, camera) in cameras.iter().enumerate() {
        frames.push(step(&mut roam, &hierarchy, frame as u64, camera, false));
        let check = if config.deferral {
            match config.goal {
                RoamGoal::TolerancePx(tau) => PriorityCheck::SameSideOf(tau),
                RoamGoal::TargetTriangles(_) => PriorityCheck::Exact,
            }
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
    let per_strip = extra(&roam, strips, TRIANGLES_PER_STRIP);
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
            if let Err(error) = deferred.validate(camera, PriorityCheck::SameSideOf(1.0)) {
                panic!("flags {culling_flags}, frame {frame}: {error}");
            }
            assert_eq!(
                deferred.vertex_set(),
                full.vertex_set(),
                "flags {culling_flags}, frame {frame}"
            );
            total_deferred += extra(&deferred, &stats, DEFERRED);
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
    assert_eq!(extra(&roam, &quiet, REVALIDATIONS), 0.0);
    let jump = step(&mut roam, &hierarchy, 4, &near, true);
    assert_eq!(extra(&roam, &jump, REVALIDATIONS), 1.0);
    assert_eq!(extra(&roam, &jump, DEFERRED), 0.0);
    roam.validate(&near, PriorityCheck::SameSideOf(1.0))
        .unwrap();

    // Without the report, deferred priorities go stale: that is what the revalidation prevents.
    let mut unaware = Roam::new(&hierarchy, config, SPEED);
    for frame in 0..4 {
        step(&mut unaware, &hierarchy, frame, &far, false);
    }
    step(&mut unaware, &hierarchy, 4, &near, false);
    assert!(
        unaware
            .validate(&near, PriorityCheck::SameSideOf(1.0))
            .is_err()
    );
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
        let mesh = roam.vertex_set().clone();
        for frame in 1..5 {
            let stats = step(&mut roam, &hierarchy, frame, &camera, false);
            assert_eq!(
                (stats.splits, stats.merges),
                (0, 0),
                "budget {budget}, frame {frame}: the mesh changed under a still camera"
            );
            assert_eq!(roam.vertex_set(), &mesh);
        }
        roam.validate(&camera, PriorityCheck::Exact).unwrap();
    }
}

#[test]
fn the_guard_refuses_to_undo_a_frame_s_swaps_while_turning() {
    // A turning camera makes the dual queue swap (merge to make room, then split) every frame.
    // Each frame must end within budget with bounded work, and the guard is what refuses to
    // re-split a diamond merged in the same frame (or merge one just split).
    let hierarchy = bumpy_terrain(5);
    let mut roam = Roam::new(&hierarchy, target(151), SPEED);
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
        guard_stops += extra(&roam, &stats, OSCILLATION_GUARD_STOPS);
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
            rebuild.vertex_set().is_subset(roam.vertex_set()),
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
    fn deferral_is_refused_where_it_cannot_be_safe() {
        let problems =
            problems_of(json!({"name": "roam", "target_triangles": 100, "deferral": true}));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].starts_with("algorithms[0].deferral: true with"));
        let problems = problems_of(json!({"name": "roam-rebuild", "tau_px": 1, "deferral": true}));
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(problems[0].contains("roam-rebuild starts from scratch"));
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
    // Eq. 3 depends on the view direction and the experiment bounds only the eye's speed.
    let hierarchy = bumpy_terrain(5);
    let config = RoamConfig {
        deferral: true,
        ..tolerance(1.0)
    };
    let mut roam = Roam::new(&hierarchy, config, SPEED);
    for (frame, camera) in turning_flight(10).iter().enumerate() {
        let stats = step(&mut roam, &hierarchy, frame as u64, camera, false);
        assert_eq!(extra(&roam, &stats, REVALIDATIONS), 1.0, "frame {frame}");
        assert_eq!(extra(&roam, &stats, DEFERRED), 0.0, "frame {frame}");
        roam.validate(camera, PriorityCheck::Exact).unwrap();
    }
}
