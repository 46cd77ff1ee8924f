//! Unit tests: the criterion's values, the roughness and its propagation, the blend and morph
//! values, one frame against the brute force, a block at blend 0 against the coarser surface.

use super::*;
use crate::sim::algorithm::{FrameInput, LodAlgorithm};
use crate::sim::audit::{AuditSettings, Auditor};
use crate::sim::hierarchy::{Lattice, VertexClass};
use crate::sim::mesh::validate::validate_reported;
use crate::sim::stats::PoppingFrame;
use crate::sim::terrain::{Heightfield, Spacing};
use crate::sim::view::{Camera, Pose, ViewSettings};
use glam::DVec3;

fn terrain(side: usize, height: impl Fn(usize, usize) -> f32) -> Hierarchy {
    let heights = (0..side * side)
        .map(|k| height(k % side, k / side))
        .collect();
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

fn bumpy(side: usize) -> Hierarchy {
    terrain(side, |i, j| {
        let (x, y) = (i as f32, j as f32);
        12.0 * (0.7 * x).sin() * (0.45 * y).cos() + ((i * 31 + j * 17) % 13) as f32 * 0.4
    })
}

fn config(minimum_resolution: f64, desired_resolution: f64) -> RottgerConfig {
    RottgerConfig {
        minimum_resolution,
        desired_resolution,
        load: None,
        distance: DistanceNorm::L1,
        d2_propagation: true,
        clipping: false,
        geomorphing: true,
    }
}

fn camera(eye: DVec3) -> Camera {
    Camera::new(
        &Pose {
            position: eye,
            yaw: 0.6,
            pitch: -0.5,
        },
        ViewSettings {
            width_px: 600,
            height_px: 600,
            fovy: 60f64.to_radians(),
            near: 1.0,
            far: 1e5,
        },
    )
}

fn step(rottger: &mut Rottger, frame: u64, camera: &Camera) -> FrameStats {
    let mut stats = FrameStats::default();
    rottger.update(
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
fn the_blend_is_two_times_one_minus_f_clamped_and_its_byte_rounds_up() {
    assert_eq!(blend(0.3), 1.0);
    assert_eq!(blend(0.75), 0.5);
    assert_eq!(blend(1.0), 0.0);
    assert_eq!(blend(1.7), 0.0);
    assert_eq!(blend_byte(0.75), 128);
    assert_eq!(blend_byte(0.5), 255);
    assert_eq!(blend_byte(0.0), 255);
    assert_eq!(blend_byte(1.0 - 1e-9), 1);
    assert_eq!(morph_factor(255), 1.0);
    assert!(subdivides(0.999_999) && !subdivides(1.0));
}

#[test]
fn k_is_one_at_c_two_and_falls_towards_a_half() {
    assert_eq!(propagation_factor(2.0), 1.0);
    assert_eq!(propagation_factor(8.0), 8.0 / 14.0);
    assert!((propagation_factor(1e9) - 0.5).abs() < 1e-9);
}

#[test]
fn the_local_d2_is_the_largest_of_six_differences_over_the_edge_length() {
    // A 5 × 5 field, zero but for a 4 m bump at the root's east midpoint (4, 2) and 1 m at the
    // centre (2, 2).
    let hierarchy = terrain(5, |i, j| match (i, j) {
        (4, 2) => 4.0,
        (2, 2) => 1.0,
        _ => 0.0,
    });
    // Root: edge 40 m; the east midpoint differs by 4 m from its edge's ends.
    assert_eq!(local_d2(&hierarchy, GridPoint::new(2, 2), 2), 4.0 / 40.0);
    // The finest block at (1, 3): corner (2, 2) = 1, everything else 0; its largest difference
    // is 0.5 m (its south and east midpoints, and its centre against one diagonal) over 20 m.
    assert_eq!(local_d2(&hierarchy, GridPoint::new(1, 3), 1), 0.5 / 20.0);
    assert_eq!(block_edge_m(&hierarchy, 2), 40.0);
}

#[test]
fn an_interior_block_has_twelve_adjacent_finer_blocks_and_a_corner_block_eight() {
    let cells = 16;
    assert_eq!(
        adjacent_finer_blocks(cells, GridPoint::new(6, 6), 2).count(),
        12
    );
    // The south-west block of half 2 has no neighbours to the south and west.
    assert_eq!(
        adjacent_finer_blocks(cells, GridPoint::new(2, 2), 2).count(),
        4 + 2 + 2
    );
    assert_eq!(
        adjacent_finer_blocks(cells, GridPoint::new(8, 8), 8).count(),
        4
    );
}

#[test]
fn the_matrix_is_valid_with_and_without_propagation_and_propagation_only_raises_d2() {
    let hierarchy = bumpy(33);
    for minimum_resolution in [2.0, 4.0, 8.0, 100.0] {
        let with = roughness::build_matrix(&hierarchy, minimum_resolution, true);
        let without = roughness::build_matrix(&hierarchy, minimum_resolution, false);
        validate::validate_roughness(&hierarchy, &with, minimum_resolution, true).unwrap();
        validate::validate_roughness(&hierarchy, &without, minimum_resolution, false).unwrap();
        let lattice = hierarchy.lattice();
        let mut raised = 0;
        let mut half = 1;
        while half < lattice.cells() {
            for p in crate::sim::hierarchy::square_points(lattice, half) {
                assert!(with.d2_code(p, half) >= without.d2_code(p, half));
                raised += usize::from(with.d2_code(p, half) > without.d2_code(p, half));
            }
            half *= 2;
        }
        assert!(
            raised > 0,
            "C = {minimum_resolution}: propagation changed nothing"
        );
    }
}

#[test]
fn a_corrupted_d2_code_is_caught() {
    let hierarchy = bumpy(17);
    let mut matrix = roughness::build_matrix(&hierarchy, 8.0, true);
    let p = GridPoint::new(4, 12);
    let code = matrix.d2_code(p, 4);
    assert!((2..255).contains(&code), "{code}");
    matrix.set_d2_code(p, 4, code - 1);
    assert!(validate::validate_roughness(&hierarchy, &matrix, 8.0, true).is_err());
    matrix.set_d2_code(p, 4, code + 1);
    assert!(validate::validate_roughness(&hierarchy, &matrix, 8.0, true).is_err());
}

#[test]
fn frames_along_a_flight_equal_the_brute_force_and_pass_the_validators() {
    let hierarchy = bumpy(33);
    for distance in [DistanceNorm::L1, DistanceNorm::Euclidean] {
        for clipping in [false, true] {
            let config = RottgerConfig {
                distance,
                clipping,
                ..config(4.0, 30.0)
            };
            let mut rottger = Rottger::new(&hierarchy, config);
            rottger.validate_roughness().unwrap();
            for frame in 0..24u64 {
                let eye = DVec3::new(
                    -30.0 + 15.0 * frame as f64,
                    40.0 + 9.0 * frame as f64,
                    25.0 + 2.0 * frame as f64,
                );
                let camera = camera(eye);
                let stats = step(&mut rottger, frame, &camera);
                validate_reported(hierarchy.lattice(), rottger.vertex_set(), stats.triangles)
                    .unwrap();
                rottger.validate_frame().unwrap();
                let expected = frame_from_scratch(&FromScratchView {
                    hierarchy: &hierarchy,
                    matrix: rottger.matrix(),
                    criterion: Criterion {
                        minimum_resolution: config.minimum_resolution,
                        desired_resolution: config.desired_resolution,
                        norm: distance,
                    },
                    camera: &camera,
                    clipping,
                });
                assert!(
                    rottger.vertex_set() == &expected.mesh,
                    "{config:?}, frame {frame}"
                );
                assert_eq!(stats.extra[2], expected.fans.fans as f64);
                assert_eq!(stats.extra[3], expected.fans.vertices as f64);
                assert_eq!(stats.extra[4], expected.fans.triangles as f64);
                assert_eq!(stats.extra[7], expected.subdivided_by_criterion as f64);
                assert_eq!(stats.extra[8], expected.forced as f64);
                assert_eq!(stats.extra[10], expected.morphing as f64);
            }
        }
    }
}

#[test]
fn a_shared_midpoint_morphs_with_the_smaller_blend_of_its_two_blocks() {
    let hierarchy = bumpy(17);
    let lattice = hierarchy.lattice();
    let mut rottger = Rottger::new(&hierarchy, config(2.0, 0.0));
    // Low and off-centre: the root's children subdivide with different f between ½ and 1.
    let camera = camera(DVec3::new(50.0, 70.0, 60.0));
    step(&mut rottger, 0, &camera);
    let mut checked = 0;
    for id in rottger.vertex_set().iter() {
        let p = lattice.point(id);
        let VertexClass::Rotated { .. } = lattice.classify(p) else {
            continue;
        };
        let parents = lattice.parents(p);
        let bytes: Vec<u8> = parents
            .as_slice()
            .iter()
            .map(|q| rottger.matrix().blend_byte(lattice.id(*q)))
            .collect();
        let smallest = *bytes.iter().min().unwrap();
        assert_eq!(rottger.vertex_blend(p), Some(morph_factor(smallest)));
        let z = f64::from(hierarchy.height(p));
        let expected = z - (1.0 - morph_factor(smallest)) * hierarchy.vertex_error(p);
        assert_eq!(rottger.drawn_height(p), expected);
        checked += usize::from(bytes.len() == 2 && bytes[0] != bytes[1]);
    }
    assert!(
        checked > 0,
        "no midpoint between blocks of different blends"
    );
}

#[test]
fn morphed_heights_run_from_the_mean_of_the_bisected_edge_to_the_sample() {
    let hierarchy = bumpy(9);
    let lattice = hierarchy.lattice();
    for (i, j) in [(4, 4), (4, 0), (3, 5), (6, 3)] {
        let p = GridPoint::new(i, j);
        let [a, b] = lattice.bisected_edge(p).unwrap();
        let mean = 0.5 * (f64::from(hierarchy.height(a)) + f64::from(hierarchy.height(b)));
        let z = f64::from(hierarchy.height(p));
        assert_eq!(geomorph::morphed_height(&hierarchy, p, 255), z);
        let near_zero = geomorph::morphed_height(&hierarchy, p, 1);
        assert!(
            (near_zero - (mean + (z - mean) / 255.0)).abs() < 1e-9,
            "{p:?}"
        );
        let half_way = geomorph::morphed_height(&hierarchy, p, 128);
        assert!((half_way - (mean + (z - mean) * 128.0 / 255.0)).abs() < 1e-9);
    }
}

#[test]
fn without_geomorphing_vertices_are_drawn_at_their_samples_and_none_morph() {
    let hierarchy = bumpy(17);
    let lattice = hierarchy.lattice();
    let mut rottger = Rottger::new(
        &hierarchy,
        RottgerConfig {
            geomorphing: false,
            ..config(2.0, 0.0)
        },
    );
    let stats = step(&mut rottger, 0, &camera(DVec3::new(80.0, 80.0, 180.0)));
    assert_eq!(stats.extra[10], 0.0);
    for id in rottger.vertex_set().iter() {
        let p = lattice.point(id);
        assert_eq!(rottger.drawn_height(p), f64::from(hierarchy.height(p)));
    }
}

#[test]
fn the_base_mesh_is_one_fan_of_two_triangles() {
    let hierarchy = bumpy(9);
    let mut rottger = Rottger::new(&hierarchy, config(8.0, 10.0));
    let stats = step(&mut rottger, 0, &camera(DVec3::new(0.0, 0.0, 1e9)));
    assert_eq!(
        rottger.vertex_set(),
        &VertexSet::base_mesh(&Lattice::new(3))
    );
    assert_eq!(stats.triangles, 2);
    assert_eq!(&stats.extra[2..5], &[1.0, 4.0, 2.0]);
    rottger.validate_frame().unwrap();
}

/// The change of the drawn surface from `from` to `to` at every sample, seen from far above.
fn popping_between(hierarchy: &Hierarchy, from: MeshOutput, to: MeshOutput) -> PoppingFrame {
    let side = hierarchy.field().side() as f64 * 10.0;
    let overhead = Camera::new(
        &Pose {
            position: DVec3::new(0.5 * side, 0.5 * side, 20.0 * side),
            yaw: 0.0,
            pitch: -1.5,
        },
        camera(DVec3::ZERO).settings,
    );
    let mut auditor = Auditor::new(
        hierarchy,
        AuditSettings {
            stride: 1,
            popping: true,
            detail_stride: None,
        },
    );
    auditor.audit(hierarchy, from, &overhead);
    let popping = auditor.audit(hierarchy, to, &overhead).popping.unwrap();
    assert_eq!(
        popping.samples,
        hierarchy.field().side().pow(2) as u64,
        "every sample in view"
    );
    popping
}

#[test]
fn a_block_at_blend_zero_draws_exactly_the_coarser_surface() {
    let hierarchy = bumpy(33);
    let lattice = hierarchy.lattice();
    let mut rottger = Rottger::new(&hierarchy, config(4.0, 30.0));
    step(&mut rottger, 0, &camera(DVec3::new(60.0, 80.0, 40.0)));
    let mesh = rottger.vertex_set();
    let mut tested = 0;
    for &centre_id in &rottger.subdivided {
        let centre = lattice.point(centre_id);
        let VertexClass::Square { half } = lattice.classify(centre) else {
            unreachable!("only block centres are subdivided");
        };
        // The coarser mesh: the frame's without the block's centre and drawn midpoints, every
        // other vertex drawn as the frame draws it. Blocks whose vertices others need (a
        // subdivided child, or a neighbour's child beside a midpoint) have none.
        let mut coarse = mesh.clone();
        let mut coarse_morphed = rottger.morphed.clone();
        coarse.remove(centre_id);
        coarse_morphed.remove(centre_id);
        for midpoint in lattice.boundary_vertices(centre, half) {
            if mesh.contains_point(lattice, midpoint) {
                coarse.remove(lattice.id(midpoint));
                coarse_morphed.remove(lattice.id(midpoint));
            }
        }
        if crate::sim::mesh::validate::validate(lattice, &coarse).is_err() {
            continue;
        }
        // The frame's mesh with this block's blend at 0.
        let mut matrix = rottger.matrix.clone();
        matrix.set_blend_byte(centre_id, 0);
        let mut at_zero = MorphedHeights::new();
        geomorph::rebuild_morphed(&hierarchy, &matrix, rottger.mesh.active(), &mut at_zero);
        let coarser = MeshOutput::morphed_lattice(&coarse, &coarse_morphed);
        let zero = popping_between(
            &hierarchy,
            coarser,
            MeshOutput::morphed_lattice(mesh, &at_zero),
        );
        assert!(
            zero.max_m <= 1e-4,
            "block {centre:?} (half {half}) at blend 0 is {} m off the coarser surface",
            zero.max_m
        );
        // At its own blend the block draws something else, where it has relief to draw.
        let own = popping_between(&hierarchy, coarser, rottger.mesh());
        tested += usize::from(own.max_m > 0.01);
    }
    assert!(tested > 0, "no block with relief to morph");
}

#[test]
fn a_wrong_or_missing_morphed_height_in_the_output_is_caught() {
    let hierarchy = bumpy(17);
    let mut rottger = Rottger::new(&hierarchy, config(2.0, 0.0));
    step(&mut rottger, 0, &camera(DVec3::new(50.0, 70.0, 60.0)));
    rottger.validate_frame().unwrap();
    let id = rottger.morphed.sorted_ids()[0];
    let z = rottger.morphed.get(id).unwrap();
    rottger.morphed.set(id, z + 0.5);
    let error = rottger.validate_frame().unwrap_err().to_string();
    assert!(error.contains("in the mesh output"), "{error}");
    rottger.morphed.remove(id);
    assert!(rottger.validate_frame().is_err());
    rottger.morphed.set(id, z);
    rottger.validate_frame().unwrap();
    // A morph of a vertex that does not morph (a corner).
    let corner = hierarchy.lattice().id(GridPoint::new(0, 0));
    rottger.morphed.set(corner, 1.0);
    assert!(rottger.validate_frame().is_err());
}
