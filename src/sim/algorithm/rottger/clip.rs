//! Frustum clipping of quadtree blocks (§2.4): a block's box against the view frustum.
//!
//! A block's box is its footprint × its samples' height range (the shared hierarchy's O(1)
//! range). Mesh generation tests the box **three times as large** (every extent tripled about
//! the box's centre, so the footprint covers the block's eight neighbours), as the paper says,
//! because a neighbour's blend and subdivision shape the fans of visible blocks; counting the
//! fans drawn tests the plain box. The test is conservative: a box is rejected only when all
//! eight of its corners lie outside one of the frustum's six planes.

use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::view::Camera;
use glam::DVec3;

/// How much larger than the block the box tested during mesh generation is (the paper's 3).
pub const GENERATION_BOX_SCALE: f64 = 3.0;

/// The box of the block centred at `centre` (half-size `half`), every extent multiplied by
/// `scale` about the box's centre: (lowest corner, highest corner).
pub fn block_box(
    hierarchy: &Hierarchy,
    centre: GridPoint,
    half: u32,
    scale: f64,
) -> (DVec3, DVec3) {
    let spacing = hierarchy.field().spacing();
    let (z_min, z_max) = hierarchy.node_height_range(centre, half);
    let (z_min, z_max) = (f64::from(z_min), f64::from(z_max));
    let middle = DVec3::new(
        f64::from(centre.i) * spacing.dx,
        f64::from(centre.j) * spacing.dy,
        0.5 * (z_min + z_max),
    );
    let half_extent = DVec3::new(
        f64::from(half) * spacing.dx,
        f64::from(half) * spacing.dy,
        0.5 * (z_max - z_min),
    ) * scale;
    (middle - half_extent, middle + half_extent)
}

/// Whether the box [low, high] may meet the view frustum: `false` only when all eight corners
/// are outside one plane.
pub fn box_may_be_seen(camera: &Camera, low: DVec3, high: DVec3) -> bool {
    let settings = camera.settings;
    let tan_y = (0.5 * settings.fovy).tan();
    let tan_x = tan_y * settings.aspect();
    let mut outside = [true; 6];
    for k in 0..8 {
        let corner = DVec3::new(
            if k & 1 == 0 { low.x } else { high.x },
            if k & 2 == 0 { low.y } else { high.y },
            if k & 4 == 0 { low.z } else { high.z },
        );
        let c = camera.to_camera(corner);
        let tests = [
            c.z < settings.near,
            c.z > settings.far,
            c.x > c.z * tan_x,
            -c.x > c.z * tan_x,
            c.y > c.z * tan_y,
            -c.y > c.z * tan_y,
        ];
        for (all_outside, out) in outside.iter_mut().zip(tests) {
            *all_outside &= out;
        }
    }
    !outside.iter().any(|&o| o)
}

/// Whether mesh generation may subdivide the block: its box, three times as large, may be seen.
pub fn generation_may_see(
    hierarchy: &Hierarchy,
    camera: &Camera,
    centre: GridPoint,
    half: u32,
) -> bool {
    let (low, high) = block_box(hierarchy, centre, half, GENERATION_BOX_SCALE);
    box_may_be_seen(camera, low, high)
}

/// Whether the block's fan is drawn: its own box may be seen.
pub fn fan_may_be_seen(
    hierarchy: &Hierarchy,
    camera: &Camera,
    centre: GridPoint,
    half: u32,
) -> bool {
    let (low, high) = block_box(hierarchy, centre, half, 1.0);
    box_may_be_seen(camera, low, high)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::view::{Pose, ViewSettings};

    fn camera(position: DVec3, yaw: f64) -> Camera {
        Camera::new(
            &Pose {
                position,
                yaw,
                pitch: 0.0,
            },
            ViewSettings {
                width_px: 600,
                height_px: 600,
                fovy: 60f64.to_radians(),
                near: 1.0,
                far: 1000.0,
            },
        )
    }

    #[test]
    fn a_box_ahead_is_seen_and_a_box_behind_or_beyond_far_is_not() {
        let looking_east = camera(DVec3::ZERO, 0.0);
        let unit = DVec3::splat(1.0);
        assert!(box_may_be_seen(
            &looking_east,
            DVec3::new(10.0, -1.0, -1.0),
            DVec3::new(12.0, 1.0, 1.0)
        ));
        assert!(!box_may_be_seen(
            &looking_east,
            DVec3::new(-12.0, -1.0, -1.0),
            DVec3::new(-10.0, 1.0, 1.0)
        ));
        assert!(!box_may_be_seen(
            &looking_east,
            DVec3::new(2000.0, 0.0, 0.0),
            DVec3::new(2000.0, 0.0, 0.0) + unit
        ));
        // Far to the side: outside the left plane.
        assert!(!box_may_be_seen(
            &looking_east,
            DVec3::new(10.0, 100.0, -1.0),
            DVec3::new(12.0, 102.0, 1.0)
        ));
        // A box around the eye is seen.
        assert!(box_may_be_seen(&looking_east, -unit, unit));
    }

    #[test]
    fn the_generation_box_is_three_times_the_block_about_its_centre() {
        let heights = (0..25).map(|k| (k % 5) as f32).collect();
        let field = crate::sim::terrain::Heightfield::new(
            5,
            heights,
            crate::sim::terrain::Spacing { dx: 10.0, dy: 20.0 },
        )
        .unwrap();
        let hierarchy = Hierarchy::new(field);
        let (low, high) = block_box(&hierarchy, GridPoint::new(2, 2), 2, 1.0);
        assert_eq!(
            (low, high),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(40.0, 80.0, 4.0))
        );
        let (low, high) = block_box(&hierarchy, GridPoint::new(2, 2), 2, GENERATION_BOX_SCALE);
        assert_eq!(
            (low, high),
            (DVec3::new(-40.0, -80.0, -4.0), DVec3::new(80.0, 160.0, 8.0))
        );
    }
}
