//! ROAM's priorities: eq. (3)'s wedgie bound (ROAM'97; SPEC §4) over the nested thicknesses of
//! `thickness.rs`, with everything that depends only on the frame computed once per frame. What
//! is done with a priority (queues, deferral) is the core's.
//!
//! **Priority.** A triangle's priority is eq. (3)'s wedgie bound over its three corners: with
//! (p, q, r) a corner in camera coordinates and (a, b, c) the camera-space image of the thickness
//! vector (0, 0, e_T), 2·k·max √((ar−cp)² + (br−cq)²) / min (r² − c²), k the pixels per unit
//! at distance 1; +∞ when a corner's wedgie reaches behind the near plane (r − |c| < near). The
//! thickness e_T comes from `thickness.rs` (0 at the finest level, where nothing can split: then
//! the priority is 0 whatever the camera). With culling flags on, a triangle labelled `Out` has
//! priority 0 too. A diamond's priority is the larger of its parents'. Priorities are monotone:
//! a child's corners are corners of its parent or the midpoint of its hypotenuse, so its smallest
//! depth is at least its parent's and its largest numerator at most its parent's (the numerator is
//! a norm of a linear map of the corner); its thickness is at most its parent's; the near-plane
//! rule is monotone for the same reasons; and an `Out` parent has `Out` children.
//!
//! **What is computed once per frame** ([`ViewFrame`]): the camera-space image of the world's up
//! direction (so the thickness vector is e_T times it), the pixels per unit (tan(fovy/2), hoisted
//! out of every priority and every frustum test, with bit-identical priorities) and the frustum's
//! planes. The metric is the same as
//! [`crate::sim::metrics::wedgie_error_px`]; a test checks they agree bit for bit.
//!
//! **What is read.** Each triangle carries a copy of its corners and thicknesses
//! ([`super::bintree::Geometry`], filled in when it is created and checked by the validator), so
//! a priority reads one slot of the bintree and nothing else.
//!
//! **For deferral** ([`Wedgie`]) the evaluation also returns the ingredients of eq. (3) that the
//! time-dependent bounds of `deferral.rs` need: the largest numerator, the smallest depth, |c|,
//! the thickness and the largest distance from the eye to a corner.

use super::bintree::BinTriangle;
use super::cull::Frustum;
use crate::sim::view::Camera;
use glam::DVec3;

/// What every priority of one frame shares.
#[derive(Clone, Copy, Debug)]
pub struct ViewFrame {
    pub camera: Camera,
    pub frustum: Frustum,
    /// The camera-space image of the world's unit up vector.
    up_in_camera: DVec3,
    /// (h/2)/tan(fovy/2).
    pixels_per_unit: f64,
}

impl ViewFrame {
    pub fn new(camera: &Camera) -> ViewFrame {
        ViewFrame {
            camera: *camera,
            frustum: Frustum::new(camera),
            up_in_camera: camera.direction_to_camera(DVec3::Z),
            pixels_per_unit: camera.settings.pixels_per_unit(),
        }
    }

    /// 2·k: the factor of eq. (3) in pixels.
    pub fn scale(&self) -> f64 {
        2.0 * self.pixels_per_unit
    }

    pub fn near(&self) -> f64 {
        self.camera.settings.near
    }
}

/// Eq. (3) for one triangle, with what deferral needs to bound it over the next frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wedgie {
    /// The priority in pixels (0 when culled or of zero thickness, +∞ behind the near plane).
    pub value: f64,
    /// True when the value cannot change while the triangle's flags stay: culled, or zero
    /// thickness.
    pub constant: bool,
    /// e_T.
    pub thickness: f64,
    /// The largest √((ar−cp)² + (br−cq)²) over the corners.
    pub max_numerator: f64,
    /// The smallest depth r over the corners.
    pub min_depth: f64,
    /// |c|.
    pub c_abs: f64,
    /// The largest distance from the eye to a corner (only with `with_distance`).
    pub max_distance: f64,
}

/// What priority evaluation reads besides the triangle: the frame and whether culling flags
/// count.
pub struct PriorityContext<'a> {
    pub view: &'a ViewFrame,
    pub culling_flags: bool,
}

impl PriorityContext<'_> {
    /// The triangle's corners in world (terrain-local) coordinates.
    #[cfg(test)]
    pub fn corners(&self, triangle: &BinTriangle) -> [DVec3; 3] {
        triangle.geometry.corners
    }

    /// e_T of a triangle for its priority (0 at the finest level).
    pub fn thickness_of(&self, triangle: &BinTriangle) -> f64 {
        f64::from(triangle.geometry.thickness)
    }

    /// The triangle's priority under its current flags.
    pub fn priority(&self, triangle: &BinTriangle) -> f64 {
        self.evaluate::<false>(triangle).value
    }

    /// The priority and the ingredients of its deferral bounds.
    pub fn measure(&self, triangle: &BinTriangle) -> Wedgie {
        self.evaluate::<true>(triangle)
    }

    /// Eq. (3) from the triangle's own copy of its corners and thickness. Minima and maxima are
    /// plain comparisons (the values are never NaN).
    fn evaluate<const WITH_DISTANCE: bool>(&self, triangle: &BinTriangle) -> Wedgie {
        let thickness = self.thickness_of(triangle);
        if thickness == 0.0 || (self.culling_flags && triangle.flags.is_out()) {
            return Wedgie {
                value: 0.0,
                constant: true,
                thickness,
                max_numerator: 0.0,
                min_depth: f64::INFINITY,
                c_abs: 0.0,
                max_distance: 0.0,
            };
        }
        let camera = &self.view.camera;
        let e = self.view.up_in_camera * thickness;
        let (a, b, c) = (e.x, e.y, e.z);
        let c_abs = c.abs();
        let near = self.view.near();
        // The largest squared numerator: √ is monotone, so one square root of the largest gives
        // exactly the largest of the square roots.
        let mut max_numerator_squared: f64 = 0.0;
        let mut min_denominator = f64::INFINITY;
        let mut min_depth = f64::INFINITY;
        let mut max_distance: f64 = 0.0;
        let mut behind = false;
        for corner in triangle.geometry.corners {
            let p = camera.to_camera(corner);
            if WITH_DISTANCE {
                let distance = p.length();
                if distance > max_distance {
                    max_distance = distance;
                }
            }
            if p.z < min_depth {
                min_depth = p.z;
            }
            if p.z - c_abs < near {
                behind = true;
                if !WITH_DISTANCE {
                    break;
                }
                continue;
            }
            let u = a * p.z - c * p.x;
            let v = b * p.z - c * p.y;
            let numerator_squared = u * u + v * v;
            if numerator_squared > max_numerator_squared {
                max_numerator_squared = numerator_squared;
            }
            let denominator = p.z * p.z - c * c;
            if denominator < min_denominator {
                min_denominator = denominator;
            }
        }
        let max_numerator = max_numerator_squared.sqrt();
        let value = if behind {
            f64::INFINITY
        } else {
            2.0 * max_numerator / min_denominator * self.view.pixels_per_unit
        };
        Wedgie {
            value,
            constant: false,
            thickness,
            max_numerator,
            min_depth,
            c_abs,
            max_distance,
        }
    }
}
