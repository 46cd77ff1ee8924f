//! The quadtree matrix: one byte per grid point, as the paper stores it (§2.3, §3).
//!
//! The matrix has the grid's (2^n + 1)² entries, indexed like the vertices. Two kinds of entry
//! share it without overlapping:
//!
//! - at every **block centre** (a square vertex of the 4-8 lattice): the block's blend byte for
//!   this frame. 0 = not subdivided; 1..=255 = subdivided, with blend b = byte/255 (the paper's
//!   "255 morphing steps"). Rewritten every frame.
//! - at every block's **north edge midpoint** (c.i, c.j + half), a rotated vertex: the block's d2
//!   roughness as a one-byte code ([`D2Scale`]). Written once, by preprocessing. Each horizontal
//!   edge midpoint is the north midpoint of exactly one block (the one south of it), so no two
//!   blocks share a d2 entry, and no d2 entry sits on a block centre.
//!
//! The remaining entries (corners, vertical edge midpoints, the south border) stay 0. So the
//! paper's memory claim holds exactly: d2 and the blend values together take one byte per grid
//! point ([`QuadtreeMatrix::bytes_per_sample`]).
//!
//! The d2 code is logarithmic and relative to the terrain's largest local d2: code k ≥ 1 stands
//! for d2_max · 2^((k − 255)/8) (steps of 9 %, 31¾ octaves below d2_max), code 0 for exactly 0.
//! Values are rounded **up** to the next code, so a stored d2 never under-states the roughness;
//! below the smallest code they become the smallest code. The scale is dimensionless and a pure
//! function of the terrain's shape, so scaling terrain and flight together changes no code.

use crate::sim::hierarchy::{GridPoint, Lattice};

/// 2^(r/8) for r = 0..8, written out so that the code table is the same on every platform.
const EIGHTH_OCTAVES: [f64; 8] = [
    1.0,
    1.090_507_732_665_257_7,
    1.189_207_115_002_721,
    1.296_839_554_651_009_6,
    std::f64::consts::SQRT_2,
    1.542_210_825_407_940_7,
    1.681_792_830_507_429,
    1.834_008_086_409_342_4,
];

/// The one-byte code of d2 values: 256 values, increasing, code 255 = the terrain's largest d2.
#[derive(Clone, Debug, PartialEq)]
pub struct D2Scale {
    values: [f64; 256],
}

impl D2Scale {
    /// The scale whose top code is `d2_max` (≥ 0, finite). With `d2_max` = 0 every code decodes
    /// to 0.
    pub fn new(d2_max: f64) -> D2Scale {
        assert!(
            d2_max >= 0.0 && d2_max.is_finite(),
            "the largest d2 must be finite and at least 0, not {d2_max}"
        );
        let mut values = [0.0; 256];
        for (k, value) in values.iter_mut().enumerate().skip(1) {
            // k − 255 = 8q + r with 0 ≤ r < 8.
            let steps = k as i32 - 255;
            let q = steps.div_euclid(8);
            let r = steps.rem_euclid(8) as usize;
            *value = d2_max * EIGHTH_OCTAVES[r] * 2f64.powi(q);
        }
        D2Scale { values }
    }

    /// The value a code stands for.
    pub fn decode(&self, code: u8) -> f64 {
        self.values[code as usize]
    }

    /// The smallest code whose value is at least `d2` (255 for anything above the top), 0 only
    /// for `d2` ≤ 0.
    pub fn encode(&self, d2: f64) -> u8 {
        if d2 <= 0.0 || self.values[255] == 0.0 {
            return 0;
        }
        // First k in 1..=255 with values[k] ≥ d2.
        let k = 1 + self.values[1..].partition_point(|&value| value < d2);
        k.min(255) as u8
    }

    /// The top value (the terrain's largest local d2).
    pub fn largest(&self) -> f64 {
        self.values[255]
    }
}

/// One byte per grid point: blend bytes at block centres, d2 codes at north edge midpoints.
#[derive(Clone, Debug)]
pub struct QuadtreeMatrix {
    lattice: Lattice,
    bytes: Vec<u8>,
    scale: D2Scale,
}

impl QuadtreeMatrix {
    /// A matrix of zeros (no d2, nothing subdivided) with the given d2 scale.
    pub fn new(lattice: &Lattice, scale: D2Scale) -> QuadtreeMatrix {
        QuadtreeMatrix {
            lattice: *lattice,
            bytes: vec![0; lattice.n_vertices()],
            scale,
        }
    }

    pub fn scale(&self) -> &D2Scale {
        &self.scale
    }

    /// The entry holding the d2 code of the block centred at `centre` with half-size `half`.
    fn d2_index(&self, centre: GridPoint, half: u32) -> usize {
        self.lattice.id(GridPoint::new(centre.i, centre.j + half)) as usize
    }

    /// The stored d2 code of a block.
    pub fn d2_code(&self, centre: GridPoint, half: u32) -> u8 {
        self.bytes[self.d2_index(centre, half)]
    }

    /// The stored d2 of a block, decoded.
    pub fn d2(&self, centre: GridPoint, half: u32) -> f64 {
        self.scale.decode(self.d2_code(centre, half))
    }

    pub(super) fn set_d2_code(&mut self, centre: GridPoint, half: u32, code: u8) {
        let index = self.d2_index(centre, half);
        self.bytes[index] = code;
    }

    /// The blend byte of the block centred at vertex `id` (0: not subdivided this frame).
    pub fn blend_byte(&self, centre_id: u32) -> u8 {
        self.bytes[centre_id as usize]
    }

    pub(super) fn set_blend_byte(&mut self, centre_id: u32, byte: u8) {
        self.bytes[centre_id as usize] = byte;
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.bytes.capacity()
    }

    /// Bytes of the matrix per grid point: 1.
    pub fn bytes_per_sample(&self) -> f64 {
        self.bytes.len() as f64 / self.lattice.n_vertices() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_up_to_within_nine_percent_and_keep_zero_for_zero() {
        let scale = D2Scale::new(3.0);
        assert_eq!(scale.decode(255), 3.0);
        assert_eq!(scale.decode(247), 1.5);
        assert_eq!(scale.encode(0.0), 0);
        assert_eq!(scale.decode(0), 0.0);
        assert_eq!(scale.encode(3.0), 255);
        assert_eq!(scale.encode(1e9), 255);
        for k in 1..=254u8 {
            assert!(scale.decode(k) < scale.decode(k + 1));
            let ratio = scale.decode(k + 1) / scale.decode(k);
            assert!((ratio - 2f64.powf(0.125)).abs() < 1e-12, "{k}: {ratio}");
        }
        for x in [1e-12, 1e-9, 1e-3, 0.0123, 0.5, 1.0, 2.999] {
            let code = scale.encode(x);
            assert!(scale.decode(code) >= x, "{x} rounded down to {code}");
            if code > 1 {
                assert!(
                    scale.decode(code - 1) < x,
                    "{x} not rounded to the next code"
                );
            }
        }
    }

    #[test]
    fn a_flat_terrain_scale_stores_only_zeros() {
        let scale = D2Scale::new(0.0);
        assert_eq!(scale.encode(0.0), 0);
        assert_eq!(scale.decode(255), 0.0);
    }

    #[test]
    fn the_eighth_octave_table_matches_exp2() {
        for (r, value) in EIGHTH_OCTAVES.iter().enumerate() {
            assert!((value - (r as f64 / 8.0).exp2()).abs() < 1e-15);
        }
    }

    #[test]
    fn d2_entries_of_distinct_blocks_never_collide_with_each_other_or_with_centres() {
        let lattice = Lattice::new(4);
        let matrix = QuadtreeMatrix::new(&lattice, D2Scale::new(1.0));
        let mut owner = vec![None; lattice.n_vertices()];
        let mut half = 1;
        while half < lattice.cells() {
            for p in crate::sim::hierarchy::square_points(&lattice, half) {
                for index in [lattice.id(p) as usize, matrix.d2_index(p, half)] {
                    assert_eq!(owner[index], None, "{p:?} half {half}");
                    owner[index] = Some((p, half));
                }
            }
            half *= 2;
        }
        assert_eq!(matrix.bytes_per_sample(), 1.0);
    }
}
