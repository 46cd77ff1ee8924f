//! One error segment's figures (SPEC §7: the vertical distance between a sample and the drawn
//! surface, "converted to projected screen-space pixels and to view-angle pixels from the
//! current eye", the metrics of SPEC §4): [`ErrorGeometry`], the camera's constants of a frame,
//! and [`segment_figures`], everything but the view angle's `atan2`. It holds no state and
//! decides nothing about which samples count (`batch.rs` calls it, and drops what is not seen).
//!
//! Decisions:
//!
//! - **The metrics' operations, in their order.** Each value is computed with exactly the IEEE
//!   operations of [`projected_error_px_at`](crate::sim::metrics::projected_error_px_at) and
//!   [`view_angle_error_px`](crate::sim::metrics::view_angle_error_px), in the same order, so it
//!   is theirs to the bit; even the products by zero of `Camera::direction_to_camera` are kept
//!   (their sign of zero). Rust never fuses a product and a sum, so every compilation gives the
//!   same bits.
//! - **No branch.** The metrics' special cases (a segment of no length, the eye at an end of
//!   it, an end behind the near plane) are computed as values beside the figures, so that the
//!   compiler makes vector instructions of a loop over segments; `x + 0.0 == 0.0` is
//!   `x == 0.0`. Rejected: a reciprocal for `1 / z` (not bit-identical).

use crate::sim::view::Camera;
use glam::DVec3;

/// The camera's constants of one frame's error segments.
pub(super) struct ErrorGeometry {
    /// `Camera::direction_to_camera((0, 0, δ))` is `zero + δ · axis.z` per camera axis: the
    /// sums of its two zero products, which depend on the camera only (their sign of zero).
    zero: DVec3,
    right_z: f64,
    up_z: f64,
    forward_z: f64,
    pub(super) near: f64,
    pixels_per_unit: f64,
    pub(super) pixel_angle: f64,
    /// The view angle of a segment with the eye at an end, in pixels.
    eye_on_segment: f64,
}

impl ErrorGeometry {
    pub(super) fn new(camera: &Camera) -> ErrorGeometry {
        let zero_products = |axis: DVec3| 0.0 * axis.x + 0.0 * axis.y;
        ErrorGeometry {
            zero: DVec3::new(
                zero_products(camera.right),
                zero_products(camera.up),
                zero_products(camera.forward),
            ),
            right_z: camera.right.z,
            up_z: camera.up.z,
            forward_z: camera.forward.z,
            near: camera.settings.near,
            pixels_per_unit: camera.pixels_per_unit(),
            pixel_angle: camera.settings.pixel_angle(),
            eye_on_segment: std::f64::consts::PI / camera.settings.pixel_angle(),
        }
    }
}

/// What one segment's figures need before the view angle's `atan2`.
pub(super) struct SegmentFigures {
    /// Its projected length in pixels, when both ends are in front of the near plane.
    pub(super) projected: f64,
    pub(super) in_front: bool,
    /// The two arguments of the view angle's `atan2`.
    pub(super) sine: f64,
    pub(super) cosine: f64,
    /// The view angle in pixels of a segment of no length (0) or with the eye at an end
    /// (π / pixel angle); −1: none, the angle is `atan2(sine, cosine)` / pixel angle.
    pub(super) special: f64,
}

/// The figures of the vertical segment `delta` long whose base is `a` in camera coordinates
/// and `to_base` from the eye: [`projected_error_px_at`]'s and `view_angle_error_px`'s
/// operations in their order, with no branch (the compiler makes vector instructions of a
/// loop of it).
///
/// [`projected_error_px_at`]: crate::sim::metrics::projected_error_px_at
#[inline(always)]
pub(super) fn segment_figures(
    g: &ErrorGeometry,
    a: DVec3,
    to_base: DVec3,
    delta: f64,
) -> SegmentFigures {
    let (projected, in_front) = projected_segment(g, a, delta);
    // view_angle_error_px: |to_base × to_top| and to_base · to_top.
    let (tx, ty, tz) = (to_base.x, to_base.y, to_base.z);
    let (sx, sy, sz) = (tx + 0.0, ty + 0.0, tz + delta);
    let cx = ty * sz - sy * tz;
    let cy = tz * sx - sz * tx;
    let cz = tx * sy - sx * ty;
    // Its special cases (`x + 0.0 == 0.0` is `x == 0.0`).
    let eye_at_end = (tx == 0.0) & (ty == 0.0) & ((tz == 0.0) | (sz == 0.0));
    let special = if eye_at_end { g.eye_on_segment } else { -1.0 };
    SegmentFigures {
        projected,
        in_front,
        sine: (cx * cx + cy * cy + cz * cz).sqrt(),
        cosine: tx * sx + ty * sy + tz * sz,
        special: if delta == 0.0 { 0.0 } else { special },
    }
}

/// [`projected_error_px_at`] of the vertical segment `delta` long whose base is `a` in camera
/// coordinates, with no branch: its length in pixels and whether both its ends are in front of
/// the near plane (otherwise the length is not the segment's).
///
/// [`projected_error_px_at`]: crate::sim::metrics::projected_error_px_at
#[inline(always)]
pub(super) fn projected_segment(g: &ErrorGeometry, a: DVec3, delta: f64) -> (f64, bool) {
    let (ax, ay, az) = (a.x, a.y, a.z);
    // b = a + direction_to_camera((0, 0, δ)), both projected.
    let bx = ax + (g.zero.x + delta * g.right_z);
    let by = ay + (g.zero.y + delta * g.up_z);
    let bz = az + (g.zero.z + delta * g.forward_z);
    let (pax, pay) = (ax / az * g.pixels_per_unit, ay / az * g.pixels_per_unit);
    let (pbx, pby) = (bx / bz * g.pixels_per_unit, by / bz * g.pixels_per_unit);
    let (dx, dy) = (pax - pbx, pay - pby);
    ((dx * dx + dy * dy).sqrt(), (az >= g.near) & (bz >= g.near))
}

#[cfg(test)]
mod tests {
    use super::{ErrorGeometry, segment_figures};
    use crate::sim::audit::tests::{camera_above, spike_field};
    use crate::sim::metrics::view_angle_error_px;
    use glam::DVec3;

    #[test]
    fn the_batched_view_angle_equals_the_metric_in_its_special_cases_bit_for_bit() {
        let camera = camera_above(&spike_field());
        let g = ErrorGeometry::new(&camera);
        let pixel_angle = camera.settings.pixel_angle();
        // (eye to base, length): no length, the eye at the base or at the top (with zeros of
        // either sign), on the segment's line but off it, and ordinary segments.
        let cases = [
            (DVec3::new(0.0, 0.0, 0.0), 0.0),
            (DVec3::new(3.0, 4.0, -2.0), 0.0),
            (DVec3::new(0.0, 0.0, 0.0), 5.0),
            (DVec3::new(-0.0, 0.0, -0.0), 5.0),
            (DVec3::new(0.0, 0.0, -5.0), 5.0),
            (DVec3::new(-0.0, -0.0, -5.0), 5.0),
            (DVec3::new(0.0, 0.0, -7.0), 5.0),
            (DVec3::new(0.0, 0.0, 2.0), 5.0),
            (DVec3::new(1e-300, 0.0, -5.0), 5.0),
            (DVec3::new(3.0, 4.0, -2.0), 1.5),
            (DVec3::new(-30.0, 400.0, -200.0), 0.25),
        ];
        for (to_base, delta) in cases {
            let f = segment_figures(&g, DVec3::new(1.0, 1.0, 10.0), to_base, delta);
            let ours = if f.special >= 0.0 {
                f.special
            } else {
                f.sine.atan2(f.cosine) / pixel_angle
            };
            // The metric with the eye at the origin: its eye-to-base vector is `to_base`.
            let theirs = view_angle_error_px(DVec3::ZERO, to_base, delta, pixel_angle);
            assert_eq!(ours.to_bits(), theirs.to_bits(), "{to_base:?}, {delta}");
        }
    }
}
