//! The per-patch level of detail of Vaněk–Ježek (§3): k = n below `mindist`, 0 beyond
//! `maxdist`, between them n·(1 − ((dist − mindist)/(maxdist − mindist))^exp), rounded as the
//! configuration says; and the patch distance the formula reads. The formula is the paper's;
//! the rounding and the distance (the paper says only "the patch distance from the camera
//! position") are roamsim's choices, recorded in `mod.rs`.
//!
//! Distances are multiplied by a factor μ before the test (1 without a target): the triangle
//! target scales `mindist` and `maxdist` together by 1/μ, which is the same thing. μ = 0 puts
//! every patch at k = n.

use glam::DVec3;

/// How the continuous k of the paper's formula becomes a level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LodRounding {
    /// ⌊k⌋, as an integer conversion in the paper's C code truncates: k = n only nearer than
    /// `mindist`, exactly as the formula's first case says. The default.
    Down,
    /// The nearest level, halves up.
    Nearest,
    /// ⌈k⌉: never coarser than the formula asks; k = 0 only beyond `maxdist`.
    Up,
}

/// How a patch's `dist` is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatchDistance {
    /// From the eye to the patch's box (its square × its samples' height range), 0 inside it:
    /// the nearest point the patch can draw. The default.
    Box,
    /// From the eye to the centre of that box.
    Centre,
}

/// The distances of the paper's formula and its exponent (validated by the experiment:
/// 0 ≤ `min_dist_m` < `max_dist_m`, both finite, `exponent` finite and > 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodCurve {
    pub min_dist_m: f64,
    pub max_dist_m: f64,
    pub exponent: f64,
    pub rounding: LodRounding,
}

impl LodCurve {
    /// The level (0 ..= `n`) of a patch at distance `dist` (metres, ≥ 0, possibly +∞).
    pub fn lod(&self, n: u32, dist: f64) -> u32 {
        if dist <= self.min_dist_m {
            return n;
        }
        if dist >= self.max_dist_m {
            return 0;
        }
        let t =
            ((dist - self.min_dist_m) / (self.max_dist_m - self.min_dist_m)).powf(self.exponent);
        let k = f64::from(n) * (1.0 - t);
        let rounded = match self.rounding {
            LodRounding::Down => k.floor(),
            LodRounding::Nearest => (k + 0.5).floor(),
            LodRounding::Up => k.ceil(),
        };
        rounded.clamp(0.0, f64::from(n)) as u32
    }
}

/// The distance from `eye` to the box from `low` to `high`, as `how` measures it.
pub fn patch_distance(eye: DVec3, low: DVec3, high: DVec3, how: PatchDistance) -> f64 {
    match how {
        PatchDistance::Box => (eye.clamp(low, high) - eye).length(),
        PatchDistance::Centre => (0.5 * (low + high) - eye).length(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(rounding: LodRounding) -> LodCurve {
        LodCurve {
            min_dist_m: 100.0,
            max_dist_m: 500.0,
            exponent: 1.0,
            rounding,
        }
    }

    #[test]
    fn the_formula_its_two_ends_and_the_three_roundings() {
        // n = 8, linear: k = 8·(1 − (d − 100)/400); at d = 250, k = 5; at d = 260, k = 4.8.
        let cases = [
            (0.0, [8, 8, 8]),
            (100.0, [8, 8, 8]),
            (250.0, [5, 5, 5]),
            (260.0, [4, 5, 5]),
            (280.0, [4, 4, 5]),
            (499.0, [0, 0, 1]),
            (500.0, [0, 0, 0]),
            (f64::INFINITY, [0, 0, 0]),
        ];
        for (d, expected) in cases {
            let got = [LodRounding::Down, LodRounding::Nearest, LodRounding::Up]
                .map(|r| curve(r).lod(8, d));
            assert_eq!(got, expected, "d = {d}");
        }
        // The exponent bends the curve: squared, halfway is 8·(1 − 1/4) = 6.
        let squared = LodCurve {
            exponent: 2.0,
            ..curve(LodRounding::Down)
        };
        assert_eq!(squared.lod(8, 300.0), 6);
    }

    #[test]
    fn the_level_never_rises_with_distance() {
        for rounding in [LodRounding::Down, LodRounding::Nearest, LodRounding::Up] {
            for exponent in [0.25, 1.0, 3.0] {
                let c = LodCurve {
                    exponent,
                    ..curve(rounding)
                };
                let mut last = c.lod(10, 0.0);
                for step in 0..=700 {
                    let k = c.lod(10, f64::from(step));
                    assert!(k <= last, "{c:?} at {step} m");
                    last = k;
                }
            }
        }
    }

    #[test]
    fn box_and_centre_distances() {
        let (low, high) = (DVec3::ZERO, DVec3::new(10.0, 10.0, 2.0));
        let eye = DVec3::new(5.0, 5.0, 12.0);
        assert_eq!(patch_distance(eye, low, high, PatchDistance::Box), 10.0);
        assert_eq!(patch_distance(eye, low, high, PatchDistance::Centre), 11.0);
        let inside = DVec3::new(1.0, 1.0, 1.0);
        assert_eq!(patch_distance(inside, low, high, PatchDistance::Box), 0.0);
    }
}
