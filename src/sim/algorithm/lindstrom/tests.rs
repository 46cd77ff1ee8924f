//! Unit tests of the block quadtree, the interval bounds and the bottom-up step.

use super::blocks::BlockTree;
use super::validate::validate_blocks;
use super::*;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::metrics::vertical_projection_error_px;
use crate::sim::terrain::{Heightfield, Spacing};
use glam::DVec3;

fn bumpy(level: u32) -> Hierarchy {
    let side = (1usize << level) + 1;
    let heights = (0..side * side)
        .map(|k| {
            let (i, j) = ((k % side) as f32, (k / side) as f32);
            15.0 * (0.8 * i).sin() * (0.6 * j).cos() + ((k * 2654435761) % 89) as f32 * 0.2
        })
        .collect();
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

#[test]
fn block_trees_of_every_block_level_partition_the_vertices_into_their_boxes() {
    for level in 1..=5 {
        let hierarchy = bumpy(level);
        let nested = hierarchy.nested_vertex_errors(NestingRule::Max);
        for block_level in 0..=level + 1 {
            let blocks = BlockTree::new(&hierarchy, nested.clone(), block_level);
            assert_eq!(blocks.block_level(), block_level.clamp(1, level));
            assert_eq!(blocks.depth(), level - blocks.block_level());
            if let Err(error) = validate_blocks(&blocks, &hierarchy, &nested) {
                panic!("level {level}, k = {block_level}: {error}");
            }
        }
    }
}

#[test]
fn a_33_grid_with_blocks_of_9_samples_has_21_nodes_and_the_leaves_own_the_finest_level() {
    let hierarchy = bumpy(5);
    let nested = hierarchy.nested_vertex_errors(NestingRule::Max);
    let blocks = BlockTree::new(&hierarchy, nested, 3);
    assert_eq!(blocks.nodes().len(), 1 + 4 + 16);
    let lattice = hierarchy.lattice();
    for node in &blocks.nodes()[5..] {
        assert_eq!(node.side, 8);
        for &id in blocks.owned_ids(node) {
            let point = lattice.point(id);
            assert!(point.i % 2 == 1 || point.j % 2 == 1, "{point:?}");
        }
    }
    assert_eq!(blocks.nodes()[0].subtree_vertices, 33 * 33 - 4);
}

/// The factor the bounds claim to bound, at one point.
fn factor(eye: DVec3, point: DVec3, lambda: f64) -> f64 {
    vertical_projection_error_px(eye, point, 1.0, lambda)
}

#[test]
fn projection_bounds_hold_at_every_point_of_the_box_from_eyes_all_around_it() {
    let low = DVec3::new(0.0, 0.0, -5.0);
    let high = DVec3::new(40.0, 80.0, 25.0);
    let lambda = 519.6;
    let steps = 8;
    let coordinate = |lo: f64, hi: f64, k: u32| lo + (hi - lo) * f64::from(k) / f64::from(steps);
    for eye in [
        DVec3::new(-30.0, 10.0, 100.0),
        DVec3::new(20.0, 40.0, 200.0),
        DVec3::new(20.0, 40.0, 10.0),
        DVec3::new(100.0, 200.0, 0.0),
        DVec3::new(41.0, 81.0, -50.0),
        DVec3::new(-1000.0, 5.0, 30.0),
    ] {
        let bounds = ProjectionBounds::over_box(eye, low, high, lambda);
        assert!(bounds.min <= bounds.max);
        for a in 0..=steps {
            for b in 0..=steps {
                for c in 0..=steps {
                    let point = DVec3::new(
                        coordinate(low.x, high.x, a),
                        coordinate(low.y, high.y, b),
                        coordinate(low.z, high.z, c),
                    );
                    let g = factor(eye, point, lambda);
                    assert!(
                        bounds.min * (1.0 - 1e-12) <= g && g <= bounds.max * (1.0 + 1e-12),
                        "eye {eye:?}, point {point:?}: {g} outside {bounds:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn an_eye_inside_the_box_makes_every_vertex_with_error_undecidable_from_above() {
    let bounds = ProjectionBounds::over_box(
        DVec3::new(5.0, 5.0, 5.0),
        DVec3::ZERO,
        DVec3::splat(10.0),
        100.0,
    );
    assert_eq!(bounds.max, f64::INFINITY);
    assert_eq!(bounds.min, 0.0);
    assert!(!bounds.removes(1e-6, 1e9));
    assert!(bounds.removes(0.0, 0.0));
    assert!(!bounds.keeps(1e6, 1e-9));
}

#[test]
fn the_algorithm_matches_the_brute_force_mesh_along_a_low_flight_for_every_block_level() {
    use crate::sim::algorithm::{FrameInput, LodAlgorithm};
    use crate::sim::mesh::validate::validate_reported;
    use crate::sim::stats::FrameStats;
    use crate::sim::view::{Camera, Pose};

    let hierarchy = bumpy(5);
    let nested = hierarchy.nested_vertex_errors(NestingRule::Max);
    let settings = ViewSettings {
        width_px: 600,
        height_px: 600,
        fovy: 60f64.to_radians(),
        near: 1.0,
        far: 1e5,
    };
    for block_level in 1..=5 {
        let config = LindstromConfig {
            nesting: crate::sim::hierarchy::NestingRule::Max,
            tau_px: 1.0,
            block_level,
        };
        let mut lindstrom = Lindstrom::new(&hierarchy, config, &settings);
        for frame in 0..20u32 {
            let eye = DVec3::new(
                f64::from(frame) * 17.0,
                100.0 + f64::from(frame) * 5.0,
                40.0,
            );
            let camera = Camera::new(
                &Pose {
                    position: eye,
                    yaw: 0.3,
                    pitch: -0.4,
                },
                settings,
            );
            let mut stats = FrameStats::default();
            lindstrom.update(
                &FrameInput {
                    frame: u64::from(frame),
                    camera: &camera,
                    broken_bounds: crate::sim::algorithm::BrokenBounds::NONE,
                },
                &mut stats,
            );
            let expected = mesh_from_scratch(&FromScratchView {
                hierarchy: &hierarchy,
                nested_errors: &nested,
                eye,
                lambda: settings.pixels_per_unit(),
                tau_px: config.tau_px,
            });
            assert!(
                lindstrom.vertex_set() == &expected,
                "k = {block_level}, frame {frame}"
            );
            validate_reported(hierarchy.lattice(), lindstrom.vertex_set(), stats.triangles)
                .unwrap();
            assert_eq!(
                stats.extra[3] + stats.extra[4],
                (33 * 33 - 4) as f64,
                "evaluated + by interval = every non-corner vertex"
            );
            assert_eq!(
                stats.extra[0] + stats.extra[1] + stats.extra[2],
                lindstrom.n_blocks() as f64
            );
        }
    }
}
