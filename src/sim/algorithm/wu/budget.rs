//! Wu's constant triangle budget: base shifting (Wu et al. 2001 §6, MobilizeQueues), the paper's
//! initial threshold (§6), and τ re-centring, an outer loop that is not in the paper. This file
//! decides how b and τ move; recomputing and deferring the wheels' links is the frame loop's
//! (`mod.rs`).
//!
//! **Base shifting** (the paper's MobilizeQueues, as published). With budget n and the previous
//! frame's count n_prev: n_prev > n moves b down by one, anything else (n_prev ≤ n) moves it up by
//! one, so b moves every frame; the paper's third branch ("else …") is unreachable in its
//! pseudo-code. An optional dead band d restores it: n_prev > n + d moves b down, n_prev + d < n
//! moves it up, anything else leaves it. b is clamped to [−limit, limit]; a frame that wanted to
//! move past the limit reports the clamp. With a changing b the deferral is the paper's heuristic,
//! not a guarantee (a key can fall by two in a frame: one for the eye, one for b); at a fixed b it
//! is safe, and the tests check it there (Wu's mesh between two references, `tests/wu.rs`, and
//! the queue validator with its life check).
//!
//! **τ re-centring** (an option, not in the paper): an outer loop on top of base shifting that
//! hands the budget from b to τ. A base b lets a node split or merge b frames of travel early or
//! late: its zone grows by b·v_h across (v_h the horizontal speed bound), the same for every node,
//! where a change of τ scales each zone's radius r (∝ 1/τ at the small angles Wu works at). The
//! nodes split or merged by their lives are the ones whose zone boundary the eye is crossing, so
//! they sample where the budget is decided. Over a window of `window_frames` frames, with 2r_i the
//! zone half-width of each such node and b_i the base when it was acted on, the uniform change of
//! τ that moves their zone boundaries as much as b did is Σ 2r_i / Σ (2r_i + b_i·v_h). Half of it
//! is handed over at the end of the window: τ is multiplied by the square root of that ratio
//! (clamped to [½, 2]) and b moves by half its mean over those nodes towards 0, so the zones stay
//! where they were and the count does not jump; every queued life is recomputed with the new τ
//! and b. A window whose nodes' mean b is within ±`RECENTRING_DEAD_BAND` (nothing worth a
//! revalidation), in which b clamped (an unreachable budget) or in which nothing was acted on
//! leaves both alone.
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
    } else if budget.dead_band == 0
        || previous_count.saturating_add(budget.dead_band) < budget.triangles
    {
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

/// A window whose nodes' mean b is within ± this many frames of 0 leaves τ alone: each hand-over
/// recomputes every queued life, and a b this small costs little accuracy.
const RECENTRING_DEAD_BAND: f64 = 16.0;

/// τ re-centring's state over the current window (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Recentring {
    frames: u32,
    /// Over the window's splits and merges by life: Σ 2r_i, Σ (2r_i + b_i·v_h), Σ b_i and their
    /// number.
    sum_half_widths: f64,
    sum_grown_half_widths: f64,
    sum_bases: f64,
    actions: u64,
    clamped: bool,
}

/// What a re-centring window hands from b to τ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Handover {
    /// Multiplies τ.
    pub tau_factor: f64,
    /// Is added to b.
    pub base_change: i64,
}

impl Recentring {
    /// A node with zone half-width `two_r` was split or merged by its life at base `base`.
    pub fn record(&mut self, two_r: f64, base: i64, horizontal_speed: f64) {
        if two_r.is_finite() {
            self.sum_half_widths += two_r;
            self.sum_grown_half_widths += two_r + base as f64 * horizontal_speed;
            self.sum_bases += base as f64;
            self.actions += 1;
        }
    }

    /// Ends a frame (`clamped`: b clamped in it); at the end of a window of `window_frames`,
    /// returns what to hand over, if anything.
    pub fn end_frame(&mut self, window_frames: u32, clamped: bool) -> Option<Handover> {
        self.frames += 1;
        self.clamped |= clamped;
        if self.frames < window_frames.max(1) {
            return None;
        }
        let window = std::mem::take(self);
        if window.clamped || window.actions == 0 || window.sum_half_widths <= 0.0 {
            return None;
        }
        let mean_base = window.sum_bases / window.actions as f64;
        if mean_base.abs() <= RECENTRING_DEAD_BAND {
            return None;
        }
        let ratio = window.sum_half_widths / window.sum_grown_half_widths;
        let tau_factor = if ratio > 0.0 { ratio.sqrt() } else { 2.0 };
        Some(Handover {
            tau_factor: tau_factor.clamp(0.5, 2.0),
            base_change: -(0.5 * mean_base).round() as i64,
        })
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
            tau_recentring: None,
        })
    }

    #[test]
    fn the_base_moves_towards_the_budget() {
        assert_eq!(base_shift(budget(100, 0, 50), 120, 3).new_base, 2);
        assert_eq!(base_shift(budget(100, 0, 50), 80, 3).new_base, 4);
        assert_eq!(base_shift(None, 10, 0).new_base, 0);
    }

    #[test]
    fn without_a_dead_band_the_base_moves_every_frame_as_the_paper_publishes_it() {
        // MobilizeQueues: `if (n_prev > n) … else if (n_prev <= n) …`: a count on the budget
        // raises b.
        let shift = base_shift(budget(100, 0, 50), 100, 3);
        assert_eq!((shift.new_base, shift.direction), (4, Direction::Up));
    }

    #[test]
    fn recentring_hands_half_of_the_zone_growth_from_b_to_tau() {
        // Zones of half-width 400 m acted on at b = 20 with v_h = 20: they were grown to 800 m,
        // so τ should halve; halfway there is 1/√2, and b gives up 10.
        let mut recentring = Recentring::default();
        for _ in 0..5 {
            recentring.record(400.0, 20, 20.0);
        }
        assert_eq!(recentring.end_frame(2, false), None);
        let handover = recentring.end_frame(2, false).unwrap();
        assert!((handover.tau_factor - 0.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(handover.base_change, -10);
        // The next window starts empty: nothing acted on, nothing handed over.
        assert_eq!(recentring.end_frame(1, false), None);
        // A negative b raises τ; b near 0 or a window where b clamped leaves it.
        recentring.record(100.0, -20, 10.0);
        let handover = recentring.end_frame(1, false).unwrap();
        assert!(handover.tau_factor > 1.0);
        assert_eq!(handover.base_change, 10);
        recentring.record(100.0, 15, 10.0);
        assert_eq!(recentring.end_frame(1, false), None);
        recentring.record(100.0, 30, 10.0);
        assert_eq!(recentring.end_frame(1, true), None);
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
