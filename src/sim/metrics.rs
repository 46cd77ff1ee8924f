//! The four error metrics of SPEC §4, as plain functions, all in pixels: the audit's projected
//! error and the criteria of Wu et al. 2001 §4.3, Lindstrom et al. 1996 and ROAM'97 eq. 3. They
//! are the reference forms, with no state and no decision: ROAM's hoisted priorities
//! (`roam/priority.rs`) and Lindstrom's squared test (`lindstrom/tolerance.rs`) are tested against
//! them.
//!
//! Each takes a vertical error segment (or ROAM's wedgie) and a camera, and defines its
//! degenerate cases rather than panicking:
//! - **projected** screen-space error: the segment is clipped to the near plane; a segment
//!   entirely behind it does not count (`None`);
//! - **view-angle** error (Wu): the angle the segment subtends at the eye over the pixel angle;
//!   an eye on the segment (including its ends) sees the largest possible angle, π;
//! - **vertical-projection** error (Lindstrom'96): an eye exactly at the vertex gives +∞ (the
//!   vertex must be kept);
//! - **wedgie** bound (ROAM'97 eq. 3): a wedgie reaching behind the near plane gives +∞ (the
//!   maximum priority).
//!
//! Arithmetic is `f64` on eye-relative vectors.

use crate::sim::view::Camera;
use glam::DVec3;

/// Length in pixels of the projection of the vertical segment from `base` to `base + (0,0,δ)`,
/// clipped to the near plane; `None` when it lies entirely behind the near plane.
pub fn projected_error_px(camera: &Camera, base: DVec3, delta: f64) -> Option<f64> {
    projected_error_px_at(camera, camera.to_camera(base), delta)
}

/// [`projected_error_px`] with the segment's base already in camera coordinates
/// ([`Camera::to_camera`]), for callers that have it.
pub fn projected_error_px_at(camera: &Camera, a: DVec3, delta: f64) -> Option<f64> {
    let b = a + camera.direction_to_camera(DVec3::new(0.0, 0.0, delta));
    let near = camera.settings.near;
    let (a, b) = match (a.z >= near, b.z >= near) {
        (true, true) => (a, b),
        (false, false) => return None,
        (a_in, _) => {
            let t = (near - a.z) / (b.z - a.z);
            let cut = a + (b - a) * t;
            if a_in { (a, cut) } else { (cut, b) }
        }
    };
    let pa = camera.project_camera(a)?;
    let pb = camera.project_camera(b)?;
    Some(pa.distance(pb))
}

/// The angle the vertical segment from `base` to `base + (0,0,δ)` subtends at `eye`, divided
/// by `pixel_angle` (fovy/h). An eye on the segment gives π / pixel_angle.
pub fn view_angle_error_px(eye: DVec3, base: DVec3, delta: f64, pixel_angle: f64) -> f64 {
    if delta == 0.0 {
        return 0.0;
    }
    let to_base = base - eye;
    let to_top = to_base + DVec3::new(0.0, 0.0, delta);
    if to_base == DVec3::ZERO || to_top == DVec3::ZERO {
        return std::f64::consts::PI / pixel_angle;
    }
    let angle = to_base.cross(to_top).length().atan2(to_base.dot(to_top));
    angle / pixel_angle
}

/// Lindstrom'96's vertical-projection error λ·δ·√(dx²+dy²)/(dx²+dy²+dz²), λ = (h/2)/tan(fovy/2),
/// with (dx, dy, dz) = vertex − eye. +∞ when the eye is at the vertex.
pub fn vertical_projection_error_px(eye: DVec3, vertex: DVec3, delta: f64, lambda: f64) -> f64 {
    let d = vertex - eye;
    let squared = d.length_squared();
    if squared == 0.0 {
        return if delta == 0.0 { 0.0 } else { f64::INFINITY };
    }
    lambda * delta.abs() * d.truncate().length() / squared
}

/// ROAM'97's wedgie bound (eq. 3) in pixels for a triangle with the given world corners and
/// nested thickness `thickness`: the largest projected length of the thickness segment
/// (−e_T..+e_T along z) over the three corners, using the minimum denominator and the maximum
/// numerator. +∞ when any corner's wedgie reaches behind the near plane.
pub fn wedgie_error_px(camera: &Camera, corners: [DVec3; 3], thickness: f64) -> f64 {
    let e = camera.direction_to_camera(DVec3::new(0.0, 0.0, thickness));
    let (a, b, c) = (e.x, e.y, e.z);
    let mut max_numerator: f64 = 0.0;
    let mut min_denominator = f64::INFINITY;
    for corner in corners {
        let p = camera.to_camera(corner);
        if p.z - c.abs() < camera.settings.near {
            return f64::INFINITY;
        }
        let numerator = ((a * p.z - c * p.x).powi(2) + (b * p.z - c * p.y).powi(2)).sqrt();
        max_numerator = max_numerator.max(numerator);
        min_denominator = min_denominator.min(p.z * p.z - c * c);
    }
    2.0 * max_numerator / min_denominator * camera.settings.pixels_per_unit()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::view::{Pose, ViewSettings};

    fn camera_at(position: DVec3, pitch: f64) -> Camera {
        Camera::new(
            &Pose {
                position,
                yaw: 0.0,
                pitch,
            },
            ViewSettings {
                width_px: 600,
                height_px: 600,
                fovy: 60f64.to_radians(),
                near: 1.0,
                far: 1.0e6,
            },
        )
    }

    #[test]
    fn a_segment_straight_ahead_projects_like_the_pinhole_formula() {
        let camera = camera_at(DVec3::ZERO, 0.0);
        let px = projected_error_px(&camera, DVec3::new(100.0, 0.0, 0.0), 1.0).unwrap();
        let expected = camera.settings.pixels_per_unit() / 100.0;
        assert!((px - expected).abs() < 1e-9, "{px} vs {expected}");
    }

    #[test]
    fn a_segment_behind_the_camera_does_not_count() {
        let camera = camera_at(DVec3::ZERO, 0.0);
        assert_eq!(
            projected_error_px(&camera, DVec3::new(-50.0, 0.0, 0.0), 1.0),
            None
        );
    }

    #[test]
    fn view_angle_does_not_depend_on_view_direction() {
        let eye = DVec3::new(0.0, 0.0, 0.0);
        let pixel_angle = 60f64.to_radians() / 600.0;
        let a = view_angle_error_px(eye, DVec3::new(100.0, 0.0, -0.5), 1.0, pixel_angle);
        let b = view_angle_error_px(eye, DVec3::new(0.0, -100.0, -0.5), 1.0, pixel_angle);
        assert!((a - b).abs() < 1e-12);
        // Seen side-on at distance 100, a 1 m segment subtends 2·atan(0.5/100).
        let expected = 2.0 * (0.005f64).atan() / pixel_angle;
        assert!((a - expected).abs() < 1e-9);
    }

    #[test]
    fn an_eye_on_the_segment_sees_the_largest_angle() {
        let pixel_angle = 0.001;
        let on_end = view_angle_error_px(DVec3::ZERO, DVec3::ZERO, 2.0, pixel_angle);
        let inside = view_angle_error_px(DVec3::new(0.0, 0.0, 1.0), DVec3::ZERO, 2.0, pixel_angle);
        let pi_px = std::f64::consts::PI / pixel_angle;
        assert_eq!(on_end, pi_px);
        assert!((inside - pi_px).abs() < 1e-9);
        assert_eq!(
            view_angle_error_px(DVec3::ZERO, DVec3::ZERO, 0.0, pixel_angle),
            0.0
        );
    }

    #[test]
    fn vertical_projection_vanishes_straight_below_and_is_infinite_at_the_eye() {
        let eye = DVec3::new(0.0, 0.0, 100.0);
        assert_eq!(
            vertical_projection_error_px(eye, DVec3::ZERO, 1.0, 500.0),
            0.0
        );
        assert_eq!(
            vertical_projection_error_px(eye, eye, 1.0, 500.0),
            f64::INFINITY
        );
        let side =
            vertical_projection_error_px(DVec3::ZERO, DVec3::new(100.0, 0.0, 0.0), 1.0, 500.0);
        assert!((side - 5.0).abs() < 1e-12);
    }

    #[test]
    fn the_wedgie_of_a_triangle_ahead_matches_the_projected_thickness() {
        let camera = camera_at(DVec3::ZERO, 0.0);
        let corner = DVec3::new(100.0, 0.0, 0.0);
        let px = wedgie_error_px(&camera, [corner; 3], 0.5);
        let projected =
            projected_error_px(&camera, corner - DVec3::new(0.0, 0.0, 0.5), 1.0).unwrap();
        assert!((px - projected).abs() < 1e-9, "{px} vs {projected}");
        let behind = wedgie_error_px(&camera, [DVec3::new(0.5, 0.0, 0.0); 3], 0.1);
        assert_eq!(behind, f64::INFINITY);
    }
}
