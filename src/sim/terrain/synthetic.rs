//! Seeded synthetic terrain by the diamond-square algorithm, for any (2^n+1)² size (SPEC §11:
//! synthetic terrains cover the sizes the real tiles cannot). It makes whole terrains before a
//! run; the detail chunked LOD synthesises during a run (Lauritsen–Nielsen) is separate
//! (`crate::sim::algorithm::chunked`).
//!
//! The generator is fully determined by its parameters: the random numbers come from a
//! SplitMix64 stream seeded by `seed`, visited in a fixed order, so the same parameters give
//! bit-identical heights on every machine. Displacements shrink by 2^(−roughness) per level
//! (roughness is the Hurst exponent H: 1 is smooth, 0 is rough).
//!
//! **6 bytes per sample at most.** The steps run in `f64` on the samples of even coordinates
//! only (a quarter of them, 2 bytes per sample); the finest level is computed from them straight
//! into the `f32` heights, so a 16385² terrain is made in 1.6 GB, not 3.2 GB of `f64` plus its
//! copy. The heights are bit-identical to running every level on the whole grid in `f64`
//! (`tests` keep that generator and compare).

use super::{Heightfield, HeightfieldError, Spacing};

/// Parameters of a synthetic terrain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SyntheticTerrain {
    /// The side is 2^level + 1.
    pub level: u32,
    pub seed: u64,
    /// Initial displacement amplitude in metres (heights span roughly ± this).
    pub amplitude: f64,
    /// Hurst exponent in [0, 1].
    pub roughness: f64,
    pub spacing: Spacing,
}

/// Generates the height field: 6 bytes per sample at most, its 4-byte heights included (the
/// module docs).
pub fn generate(params: &SyntheticTerrain) -> Result<Heightfield, HeightfieldError> {
    let side = (1usize << params.level) + 1;
    let decay = 0.5f64.powf(params.roughness);
    let mut rng = SplitMix64(params.seed);
    // Every level but the finest, on the samples of even coordinates: the same steps, in the same
    // order, drawing the same numbers as on the whole grid.
    let coarse_side = side.div_ceil(2);
    let (coarse, amplitude) = diamond_square(coarse_side, &mut rng, params.amplitude, decay);
    let finest = FinestLevel {
        coarse: &coarse,
        coarse_side,
        diamond_draws: rng.0,
        amplitude,
    };
    Heightfield::new(side, finest.heights(), params.spacing)
}

/// The diamond-square steps over a whole grid of side 2^k + 1 (k ≥ 0), from `amplitude`,
/// shrinking it by `decay` per level; the heights and the amplitude of the next level.
fn diamond_square(
    side: usize,
    rng: &mut SplitMix64,
    amplitude: f64,
    decay: f64,
) -> (Vec<f64>, f64) {
    let mut z = vec![0.0f64; side * side];
    let at = |i: usize, j: usize| j * side + i;
    for &(i, j) in &[(0, 0), (side - 1, 0), (0, side - 1), (side - 1, side - 1)] {
        z[at(i, j)] = rng.symmetric() * amplitude;
    }
    let mut amplitude = amplitude;
    let mut step = side - 1;
    while step > 1 {
        let half = step / 2;
        // Diamond step: block centres from the four corners.
        for j in (half..side).step_by(step) {
            for i in (half..side).step_by(step) {
                let mean = (z[at(i - half, j - half)]
                    + z[at(i + half, j - half)]
                    + z[at(i - half, j + half)]
                    + z[at(i + half, j + half)])
                    / 4.0;
                z[at(i, j)] = mean + rng.symmetric() * amplitude;
            }
        }
        // Square step: edge midpoints from their (up to four) diamond neighbours.
        for j in (0..side).step_by(half) {
            let first = if (j / half).is_multiple_of(2) {
                half
            } else {
                0
            };
            for i in (first..side).step_by(step) {
                let mut sum = 0.0;
                let mut count = 0.0;
                if i >= half {
                    sum += z[at(i - half, j)];
                    count += 1.0;
                }
                if i + half < side {
                    sum += z[at(i + half, j)];
                    count += 1.0;
                }
                if j >= half {
                    sum += z[at(i, j - half)];
                    count += 1.0;
                }
                if j + half < side {
                    sum += z[at(i, j + half)];
                    count += 1.0;
                }
                z[at(i, j)] = sum / count + rng.symmetric() * amplitude;
            }
        }
        amplitude *= decay;
        step = half;
    }
    (z, amplitude)
}

/// The finest level's diamond and square steps (step 2), written straight into the `f32`
/// heights: the samples of odd coordinates are never held in `f64`. A block centre the square
/// step needs is computed again from its corners and its own draw (SplitMix64's n-th number is
/// O(1) to reach), bit-identical to the value the whole-grid steps hold.
struct FinestLevel<'c> {
    /// The samples of even coordinates, (`coarse_side`)², in `f64`.
    coarse: &'c [f64],
    coarse_side: usize,
    /// The generator's state before the first draw of this level.
    diamond_draws: u64,
    amplitude: f64,
}

impl FinestLevel<'_> {
    fn heights(&self) -> Vec<f32> {
        let side = 2 * self.coarse_side - 1;
        let mut heights = vec![0.0f32; side * side];
        for (k, z) in self.coarse.iter().enumerate() {
            let (i, j) = (k % self.coarse_side, k / self.coarse_side);
            heights[2 * j * side + 2 * i] = *z as f32;
        }
        let centres_per_row = self.coarse_side - 1;
        for j in (1..side).step_by(2) {
            for i in (1..side).step_by(2) {
                heights[j * side + i] = self.centre(i, j) as f32;
            }
        }
        let mut rng = SplitMix64::after(
            self.diamond_draws,
            (centres_per_row * centres_per_row) as u64,
        );
        // The square step: every sample with one odd coordinate, from its (up to four)
        // neighbours, in the whole-grid steps' order.
        let z = |i: usize, j: usize| {
            if i.is_multiple_of(2) {
                self.coarse[(j / 2) * self.coarse_side + i / 2]
            } else {
                self.centre(i, j)
            }
        };
        for j in 0..side {
            let first = if j.is_multiple_of(2) { 1 } else { 0 };
            for i in (first..side).step_by(2) {
                let mut sum = 0.0;
                let mut count = 0.0;
                if i >= 1 {
                    sum += z(i - 1, j);
                    count += 1.0;
                }
                if i + 1 < side {
                    sum += z(i + 1, j);
                    count += 1.0;
                }
                if j >= 1 {
                    sum += z(i, j - 1);
                    count += 1.0;
                }
                if j + 1 < side {
                    sum += z(i, j + 1);
                    count += 1.0;
                }
                heights[j * side + i] = (sum / count + rng.symmetric() * self.amplitude) as f32;
            }
        }
        heights
    }

    /// The block centre at odd (`i`, `j`): the mean of its four corners plus its own draw.
    fn centre(&self, i: usize, j: usize) -> f64 {
        let (a, b) = ((i - 1) / 2, (j - 1) / 2);
        let corner = |a: usize, b: usize| self.coarse[b * self.coarse_side + a];
        let mean =
            (corner(a, b) + corner(a + 1, b) + corner(a, b + 1) + corner(a + 1, b + 1)) / 4.0;
        let draw = (b * (self.coarse_side - 1) + a) as u64;
        mean + SplitMix64::after(self.diamond_draws, draw).symmetric() * self.amplitude
    }
}

/// SplitMix64: a tiny, well-mixed, fully specified generator (Steele et al. 2014).
struct SplitMix64(u64);

/// SplitMix64's increment: its state after n draws is the seed plus n of them.
const SPLITMIX64_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

impl SplitMix64 {
    /// The generator `draws` numbers after one whose state is `state`.
    fn after(state: u64, draws: u64) -> SplitMix64 {
        SplitMix64(state.wrapping_add(draws.wrapping_mul(SPLITMIX64_GAMMA)))
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(SPLITMIX64_GAMMA);
        let mut x = self.0;
        x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        x ^ (x >> 31)
    }

    /// Uniform in [−1, 1).
    fn symmetric(&mut self) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        2.0 * unit - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(seed: u64) -> SyntheticTerrain {
        SyntheticTerrain {
            level: 5,
            seed,
            amplitude: 100.0,
            roughness: 0.7,
            spacing: Spacing { dx: 10.0, dy: 10.0 },
        }
    }

    #[test]
    fn the_same_seed_gives_the_same_terrain() {
        let a = generate(&params(7)).unwrap();
        let b = generate(&params(7)).unwrap();
        assert_eq!(a.heights(), b.heights());
        assert_eq!(a.side(), 33);
    }

    /// The generator as it ran before the finest level was streamed: every level on the whole
    /// grid in `f64`.
    fn whole_grid(params: &SyntheticTerrain) -> Vec<f32> {
        let side = (1usize << params.level) + 1;
        let decay = 0.5f64.powf(params.roughness);
        let (z, _) = diamond_square(side, &mut SplitMix64(params.seed), params.amplitude, decay);
        z.into_iter().map(|h| h as f32).collect()
    }

    #[test]
    fn heights_equal_the_whole_grid_generator_bit_for_bit() {
        for level in 1..=7 {
            for (seed, roughness) in [(7, 0.7), (2001, 0.5), (u64::MAX, 0.0)] {
                let params = SyntheticTerrain {
                    level,
                    seed,
                    amplitude: 300.0,
                    roughness,
                    spacing: Spacing { dx: 30.0, dy: 30.0 },
                };
                let streamed: Vec<u32> = generate(&params)
                    .unwrap()
                    .heights()
                    .iter()
                    .map(|z| z.to_bits())
                    .collect();
                let whole: Vec<u32> = whole_grid(&params).iter().map(|z| z.to_bits()).collect();
                assert_eq!(streamed, whole, "level {level}, seed {seed}");
            }
        }
    }

    #[test]
    fn different_seeds_give_different_terrains_with_relief() {
        let a = generate(&params(1)).unwrap();
        let b = generate(&params(2)).unwrap();
        assert_ne!(a.heights(), b.heights());
        let (lo, hi) = a.height_range();
        assert!(hi - lo > 10.0, "relief {lo}..{hi}");
    }
}
