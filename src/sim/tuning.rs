//! Tuning an entry's parameter to a target (`"tune"` in an experiment entry): the search over
//! short probe runs that finds the tolerance (or resolution, or distance scale) whose mean
//! rendered triangles, or mean audited p95 error, comes closest to a target.
//!
//! **A search over probe runs, not a controller inside the algorithm**, so that the entry then
//! runs at one fixed τ (or ρ, c, C, distance scale) as the paper's algorithm would, and entries
//! of every family are compared at equal mean rendered triangles or equal mean audited p95.
//!
//! Pure: the caller runs the probes; this module decides which values to probe, in which order,
//! and which probe wins. The search, documented in `docs/experiment-format.md`:
//!
//! 1. Probe the start value (clamped into the parameter's range).
//! 2. **Expand**: from the first probe's side of the target and the direction in which the
//!    measured mean moves as the parameter grows ([`Sense`]), multiply or divide the value by 2
//!    (clamped into the range) and probe again, until a probe lands on the other side of the
//!    target (the target is bracketed). A value already at the range's end, or `max_probes`
//!    probes, stops the search: not reached.
//! 3. **Bisect** the bracket geometrically (the midpoint √(a·b)), keeping the end on each side
//!    of the target, until a probe is within the tolerance (|mean − target| ≤ tolerance ·
//!    target) or `max_probes` probes were run.
//!
//! **A plateau stops the expansion.** When the last [`PLATEAU_PROBES`] probes of the expansion
//! changed the parameter (each by a factor of 2, a factor of 8 in all) and not the measured mean,
//! the parameter has stopped mattering there and the search stops with a [`Plateau`]: its value
//! range, its means, and which probes. "Not the mean" means within the probes' noise, defined
//! here: the probes are deterministic (the same value flies the same frames to the same mean, bit
//! for bit), so their noise is not a spread over repeated runs but the smallest change the search
//! can use. Means agree when their spread is at most the larger of half the tolerance band
//! (tolerance · target / 2: less than that cannot move a probe across the band) and
//! [`PLATEAU_SHARE_OF_DISTANCE`] (5 %) of the distance from the nearest of them to the target
//! (a drift that would need more than 20 such steps to arrive is not one a doubling search can
//! follow). Only the expansion stops so: inside a bracket the ends lie on two sides of the
//! target, so the parameter does move the mean there. Why the mean stopped moving is the
//! caller's to find from the probes' counters (`edge::session::tune`).
//!
//! The result is the probed value whose mean is closest to the target (ties: the earlier
//! probe); `reached` says whether that one is within the tolerance. Nothing beyond the bracket
//! assumes that the mean is monotone in the parameter (the stitching strips' is not): a
//! non-monotone function only makes the bisection find a crossing, or stop at `max_probes`
//! with the closest probe. A probe whose mean is not finite (no audited sample in any probe
//! frame) ends the search. Deterministic: the same probe means give the same probes.
//!
//! The probe flight (also here, so that it is tested without IO): `probe_frames` frames spread
//! over the flight, frames 0, s, 2s, … with s = max(1, ⌊frames / probe_frames⌋), flown with
//! the speed bounds multiplied by s ([`probe_speed`]) so that incremental algorithms keep their
//! guarantees over s frames of motion.

use crate::sim::zone::SpeedBound;

/// How the measured mean moves as the parameter grows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sense {
    /// The mean grows with the parameter (triangles against Röttger's c, say).
    Increasing,
    /// The mean falls as the parameter grows (triangles against τ).
    Decreasing,
}

impl Sense {
    /// The opposite sense (audited error moves against the triangle count).
    pub fn reversed(self) -> Sense {
        match self {
            Sense::Increasing => Sense::Decreasing,
            Sense::Decreasing => Sense::Increasing,
        }
    }
}

/// What to search for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchSettings {
    /// The first value probed (clamped into `range`).
    pub start: f64,
    /// The mean sought (> 0).
    pub target: f64,
    /// Relative: a probe within `tolerance · target` of the target ends the search.
    pub tolerance: f64,
    /// Most probes (≥ 2).
    pub max_probes: u32,
    /// The values the parameter may take, both > 0, `range.0 ≤ range.1`.
    pub range: (f64, f64),
    pub sense: Sense,
}

/// One probe: the parameter's value and the mean it gave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probe {
    pub value: f64,
    pub mean: f64,
}

/// Probes in a row of the expansion whose means agree (see the module doc) before the search
/// stops on a plateau.
pub const PLATEAU_PROBES: usize = 4;
/// A spread of the plateau's means up to this share of their distance to the target counts as
/// no change (see the module doc).
pub const PLATEAU_SHARE_OF_DISTANCE: f64 = 0.05;

/// Where the expansion found the parameter had stopped mattering: the last
/// [`PLATEAU_PROBES`] probes, whose means agree within the probes' noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plateau {
    /// The index (from 0, in `SearchResult::probes`) of the plateau's first probe; it runs to
    /// the last probe.
    pub first_probe: usize,
    /// The smallest and largest value probed on it.
    pub values: (f64, f64),
    /// The smallest and largest mean measured on it.
    pub means: (f64, f64),
}

/// The plateau the last [`PLATEAU_PROBES`] of `probes` form, if their means agree within the
/// noise of the module doc for `target` and `tolerance`.
pub fn plateau(probes: &[Probe], target: f64, tolerance: f64) -> Option<Plateau> {
    let first_probe = probes.len().checked_sub(PLATEAU_PROBES)?;
    let last = &probes[first_probe..];
    let fold = |f: fn(&Probe) -> f64| {
        last.iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    };
    let means = fold(|p| p.mean);
    let values = fold(|p| p.value);
    let nearest = last
        .iter()
        .map(|p| (p.mean - target).abs())
        .fold(f64::INFINITY, f64::min);
    let noise = (tolerance * target / 2.0).max(PLATEAU_SHARE_OF_DISTANCE * nearest);
    (means.1 - means.0 <= noise && values.0 < values.1).then_some(Plateau {
        first_probe,
        values,
        means,
    })
}

/// What the search found.
#[derive(Clone, Debug, PartialEq)]
pub struct SearchResult {
    /// The probed value whose mean is closest to the target.
    pub value: f64,
    /// Its mean.
    pub mean: f64,
    /// Whether that mean is within the tolerance of the target.
    pub reached: bool,
    /// Every probe, in the order run.
    pub probes: Vec<Probe>,
    /// The plateau the expansion stopped on, if it did.
    pub plateau: Option<Plateau>,
}

/// Runs the search, calling `probe(index, value)` (index from 1) for each probe's mean; a
/// probe's error ends the search with that error.
pub fn search<E>(
    settings: &SearchSettings,
    mut probe: impl FnMut(usize, f64) -> Result<f64, E>,
) -> Result<SearchResult, E> {
    let (low, high) = settings.range;
    let target = settings.target;
    let within = |mean: f64| (mean - target).abs() <= settings.tolerance * target;
    // `above`: the mean is above the target.
    let above = |mean: f64| mean > target;
    let mut probes: Vec<Probe> = Vec::new();
    let mut flat = None;
    let mut run = |value: f64, probes: &mut Vec<Probe>| -> Result<f64, E> {
        let mean = probe(probes.len() + 1, value)?;
        probes.push(Probe { value, mean });
        Ok(mean)
    };
    let max_probes = settings.max_probes.max(1) as usize;
    let start = settings.start.clamp(low, high);
    let first = run(start, &mut probes)?;
    'search: {
        if within(first) || !first.is_finite() {
            break 'search;
        }
        // Grow the value when the mean must grow and grows with it, or must fall and falls.
        let grow = above(first) != (settings.sense == Sense::Increasing);
        let (mut near, mut near_mean) = (start, first);
        let far = loop {
            if probes.len() >= max_probes {
                break 'search;
            }
            let next = if grow {
                (near * 2.0).min(high)
            } else {
                (near / 2.0).max(low)
            };
            if next == near {
                break 'search;
            }
            let mean = run(next, &mut probes)?;
            if within(mean) || !mean.is_finite() {
                break 'search;
            }
            if above(mean) != above(near_mean) {
                break next;
            }
            flat = plateau(&probes, target, settings.tolerance);
            if flat.is_some() {
                break 'search;
            }
            (near, near_mean) = (next, mean);
        };
        // The bracket: `near` on the first probe's side of the target, `far` on the other.
        let (mut a, mut b) = (near, far);
        let a_above = above(near_mean);
        while probes.len() < max_probes {
            let mid = (a * b).sqrt();
            if mid == a || mid == b || !mid.is_finite() {
                break;
            }
            let mean = run(mid, &mut probes)?;
            if within(mean) || !mean.is_finite() {
                break;
            }
            if above(mean) == a_above {
                a = mid;
            } else {
                b = mid;
            }
        }
    }
    let best = closest(&probes, target);
    Ok(SearchResult {
        value: best.value,
        mean: best.mean,
        reached: within(best.mean),
        probes,
        plateau: flat,
    })
}

/// The probe whose mean is closest to `target`; the earlier one on a tie; a non-finite mean is
/// farthest. `probes` is not empty.
fn closest(probes: &[Probe], target: f64) -> Probe {
    let distance = |p: &Probe| {
        let d = (p.mean - target).abs();
        if d.is_finite() { d } else { f64::INFINITY }
    };
    let mut best = probes[0];
    for p in &probes[1..] {
        if distance(p) < distance(&best) {
            best = *p;
        }
    }
    best
}

/// The probe flight's stride s = max(1, ⌈frames / probe_frames⌉) and frame count ⌈frames / s⌉
/// (at most `probe_frames`): frames 0, s, 2s, … up to the flight's end, so the probes cover the
/// whole flight, never more than s frames apart.
pub fn probe_stride(n_frames: u64, probe_frames: u64) -> (u64, u64) {
    let probe_frames = probe_frames.max(1);
    let stride = n_frames.div_ceil(probe_frames).max(1);
    (stride, n_frames.div_ceil(stride))
}

/// The speed bounds for frames `stride` apart: the distances multiplied by the stride (a
/// sound bound for `stride` frames of motion), the rotation too, capped at π.
pub fn probe_speed(bound: SpeedBound, stride: u64) -> SpeedBound {
    let s = stride as f64;
    SpeedBound {
        horizontal: bound.horizontal * s,
        vertical: bound.vertical * s,
        rotation: (bound.rotation * s).min(SpeedBound::NO_ROTATION_BOUND),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings(start: f64, target: f64, sense: Sense) -> SearchSettings {
        SearchSettings {
            start,
            target,
            tolerance: 0.02,
            max_probes: 24,
            range: (1e-4, 1e4),
            sense,
        }
    }

    fn values(result: &SearchResult) -> Vec<f64> {
        result.probes.iter().map(|p| p.value).collect()
    }

    #[test]
    fn a_monotone_function_is_bracketed_then_bisected_to_the_tolerance() {
        // Triangles ~ 1e5 / τ²: 6000 triangles at τ ≈ 4.08.
        let f = |tau: f64| 1e5 / (tau * tau);
        let result =
            search::<()>(&settings(2.0, 6000.0, Sense::Decreasing), |_, v| Ok(f(v))).unwrap();
        // 2 → 25000 (too many: grow τ), 4 → 6250 (still above), 8 → 1562 (bracketed).
        assert_eq!(values(&result)[..3], [2.0, 4.0, 8.0]);
        assert!(result.reached, "{result:?}");
        assert!((result.mean - 6000.0).abs() <= 0.02 * 6000.0);
        assert_eq!(result.mean, f(result.value));
        assert!(result.probes.len() < 24);
        // An increasing function from below: the value doubles.
        let g = |c: f64| 100.0 * c;
        let up = search::<()>(&settings(1.0, 1000.0, Sense::Increasing), |_, v| Ok(g(v))).unwrap();
        assert_eq!(values(&up)[..4], [1.0, 2.0, 4.0, 8.0]);
        assert!(up.reached);
    }

    #[test]
    fn a_start_within_the_tolerance_is_the_only_probe() {
        let result =
            search::<()>(&settings(3.0, 100.0, Sense::Decreasing), |_, _| Ok(101.0)).unwrap();
        assert_eq!(values(&result), [3.0]);
        assert!(result.reached);
    }

    #[test]
    fn a_step_function_returns_the_closest_probe_and_says_it_is_not_reached() {
        // Triangles jump from 8000 to 4000 at τ = 3: 6000 ± 2 % is never drawn.
        let step = |tau: f64| if tau < 3.0 { 8000.0 } else { 4000.0 };
        let result = search::<()>(&settings(2.0, 6000.0, Sense::Decreasing), |_, v| {
            Ok(step(v))
        })
        .unwrap();
        assert!(!result.reached);
        assert_eq!(result.probes.len(), 24, "bisection runs to max_probes");
        // Both sides are 2000 away: the earlier probe (the start, 8000) wins the tie.
        assert_eq!((result.value, result.mean), (2.0, 8000.0));
        // Every probe inside the bracket [2, 4].
        assert!(values(&result).iter().all(|&v| (2.0..=4.0).contains(&v)));
    }

    #[test]
    fn a_non_monotone_function_still_finds_a_crossing_or_the_closest_probe() {
        // Like the stitching strips' ρ: fewer triangles at 0.5 than at 1, more below.
        let bumpy = |rho: f64| {
            if rho < 0.4 {
                3000.0 + (0.4 - rho) * 1e5
            } else if rho < 0.75 {
                3000.0
            } else {
                5000.0 / rho
            }
        };
        // Target 4000 from ρ = 1 (5000, too many): 2 → 2500 brackets [1, 2]; the bisection
        // finds ρ ≈ 1.24.
        let result = search::<()>(&settings(1.0, 4000.0, Sense::Decreasing), |_, v| {
            Ok(bumpy(v))
        })
        .unwrap();
        assert!(result.reached, "{result:?}");
        assert!((1.0..=2.0).contains(&result.value));
        // Target 10000 from ρ = 1 (5000, too few: shrink ρ): 0.5 → 3000 (further away, but the
        // same side), 0.25 → 18000 brackets [0.25, 0.5]; the bisection needs no monotonicity.
        let result = search::<()>(&settings(1.0, 10_000.0, Sense::Decreasing), |_, v| {
            Ok(bumpy(v))
        })
        .unwrap();
        assert_eq!(values(&result)[..3], [1.0, 0.5, 0.25]);
        assert!(result.reached, "{result:?}");
        assert!((0.25..=0.5).contains(&result.value));
    }

    #[test]
    fn a_target_out_of_range_stops_at_the_range_end_not_reached() {
        // Fewer triangles as τ grows, never below 1: 0.5 is never bracketed.
        let falling = |tau: f64| 1.0 + 1000.0 / tau;
        let result = search::<()>(&settings(2.0, 0.5, Sense::Decreasing), |_, v| {
            Ok(falling(v))
        })
        .unwrap();
        assert!(!result.reached);
        assert_eq!(
            *values(&result).last().unwrap(),
            1e4,
            "stopped at the range's end"
        );
        assert_eq!(result.plateau, None, "the mean moved all the way");
        let capped = |tau: f64| (1000.0 / tau).min(1000.0);
        // With few probes allowed, the expansion stops at max_probes.
        let few = SearchSettings {
            max_probes: 3,
            ..settings(2.0, 5000.0, Sense::Decreasing)
        };
        let result = search::<()>(&few, |_, v| Ok(capped(v))).unwrap();
        assert_eq!(values(&result), [2.0, 1.0, 0.5]);
        assert!(!result.reached);
    }

    #[test]
    fn a_parameter_that_stopped_mattering_stops_the_search_on_a_plateau() {
        // At most 1000 triangles, whatever τ below 1: 5000 is never bracketed, and halving τ
        // past 1 changes nothing.
        let capped = |tau: f64| (1000.0 / tau).min(1000.0);
        let result = search::<()>(&settings(2.0, 5000.0, Sense::Decreasing), |_, v| {
            Ok(capped(v))
        })
        .unwrap();
        assert_eq!(values(&result), [2.0, 1.0, 0.5, 0.25, 0.125]);
        assert!(!result.reached);
        let plateau = result.plateau.expect("four probes at 1000");
        assert_eq!(plateau.first_probe, 1);
        assert_eq!(plateau.values, (0.125, 1.0));
        assert_eq!(plateau.means, (1000.0, 1000.0));
        // The stitching strips' audited p95 at ρ → 0: a drift of 0.03 px, 0.93 px from the
        // target, is no change a doubling search can follow.
        let drifting = |rho: f64| 1.23 + 0.004 * (1.0 / rho).log2().max(0.0);
        let result = search::<()>(&settings(1.0, 0.3, Sense::Increasing), |_, v| {
            Ok(drifting(v))
        })
        .unwrap();
        assert_eq!(result.probes.len(), PLATEAU_PROBES);
        assert!(result.plateau.is_some());
        // A mean that keeps moving towards the target is no plateau.
        let steady = search::<()>(&settings(2.0, 1.0, Sense::Decreasing), |_, v| {
            Ok(1.0 + 64.0 / v)
        })
        .unwrap();
        assert_eq!(steady.plateau, None);
        assert!(steady.probes.len() > PLATEAU_PROBES);
    }

    #[test]
    fn a_probe_error_ends_the_search_with_it() {
        let result = search(&settings(2.0, 5000.0, Sense::Decreasing), |k, _| {
            if k == 2 {
                Err("too many triangles")
            } else {
                Ok(100.0)
            }
        });
        assert_eq!(result, Err("too many triangles"));
    }

    #[test]
    fn probe_frames_are_spread_over_the_flight_with_scaled_bounds() {
        assert_eq!(probe_stride(6000, 200), (30, 200));
        assert_eq!(probe_stride(150, 200), (1, 150));
        // 399 frames: every other frame, up to frame 398 (not frames 0 to 199).
        assert_eq!(probe_stride(399, 200), (2, 200));
        // 720 frames: every 4th, up to frame 716, 180 probe frames.
        assert_eq!(probe_stride(720, 200), (4, 180));
        for (frames, probes) in [(6001, 200), (45, 7), (1, 200), (1000, 3)] {
            let (stride, count) = probe_stride(frames, probes);
            assert!(
                count <= probes && (count - 1) * stride < frames,
                "{frames} {probes}"
            );
            assert!(
                count * stride >= frames,
                "the last probe frame is within s of the end"
            );
        }
        let bound = SpeedBound {
            horizontal: 2.0,
            vertical: 0.5,
            rotation: 0.2,
        };
        let scaled = probe_speed(bound, 30);
        assert_eq!((scaled.horizontal, scaled.vertical), (60.0, 15.0));
        assert_eq!(scaled.rotation, SpeedBound::NO_ROTATION_BOUND);
        assert_eq!(probe_speed(bound, 3).rotation, 0.2 * 3.0);
    }
}
