//! The constant triangle budget: base shifting, and the paper's initial threshold.
//!
//! **Base shifting.** With budget n and the previous frame's count n_prev: n_prev > n + dead band
//! moves b down by one, n_prev + dead band < n moves it up by one, anything else leaves it (the
//! paper's third branch, unreachable in its pseudo-code without a dead band). b is clamped to
//! [−limit, limit]; a frame that wanted to move past the limit reports the clamp.
//!
//! **Initial τ** (paper §6): τ = k·√(6π·Σ_{i=0}^{D−1} 4^i) · (h/fovy) · δ_ave / (L·√tpf).
//! The paper writes d for two things; dimensional analysis settles it: Σ 4^i runs over the D
//! levels of the quadtree (it is the node count), while the d in the denominator is the mesh side
//! L (the terrain is L × L cells) measured in the same unit as δ_ave, so that δ_ave/L is an angle
//! scale and τ comes out in pixels. We use L = 2^n cells, δ_ave = the mean node error in metres
//! divided by the mean grid spacing, fovy in radians, h the window height in pixels.

use super::BudgetConfig;
use crate::sim::hierarchy::{Hierarchy, square_points};
use crate::sim::view::ViewSettings;
use crate::sim::zone::NodeErrors;

/// Which way b moved this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Direction {
    Down,
    Up,
    Stay,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Shift {
    pub new_base: i64,
    pub direction: Direction,
    pub clamped: bool,
}

/// This frame's base shift.
pub(super) fn base_shift(budget: Option<BudgetConfig>, previous_count: u64, base: i64) -> Shift {
    let stay = Shift {
        new_base: base,
        direction: Direction::Stay,
        clamped: false,
    };
    let Some(budget) = budget else {
        return stay;
    };
    let wanted = if previous_count > budget.triangles.saturating_add(budget.dead_band) {
        Direction::Down
    } else if previous_count.saturating_add(budget.dead_band) < budget.triangles {
        Direction::Up
    } else {
        Direction::Stay
    };
    let step = match wanted {
        Direction::Down => -1,
        Direction::Up => 1,
        Direction::Stay => 0,
    };
    let limit = budget.base_limit.max(0);
    let new_base = (base + step).clamp(-limit, limit);
    if new_base == base && step != 0 {
        return Shift {
            clamped: true,
            ..stay
        };
    }
    Shift {
        new_base,
        direction: wanted,
        clamped: false,
    }
}

/// The paper's initial τ for a budget (see the module docs).
pub fn initial_tau_px(
    hierarchy: &Hierarchy,
    errors: &NodeErrors,
    view: &ViewSettings,
    budget: BudgetConfig,
) -> f64 {
    let lattice = hierarchy.lattice();
    let (mut sum, mut count) = (0.0f64, 0u64);
    let mut half = 1;
    while half < lattice.cells() {
        for p in square_points(lattice, half) {
            sum += f64::from(errors.error(hierarchy, p, half));
            count += 1;
        }
        half *= 2;
    }
    let spacing = hierarchy.field().spacing();
    let mean_spacing = 0.5 * (spacing.dx + spacing.dy);
    let delta_average = sum / count.max(1) as f64 / mean_spacing;
    let n_nodes = count as f64;
    let side = f64::from(lattice.cells());
    let tpf = budget.triangles.max(1) as f64;
    budget.initial_tau_k
        * (6.0 * std::f64::consts::PI * n_nodes).sqrt()
        * (f64::from(view.height_px) / view.fovy)
        * delta_average
        / (side * tpf.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn budget(triangles: u64, dead_band: u64, base_limit: i64) -> Option<BudgetConfig> {
        Some(BudgetConfig {
            triangles,
            dead_band,
            base_limit,
            initial_tau_k: 1.5,
        })
    }

    #[test]
    fn the_base_moves_towards_the_budget() {
        assert_eq!(base_shift(budget(100, 0, 50), 120, 3).new_base, 2);
        assert_eq!(base_shift(budget(100, 0, 50), 80, 3).new_base, 4);
        assert_eq!(
            base_shift(budget(100, 0, 50), 100, 3).direction,
            Direction::Stay
        );
        assert_eq!(base_shift(None, 10, 0).new_base, 0);
    }

    #[test]
    fn a_dead_band_restores_the_third_branch() {
        let shift = base_shift(budget(100, 10, 50), 108, 0);
        assert_eq!((shift.new_base, shift.direction), (0, Direction::Stay));
        assert_eq!(base_shift(budget(100, 10, 50), 111, 0).new_base, -1);
    }

    #[test]
    fn an_unreachable_budget_clamps_the_base_and_says_so() {
        let shift = base_shift(budget(1_000_000, 0, 5), 10, 5);
        assert_eq!(shift.new_base, 5);
        assert!(shift.clamped);
        assert_eq!(shift.direction, Direction::Stay);
    }
}
