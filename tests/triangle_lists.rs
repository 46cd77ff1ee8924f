//! The general mesh path, proved with the test-only algorithms of `tests/common/patches.rs`
//! (patches with skirts, collapsed borders, degenerate strip joins and geomorphing, and a 4-8
//! mesh with morphed heights): they go through the same runner as every algorithm — the
//! validators every frame, culling, the audit with its holes and crack gaps, popping, the mesh
//! counts — and each measure is checked against what the scene must give.

mod common;

use common::algorithms::{reference, rottger};
use common::patches::{Borders, MorphingLattice, PatchConfig, Patches};
use common::{bumpy_terrain, checked_step, step, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::rottger::{Criterion, FromScratchView, frame_from_scratch};
use roamsim::sim::algorithm::{LodAlgorithm, Reference, Rottger};
use roamsim::sim::audit::{AuditSettings, Auditor};
use roamsim::sim::flight::Flight;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::check::{MeshCheckError, MeshChecker};
use roamsim::sim::mesh::list_validate::TriangleListError;
use roamsim::sim::mesh::{CrackPolicy, MeshOutput, MorphedHeights, TriangleList, TriangleRole};
use roamsim::sim::run::{Effects, RunInputs, run_algorithm};
use roamsim::sim::stats::{FrameStats, SurfaceCoverage};
use roamsim::sim::view::{Camera, Pose};
use roamsim::sim::zone::{SpeedBound, ZoneVariant};

/// Skirts 15 m deep, geomorphing and strip joins on 8×8-cell patches of a 65² terrain.
fn skirted() -> PatchConfig {
    PatchConfig {
        patch_level: 3,
        borders: Borders::Skirts { depth_m: 15.0 },
        morph: true,
        strip_joins: true,
        detail_distance_m: 60.0,
    }
}

fn collapsed() -> PatchConfig {
    PatchConfig {
        borders: Borders::Collapsed,
        ..skirted()
    }
}

fn open() -> PatchConfig {
    PatchConfig {
        borders: Borders::Open,
        ..skirted()
    }
}

/// A camera at `eye` looking at the terrain's middle, 40° down.
fn camera_towards_middle(eye: DVec3) -> Camera {
    let to_middle = DVec3::new(320.0, 320.0, 0.0) - eye;
    Camera::new(
        &Pose {
            position: eye,
            yaw: to_middle.y.atan2(to_middle.x),
            pitch: -0.7,
        },
        view_600(),
    )
}

/// A low circle over the 65² terrain: near patches fine, far ones coarse.
fn circle(frames: u32) -> Vec<Pose> {
    (0..frames)
        .map(|k| {
            let angle = 0.04 * f64::from(k);
            Pose {
                position: DVec3::new(
                    320.0 + 200.0 * angle.cos(),
                    320.0 + 200.0 * angle.sin(),
                    50.0,
                ),
                yaw: angle + std::f64::consts::FRAC_PI_2,
                pitch: -0.4,
            }
        })
        .collect()
}

fn audit_settings(popping: bool) -> AuditSettings {
    AuditSettings {
        stride: 1,
        popping,
        detail_stride: None,
    }
}

/// Runs `algorithm` through the shared runner with every effect on and the checks every frame.
fn run_with_every_effect(
    hierarchy: &Hierarchy,
    algorithm: &mut dyn LodAlgorithm,
) -> Vec<FrameStats> {
    let flight = Flight::from_poses(circle(30)).unwrap();
    let inputs = RunInputs {
        hierarchy,
        view: &view_600(),
        flight: &flight,
        violations: &[],
        effects: Effects {
            audit: Some(audit_settings(true)),
            culling: true,
            check_meshes: true,
        },
        max_triangles: None,
        detail_truth: None,
    };
    run_algorithm(&inputs, algorithm.name(), algorithm, &mut |_| {}).unwrap()
}

#[test]
fn skirted_patches_pass_every_check_and_the_audit_measures_their_cracks() {
    let hierarchy = bumpy_terrain(6);
    let frames = run_with_every_effect(&hierarchy, &mut Patches::new(&hierarchy, skirted()));
    for stats in &frames {
        let counts = stats.mesh.unwrap();
        let [surface, skirt, degenerate, stitch] = counts.triangles_by_role;
        assert_eq!(surface + skirt + degenerate + stitch, stats.triangles);
        assert!(skirt > 0 && degenerate > 0 && stitch == 0, "{counts:?}");
        assert!(stats.triangles_rendered < stats.triangles);
        let audit = stats.audit.unwrap();
        let coverage = audit.coverage.unwrap();
        assert_eq!(coverage.holes, 0, "frame {}", stats.frame);
        assert!(
            coverage.crack_samples > 0 && coverage.crack_gap_max_m > 0.0,
            "frame {}: patches of different steps meet with T-junctions",
            stats.frame
        );
    }
    assert!(frames.iter().any(|f| f.mesh.unwrap().morphing_vertices > 0));
    assert!(
        frames[1..]
            .iter()
            .all(|f| f.audit.unwrap().popping.is_some())
    );
    assert!(
        frames[1..]
            .iter()
            .any(|f| f.audit.unwrap().popping.unwrap().max_m > 0.0)
    );
}

#[test]
fn without_skirts_the_validator_finds_the_first_uncovered_crack() {
    let hierarchy = bumpy_terrain(6);
    let mut patches = Patches::new(&hierarchy, open());
    let camera = camera_towards_middle(DVec3::new(100.0, 100.0, 40.0));
    let stats = step(&mut patches, 0, &camera, false);
    let error = MeshChecker::new()
        .check(&hierarchy, patches.mesh(), stats.triangles)
        .unwrap_err();
    assert!(
        matches!(
            error,
            MeshCheckError::TriangleList(TriangleListError::CrackNotSkirted { .. })
        ),
        "{error}"
    );
}

#[test]
fn skirts_hide_cracks_but_do_not_close_them_and_collapsed_borders_close_them() {
    // The same view three ways: the surface with skirts and without is the same, so the audit
    // finds the same crack gaps (skirts are never surface), which the skirts cover and nothing
    // covers without them; collapsing the borders closes them.
    let hierarchy = bumpy_terrain(6);
    let camera = camera_towards_middle(DVec3::new(100.0, 100.0, 40.0));
    let audit_of = |config: PatchConfig| {
        let mut patches = Patches::new(&hierarchy, config);
        step(&mut patches, 0, &camera, false);
        let mut auditor = Auditor::new(&hierarchy, audit_settings(false));
        auditor.audit(&hierarchy, patches.mesh(), &camera)
    };
    let (with_skirts, without, closed) =
        (audit_of(skirted()), audit_of(open()), audit_of(collapsed()));
    let (skirted_coverage, bare) = (with_skirts.coverage.unwrap(), without.coverage.unwrap());
    let surface = |c: SurfaceCoverage| (c.holes, c.crack_samples, c.crack_gap_max_m);
    assert_eq!(surface(skirted_coverage), surface(bare));
    assert_eq!(with_skirts.projected, without.projected);
    assert!(skirted_coverage.crack_samples > 0);
    assert_eq!(bare.cracks_uncovered, bare.crack_samples);
    assert!(skirted_coverage.cracks_uncovered < bare.cracks_uncovered);
    let closed_coverage = closed.coverage.unwrap();
    assert_eq!(
        (closed_coverage.holes, closed_coverage.crack_samples),
        (0, 0)
    );
}

#[test]
fn collapsed_borders_leave_zero_area_triangles_and_pass_the_closed_checks_from_every_eye() {
    // Every eye over a 17² terrain of 4×4-cell patches (so neighbouring steps differ by up to
    // two levels), at three heights: the collapsed mesh tiles the domain and is watertight.
    let hierarchy = bumpy_terrain(4);
    let config = PatchConfig {
        patch_level: 2,
        detail_distance_m: 15.0,
        ..collapsed()
    };
    let mut patches = Patches::new(&hierarchy, config);
    let (mut frame, mut degenerate, mut level_gaps) = (0, 0, 0);
    for j in 0..17 {
        for i in 0..17 {
            for z in [5.0, 40.0, 400.0] {
                let eye = DVec3::new(f64::from(i) * 10.0, f64::from(j) * 10.0, z);
                let camera = camera_towards_middle(eye);
                let context = format!("eye {eye:?}");
                let stats = checked_step(&hierarchy, &mut patches, frame, &camera, false, context);
                frame += 1;
                let counts = patches.mesh().counts(stats.triangles).unwrap();
                degenerate += counts.triangles_by_role[TriangleRole::Degenerate.index()];
                let steps: Vec<u32> = (0..4).map(|p| patches.step_level(p, 0)).collect();
                level_gaps += u64::from(steps.windows(2).any(|w| w[0].abs_diff(w[1]) > 1));
            }
        }
    }
    assert!(degenerate > 0, "no border was ever collapsed");
    assert!(
        level_gaps > 0,
        "neighbouring patches never differed by two levels"
    );
}

#[test]
fn every_eye_over_17_by_17_gives_valid_skirted_patches() {
    let hierarchy = bumpy_terrain(4);
    let config = PatchConfig {
        patch_level: 2,
        detail_distance_m: 15.0,
        ..skirted()
    };
    let mut patches = Patches::new(&hierarchy, config);
    let (mut frame, mut mixed) = (0, 0);
    for j in 0..17 {
        for i in 0..17 {
            let eye = DVec3::new(f64::from(i) * 10.0, f64::from(j) * 10.0, 30.0);
            let context = format!("eye {eye:?}");
            checked_step(
                &hierarchy,
                &mut patches,
                frame,
                &camera_towards_middle(eye),
                false,
                context,
            );
            frame += 1;
            let steps: Vec<u32> = (0..4).map(|p| patches.step_level(p, p)).collect();
            mixed += u32::from(steps.iter().any(|&k| k != steps[0]));
        }
    }
    assert!(
        mixed > 100,
        "patches of different steps met in only {mixed} of 289 views"
    );
}

/// The triangles of `mesh` as a triangle list of its own (every triangle a surface one).
fn as_triangle_list(hierarchy: &Hierarchy, mesh: MeshOutput) -> TriangleList {
    let mut list = TriangleList::new(hierarchy.lattice(), CrackPolicy::Closed);
    mesh.for_each_triangle(hierarchy, |triangle| {
        let corners = triangle.corners.map(|c| list.add_vertex(c.position, c.z));
        list.add_triangle(corners, triangle.info);
    });
    list
}

#[test]
fn a_4_8_mesh_drawn_as_a_triangle_list_passes_its_checks_and_audits_the_same() {
    // The general rasteriser with its tie rule against the 4-8 fast path, on the same
    // triangles: the same samples, heights equal up to rounding, so the same error figures.
    let hierarchy = bumpy_terrain(6);
    let speed = SpeedBound {
        horizontal: 10.0,
        vertical: 5.0,
        rotation: SpeedBound::NO_ROTATION_BOUND,
    };
    let mut reference = Reference::new(
        &hierarchy,
        reference(1.0, ZoneVariant::Conservative),
        &view_600(),
        speed,
    );
    for (frame, pose) in circle(10).iter().enumerate() {
        let camera = Camera::new(pose, view_600());
        let stats = step(&mut reference, frame as u64, &camera, frame == 0);
        let list = as_triangle_list(&hierarchy, reference.mesh());
        MeshChecker::new()
            .check(&hierarchy, MeshOutput::triangles(&list), stats.triangles)
            .unwrap();
        let mut lattice_auditor = Auditor::new(&hierarchy, audit_settings(false));
        let mut list_auditor = Auditor::new(&hierarchy, audit_settings(false));
        let fast = lattice_auditor.audit(&hierarchy, reference.mesh(), &camera);
        let general = list_auditor.audit(&hierarchy, MeshOutput::triangles(&list), &camera);
        let coverage = general.coverage.unwrap();
        assert_eq!((coverage.holes, coverage.crack_samples), (0, 0));
        assert_eq!(fast.samples_in_view, general.samples_in_view);
        let (fast, general) = (fast.projected.unwrap(), general.projected.unwrap());
        for (a, b) in [
            (fast.max, general.max),
            (fast.mean, general.mean),
            (fast.p95, general.p95),
        ] {
            assert!(
                (a - b).abs() <= 1e-6 * a.abs().max(1.0),
                "frame {frame}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn a_morphed_rottger_mesh_audits_and_pops_as_its_surface_built_from_scratch() {
    // Röttger's morphed mesh through the audit's 4-8 fast path, against the brute force's mesh
    // and morphed heights (computed from its own blends, `frame_from_scratch`) drawn as a
    // triangle list through the general rasteriser: the same error and popping figures.
    let hierarchy = bumpy_terrain(6);
    let config = rottger(4.0, 20.0);
    let mut algorithm = Rottger::new(&hierarchy, config);
    let mut fast_auditor = Auditor::new(&hierarchy, audit_settings(true));
    let mut general_auditor = Auditor::new(&hierarchy, audit_settings(true));
    let mut plain_auditor = Auditor::new(&hierarchy, audit_settings(true));
    let (mut morphing, mut plain_differs) = (0, false);
    for (frame, pose) in circle(20).iter().enumerate() {
        let camera = Camera::new(pose, view_600());
        checked_step(
            &hierarchy,
            &mut algorithm,
            frame as u64,
            &camera,
            false,
            "rottger",
        );
        let expected = frame_from_scratch(&FromScratchView {
            hierarchy: &hierarchy,
            matrix: algorithm.matrix(),
            criterion: Criterion {
                minimum_resolution: config.minimum_resolution,
                desired_resolution: config.desired_resolution,
                norm: config.distance,
            },
            camera: &camera,
            clipping: config.clipping,
        });
        let mut morphed = MorphedHeights::new();
        for (&id, &z) in &expected.morphed {
            morphed.set(id, z as f32);
        }
        morphing += morphed.len();
        let list = as_triangle_list(
            &hierarchy,
            MeshOutput::morphed_lattice(&expected.mesh, &morphed),
        );
        let fast = fast_auditor.audit(&hierarchy, algorithm.mesh(), &camera);
        let general = general_auditor.audit(&hierarchy, MeshOutput::triangles(&list), &camera);
        let plain = plain_auditor.audit(
            &hierarchy,
            MeshOutput::lattice(algorithm.vertex_set()),
            &camera,
        );
        let coverage = general.coverage.unwrap();
        assert_eq!((coverage.holes, coverage.crack_samples), (0, 0));
        assert_eq!(fast.samples_in_view, general.samples_in_view);
        let (fast_error, general_error) = (fast.projected.unwrap(), general.projected.unwrap());
        let mut pairs = vec![
            (fast_error.max, general_error.max),
            (fast_error.mean, general_error.mean),
            (fast_error.p95, general_error.p95),
        ];
        if frame > 0 {
            let (a, b) = (fast.popping.unwrap(), general.popping.unwrap());
            assert_eq!(a.samples, b.samples);
            pairs.extend([
                (a.rmse_m, b.rmse_m),
                (a.max_m, b.max_m),
                (a.max_px, b.max_px),
            ]);
            plain_differs |= plain.popping.unwrap().max_m != a.max_m;
        }
        for (a, b) in pairs {
            assert!(
                (a - b).abs() <= 1e-5 * a.abs().max(1.0),
                "frame {frame}: {a} vs {b}"
            );
        }
        plain_differs |= plain.projected.unwrap().mean != fast_error.mean;
    }
    // The flight morphs, and the morphed surface is not the plain mesh's.
    assert!(morphing > 0 && plain_differs);
}

#[test]
fn morphed_heights_are_what_the_audit_measures_and_what_pops() {
    let hierarchy = bumpy_terrain(6);
    let mut morphing = MorphingLattice::new(&hierarchy, 1, 100.0, 300.0);
    let mut auditor = Auditor::new(&hierarchy, audit_settings(true));
    let near = camera_towards_middle(DVec3::new(300.0, 300.0, 30.0));
    let far = camera_towards_middle(DVec3::new(-400.0, -400.0, 300.0));
    let (mut popping, mut errors, mut morphing_vertices) = (Vec::new(), Vec::new(), Vec::new());
    for (frame, camera) in [near, near, far, far].iter().enumerate() {
        let stats = checked_step(
            &hierarchy,
            &mut morphing,
            frame as u64,
            camera,
            false,
            "morph",
        );
        let audit = auditor.audit(&hierarchy, morphing.mesh(), &near);
        popping.push(audit.popping.map(|p| p.max_m));
        errors.push(audit.projected.unwrap().max);
        let counts = morphing.mesh().counts(stats.triangles).unwrap();
        morphing_vertices.push(counts.morphing_vertices);
    }
    // Every fine vertex morphs from far away (1089 − 289 of the 33² grid), fewer from near.
    assert_eq!(morphing_vertices[2], 800);
    assert!(
        morphing_vertices[0] < morphing_vertices[2],
        "{morphing_vertices:?}"
    );
    // Still camera: nothing pops; moving away morphs the fine vertices towards the coarse
    // surface: it pops, and the audit (always from `near`) sees the coarser surface's error.
    assert_eq!(popping[0], None);
    assert_eq!(popping[1], Some(0.0));
    assert!(popping[2].unwrap() > 0.5, "{popping:?}");
    assert_eq!(popping[3], Some(0.0));
    assert!(errors[2] > errors[1], "{errors:?}");
}

#[test]
fn an_exported_triangle_list_holds_every_triangle_with_its_role_level_and_group() {
    use roamsim::edge::output::mesh_ply::{PlyHeader, mesh_ply};
    let hierarchy = bumpy_terrain(6);
    let mut patches = Patches::new(&hierarchy, skirted());
    let camera = camera_towards_middle(DVec3::new(100.0, 100.0, 40.0));
    let stats = step(&mut patches, 0, &camera, false);
    let header = PlyHeader {
        experiment: "test",
        entry: "patches",
        frame: 0,
    };
    let text = mesh_ply(&hierarchy, patches.mesh(), &header);
    let (head, body) = text.split_once("end_header\n").unwrap();
    let count = |element: &str| -> usize {
        head.lines()
            .find_map(|l| l.strip_prefix(&format!("element {element} ")))
            .unwrap()
            .parse()
            .unwrap()
    };
    let (n_vertices, n_faces) = (count("vertex"), count("face"));
    let lines: Vec<&str> = body.lines().collect();
    assert_eq!(lines.len(), n_vertices + n_faces);
    assert_eq!(n_faces as u64, stats.triangles);
    // Faces as the visitor gives them, in its order: corners (by position and height), role,
    // level, group.
    let vertices: Vec<[f64; 3]> = lines[..n_vertices]
        .iter()
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let spacing = hierarchy.field().spacing();
    let mut faces = lines[n_vertices..].iter();
    let mut roles = [0u64; 4];
    patches.mesh().for_each_triangle(&hierarchy, |t| {
        let face: Vec<u64> = faces
            .next()
            .unwrap()
            .split(' ')
            .map(|x| x.parse().unwrap())
            .collect();
        assert_eq!(face[0], 3);
        for (k, corner) in t.corners.iter().enumerate() {
            let local = corner.local(spacing);
            assert_eq!(vertices[face[1 + k] as usize], [local.x, local.y, local.z]);
        }
        let info = t.info;
        assert_eq!(
            face[4..],
            [
                info.role.index() as u64,
                u64::from(info.level),
                u64::from(info.group)
            ]
        );
        roles[face[4] as usize] += 1;
    });
    assert_eq!(
        roles,
        patches
            .mesh()
            .counts(stats.triangles)
            .unwrap()
            .triangles_by_role
    );
}
