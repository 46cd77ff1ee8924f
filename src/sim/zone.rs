//! Wu's split zones and the signed valid life of a node (Wu et al. 2001 §4.3 and §5, as SPEC §5
//! fixes them), shared by `wu` and `reference`, and the motion bounds they assume
//! ([`SpeedBound`]). Pure functions of a node and an eye: no queues, no state between frames.
//!
//! A vertical error segment of length δ subtends more than θ = τ·fovy/h (Wu's small-angle form)
//! only from inside two circles of radius r = δ/(2·sin θ) through its ends (a horn torus in 3D).
//! Wu replaces that zone by an axis-aligned box, 4r × 4r wide and 2r high, centred on the
//! segment. Two variants:
//! - [`ZoneVariant::Paper`]: the box centred on the node's centre vertex, as published;
//! - [`ZoneVariant::Conservative`]: the box grown by the block's footprint and height range (a
//!   Minkowski sum: the footprint × the sample height range, grown by 2r across and r up and
//!   down). Every vertex error the node's δ covers is a vertical segment inside that footprint and
//!   height range, so wherever it sits in the block it is really below τ from outside the zone.
//!
//! The zone is sized by [`NodeErrors`]: Wu's δ as preprocessing stores it (the max rule, nothing
//! more in memory), or, for the `max_plus_own` nesting, the centre vertex's max-plus-own nested
//! error (4 bytes per sample), which bounds the boundary vertices and sub-blocks too and nests
//! like δ.
//!
//! θ is clamped to π/2 before taking the sine: for larger angles the exact zone only shrinks, so
//! r = δ/2 stays conservative and τ never produces a negative or infinite radius by wrap-around.
//! θ = 0 (τ = 0) gives an infinite zone; δ = 0 gives no zone at all (the node never needs to
//! split).
//!
//! The signed life ℓ = max over axes of (gap along the axis)/(speed bound along it), where the
//! gap is the eye's distance beyond the box face (negative inside). Under the speed bound ℓ
//! changes by at most 1 per frame. A zero speed bound makes an axis's life +∞ outside the box and
//! −∞ on or inside it. ℓ equals the paper's `ValidLife()` when v_v = v_h/2 and the box is
//! 4r × 4r × 2r, and it is monotone under box inclusion (a larger box never gives a longer life).
//!
//! [`SpeedBound`] is what the experiment declares: metres per frame horizontally and vertically,
//! and the angle the look direction may turn in a frame. An experiment that declares no rotation
//! bound gets π, which every turn honours, so such files run unchanged: Wu's view keys then defer
//! little, and ROAM's deferral reads π as no rotation bound.

use crate::sim::hierarchy::{GridPoint, Hierarchy, NestingRule};
use glam::DVec3;

/// Which box approximates the split zone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZoneVariant {
    Paper,
    Conservative,
}

impl ZoneVariant {
    pub fn name(self) -> &'static str {
        match self {
            ZoneVariant::Paper => "paper",
            ZoneVariant::Conservative => "conservative",
        }
    }
}

/// The motion bounds an experiment declares: how far the eye may move and how fast the look
/// direction may turn between consecutive frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedBound {
    /// Bound on the horizontal (xy) displacement per frame, metres.
    pub horizontal: f64,
    /// Bound on the vertical displacement per frame, metres.
    pub vertical: f64,
    /// Bound on the angle between consecutive look directions, radians per frame. π bounds
    /// nothing (two directions are never further apart); an experiment that declares no rotation
    /// bound gets its flight's largest turn instead (`edge::experiment`'s load).
    pub rotation: f64,
}

impl SpeedBound {
    /// A rotation bound that bounds nothing: π, which every turn honours (for callers that know
    /// no flight, such as tests; experiments never get it by default).
    pub const NO_ROTATION_BOUND: f64 = std::f64::consts::PI;

    /// The longest the eye may move in one frame (the length of the displacement vector).
    pub fn eye_step(&self) -> f64 {
        self.horizontal.hypot(self.vertical)
    }
}

/// An axis-aligned box: centre and half-extents (half-extents may be +∞).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZoneBox {
    pub centre: DVec3,
    pub half: DVec3,
}

impl ZoneBox {
    /// Signed gaps of `eye` beyond the box along x, y, z (≤ 0 inside).
    pub fn gaps(&self, eye: DVec3) -> DVec3 {
        (eye - self.centre).abs() - self.half
    }

    /// Whether `eye` is inside or on the box.
    pub fn contains(&self, eye: DVec3) -> bool {
        self.gaps(eye).max_element() <= 0.0
    }
}

/// The zone radius r = δ / (2 sin θ) with θ clamped to π/2; +∞ when θ = 0 and δ > 0.
pub fn zone_radius(delta: f64, theta: f64) -> f64 {
    let theta = theta.min(std::f64::consts::FRAC_PI_2);
    if theta <= 0.0 {
        return if delta > 0.0 { f64::INFINITY } else { 0.0 };
    }
    delta / (2.0 * theta.sin())
}

/// r per metre of error for the angular tolerance `theta`: 1/(2 sin θ) with θ clamped to π/2,
/// +∞ for θ = 0. Computed once per run, not per node.
pub fn radius_per_error(theta: f64) -> f64 {
    zone_radius(1.0, theta)
}

/// The node error δ that sizes a split zone, under a nesting rule.
#[derive(Clone, Debug)]
pub enum NodeErrors {
    /// Wu's rule, δ as preprocessing stores it (max of sub-blocks', centre's and boundary
    /// vertices' errors): nothing extra in memory.
    Stored,
    /// ROAM's max-plus-own nested error of the node's centre vertex, per vertex id (4 bytes per
    /// sample). The boundary vertices are the centre's children in the 4-8 hierarchy, so it bounds
    /// them and every sub-block, and nests like Wu's δ.
    CentreMaxPlusOwn(Vec<f32>),
}

impl NodeErrors {
    /// The errors under `rule`: [`NestingRule::Max`] is Wu's own.
    pub fn new(hierarchy: &Hierarchy, rule: NestingRule) -> NodeErrors {
        match rule {
            NestingRule::Max => NodeErrors::Stored,
            NestingRule::MaxPlusOwn => NodeErrors::CentreMaxPlusOwn(
                hierarchy.nested_vertex_errors(NestingRule::MaxPlusOwn),
            ),
        }
    }

    /// δ of the square node at `node` with half-size `half`.
    pub fn error(&self, hierarchy: &Hierarchy, node: GridPoint, half: u32) -> f32 {
        match self {
            NodeErrors::Stored => hierarchy.node_error(node, half),
            NodeErrors::CentreMaxPlusOwn(nested) => nested[hierarchy.lattice().id(node) as usize],
        }
    }

    /// δ and the block's sample height range (z_min, z_max).
    pub fn error_and_range(
        &self,
        hierarchy: &Hierarchy,
        node: GridPoint,
        half: u32,
    ) -> (f32, f32, f32) {
        let (delta, z_min, z_max) = hierarchy.node_error_and_range(node, half);
        match self {
            NodeErrors::Stored => (delta, z_min, z_max),
            NodeErrors::CentreMaxPlusOwn(nested) => {
                (nested[hierarchy.lattice().id(node) as usize], z_min, z_max)
            }
        }
    }

    pub fn memory_bytes(&self) -> usize {
        match self {
            NodeErrors::Stored => 0,
            NodeErrors::CentreMaxPlusOwn(nested) => nested.capacity() * std::mem::size_of::<f32>(),
        }
    }
}

/// The split zone of the square node at `node` (half-size `half`) for the angular tolerance
/// `theta`, or `None` when its error δ is 0.
pub fn split_zone(
    hierarchy: &Hierarchy,
    errors: &NodeErrors,
    node: GridPoint,
    half: u32,
    theta: f64,
    variant: ZoneVariant,
) -> Option<ZoneBox> {
    split_zone_scaled(
        hierarchy,
        errors,
        node,
        half,
        radius_per_error(theta),
        variant,
    )
}

/// [`split_zone`] with r/δ precomputed by [`radius_per_error`].
pub fn split_zone_scaled(
    hierarchy: &Hierarchy,
    errors: &NodeErrors,
    node: GridPoint,
    half: u32,
    radius_per_error: f64,
    variant: ZoneVariant,
) -> Option<ZoneBox> {
    let error_and_range = errors.error_and_range(hierarchy, node, half);
    split_zone_of(
        hierarchy,
        node,
        half,
        error_and_range,
        radius_per_error,
        variant,
    )
}

/// [`split_zone_scaled`] for a node whose δ and height range `(δ, z_min, z_max)` were already
/// looked up (by [`NodeErrors::error_and_range`]).
pub fn split_zone_of(
    hierarchy: &Hierarchy,
    node: GridPoint,
    half: u32,
    (delta, z_min, z_max): (f32, f32, f32),
    radius_per_error: f64,
    variant: ZoneVariant,
) -> Option<ZoneBox> {
    let delta = f64::from(delta);
    if delta <= 0.0 {
        return None;
    }
    let r = delta * radius_per_error;
    let spacing = hierarchy.field().spacing();
    let x = f64::from(node.i) * spacing.dx;
    let y = f64::from(node.j) * spacing.dy;
    Some(match variant {
        ZoneVariant::Paper => ZoneBox {
            centre: DVec3::new(x, y, f64::from(hierarchy.height(node))),
            half: DVec3::new(2.0 * r, 2.0 * r, r),
        },
        ZoneVariant::Conservative => {
            let (z_min, z_max) = (f64::from(z_min), f64::from(z_max));
            ZoneBox {
                centre: DVec3::new(x, y, 0.5 * (z_min + z_max)),
                half: DVec3::new(
                    f64::from(half) * spacing.dx + 2.0 * r,
                    f64::from(half) * spacing.dy + 2.0 * r,
                    0.5 * (z_max - z_min) + r,
                ),
            }
        }
    })
}

/// The signed life ℓ of a zone for an eye, in frames (see the module docs); +∞ without a zone.
pub fn signed_life(zone: Option<&ZoneBox>, eye: DVec3, speed: SpeedBound) -> f64 {
    let Some(zone) = zone else {
        return f64::INFINITY;
    };
    let gaps = zone.gaps(eye);
    let axis = |gap: f64, bound: f64| {
        if bound > 0.0 {
            gap / bound
        } else if gap > 0.0 {
            f64::INFINITY
        } else {
            f64::NEG_INFINITY
        }
    };
    axis(gaps.x, speed.horizontal)
        .max(axis(gaps.y, speed.horizontal))
        .max(axis(gaps.z, speed.vertical))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::metrics::view_angle_error_px;

    const SPEED: SpeedBound = SpeedBound {
        horizontal: 10.0,
        vertical: 5.0,
        rotation: SpeedBound::NO_ROTATION_BOUND,
    };

    fn unit_zone() -> ZoneBox {
        ZoneBox {
            centre: DVec3::ZERO,
            half: DVec3::new(20.0, 20.0, 10.0),
        }
    }

    #[test]
    fn life_counts_frames_to_the_zone_at_full_speed() {
        let zone = unit_zone();
        assert_eq!(
            signed_life(Some(&zone), DVec3::new(50.0, 0.0, 0.0), SPEED),
            3.0
        );
        assert_eq!(
            signed_life(Some(&zone), DVec3::new(0.0, 0.0, 20.0), SPEED),
            2.0
        );
        // Inside, −ℓ is the time to leave through the nearest face.
        assert_eq!(
            signed_life(Some(&zone), DVec3::new(5.0, 0.0, 0.0), SPEED),
            -1.5
        );
        assert_eq!(signed_life(None, DVec3::ZERO, SPEED), f64::INFINITY);
    }

    #[test]
    fn the_paper_valid_life_is_the_formula_for_half_vertical_speed() {
        // ValidLife(): d_h > 2 d_v ? (d_h − 2r)/v_h : (d_v − r)/v_v, with v_v = v_h/2.
        let r = 10.0;
        let zone = ZoneBox {
            centre: DVec3::ZERO,
            half: DVec3::new(2.0 * r, 2.0 * r, r),
        };
        for eye in [
            DVec3::new(70.0, -30.0, 12.0),
            DVec3::new(5.0, 3.0, 40.0),
            DVec3::new(-15.0, 16.0, -9.0),
        ] {
            let d_h = eye.x.abs().max(eye.y.abs());
            let d_v = eye.z.abs();
            let paper = if d_h > 2.0 * d_v {
                (d_h - 2.0 * r) / SPEED.horizontal
            } else {
                (d_v - r) / SPEED.vertical
            };
            assert!((signed_life(Some(&zone), eye, SPEED) - paper).abs() < 1e-12);
        }
    }

    #[test]
    fn zero_speed_bounds_give_infinite_lives() {
        let still = SpeedBound {
            horizontal: 0.0,
            vertical: 0.0,
            rotation: 0.0,
        };
        let zone = unit_zone();
        assert_eq!(
            signed_life(Some(&zone), DVec3::new(50.0, 0.0, 0.0), still),
            f64::INFINITY
        );
        assert_eq!(
            signed_life(Some(&zone), DVec3::ZERO, still),
            f64::NEG_INFINITY
        );
    }

    #[test]
    fn the_zone_radius_handles_zero_and_huge_tolerances() {
        assert_eq!(zone_radius(1.0, 0.0), f64::INFINITY);
        assert_eq!(zone_radius(0.0, 0.0), 0.0);
        assert_eq!(zone_radius(2.0, 10.0), 1.0);
    }

    #[test]
    fn outside_the_paper_box_a_segment_subtends_less_than_theta() {
        // Sample eyes on the box surface, slightly outside: the exact view angle is below θ.
        let delta = 3.0;
        let theta = 0.01;
        let r = zone_radius(delta, theta);
        let base = DVec3::new(0.0, 0.0, -delta / 2.0);
        let centre = DVec3::ZERO;
        let half = DVec3::new(2.0 * r, 2.0 * r, r) * 1.000001;
        for k in 0..200 {
            let t = k as f64 / 200.0 * std::f64::consts::TAU;
            let u = (k as f64 * 0.37).sin();
            for eye in [
                centre + DVec3::new(half.x * t.cos().signum(), half.y * t.sin(), half.z * u),
                centre + DVec3::new(half.x * t.cos(), half.y * u, half.z * t.sin().signum()),
            ] {
                let pixels = view_angle_error_px(eye, base, delta, 1.0);
                assert!(pixels < theta, "eye {eye:?}: angle {pixels} ≥ θ {theta}");
            }
        }
    }
}
