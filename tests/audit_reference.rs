//! The optimised audit (SPEC §7) against its differential reference (`sim::audit::reference`, the
//! audit as first written): every figure — error maxima, means and p95s, holes, cracks, skirts,
//! popping — equal to the last bit, for 4-8 meshes and triangle lists (skirts, degenerate and
//! collapsed triangles), at several strides, with and without popping, from eyes inside and outside
//! the terrain, looking along it, straight down, and away from it, with near and far planes that
//! cut it, on a terrain whose side is not a multiple of the tile; and so are the auditor told each
//! frame the next frame's camera (as a run is) and the auditor kept to the baseline instruction set
//! (`Auditor::without_wide_vectors`).

mod common;

use common::algorithms::{chunked_with_everything, geomipmap, reference, vanek};
use common::{bumpy_terrain, step};
use glam::DVec3;
use roamsim::sim::algorithm::{AlgorithmConfig, LodAlgorithm};
use roamsim::sim::audit::reference::ReferenceAuditor;
use roamsim::sim::audit::{AuditSettings, Auditor};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::view::{Camera, Pose, ViewSettings};
use roamsim::sim::zone::{SpeedBound, ZoneVariant};

const SPEED: SpeedBound = SpeedBound {
    horizontal: 1e6,
    vertical: 1e6,
    rotation: SpeedBound::NO_ROTATION_BOUND,
};

/// Views of a 10 m-post terrain `extent` metres wide: eye, yaw, pitch, near, far.
fn views(extent: f64) -> Vec<(DVec3, f64, f64, f64, f64)> {
    let middle = extent / 2.0;
    vec![
        (DVec3::new(-50.0, middle, 60.0), 0.0, -0.3, 1.0, 1e5),
        (DVec3::new(middle, middle, 150.0), 0.7, -1.55, 1.0, 1e5),
        (
            DVec3::new(middle * 0.3, middle * 1.2, 25.0),
            2.2,
            -0.05,
            5.0,
            extent * 0.4,
        ),
        (DVec3::new(-400.0, -300.0, 500.0), 0.6, -0.6, 200.0, 1e5),
        // Looking away: nothing in view.
        (
            DVec3::new(-100.0, middle, 50.0),
            std::f64::consts::PI,
            0.0,
            1.0,
            1e5,
        ),
        (
            DVec3::new(extent + 20.0, extent * 0.8, 5.0),
            3.5,
            0.2,
            1.0,
            1e5,
        ),
    ]
}

fn camera(view: (DVec3, f64, f64, f64, f64), width_px: u32) -> Camera {
    let (position, yaw, pitch, near, far) = view;
    Camera::new(
        &Pose {
            position,
            yaw,
            pitch,
        },
        ViewSettings {
            width_px,
            height_px: 600,
            fovy: 60f64.to_radians(),
            near,
            far,
        },
    )
}

/// Audits every view's mesh of `config` with both auditors and compares every figure bit for
/// bit (through `Debug`, which prints each `f64` exactly, NaN included).
fn compare(hierarchy: &Hierarchy, config: AlgorithmConfig, extent: f64) {
    for stride in [1, 3, 16] {
        for popping in [false, true] {
            let settings = AuditSettings {
                stride,
                popping,
                detail_stride: None,
            };
            let mut optimised = Auditor::new(hierarchy, settings);
            // Told each frame the next frame's camera, as a run is.
            let mut told_next = Auditor::new(hierarchy, settings);
            // The lattice path compiled for the baseline instruction set (the others use
            // 256-bit vectors where the CPU has them).
            let mut portable = Auditor::new(hierarchy, settings).without_wide_vectors();
            let mut reference = ReferenceAuditor::new(hierarchy, settings);
            let mut algorithm: Box<dyn LodAlgorithm + '_> =
                config.build(hierarchy, &common::view_600(), SPEED);
            let cameras: Vec<Camera> = (views(extent).into_iter().enumerate())
                .map(|(frame, view)| camera(view, if frame % 2 == 0 { 600 } else { 900 }))
                .collect();
            for (frame, camera) in cameras.iter().enumerate() {
                step(algorithm.as_mut(), frame as u64, camera, true);
                let a = optimised.audit(hierarchy, algorithm.mesh(), camera);
                let b = reference.audit(hierarchy, algorithm.mesh(), camera);
                let c = match cameras.get(frame + 1) {
                    Some(next) => {
                        told_next.audit_followed_by(hierarchy, algorithm.mesh(), camera, next)
                    }
                    None => told_next.audit(hierarchy, algorithm.mesh(), camera),
                };
                let d = portable.audit(hierarchy, algorithm.mesh(), camera);
                let context =
                    format!("{config:?}, stride {stride}, popping {popping}, view {frame}");
                assert_eq!(format!("{a:?}"), format!("{b:?}"), "{context}");
                assert_eq!(format!("{d:?}"), format!("{b:?}"), "{context}, portable");
                assert_eq!(
                    format!("{c:?}"),
                    format!("{b:?}"),
                    "{context}, next camera told"
                );
            }
        }
    }
}

#[test]
fn the_audit_of_4_8_meshes_equals_its_reference_bit_for_bit() {
    // 129² samples: 129 is not a multiple of the 16-sample tile at any stride tested.
    let hierarchy = bumpy_terrain(7);
    compare(
        &hierarchy,
        AlgorithmConfig::Reference(reference(1.5, ZoneVariant::Conservative)),
        1280.0,
    );
}

#[test]
fn the_audit_of_triangle_lists_equals_its_reference_bit_for_bit() {
    let hierarchy = bumpy_terrain(7);
    for config in [
        AlgorithmConfig::Geomipmap(geomipmap(1.0, 3)),
        AlgorithmConfig::Chunked(chunked_with_everything(2.0, 3)),
        AlgorithmConfig::Vanek(vanek(3, 50.0, 900.0)),
    ] {
        compare(&hierarchy, config, 1280.0);
    }
}

#[test]
fn every_view_of_the_tests_sees_something_but_one() {
    // The comparisons above would pass vacuously if no sample were in view.
    let hierarchy = bumpy_terrain(7);
    let mut algorithm = AlgorithmConfig::Reference(reference(1.5, ZoneVariant::Conservative))
        .build(&hierarchy, &common::view_600(), SPEED);
    let mut auditor = Auditor::new(
        &hierarchy,
        AuditSettings {
            stride: 1,
            popping: false,
            detail_stride: None,
        },
    );
    let mut in_view = Vec::new();
    for (frame, view) in views(1280.0).into_iter().enumerate() {
        let camera = camera(view, 600);
        step(algorithm.as_mut(), frame as u64, &camera, true);
        in_view.push(
            auditor
                .audit(&hierarchy, algorithm.mesh(), &camera)
                .samples_in_view,
        );
    }
    assert_eq!(
        in_view.iter().filter(|&&n| n == 0).count(),
        1,
        "{in_view:?}"
    );
    assert!(
        in_view.iter().filter(|&&n| n > 1000).count() >= 3,
        "{in_view:?}"
    );
}
