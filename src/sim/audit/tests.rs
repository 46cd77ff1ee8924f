//! The auditor's tests through its public calls (SPEC §7): small scenes whose figures are known
//! by hand (a spike under a flat mesh, a T-junction, a missing triangle, skirts of two depths).
//! The tallies and one segment's figures are tested beside their code (`figures.rs`,
//! `geometry.rs`); the differential test against the reference is `tests/audit_reference.rs`.

use super::{AuditSettings, Auditor};
use crate::sim::hierarchy::{Hierarchy, Lattice};
use crate::sim::mesh::{
    CrackPolicy, MeshOutput, SubgridPoint, TriangleInfo, TriangleList, TriangleRole, VertexSet,
};
use crate::sim::metrics::{projected_error_px, view_angle_error_px};
use crate::sim::terrain::{Heightfield, Spacing};
use crate::sim::view::{Camera, Pose, ViewSettings};
use glam::DVec3;

fn settings(stride: u32, popping: bool) -> AuditSettings {
    AuditSettings {
        stride,
        popping,
        detail_stride: None,
    }
}

pub(super) fn camera_above(hierarchy: &Hierarchy) -> Camera {
    let (w, h) = hierarchy.field().extent();
    Camera::new(
        &Pose {
            position: DVec3::new(w / 2.0, h / 2.0, 200.0),
            yaw: 0.0,
            pitch: -std::f64::consts::FRAC_PI_2,
        },
        ViewSettings {
            width_px: 100,
            height_px: 100,
            fovy: 120f64.to_radians(),
            near: 1.0,
            far: 1000.0,
        },
    )
}

pub(super) fn spike_field() -> Hierarchy {
    let side = 9;
    let heights = (0..side * side)
        .map(|k| if k == 4 * side + 4 { 8.0 } else { 0.0 })
        .collect();
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

#[test]
fn the_full_mesh_has_no_error_and_the_base_mesh_misses_the_spike() {
    let hierarchy = spike_field();
    let lattice = hierarchy.lattice();
    let camera = camera_above(&hierarchy);
    let mut auditor = Auditor::new(&hierarchy, settings(1, true));
    let mut full = VertexSet::new(lattice);
    for id in 0..lattice.n_vertices() as u32 {
        full.insert(id);
    }
    let exact = auditor.audit(&hierarchy, MeshOutput::lattice(&full), &camera);
    assert_eq!(exact.samples_in_view, 81);
    assert_eq!(exact.view_angle.unwrap().max, 0.0);
    assert_eq!(exact.projected.unwrap().max, 0.0);
    assert_eq!((exact.coverage, exact.popping), (None, None));

    let base_mesh = VertexSet::base_mesh(lattice);
    let base = auditor.audit(&hierarchy, MeshOutput::lattice(&base_mesh), &camera);
    let worst = base.view_angle.unwrap();
    // The spike (8 m, seen from 192 m straight above) is the only error.
    let expected = view_angle_error_px(
        DVec3::new(40.0, 40.0, 200.0),
        DVec3::new(40.0, 40.0, 0.0),
        8.0,
        camera.settings.pixel_angle(),
    );
    assert!((worst.max - expected).abs() < 1e-9);
    assert!((worst.mean - expected / 81.0).abs() < 1e-9);
    assert_eq!(worst.p95, 0.0);
    // From the full mesh to the base mesh only the spike's sample moved: 8 m of 81 samples.
    let popping = base.popping.unwrap();
    assert_eq!((popping.samples, popping.max_m), (81, 8.0));
    assert!((popping.rmse_m - 8.0 / 9.0).abs() < 1e-12);
    let spike_px = projected_error_px(&camera, DVec3::new(40.0, 40.0, 0.0), 8.0).unwrap();
    assert!((popping.max_px - spike_px).abs() < 1e-9);
}

/// Over the spike field's 8×8 cells: the west half as two triangles, the east half as two
/// squares meeting at the spike (4, 4), so the west half's edge x = 4 has a T-junction
/// there; `drop_one` leaves out a triangle of the south-east square.
fn t_junction_list(drop_one: bool) -> TriangleList {
    let mut list = TriangleList::new(&Lattice::new(3), CrackPolicy::Skirted);
    let mut v = |i: u32, j: u32| {
        let z = if (i, j) == (4, 4) { 8.0 } else { 0.0 };
        list.add_vertex(SubgridPoint::grid(i, j), z)
    };
    let corners = [
        [v(0, 0), v(4, 0), v(4, 8)],
        [v(0, 0), v(4, 8), v(0, 8)],
        [v(4, 0), v(8, 0), v(8, 4)],
        [v(4, 0), v(8, 4), v(4, 4)],
        [v(4, 4), v(8, 4), v(8, 8)],
        [v(4, 4), v(8, 8), v(4, 8)],
    ];
    for (k, corners) in corners.into_iter().enumerate() {
        if !(drop_one && k == 3) {
            let info = TriangleInfo {
                role: TriangleRole::Surface,
                group: 0,
                level: 0,
            };
            list.add_triangle(corners, info);
        }
    }
    list
}

#[test]
fn a_t_junction_is_a_crack_and_a_missing_triangle_leaves_holes() {
    let hierarchy = spike_field();
    let camera = camera_above(&hierarchy);
    let mut auditor = Auditor::new(&hierarchy, settings(1, true));
    let whole = t_junction_list(false);
    let frame = auditor.audit(&hierarchy, MeshOutput::triangles(&whole), &camera);
    let coverage = frame.coverage.unwrap();
    // Along x = 4 the west half draws 0 m; the east half rises to the spike: 2, 4, 6, 8,
    // 6, 4, 2 m at j = 1..=7.
    assert_eq!(coverage.holes, 0);
    assert_eq!((coverage.crack_samples, coverage.crack_gap_max_m), (7, 8.0));
    assert!(coverage.crack_gap_max_px > 0.0);
    assert_eq!(frame.samples_in_view, 81);

    // The spike's sample belongs to the east half (the tie rule nudges it east), which draws
    // it at 8 m: flattening the surface moves it by 8 m, more than any other sample.
    let mut flat = TriangleList::new(&Lattice::new(3), CrackPolicy::Closed);
    let corners = [(0, 0), (8, 0), (8, 8), (0, 8)]
        .map(|(i, j)| flat.add_vertex(SubgridPoint::grid(i, j), 0.0));
    let surface = TriangleInfo {
        role: TriangleRole::Surface,
        group: 0,
        level: 0,
    };
    flat.add_triangle([corners[0], corners[1], corners[2]], surface);
    flat.add_triangle([corners[0], corners[2], corners[3]], surface);
    let frame = auditor.audit(&hierarchy, MeshOutput::triangles(&flat), &camera);
    let popping = frame.popping.unwrap();
    assert_eq!((popping.samples, popping.max_m), (81, 8.0));

    let torn = t_junction_list(true);
    let frame = auditor.audit(&hierarchy, MeshOutput::triangles(&torn), &camera);
    let coverage = frame.coverage.unwrap();
    // The missing triangle's three inner samples and the three on its west edge (which
    // the tie rule gives to the east side); its diagonal belongs to its neighbour.
    assert_eq!(coverage.holes, 6);
    assert_eq!(frame.samples_in_view, 75);
    assert_eq!(coverage.crack_samples, 4);
    assert_eq!(
        frame.popping.unwrap().samples,
        75,
        "holes are left out of popping"
    );
}

#[test]
fn skirts_cover_the_part_of_a_crack_they_span_and_the_rest_is_left_open() {
    let hierarchy = spike_field();
    let camera = camera_above(&hierarchy);
    let mut auditor = Auditor::new(&hierarchy, settings(1, false));
    // The T-junction of `t_junction_list`: along x = 4 the east half rises to 8 m over the
    // west half's 0 m. A skirt hung from the east half's edges reaching `depth` below.
    let skirted = |depth: f32| {
        let mut list = t_junction_list(false);
        let skirt = TriangleInfo {
            role: TriangleRole::Skirt,
            group: 1,
            level: 0,
        };
        for (from, to) in [((4, 0, 0.0), (4, 4, 8.0)), ((4, 4, 8.0), (4, 8, 0.0))] {
            let mut v = |(i, j, z): (u32, u32, f32)| list.add_vertex(SubgridPoint::grid(i, j), z);
            let (top_a, top_b) = (v(from), v(to));
            let (bottom_a, bottom_b) = (
                v((from.0, from.1, from.2 - depth)),
                v((to.0, to.1, to.2 - depth)),
            );
            list.add_triangle([top_a, top_b, bottom_b], skirt);
            list.add_triangle([top_a, bottom_b, bottom_a], skirt);
        }
        list
    };
    let coverage = |list: &TriangleList, auditor: &mut Auditor| {
        auditor
            .audit(&hierarchy, MeshOutput::triangles(list), &camera)
            .coverage
            .unwrap()
    };
    let bare = coverage(&t_junction_list(false), &mut auditor);
    assert_eq!((bare.crack_samples, bare.cracks_uncovered), (7, 7));
    assert_eq!(bare.crack_uncovered_max_m, 8.0);
    // Deep enough: every crack covered.
    let deep = coverage(&skirted(8.0), &mut auditor);
    assert_eq!((deep.crack_samples, deep.cracks_uncovered), (7, 0));
    assert_eq!(deep.crack_uncovered_max_m, 0.0);
    // 3 m deep: the gaps of 2, 4, 6, 8, 6, 4, 2 m keep 0, 1, 3, 5, 3, 1, 0 m open.
    let shallow = coverage(&skirted(3.0), &mut auditor);
    assert_eq!((shallow.crack_samples, shallow.cracks_uncovered), (7, 5));
    assert_eq!(shallow.crack_uncovered_max_m, 5.0);
    assert!(shallow.crack_uncovered_max_px > 0.0);
}

#[test]
fn nothing_in_view_gives_no_error_figures() {
    let hierarchy = spike_field();
    let mut camera = camera_above(&hierarchy);
    camera = Camera::new(
        &Pose {
            position: camera.eye,
            yaw: 0.0,
            pitch: std::f64::consts::FRAC_PI_2,
        },
        camera.settings,
    );
    let mut auditor = Auditor::new(&hierarchy, settings(2, false));
    let base_mesh = VertexSet::base_mesh(hierarchy.lattice());
    let frame = auditor.audit(&hierarchy, MeshOutput::lattice(&base_mesh), &camera);
    assert_eq!(frame.samples_in_view, 0);
    assert_eq!(frame.view_angle, None);
}

#[test]
#[should_panic(expected = "was promised the next frame's camera")]
fn popping_refuses_a_camera_other_than_the_one_promised() {
    let hierarchy = spike_field();
    let camera = camera_above(&hierarchy);
    let elsewhere = Camera::new(
        &Pose {
            position: camera.eye + DVec3::new(5.0, 0.0, 0.0),
            yaw: 0.0,
            pitch: -std::f64::consts::FRAC_PI_2,
        },
        camera.settings,
    );
    let mut auditor = Auditor::new(&hierarchy, settings(1, true));
    let base_mesh = VertexSet::base_mesh(hierarchy.lattice());
    let mesh = MeshOutput::lattice(&base_mesh);
    auditor.audit_followed_by(&hierarchy, mesh, &camera, &camera);
    // Kept as promised: the same camera again.
    auditor.audit_followed_by(&hierarchy, mesh, &camera, &camera);
    auditor.audit(&hierarchy, mesh, &elsewhere);
}
