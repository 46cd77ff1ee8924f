//! Holding a triangle target by choosing τ every frame: the controller of the block
//! algorithms' `target_triangles` option (what makes them comparable with the budget-driven
//! Wu and ROAM at equal triangles). It is roamsim's: none of the block papers holds a count.
//!
//! **The controller.** Each frame, τ is the smallest value on a fixed grid (every 1/64 of an
//! octave between 2^−40 and 2^40 px, plus 0) whose mesh has at most the target's triangles,
//! skirts and stitches included: the finest mesh the target allows. The algorithm gives the
//! triangle count for any τ (`count`, a selection pass that builds no mesh). The search starts
//! from the previous frame's τ: it brackets the answer by octaves outwards from there, then
//! halves the bracket six times. Since a block algorithm's triangle count never rises with τ
//! (a larger τ coarsens every block or leaves it), the answer is the same whatever the starting
//! τ: a pure function of the view, so a fresh instance and one that has flown for a million
//! frames choose the same mesh. The start only saves evaluations: a few when τ moves little
//! between frames, 2 + 2·(octaves moved) + 6 at most.
//!
//! **Limits.** When even τ = 2^40 px leaves more triangles than the target (the coarsest mesh
//! is above it; an eye inside a block's box refines it at every finite τ), τ = 2^40 px is used
//! and the frame reports the target unreachable. When τ = 0 (every block at full resolution)
//! fits, τ = 0.
//!
//! Compared with Wu's base shifting (one step of b per frame from the previous count) this
//! controller never overshoots the target and has no drift, at the price of several selection
//! passes per frame; the passes are counted in `metric_evaluations`.

/// The largest τ the search tries, pixels.
pub(crate) const TAU_MAX_PX: f64 = 1_099_511_627_776.0; // 2^40
/// log2 of the smallest positive τ tried.
const LOG2_TAU_MIN: f64 = -40.0;
/// log2 of [`TAU_MAX_PX`].
const LOG2_TAU_MAX: f64 = 40.0;
/// The search's resolution: τ is found to 1/64 of an octave (1.1 %).
const RESOLUTION_OCTAVES: f64 = 1.0 / 64.0;

/// What the search chose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct TauChoice {
    pub(crate) tau_px: f64,
    /// The triangle count at `tau_px`.
    pub(crate) triangles: u64,
    /// Even τ = 2^40 px leaves more than the target.
    pub(crate) unreachable: bool,
    /// Selection passes run (calls of `count`).
    pub(crate) passes: u64,
}

/// The smallest τ on the search's grid whose triangle count (`count(τ)`) is at most `target`,
/// searched outwards from `start_px` (see the module docs).
pub(crate) fn finest_tau_within(
    target: u64,
    start_px: f64,
    mut count: impl FnMut(f64) -> u64,
) -> TauChoice {
    let mut passes = 0;
    let mut n = |tau: f64| {
        passes += 1;
        count(tau)
    };
    let finest = n(0.0);
    if finest <= target {
        return TauChoice {
            tau_px: 0.0,
            triangles: finest,
            unreachable: false,
            passes,
        };
    }
    let coarsest = n(TAU_MAX_PX);
    if coarsest > target {
        return TauChoice {
            tau_px: TAU_MAX_PX,
            triangles: coarsest,
            unreachable: true,
            passes,
        };
    }
    // Bracket: n(2^low) > target ≥ n(2^high), both whole octaves (or the limits).
    let start = if start_px > 0.0 && start_px.is_finite() {
        start_px.log2().round().clamp(LOG2_TAU_MIN, LOG2_TAU_MAX)
    } else {
        0.0
    };
    let (mut low, mut high, mut at_high);
    let at_start = n(start.exp2());
    if at_start <= target {
        (high, at_high) = (start, at_start);
        low = high - 1.0;
        loop {
            if low < LOG2_TAU_MIN {
                // Below 2^−40 px: as fine as the search resolves.
                return TauChoice {
                    tau_px: high.exp2(),
                    triangles: at_high,
                    unreachable: false,
                    passes,
                };
            }
            let at_low = n(low.exp2());
            if at_low > target {
                break;
            }
            (high, at_high) = (low, at_low);
            low -= 1.0;
        }
    } else {
        low = start;
        high = low + 1.0;
        loop {
            if high >= LOG2_TAU_MAX {
                (high, at_high) = (LOG2_TAU_MAX, coarsest);
                break;
            }
            let at = n(high.exp2());
            if at <= target {
                at_high = at;
                break;
            }
            low = high;
            high += 1.0;
        }
    }
    while high - low > RESOLUTION_OCTAVES {
        let middle = 0.5 * (low + high);
        let at = n(middle.exp2());
        if at <= target {
            (high, at_high) = (middle, at);
        } else {
            low = middle;
        }
    }
    TauChoice {
        tau_px: high.exp2(),
        triangles: at_high,
        unreachable: false,
        passes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A staircase count: 10 000 triangles at τ = 1 px, falling as 1/τ², at least 2.
    fn count(tau: f64) -> u64 {
        if tau == 0.0 {
            return u64::MAX;
        }
        ((10_000.0 / (tau * tau)).floor() as u64).max(2)
    }

    #[test]
    fn the_finest_tau_within_the_target_is_found_whatever_the_start() {
        let expected = finest_tau_within(2_500, 1.0, count);
        // n = 10 000/τ² ≤ 2 500 from τ = 2 px.
        assert_eq!(expected.tau_px, 2.0);
        assert_eq!(expected.triangles, 2_500);
        assert!(!expected.unreachable);
        for start in [1e-9, 0.01, 1.0, 3.0, 1e6, 0.0, f64::INFINITY] {
            let choice = finest_tau_within(2_500, start, count);
            assert_eq!(choice.tau_px, expected.tau_px, "start {start}");
        }
        // One grid step finer is over the target.
        assert!(count(2.0 * (-RESOLUTION_OCTAVES).exp2()) > 2_500);
        // A target between steps: the count at the answer is within it.
        let choice = finest_tau_within(3_000, 50.0, count);
        assert!(choice.triangles <= 3_000);
        assert!(count(choice.tau_px * (-RESOLUTION_OCTAVES).exp2()) > 3_000);
    }

    #[test]
    fn a_warm_start_saves_passes() {
        let cold = finest_tau_within(2_500, 1e6, count);
        let warm = finest_tau_within(2_500, 2.0, count);
        assert!(
            warm.passes < cold.passes,
            "{} vs {}",
            warm.passes,
            cold.passes
        );
        assert!(warm.passes <= 2 + 2 + 6);
    }

    #[test]
    fn targets_below_the_coarsest_and_above_the_finest_mesh_are_clamped() {
        let below = finest_tau_within(1, 1.0, count);
        assert_eq!((below.tau_px, below.unreachable), (TAU_MAX_PX, true));
        let everything = finest_tau_within(u64::MAX, 1.0, count);
        assert_eq!((everything.tau_px, everything.unreachable), (0.0, false));
    }
}
