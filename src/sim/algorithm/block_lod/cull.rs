//! Box culling (Lauritsen–Nielsen §3.2.12): a block whose box lies entirely outside the view
//! volume is not drawn, and nothing below it in the quadtree is looked at.
//!
//! The test is the usual conservative one: the box is outside when its eight corners are all
//! beyond one of the six planes of the frustum (near, far, left, right, bottom, top), by a
//! relative margin ([`CULL_MARGIN`]) so that no rounding can cull a box a sample of which the
//! camera sees ([`Camera::sees`], the audit's test): every point of the box is a convex
//! combination of its corners, and the planes are linear. A box that straddles a corner of the
//! frustum may be kept although it is outside (the test is per plane); that costs triangles,
//! never a hole.

use super::threshold::BlockBox;
use crate::sim::view::Camera;
use glam::DVec3;

/// Relative margin by which every corner must clear a plane before the box is culled: far above
/// the rounding of the camera transform (~10⁻¹⁵), far below anything visible.
pub(crate) const CULL_MARGIN: f64 = 1e-9;

/// Whether the box lies entirely outside the camera's view volume.
///
/// The camera's tangents, computed once per camera (a tangent per box was a tenth of the box
/// tests' instructions); each corner's margin scale computed once, not once per plane.
pub(crate) fn box_outside_view(camera: &Camera, block: &BlockBox) -> bool {
    let (tan_x, tan_y) = camera.tan_half_fov();
    let (near, far) = (camera.settings.near, camera.settings.far);
    let mut corners = [DVec3::ZERO; 8];
    let mut margins = [0.0; 8];
    for (k, (corner, margin)) in corners.iter_mut().zip(&mut margins).enumerate() {
        let pick = |bit: usize, low: f64, high: f64| if k & bit == 0 { low } else { high };
        let world = DVec3::new(
            pick(1, block.low.x, block.high.x),
            pick(2, block.low.y, block.high.y),
            pick(4, block.low.z, block.high.z),
        );
        let p = camera.to_camera(world);
        *corner = p;
        *margin = CULL_MARGIN * (p.x.abs() + p.y.abs() + p.z.abs() + near);
    }
    // Each plane as "how far outside" a camera-space point is (positive: outside); the box is
    // outside when every corner is outside one plane by more than its margin.
    fn all_outside(
        corners: &[DVec3; 8],
        margins: &[f64; 8],
        outside: impl Fn(DVec3) -> f64,
    ) -> bool {
        corners
            .iter()
            .zip(margins)
            .all(|(&p, &margin)| outside(p) > margin)
    }
    let (c, m) = (&corners, &margins);
    all_outside(c, m, |p| near - p.z)
        || all_outside(c, m, |p| p.z - far)
        || all_outside(c, m, |p| p.x - p.z * tan_x)
        || all_outside(c, m, |p| -p.x - p.z * tan_x)
        || all_outside(c, m, |p| p.y - p.z * tan_y)
        || all_outside(c, m, |p| -p.y - p.z * tan_y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::view::{Pose, ViewSettings};

    fn camera() -> Camera {
        Camera::new(
            &Pose {
                position: DVec3::ZERO,
                yaw: 0.0,
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

    fn cube(centre: DVec3, half: f64) -> BlockBox {
        BlockBox {
            low: centre - DVec3::splat(half),
            high: centre + DVec3::splat(half),
        }
    }

    #[test]
    fn boxes_ahead_are_kept_and_boxes_behind_beyond_or_aside_are_culled() {
        let camera = camera();
        assert!(!box_outside_view(
            &camera,
            &cube(DVec3::new(50.0, 0.0, 0.0), 5.0)
        ));
        assert!(box_outside_view(
            &camera,
            &cube(DVec3::new(-50.0, 0.0, 0.0), 5.0)
        ));
        assert!(box_outside_view(
            &camera,
            &cube(DVec3::new(2000.0, 0.0, 0.0), 5.0)
        ));
        assert!(box_outside_view(
            &camera,
            &cube(DVec3::new(50.0, 200.0, 0.0), 5.0)
        ));
        // Containing the eye, or straddling the left plane: kept.
        assert!(!box_outside_view(&camera, &cube(DVec3::ZERO, 5.0)));
        assert!(!box_outside_view(
            &camera,
            &cube(DVec3::new(50.0, 30.0, 0.0), 5.0)
        ));
    }

    #[test]
    fn a_box_whose_corner_the_camera_sees_is_never_culled() {
        let camera = camera();
        // A corner exactly on the left plane of the frustum, the rest outside it.
        let tan_x = (0.5 * 60f64.to_radians()).tan();
        let corner = DVec3::new(100.0, 100.0 * tan_x, 0.0);
        assert!(camera.sees(corner));
        let block = BlockBox {
            low: corner,
            high: corner + DVec3::new(10.0, 10.0, 10.0),
        };
        assert!(!box_outside_view(&camera, &block));
    }
}
