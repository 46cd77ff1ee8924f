//! Unit tests of ROAM's core operations: every split and merge keeps the bintree, flags, strips
//! and queues valid; the paper's literal loop oscillates where the guard stops it; forced
//! splits cost what they add; eq. (3) matches the shared metric bit for bit; both queue kinds
//! give the same meshes.

use super::*;
use crate::sim::algorithm::FrameInput;
use crate::sim::metrics::wedgie_error_px;
use crate::sim::terrain::{Heightfield, Spacing};
use crate::sim::view::{Pose, ViewSettings};
use bintree::TriangleKey;
use split::split_cost;

fn bumpy(level: u32) -> Hierarchy {
    let side = (1usize << level) + 1;
    let heights = (0..side * side)
        .map(|k| {
            let (i, j) = ((k % side) as f32, (k / side) as f32);
            15.0 * (0.8 * i).sin() * (0.6 * j).cos() + ((k * 7919) % 13) as f32
        })
        .collect();
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

fn camera(x: f64, y: f64, yaw: f64) -> Camera {
    Camera::new(
        &Pose {
            position: DVec3::new(x, y, 60.0),
            yaw,
            pitch: -0.4,
        },
        ViewSettings {
            width_px: 600,
            height_px: 600,
            fovy: 60f64.to_radians(),
            near: 1.0,
            far: 10_000.0,
        },
    )
}

fn config(culling_flags: bool) -> RoamConfig {
    RoamConfig {
        nesting: NestingRule::MaxPlusOwn,
        thickness: ThicknessScope::PerTriangle,
        queue: QueueKind::Buckets,
        goal: RoamGoal::TolerancePx(2.0),
        deferral: false,
        culling_flags,
        // On, so that the validator checks the strips after every operation.
        strips: true,
    }
}

const STILL: SpeedBound = SpeedBound {
    horizontal: 1.0,
    vertical: 1.0,
    rotation: SpeedBound::NO_ROTATION_BOUND,
};

/// Points the core at `camera`: flags and every priority recomputed.
fn look(core: &mut Core, camera: &Camera) {
    core.view = ViewFrame::new(camera);
    core.update_flags();
    core.apply_flag_changes(true);
    core.recompute_queue(0, false);
    core.recompute_queue(1, false);
}

fn assert_valid(roam: &Roam, camera: &Camera) {
    if let Err(error) = roam.validate(camera, PriorityCheck::Exact) {
        panic!("{error}");
    }
}

/// Splits a leaf picked by grid position or merges the bottom diamond, in a pseudo-random mix,
/// checking everything after every operation.
fn exercise(culling_flags: bool) {
    let hierarchy = bumpy(4);
    let mut roam = Roam::new(&hierarchy, config(culling_flags), STILL);
    let camera = camera(40.0, 30.0, 0.7);
    look(&mut roam.core, &camera);
    assert_valid(&roam, &camera);
    let mut state = 12345u64;
    let (mut splits, mut merges) = (0, 0);
    for _ in 0..400 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let choice = (state >> 33) % 10;
        if choice < 6 {
            let mut leaves: Vec<TriangleKey> = Vec::new();
            roam.core.queues.split.keys_into(&mut leaves);
            let lattice = hierarchy.lattice();
            let mut ordered: Vec<(u64, TriangleKey)> = leaves
                .iter()
                .map(|&k| {
                    let t = roam.core.bintree.get(k).shape;
                    (
                        (u64::from(lattice.id(t.apex)) << 32) | u64::from(lattice.id(t.left)),
                        k,
                    )
                })
                .collect();
            ordered.sort();
            if let Some(&(_, key)) = ordered.get((state >> 20) as usize % ordered.len().max(1)) {
                roam.core.split(key);
                splits += 1;
            }
        } else if let Some((key, _)) = roam.core.queues.bottom_merge() {
            roam.core.merge(key);
            merges += 1;
        }
        assert_valid(&roam, &camera);
    }
    assert!(
        splits > 100 && merges > 50,
        "{splits} splits, {merges} merges"
    );
    assert!(
        roam.core.counters.forced > 0,
        "no forced split was exercised"
    );
    assert!(roam.core.bintree.strip_counts().strips > 1);
}

#[test]
fn every_split_and_merge_keeps_the_bintree_strips_and_queues_valid() {
    exercise(false);
}

#[test]
fn every_split_and_merge_keeps_the_flags_and_the_strips_of_drawn_leaves_valid_with_culling() {
    exercise(true);
}

fn run_frame(roam: &mut Roam, frame: u64, camera: &Camera) -> FrameStats {
    let mut stats = FrameStats::default();
    roam.update(
        &FrameInput {
            frame,
            camera,
            broken_bounds: crate::sim::algorithm::BrokenBounds::NONE,
        },
        &mut stats,
    );
    stats
}

#[test]
fn the_papers_loop_oscillates_on_an_odd_budget_and_the_guard_stops_it() {
    let hierarchy = bumpy(4);
    let camera = camera(40.0, 30.0, 0.7);
    let budget = RoamConfig {
        goal: RoamGoal::TargetTriangles(41),
        ..config(false)
    };
    let mut literal = Roam::new(&hierarchy, budget, STILL);
    literal.core.oscillation_guard = false;
    let stats = run_frame(&mut literal, 0, &camera);
    // Split to 42, merge to 40, split to 42, … until the cap.
    assert_eq!(literal.core.counters.guard_stops, 1, "{stats:?}");
    assert!(stats.splits + stats.merges >= literal.core.iteration_cap() - 1);

    let mut guarded = Roam::new(&hierarchy, budget, STILL);
    let first = run_frame(&mut guarded, 0, &camera);
    assert!(first.triangles <= 41 && first.splits < 41, "{first:?}");
    let second = run_frame(&mut guarded, 1, &camera);
    assert_eq!((second.splits, second.merges), (0, 0));
    assert_valid(&guarded, &camera);
}

#[test]
fn a_forced_split_costs_what_the_split_adds() {
    let hierarchy = bumpy(4);
    let mut roam = Roam::new(&hierarchy, config(false), STILL);
    let camera = camera(40.0, 30.0, 0.7);
    look(&mut roam.core, &camera);
    // Refine one corner deeply so that its neighbours must be forced.
    for _ in 0..12 {
        let Some((key, _)) = roam.core.queues.top_split() else {
            break;
        };
        let before = roam.core.bintree.n_leaves();
        let cost = split_cost(&roam.core.bintree, key);
        roam.core.split(key);
        assert_eq!(roam.core.bintree.n_leaves(), before + cost);
    }
    assert_valid(&roam, &camera);
}

#[test]
fn eq_3_with_the_frame_hoisted_is_bit_identical_to_the_shared_metric() {
    // tan(fovy/2) and the up vector in camera space are computed once per frame; the priorities
    // must not change by a bit.
    let hierarchy = bumpy(4);
    let mut roam = Roam::new(&hierarchy, config(false), STILL);
    let camera = camera(40.0, 30.0, 0.7);
    look(&mut roam.core, &camera);
    for _ in 0..30 {
        if let Some((key, _)) = roam.core.queues.top_split() {
            roam.core.split(key);
        }
    }
    let context = roam.core.context();
    let mut compared = 0;
    for (_, triangle) in roam.core.bintree.iter() {
        let thickness = context.thickness_of(triangle);
        if thickness == 0.0 {
            continue;
        }
        let expected = wedgie_error_px(&camera, context.corners(triangle), thickness);
        assert_eq!(
            context.priority(triangle).to_bits(),
            expected.to_bits(),
            "{:?}",
            triangle.shape
        );
        compared += 1;
    }
    assert!(compared > 50);
}

#[test]
fn the_bucketed_and_the_heap_queues_give_the_same_meshes_frame_after_frame() {
    let hierarchy = bumpy(5);
    for goal in [RoamGoal::TargetTriangles(300), RoamGoal::TolerancePx(1.5)] {
        let buckets_config = RoamConfig {
            goal,
            ..config(true)
        };
        let heap_config = RoamConfig {
            queue: QueueKind::Heap,
            ..buckets_config
        };
        let mut buckets = Roam::new(&hierarchy, buckets_config, STILL);
        let mut heap = Roam::new(&hierarchy, heap_config, STILL);
        for frame in 0..40u64 {
            let angle = 0.06 * frame as f64;
            let camera = camera(
                160.0 + 100.0 * angle.cos(),
                160.0 + 100.0 * angle.sin(),
                angle + 1.6,
            );
            let a = run_frame(&mut buckets, frame, &camera);
            let b = run_frame(&mut heap, frame, &camera);
            assert!(
                buckets.vertex_set() == heap.vertex_set(),
                "{goal:?}, frame {frame}"
            );
            assert_eq!(
                (a.splits, a.merges, a.metric_evaluations),
                (b.splits, b.merges, b.metric_evaluations)
            );
            assert_valid(&buckets, &camera);
        }
    }
}

#[test]
fn every_combination_of_options_fills_exactly_its_declared_columns() {
    let hierarchy = bumpy(4);
    let view = camera(40.0, 30.0, 0.7);
    for (goal, deferral, culling_flags, strips) in [
        (RoamGoal::TolerancePx(2.0), false, false, false),
        (RoamGoal::TolerancePx(2.0), true, false, false),
        (RoamGoal::TolerancePx(2.0), false, true, true),
        (RoamGoal::TolerancePx(2.0), true, true, true),
        (RoamGoal::TargetTriangles(100), true, true, false),
        (RoamGoal::TargetTriangles(100), false, false, true),
    ] {
        let options = RoamConfig {
            goal,
            deferral,
            culling_flags,
            strips,
            ..config(false)
        };
        let input = FrameInput {
            frame: 0,
            camera: &view,
            broken_bounds: crate::sim::algorithm::BrokenBounds::ALL,
        };
        let algorithms: [Box<dyn LodAlgorithm>; 2] = [
            Box::new(Roam::new(&hierarchy, options, STILL)),
            Box::new(RoamRebuild::new(&hierarchy, options, STILL)),
        ];
        for mut algorithm in algorithms {
            let mut stats = FrameStats::default();
            algorithm.update(&input, &mut stats);
            let declared = algorithm.extra_columns();
            assert_eq!(stats.extra.len(), declared.len(), "{options:?}");
            assert!(declared.iter().all(|c| super::super::columns::is_known(c)));
        }
    }
}
