//! The mesh validator on exhaustive small cases: the reference algorithm from every eye position
//! on a grid over 9×9 and 17×17 terrains (below, just above and 100 km above the terrain, at three tolerances) always produces
//! a closed mesh whose own triangle count equals 2 + Σ parents and the enumerated count.

mod common;

use common::algorithms::reference;
use common::{bumpy_terrain, camera_at, checked_step, step, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::Reference;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::zone::{SpeedBound, ZoneVariant};

const SPEED: SpeedBound = SpeedBound {
    horizontal: 5.0,
    vertical: 2.5,
};

/// Runs the reference from every eye position on the grid (one frame each, in sequence, so the
/// inserted/deleted bookkeeping is exercised too) and validates every mesh. Returns the smallest
/// and largest triangle counts seen.
fn check_every_eye(hierarchy: &Hierarchy, tau_px: f64, zone: ZoneVariant) -> (u64, u64) {
    let config = reference(tau_px, zone);
    let mut reference = Reference::new(hierarchy, config, &view_600(), SPEED);
    let field = hierarchy.field();
    let (min_z, max_z) = field.height_range();
    let mut counts = (u64::MAX, 0);
    for frame_j in 0..field.side() {
        for frame_i in 0..field.side() {
            for z in [f64::from(min_z) - 5.0, f64::from(max_z) + 1.0, 100_000.0] {
                let eye = DVec3::new(frame_i as f64 * 10.0, frame_j as f64 * 10.0, z);
                let context = format!("eye {eye:?}, τ = {tau_px}");
                let stats = checked_step(
                    hierarchy,
                    &mut reference,
                    0,
                    &camera_at(eye),
                    false,
                    context,
                );
                counts = (counts.0.min(stats.triangles), counts.1.max(stats.triangles));
            }
        }
    }
    counts
}

#[test]
fn every_eye_over_9_by_9_gives_a_valid_mesh() {
    let hierarchy = bumpy_terrain(3);
    for tau_px in [0.5, 4.0, 50.0] {
        for zone in [ZoneVariant::Conservative, ZoneVariant::Paper] {
            let (fewest, most) = check_every_eye(&hierarchy, tau_px, zone);
            assert!(fewest >= 2 && most <= 128, "{fewest}..{most}");
        }
    }
}

#[test]
fn every_eye_over_17_by_17_gives_a_valid_mesh_that_refines_near_the_eye() {
    let hierarchy = bumpy_terrain(4);
    let (fewest, most) = check_every_eye(&hierarchy, 1.0, ZoneVariant::Conservative);
    // Far eyes (100 km up) see a coarse mesh, eyes on the terrain the full one.
    assert!(fewest < most, "{fewest}..{most}");
    assert_eq!(most, 2 * 16 * 16);
}

#[test]
fn tau_zero_refines_every_node_with_an_error() {
    let hierarchy = bumpy_terrain(4);
    let config = reference(0.0, ZoneVariant::Conservative);
    let mut reference = Reference::new(&hierarchy, config, &view_600(), SPEED);
    let camera = camera_at(DVec3::new(-5000.0, -5000.0, 5000.0));
    let stats = step(&mut reference, 0, &camera, false);
    assert_eq!(stats.triangles, 2 * 16 * 16);
}
