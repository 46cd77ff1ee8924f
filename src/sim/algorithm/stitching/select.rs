//! The paper's view-dependent choice (§3.3.1): a block's object-space errors δ_i turned into
//! screen-space errors ρ_i = λ·δ_i·sinθ/d (eq. 3), the split test ρ_32 > ρ_thr, and the
//! tessellation factor of eq. 4 between the two bracketing levels. Pure functions of the camera
//! and a block: the traversal (`mod.rs`) and the brute-force check (`validate.rs`) share them.

use super::tessellate::{MAX_FACTOR, MIN_FACTOR};
use super::tree::LEVELS;
use crate::sim::view::Camera;
use glam::DVec3;

/// The paper's three methods, as options of one algorithm.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StitchingMethod {
    /// The paper's own: quadtree M-blocks at continuous factors, P-blocks and dynamic stitching
    /// strips between them.
    Strips,
    /// Method I: the same quadtree, factors rounded up to powers of two, no gaps and no strips;
    /// each shared edge tessellated with one spacing that both sides' vertices share.
    PowerOfTwo,
    /// Method II: uniform blocks (all at the deepest level), continuous factors, no strips; a
    /// shared edge takes the larger of its two blocks' factors.
    Uniform,
}

/// How d, the distance from the viewpoint to an M-block, is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlockDistance {
    /// To the block's centre (its region's centre, at the middle of its height range): the
    /// paper's O in §4.1.
    Centre,
    /// To the block's box (region × height range), 0 inside it.
    Box,
}

/// What θ is measured from: the angle between a direction e and the +Z normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewDirection {
    /// e from the viewpoint to the block's centre (the paper's figure 13: the direction in
    /// which the block is seen).
    ToBlock,
    /// e the camera's look direction.
    Look,
}

/// A block as the metric sees it: its box in terrain-local metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetricBox {
    pub low: DVec3,
    pub high: DVec3,
}

/// λ·sinθ/d for a block: the factor turning δ into ρ. +∞ when d = 0 and sinθ > 0 (the eye
/// in or on the block); when e is the zero vector (the eye at the block's centre) sinθ is
/// taken as 1.
pub fn error_scale(
    camera: &Camera,
    block: &MetricBox,
    distance: BlockDistance,
    direction: ViewDirection,
) -> f64 {
    let lambda = camera.settings.pixels_per_unit();
    let eye = camera.eye;
    let centre = 0.5 * (block.low + block.high);
    let d = match distance {
        BlockDistance::Centre => (centre - eye).length(),
        BlockDistance::Box => (eye.clamp(block.low, block.high) - eye).length(),
    };
    let e = match direction {
        ViewDirection::ToBlock => centre - eye,
        ViewDirection::Look => camera.forward,
    };
    let length = e.length();
    let sin_theta = if length > 0.0 {
        (e.x.hypot(e.y) / length).min(1.0)
    } else {
        1.0
    };
    if sin_theta == 0.0 {
        0.0
    } else if d > 0.0 {
        lambda * sin_theta / d
    } else {
        f64::INFINITY
    }
}

/// ρ = scale·δ, with no error never on screen (0·∞ = 0).
pub fn screen_error(scale: f64, delta: f32) -> f64 {
    if delta == 0.0 {
        0.0
    } else {
        scale * f64::from(delta)
    }
}

/// Whether the block must split: ρ_32 > ρ_thr (it is not fine enough even at F = 64).
pub fn needs_split(scale: f64, errors: &[f32; LEVELS], threshold_px: f64) -> bool {
    screen_error(scale, errors[LEVELS - 1]) > threshold_px
}

/// The tessellation factor F_thr of eq. 4: from i = 32 down, the first ρ_i above ρ_thr; F
/// placed between 2i and 2(i + 1) where ρ_thr falls between ρ_i and ρ_{i+1} (linearly). 2 when
/// every ρ_i is within the threshold, 64 when ρ_32 is not (a block that cannot split).
pub fn tessellation_factor(scale: f64, errors: &[f32; LEVELS], threshold_px: f64) -> f64 {
    let rho = |i: usize| screen_error(scale, errors[i - 1]);
    let Some(i) = (1..=LEVELS).rev().find(|&i| rho(i) > threshold_px) else {
        return MIN_FACTOR;
    };
    if i == LEVELS {
        return MAX_FACTOR;
    }
    let (above, below) = (rho(i), rho(i + 1));
    let fraction = if above.is_infinite() {
        1.0
    } else {
        (above - threshold_px) / (above - below)
    };
    (fraction * 2.0 + 2.0 * i as f64).clamp(MIN_FACTOR, MAX_FACTOR)
}

/// Method I's factor: the smallest power of two (2 … 64) at or above F.
pub fn power_of_two_factor(factor: f64) -> f64 {
    let mut p = MIN_FACTOR;
    while p < factor && p < MAX_FACTOR {
        p *= 2.0;
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    fn falling() -> [f32; LEVELS] {
        std::array::from_fn(|i| 64.0 / (i as f32 + 1.0))
    }

    #[test]
    fn eq_4_interpolates_between_the_bracketing_levels() {
        let errors = falling();
        // scale 1: ρ_i = 64/i. ρ_thr = 5: ρ_12 = 5.33 > 5 ≥ ρ_13 = 4.92.
        let f = tessellation_factor(1.0, &errors, 5.0);
        let (r12, r13) = (f64::from(errors[11]), f64::from(errors[12]));
        let expected = (r12 - 5.0) / (r12 - r13) * 2.0 + 24.0;
        assert!((f - expected).abs() < 1e-12, "{f} vs {expected}");
        assert!(f > 24.0 && f <= 26.0);
        // Everything within the threshold: 2; nothing: 64 (and a split).
        assert_eq!(tessellation_factor(1.0, &errors, 100.0), 2.0);
        assert_eq!(tessellation_factor(1.0, &errors, 1.0), 64.0);
        assert!(needs_split(1.0, &errors, 1.0) && !needs_split(1.0, &errors, 2.0));
        // An infinite scale: the finest level with any error.
        let mut some = [0.0; LEVELS];
        some[..5].fill(1.0);
        assert_eq!(tessellation_factor(f64::INFINITY, &some, 1.0), 12.0);
        assert_eq!(power_of_two_factor(12.0), 16.0);
        assert_eq!(power_of_two_factor(2.0), 2.0);
        assert_eq!(power_of_two_factor(33.0), 64.0);
    }
}
