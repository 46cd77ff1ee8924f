//! Priorities (ROAM eq. 3 over nested thicknesses), frustum flags (§7.1) and the deferral bound
//! (§7.3).
//!
//! **Priority.** A triangle's priority is [`wedgie_error_px`] over its three corners with the
//! thickness e_T = the `MaxPlusOwn` nested error of its split vertex (0 at the finest level,
//! where it cannot split). e_T = 0 gives 0 whatever the camera: splitting cannot reduce any
//! error. With culling flags on, a triangle whose wedgie is outside the view volume gets 0 too.
//! A diamond's priority is the larger of its parents'. Priorities are monotone: a child's corners
//! are corners of its parent or the midpoint of its hypotenuse, so its smallest depth is at least
//! its parent's and its largest numerator at most its parent's (the numerator is a norm of a
//! linear map of the corner); its thickness is at most its parent's; and the near-plane rule is
//! monotone for the same reasons. An outside parent has outside children.
//!
//! **Flags.** A wedgie (triangle corners ± e_T vertically, six points) is `Outside` when all six
//! points are outside one of the six frustum planes, `Inside` when all are inside all planes,
//! `DontKnow` otherwise. A child's wedgie lies inside its parent's, so `Inside`/`Outside` are
//! inherited without a test.
//!
//! **Deferral bound.** Write a corner in camera coordinates as p = (p, q, r) and the thickness
//! vector as e = (a, b, c) (|e| = e_T). Eq. 3 is P = 2·k·max N_i / min M_i with
//! N_i = |(a·r_i − c·p_i, b·r_i − c·q_i)| and M_i = r_i² − c², k the pixels per unit. N_i is the
//! norm of two components of e × p_i, so it is e_T-Lipschitz in p_i. With the view *orientation
//! unchanged* and the eye moving at most v = √(v_h² + v_v²) metres per frame, after j frames every
//! p_i has moved by at most j·v, so every r_i by at most j·v and every N_i by at most e_T·j·v:
//! - upper bound U(j) = 2k·(max N + e_T·j·v) / ((r_min − j·v)² − c²), and +∞ once
//!   r_min − j·v − |c| < near (the near-plane rule could fire);
//! - lower bound L(j) = 2k·max(0, max N − e_T·j·v) / ((r_min + j·v)² − c²) (the corner that had
//!   the largest N keeps at least max N − e_T·j·v; the corner that had the smallest depth keeps
//!   M at most (r_min + j·v)² − c²); an infinite priority stays infinite while
//!   r_min + j·v − |c| < near.
//!
//! An element with P ≤ τ cannot exceed τ for the j frames with U(j) ≤ τ; one with P > τ cannot
//! fall to τ for the j with L(j) > τ. U grows and L shrinks with j, so the largest safe j is
//! found by a doubling then binary search (capped at [`MAX_DEFERRAL_FRAMES`]). With culling flags
//! on, the flag cannot change before some wedgie point crosses some plane, which needs
//! (its distance to the plane)/v frames; the safe j is capped by that too. The eye speed is all
//! the experiment bounds: eq. 3 depends on the view direction as well, so a frame whose camera
//! orientation differs from the previous frame's revalidates everything (as does a frame that
//! broke the speed bounds).

use super::bintree::{BinTriangle, CullFlag};
use crate::sim::hierarchy::{GridPoint, Lattice};
use crate::sim::metrics::wedgie_error_px;
use crate::sim::terrain::Heightfield;
use crate::sim::view::Camera;
use glam::DVec3;

/// The longest a priority is ever deferred, in frames (bounds the deferral wheel's size).
pub const MAX_DEFERRAL_FRAMES: u64 = 1 << 12;

/// What priority evaluation reads: the camera, the terrain and the nested thicknesses.
pub struct PriorityContext<'a> {
    pub camera: &'a Camera,
    pub field: &'a Heightfield,
    pub lattice: &'a Lattice,
    /// `MaxPlusOwn` nested error per vertex id.
    pub thickness: &'a [f32],
    pub culling_flags: bool,
}

impl PriorityContext<'_> {
    pub fn position(&self, p: GridPoint) -> DVec3 {
        self.field.position(p.i as usize, p.j as usize)
    }

    pub fn corners(&self, triangle: &BinTriangle) -> [DVec3; 3] {
        let t = &triangle.shape;
        [t.apex, t.left, t.right].map(|p| self.position(p))
    }

    /// e_T of a triangle: the nested error of its split vertex (0 at the finest level).
    pub fn thickness_of(&self, triangle: &BinTriangle) -> f64 {
        triangle.split_vertex().map_or(0.0, |mid| {
            f64::from(self.thickness[self.lattice.id(mid) as usize])
        })
    }

    /// The triangle's priority given its flag.
    pub fn priority(&self, triangle: &BinTriangle, flag: CullFlag) -> f64 {
        let thickness = self.thickness_of(triangle);
        if thickness == 0.0 || (self.culling_flags && flag == CullFlag::Outside) {
            return 0.0;
        }
        wedgie_error_px(self.camera, self.corners(triangle), thickness)
    }

    /// The flag of a triangle's wedgie, tested against the six planes.
    pub fn classify(&self, triangle: &BinTriangle) -> CullFlag {
        let thickness = self.thickness_of(triangle);
        let planes = frustum_planes(self.camera);
        let mut all_inside = true;
        let mut outside = [true; 6];
        for corner in self.corners(triangle) {
            for dz in [-thickness, thickness] {
                let c = self.camera.to_camera(corner + DVec3::new(0.0, 0.0, dz));
                for (k, plane) in planes.iter().enumerate() {
                    let inside = plane.signed_distance(c) >= 0.0;
                    all_inside &= inside;
                    outside[k] &= !inside;
                }
            }
        }
        if outside.iter().any(|&o| o) {
            CullFlag::Outside
        } else if all_inside {
            CullFlag::Inside
        } else {
            CullFlag::DontKnow
        }
    }

    /// How many more frames the triangle's priority `value` is guaranteed to stay on its side
    /// of `tau` while the eye moves at most `speed` metres per frame and the orientation stays;
    /// `u64::MAX` when it can never change (zero thickness).
    pub fn safe_frames(&self, triangle: &BinTriangle, value: f64, tau: f64, speed: f64) -> u64 {
        let thickness = self.thickness_of(triangle);
        if thickness == 0.0 {
            // Priority 0 whatever the eye does: never worth recomputing.
            return u64::MAX;
        }
        if speed == 0.0 {
            return MAX_DEFERRAL_FRAMES;
        }
        let camera = self.camera;
        let e = camera.direction_to_camera(DVec3::new(0.0, 0.0, thickness));
        let near = camera.settings.near;
        let corners = self.corners(triangle).map(|p| camera.to_camera(p));
        let max_numerator = corners
            .iter()
            .map(|p| ((e.x * p.z - e.z * p.x).powi(2) + (e.y * p.z - e.z * p.y).powi(2)).sqrt())
            .fold(0.0, f64::max);
        let min_depth = corners.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        let scale = 2.0 * camera.settings.pixels_per_unit();
        let c = e.z.abs();
        let below = value <= tau;
        let holds = |j: u64| -> bool {
            let shift = j as f64 * speed;
            if below {
                let depth = min_depth - shift;
                if depth - c < near {
                    return false;
                }
                scale * (max_numerator + thickness * shift) / (depth * depth - c * c) <= tau
            } else if value.is_infinite() {
                min_depth + shift - c < near
            } else {
                let depth = min_depth + shift;
                let numerator = (max_numerator - thickness * shift).max(0.0);
                scale * numerator / (depth * depth - c * c) > tau
            }
        };
        let mut frames = largest_true(holds);
        if self.culling_flags {
            frames = frames.min(self.frames_until_flag_may_change(triangle, speed));
        }
        frames
    }

    fn frames_until_flag_may_change(&self, triangle: &BinTriangle, speed: f64) -> u64 {
        let thickness = self.thickness_of(triangle);
        let planes = frustum_planes(self.camera);
        let mut distance = f64::INFINITY;
        for corner in self.corners(triangle) {
            for dz in [-thickness, thickness] {
                let c = self.camera.to_camera(corner + DVec3::new(0.0, 0.0, dz));
                for plane in &planes {
                    distance = distance.min(plane.signed_distance(c).abs());
                }
            }
        }
        // A point moves at most j·v; its sign cannot change while j·v < distance.
        let frames = (distance / speed).ceil() - 1.0;
        if frames <= 0.0 {
            0
        } else {
            (frames as u64).min(MAX_DEFERRAL_FRAMES)
        }
    }
}

/// The largest j in 0..=MAX_DEFERRAL_FRAMES with `holds(1..=j)` all true, for a predicate that
/// is true up to some point and false after (0 when `holds(1)` is false).
fn largest_true(holds: impl Fn(u64) -> bool) -> u64 {
    if !holds(1) {
        return 0;
    }
    let mut good = 1;
    let mut bad = 2;
    while bad <= MAX_DEFERRAL_FRAMES && holds(bad) {
        good = bad;
        bad *= 2;
    }
    if bad > MAX_DEFERRAL_FRAMES {
        return MAX_DEFERRAL_FRAMES.max(good).min(MAX_DEFERRAL_FRAMES);
    }
    while bad - good > 1 {
        let middle = good + (bad - good) / 2;
        if holds(middle) {
            good = middle;
        } else {
            bad = middle;
        }
    }
    good
}

/// A frustum plane in camera coordinates: inside when n·p + d ≥ 0, |n| = 1.
#[derive(Clone, Copy, Debug)]
struct Plane {
    normal: DVec3,
    offset: f64,
}

impl Plane {
    fn signed_distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) + self.offset
    }
}

fn frustum_planes(camera: &Camera) -> [Plane; 6] {
    let settings = camera.settings;
    let ty = (0.5 * settings.fovy).tan();
    let tx = ty * settings.aspect();
    let side = |x: f64, y: f64, t: f64| Plane {
        normal: DVec3::new(x, y, t).normalize(),
        offset: 0.0,
    };
    [
        side(-1.0, 0.0, tx),
        side(1.0, 0.0, tx),
        side(0.0, -1.0, ty),
        side(0.0, 1.0, ty),
        Plane {
            normal: DVec3::Z,
            offset: -settings.near,
        },
        Plane {
            normal: -DVec3::Z,
            offset: settings.far,
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_safe_frame_count_is_found_exactly() {
        assert_eq!(largest_true(|j| j <= 37), 37);
        assert_eq!(largest_true(|_| false), 0);
        assert_eq!(largest_true(|_| true), MAX_DEFERRAL_FRAMES);
        assert_eq!(largest_true(|j| j <= 1), 1);
    }
}
