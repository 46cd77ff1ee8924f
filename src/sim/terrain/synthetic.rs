//! Seeded synthetic terrain by the diamond-square algorithm, for any (2^n+1)² size (SPEC §11:
//! synthetic terrains cover the sizes the real tiles cannot). It makes whole terrains before a
//! run; the detail chunked LOD synthesises during a run (Lauritsen–Nielsen) is separate
//! (`crate::sim::algorithm::chunked`).
//!
//! The generator is fully determined by its parameters: the random numbers come from a
//! SplitMix64 stream seeded by `seed`, visited in a fixed order, so the same parameters give
//! bit-identical heights on every machine. Displacements shrink by 2^(−roughness) per level
//! (roughness is the Hurst exponent H: 1 is smooth, 0 is rough).

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

/// Generates the height field.
pub fn generate(params: &SyntheticTerrain) -> Result<Heightfield, HeightfieldError> {
    let side = (1usize << params.level) + 1;
    let mut rng = SplitMix64(params.seed);
    let mut z = vec![0.0f64; side * side];
    let at = |i: usize, j: usize| j * side + i;
    for &(i, j) in &[(0, 0), (side - 1, 0), (0, side - 1), (side - 1, side - 1)] {
        z[at(i, j)] = rng.symmetric() * params.amplitude;
    }
    let mut amplitude = params.amplitude;
    let decay = 0.5f64.powf(params.roughness);
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
    let heights = z.into_iter().map(|h| h as f32).collect();
    Heightfield::new(side, heights, params.spacing)
}

/// SplitMix64: a tiny, well-mixed, fully specified generator (Steele et al. 2014).
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
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

    #[test]
    fn different_seeds_give_different_terrains_with_relief() {
        let a = generate(&params(1)).unwrap();
        let b = generate(&params(2)).unwrap();
        assert_ne!(a.heights(), b.heights());
        let (lo, hi) = a.height_range();
        assert!(hi - lo > 10.0, "relief {lo}..{hi}");
    }
}
