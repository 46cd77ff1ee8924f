//! Wu's view cone: the view frustum approximated by the cone around it (Wu et al. 2001 §7, the
//! paper's simplification), and the cone's signed distance, which every view test of
//! `visibility.rs` (and of `reference.rs` in view) is built on. It is not the frustum test behind
//! the runner's `triangles_rendered` (`view.rs`).
//!
//! The cone's apex is the eye, its axis the view direction, its half-angle the angle from the
//! axis to a frustum corner; it ignores the near and far planes. Conservative: whatever is inside
//! the frustum is inside the cone.

use crate::sim::view::Camera;
use glam::DVec3;

/// The view cone of one frame.
#[derive(Clone, Copy, Debug)]
pub(in crate::sim::algorithm) struct Cone {
    eye: DVec3,
    forward: DVec3,
    sin_half: f64,
    cos_half: f64,
}

impl Cone {
    /// The cone around the camera's frustum (half-angle below π/2 for any finite field of view).
    pub fn new(camera: &Camera) -> Cone {
        let settings = camera.settings;
        let tan_y = (0.5 * settings.fovy).tan();
        let tan_x = tan_y * settings.aspect();
        let half_angle = (tan_x * tan_x + tan_y * tan_y).sqrt().atan();
        let (sin_half, cos_half) = half_angle.sin_cos();
        Cone {
            eye: camera.eye,
            forward: camera.forward,
            sin_half,
            cos_half,
        }
    }

    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// Signed distance from `point` to the cone: negative inside (minus the distance to the
    /// surface), the distance outside. 1-Lipschitz in `point`, which is what lets a bounding
    /// sphere decide for everything in it, and bounds how fast the cone's motion can change it.
    pub fn signed_distance(&self, point: DVec3) -> f64 {
        let v = point - self.eye;
        let along = v.dot(self.forward);
        let across = v.cross(self.forward).length();
        // Distance to the cone's surface (negative inside), valid while the nearest point of the
        // cone is not its apex; behind the apex the apex is nearest.
        if along * self.cos_half + across * self.sin_half >= 0.0 {
            across * self.cos_half - along * self.sin_half
        } else {
            v.length()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::view::{Pose, ViewSettings};

    #[test]
    fn the_signed_distance_is_negative_inside_and_the_euclidean_distance_outside() {
        // A square window with fovy 90°: the cone's half-angle is atan(√2).
        let camera = Camera::new(
            &Pose {
                position: DVec3::ZERO,
                yaw: 0.0,
                pitch: 0.0,
            },
            ViewSettings {
                width_px: 100,
                height_px: 100,
                fovy: 90f64.to_radians(),
                near: 1.0,
                far: 1e6,
            },
        );
        let cone = Cone::new(&camera);
        let half = 2f64.sqrt().atan();
        // On the axis, 10 m ahead: inside, 10·sin(half) from the surface.
        assert!(
            (cone.signed_distance(DVec3::new(10.0, 0.0, 0.0)) + 10.0 * half.sin()).abs() < 1e-12
        );
        // Straight behind: the apex is nearest.
        assert_eq!(cone.signed_distance(DVec3::new(-7.0, 0.0, 0.0)), 7.0);
        // On the surface.
        let on = DVec3::new(half.cos(), half.sin(), 0.0) * 5.0;
        assert!(cone.signed_distance(on).abs() < 1e-12);
        // Beside the surface, 3 m out along its normal.
        let normal = DVec3::new(-half.sin(), half.cos(), 0.0);
        assert!((cone.signed_distance(on + 3.0 * normal) - 3.0).abs() < 1e-12);
    }
}
