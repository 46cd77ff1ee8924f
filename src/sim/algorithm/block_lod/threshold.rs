//! The detail test of the block papers and the morph factor, on a block's box
//! (Lauritsen–Nielsen §3.2.5, eq. 3.3, and §3.2.8, eq. 3.5).
//!
//! A block (a geomipmap patch at a level, a chunk) has a nested world-space error δ and a box:
//! its square times the height range of its samples. Its distance d from the eye is measured
//! by the experiment's [`Projection`]; it is too coarse when d < d_m = δ·C, with
//! C = S/(2τ·tan(fov/2)) = λ/τ (eq. 3.3; λ the pixels per unit of the image plane). δ = 0 is
//! never too coarse, so τ = 0 (C = +∞) refines exactly the blocks with an error. The morph
//! factor of a drawn block is eq. 3.5, f = 1 − (d − d_m)/(d_mp − d_m) with d_mp = δ_p·C the
//! next coarser level's distance, clamped to [0, 1]: 1 at d_m (where the finer level takes
//! over, itself at f = 0), 0 at d_mp (where the coarser level takes over).
//!
//! Everything is a product of lengths and the dimensionless C, so scaling terrain and eye
//! together by a power of two changes no decision, and translation changes none (boxes are in
//! the terrain's local frame).

use super::Projection;
use crate::sim::algorithm::lindstrom::ProjectionBounds;
use glam::DVec3;

/// An axis-aligned box in terrain-local metres: a block's square times its height range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct BlockBox {
    pub(crate) low: DVec3,
    pub(crate) high: DVec3,
}

impl BlockBox {
    /// The Euclidean distance from `eye` to the box (0 inside it).
    pub(crate) fn distance(&self, eye: DVec3) -> f64 {
        let gap = eye.clamp(self.low, self.high) - eye;
        gap.length()
    }

    /// The distance d the detail test uses, measured as `projection` says.
    pub(crate) fn lod_distance(&self, eye: DVec3, projection: Projection) -> f64 {
        match projection {
            Projection::HorizontalView => self.distance(eye),
            Projection::Exact => {
                // The largest r/(r² + h²) over the box; its inverse is the distance at which a
                // horizontal view would project δ to the same length.
                let largest = ProjectionBounds::over_box(eye, self.low, self.high, 1.0).max;
                if largest == f64::INFINITY {
                    0.0
                } else if largest == 0.0 {
                    f64::INFINITY
                } else {
                    1.0 / largest
                }
            }
        }
    }
}

/// C of eq. 3.3 for one frame's τ, and the two decisions made with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DetailThreshold {
    /// λ/τ; +∞ at τ = 0.
    c: f64,
}

impl DetailThreshold {
    /// C for tolerance `tau_px` (≥ 0, finite) in a view of `lambda` pixels per unit.
    pub(crate) fn new(lambda: f64, tau_px: f64) -> DetailThreshold {
        let c = if tau_px == 0.0 {
            f64::INFINITY
        } else {
            lambda / tau_px
        };
        DetailThreshold { c }
    }

    /// Whether a block of nested error `delta` at distance `d` is too coarse: d < δ·C
    /// (listing 3.2). A block with δ = 0 never is.
    pub(crate) fn refines(&self, delta: f32, d: f64) -> bool {
        delta > 0.0 && d < f64::from(delta) * self.c
    }

    /// The morph factor (eq. 3.5) of a drawn block of error `delta` at distance `d` whose next
    /// coarser level has error `coarser_delta`: 1 at full detail, 0 where it looks exactly like
    /// the coarser level. 1 at τ = 0 (nothing is coarsened).
    pub(crate) fn morph_factor(&self, delta: f32, coarser_delta: f32, d: f64) -> f64 {
        if self.c == f64::INFINITY {
            return 1.0;
        }
        let d_m = f64::from(delta) * self.c;
        let d_mp = f64::from(coarser_delta) * self.c;
        if d <= d_m {
            1.0
        } else if d >= d_mp {
            0.0
        } else {
            (1.0 - (d - d_m) / (d_mp - d_m)).clamp(0.0, 1.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> BlockBox {
        BlockBox {
            low: DVec3::new(0.0, 0.0, 0.0),
            high: DVec3::new(10.0, 10.0, 2.0),
        }
    }

    #[test]
    fn the_distance_is_zero_inside_and_euclidean_outside() {
        let b = unit_box();
        assert_eq!(b.distance(DVec3::new(5.0, 5.0, 1.0)), 0.0);
        assert_eq!(b.distance(DVec3::new(13.0, 14.0, 2.0)), 5.0);
        assert_eq!(b.distance(DVec3::new(5.0, 5.0, 7.0)), 5.0);
    }

    #[test]
    fn the_exact_projection_never_refines_more_and_agrees_at_the_boxs_height() {
        let b = unit_box();
        for eye in [
            DVec3::new(40.0, 5.0, 1.0),
            DVec3::new(40.0, 5.0, 300.0),
            DVec3::new(5.0, 5.0, 50.0),
            DVec3::new(-3.0, -4.0, 2.0),
        ] {
            let horizontal = b.lod_distance(eye, Projection::HorizontalView);
            let exact = b.lod_distance(eye, Projection::Exact);
            assert!(exact >= horizontal * (1.0 - 1e-12), "{eye:?}");
        }
        // Level with the box: both are the horizontal distance.
        let level = DVec3::new(40.0, 5.0, 1.0);
        assert_eq!(b.lod_distance(level, Projection::Exact), 30.0);
        // Straight above, 48 m over the box: a vertical segment foreshortens; the worst point
        // is a corner, r = √50 m, h = 48 m, so d = (50 + 48²)/√50.
        let above = DVec3::new(5.0, 5.0, 50.0);
        let expected = (50.0 + 48.0 * 48.0) / 50f64.sqrt();
        assert!((b.lod_distance(above, Projection::Exact) - expected).abs() < 1e-9);
        assert_eq!(b.lod_distance(above, Projection::HorizontalView), 48.0);
    }

    #[test]
    fn a_block_refines_below_its_distance_and_never_without_error() {
        let threshold = DetailThreshold::new(500.0, 2.0);
        // d_m = 4 m · 250 = 1000 m.
        assert!(threshold.refines(4.0, 999.0));
        assert!(!threshold.refines(4.0, 1000.0));
        assert!(!threshold.refines(0.0, 0.0));
        let exact = DetailThreshold::new(500.0, 0.0);
        assert!(exact.refines(1e-30, 1e30));
        assert!(!exact.refines(0.0, 0.0));
    }

    #[test]
    fn the_morph_factor_runs_from_one_at_d_m_to_zero_at_the_parents_distance() {
        let threshold = DetailThreshold::new(500.0, 2.0);
        // d_m = 1000 m, d_mp = 3000 m.
        assert_eq!(threshold.morph_factor(4.0, 12.0, 1000.0), 1.0);
        assert_eq!(threshold.morph_factor(4.0, 12.0, 2000.0), 0.5);
        assert_eq!(threshold.morph_factor(4.0, 12.0, 3000.0), 0.0);
        assert_eq!(threshold.morph_factor(4.0, 12.0, 9000.0), 0.0);
        assert_eq!(threshold.morph_factor(4.0, 4.0, 1000.0), 1.0);
        assert_eq!(
            DetailThreshold::new(500.0, 0.0).morph_factor(4.0, 12.0, 1e9),
            1.0
        );
    }
}
