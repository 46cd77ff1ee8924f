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

/// The view frustum of one frame, as six planes around the eye, for testing many boxes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewFrustum {
    eye: DVec3,
    /// Outward normals of the four side planes through the eye: a point q (relative to the
    /// eye) is outside a side when n·q > 0.
    sides: [DVec3; 4],
    forward: DVec3,
    near: f64,
    far: f64,
}

impl ViewFrustum {
    pub fn new(camera: &Camera) -> ViewFrustum {
        let settings = camera.settings;
        let tan_y = (0.5 * settings.fovy).tan();
        let tan_x = tan_y * settings.aspect();
        let f = camera.forward;
        ViewFrustum {
            eye: camera.eye,
            sides: [
                camera.right - f * tan_x,
                -camera.right - f * tan_x,
                camera.up - f * tan_y,
                -camera.up - f * tan_y,
            ],
            forward: f,
            near: settings.near,
            far: settings.far,
        }
    }

    /// Whether the box [low, high] may meet the frustum: `false` only when the whole box (all
    /// eight corners) is outside one plane. O(1): per plane, only the corner nearest to the
    /// inside is tested.
    pub fn may_see_box(&self, low: DVec3, high: DVec3) -> bool {
        let (low, high) = (low - self.eye, high - self.eye);
        // The smallest and largest n·q over the box.
        let least = |n: DVec3| {
            let pick = |k: usize| if n[k] > 0.0 { low[k] } else { high[k] };
            n.x * pick(0) + n.y * pick(1) + n.z * pick(2)
        };
        let most = |n: DVec3| -least(-n);
        !(self.sides.iter().any(|&n| least(n) > 0.0)
            || most(self.forward) < self.near
            || least(self.forward) > self.far)
    }
}

/// Whether the box [low, high] may meet the camera's view frustum (see
/// [`ViewFrustum::may_see_box`]).
pub fn box_may_be_seen(camera: &Camera, low: DVec3, high: DVec3) -> bool {
    ViewFrustum::new(camera).may_see_box(low, high)
}

/// Whether mesh generation may subdivide the block: its box, three times as large, may be seen.
pub fn generation_may_see(
    hierarchy: &Hierarchy,
    frustum: &ViewFrustum,
    centre: GridPoint,
    half: u32,
) -> bool {
    let (low, high) = block_box(hierarchy, centre, half, GENERATION_BOX_SCALE);
    frustum.may_see_box(low, high)
}

/// Whether the block's fan is drawn: its own box may be seen.
pub fn fan_may_be_seen(
    hierarchy: &Hierarchy,
    frustum: &ViewFrustum,
    centre: GridPoint,
    half: u32,
) -> bool {
    let (low, high) = block_box(hierarchy, centre, half, 1.0);
    frustum.may_see_box(low, high)
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

    /// The eight-corner test the plane-by-plane one must agree with.
    fn all_corners_outside_one_plane(camera: &Camera, low: DVec3, high: DVec3) -> bool {
        let settings = camera.settings;
        let tan_y = (0.5 * settings.fovy).tan();
        let tan_x = tan_y * settings.aspect();
        let corners: Vec<DVec3> = (0..8)
            .map(|k| {
                let pick = |bit: usize, a: f64, b: f64| if k & bit == 0 { a } else { b };
                camera.to_camera(DVec3::new(
                    pick(1, low.x, high.x),
                    pick(2, low.y, high.y),
                    pick(4, low.z, high.z),
                ))
            })
            .collect();
        let all = |outside: &dyn Fn(DVec3) -> bool| corners.iter().all(|&c| outside(c));
        all(&|c| c.z < settings.near)
            || all(&|c| c.z > settings.far)
            || all(&|c| c.x > c.z * tan_x)
            || all(&|c| -c.x > c.z * tan_x)
            || all(&|c| c.y > c.z * tan_y)
            || all(&|c| -c.y > c.z * tan_y)
    }

    #[test]
    fn the_plane_test_agrees_with_testing_all_eight_corners() {
        let mut disagreements = 0;
        let mut outside = 0;
        for k in 0..4000u32 {
            let r = |salt: u32| {
                let x = (k.wrapping_mul(2_654_435_761) ^ salt.wrapping_mul(40_503)) % 10_007;
                f64::from(x) / 10_007.0
            };
            let eye = DVec3::new(r(1) * 200.0 - 100.0, r(2) * 200.0 - 100.0, r(3) * 60.0);
            let camera = Camera::new(
                &Pose {
                    position: eye,
                    yaw: r(4) * 6.3,
                    pitch: r(5) * 3.0 - 1.5,
                },
                ViewSettings {
                    width_px: 800,
                    height_px: 500,
                    fovy: 0.2 + r(6) * 2.5,
                    near: 0.5,
                    far: 150.0,
                },
            );
            let low = DVec3::new(
                r(7) * 200.0 - 100.0,
                r(8) * 200.0 - 100.0,
                r(9) * 40.0 - 20.0,
            );
            let high = low + DVec3::new(r(10) * 50.0, r(11) * 50.0, r(12) * 30.0);
            let expected = !all_corners_outside_one_plane(&camera, low, high);
            outside += usize::from(!expected);
            disagreements += usize::from(box_may_be_seen(&camera, low, high) != expected);
        }
        assert_eq!(disagreements, 0);
        assert!(outside > 1000, "{outside}");
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
