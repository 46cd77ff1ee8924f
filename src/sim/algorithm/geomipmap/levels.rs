//! Each frame's patch levels: the criterion, the limit on neighbouring levels, morph factors,
//! and what each patch border is drawn at (de Boer's level selection and morphing, not in
//! `papers/`, as Lauritsen–Nielsen §2.5 surveys it). Recomputed from scratch every frame. It
//! is not the levels' errors (built once, `patches.rs`), nor the triangles (`stitch.rs`), nor
//! the choice of τ under a triangle target (`block_lod/budget.rs`).
//!
//! 1. **Criterion** (de Boer, as Lauritsen–Nielsen §2.5 and eq. 3.3 give it): a patch at
//!    distance d is drawn at its coarsest level ℓ whose d_ℓ = D_ℓ·C is not above d (d < d_ℓ
//!    would need more detail). With D nested, levels 0..=ℓ all pass and ℓ + 1.. all fail, so
//!    this is the level the survey's step-by-step rule (finer while the error is too large,
//!    coarser while the coarser one's is small enough) settles on, reached in one frame.
//! 2. **Neighbours** ([`LevelDifference::AtMostOne`], the default: the survey's fig. 2.14 skips
//!    every other border vertex, one level of difference): a patch more than one level coarser
//!    than a neighbour is refined until it is not, which never coarsens anything. The result is
//!    ℓ(P) = min over all patches Q of (ℓ_own(Q) + |P − Q|₁), computed in two raster sweeps (a
//!    city-block distance transform). [`LevelDifference::Any`] keeps the criterion's levels.
//! 3. **Morph factor** (de Boer's, eq. 3.5): f = 1 − (d − d_ℓ)/(d_ℓ+1 − d_ℓ), clamped; 1 at the
//!    coarsest level (nothing coarser to morph to) and with morphing off. A patch refined for its
//!    neighbours sits beyond d_ℓ+1 and so at f = 0: it looks like the level it would have had.
//! 4. **Borders.** The border between P and Q is drawn by both at the level and factor of the
//!    one that looks coarser (the higher level; at equal levels the smaller f), so that their
//!    vertices there agree exactly: the finer patch leaves out the border vertices the coarser
//!    one lacks (stitching, `stitch.rs`), and both morph the border's own odd vertices alike.

use super::super::block_lod::threshold::DetailThreshold;
use super::patches::PatchGrid;

/// Whether neighbouring patches may differ by more than one level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LevelDifference {
    /// At most one (the survey's figure 2.14): coarser patches are refined to keep it.
    AtMostOne,
    /// Any: stitching skips as many border vertices as the difference needs.
    Any,
}

/// A patch side, in the order of [`PatchLevels::side`].
pub(super) const WEST: usize = 0;
pub(super) const EAST: usize = 1;
pub(super) const SOUTH: usize = 2;
pub(super) const NORTH: usize = 3;

/// One frame's levels, factors and distances, per patch (row by row).
#[derive(Clone, Debug, Default)]
pub(super) struct PatchLevels {
    /// d per patch (does not depend on τ).
    pub(super) distance: Vec<f64>,
    /// The criterion's level.
    pub(super) own: Vec<u32>,
    /// The level drawn (after the neighbour limit).
    pub(super) level: Vec<u32>,
    /// The morph factor (1 with morphing off).
    pub(super) morph: Vec<f64>,
}

impl PatchLevels {
    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        (self.distance.capacity() + self.morph.capacity()) * std::mem::size_of::<f64>()
            + (self.own.capacity() + self.level.capacity()) * std::mem::size_of::<u32>()
    }

    /// The level and factor each side (WEST, EAST, SOUTH, NORTH) of patch `patch` is drawn at:
    /// its own, or its neighbour's where that looks coarser. Written out, without an array
    /// map's closure calls (the update asks it of every patch every frame).
    pub(super) fn sides(&self, grid: &PatchGrid, patch: usize) -> [(u32, f64); 4] {
        let per_side = grid.per_side() as usize;
        let (px, py) = (patch % per_side, patch / per_side);
        let own = (self.level[patch], self.morph[patch]);
        let with = |neighbour: Option<usize>| match neighbour {
            None => own,
            Some(q) => coarser(own, (self.level[q], self.morph[q])),
        };
        [
            with((px > 0).then(|| patch - 1)),
            with((px + 1 < per_side).then(|| patch + 1)),
            with((py > 0).then(|| patch - per_side)),
            with((py + 1 < per_side).then(|| patch + per_side)),
        ]
    }
}

/// The state that looks coarser: the higher level, at equal levels the smaller factor.
pub(super) fn coarser(a: (u32, f64), b: (u32, f64)) -> (u32, f64) {
    if b.0 > a.0 || (b.0 == a.0 && b.1 < a.1) {
        b
    } else {
        a
    }
}

/// Measures every patch's distance (once per frame).
pub(super) fn measure(grid: &PatchGrid, distance: impl Fn(usize) -> f64, out: &mut PatchLevels) {
    out.distance.clear();
    out.distance.extend((0..grid.n_patches()).map(distance));
}

/// Chooses every patch's level for `threshold` (steps 1 and 2); returns the level tests made.
pub(super) fn choose_levels(
    grid: &PatchGrid,
    threshold: &DetailThreshold,
    difference: LevelDifference,
    out: &mut PatchLevels,
) -> u64 {
    let k = grid.patch_level();
    let mut tests = 0;
    out.own.clear();
    for (errors, &d) in grid.errors_by_patch().zip(&out.distance) {
        let mut level = k;
        loop {
            tests += 1;
            if level == 0 || !threshold.refines(errors[level as usize], d) {
                break;
            }
            level -= 1;
        }
        out.own.push(level);
    }
    out.level.clear();
    out.level.extend_from_slice(&out.own);
    if difference == LevelDifference::AtMostOne {
        let n = grid.per_side() as usize;
        let level = &mut out.level;
        for y in 0..n {
            for x in 0..n {
                let mut l = level[y * n + x];
                if x > 0 {
                    l = l.min(level[y * n + x - 1] + 1);
                }
                if y > 0 {
                    l = l.min(level[(y - 1) * n + x] + 1);
                }
                level[y * n + x] = l;
            }
        }
        for y in (0..n).rev() {
            for x in (0..n).rev() {
                let mut l = level[y * n + x];
                if x + 1 < n {
                    l = l.min(level[y * n + x + 1] + 1);
                }
                if y + 1 < n {
                    l = l.min(level[(y + 1) * n + x] + 1);
                }
                level[y * n + x] = l;
            }
        }
    }
    tests
}

/// Sets every patch's morph factor from its level (step 3).
pub(super) fn set_morph_factors(
    grid: &PatchGrid,
    threshold: &DetailThreshold,
    morph: bool,
    out: &mut PatchLevels,
) {
    let k = grid.patch_level();
    out.morph.clear();
    for patch in 0..grid.n_patches() {
        let level = out.level[patch];
        let f = if morph && level < k {
            threshold.morph_factor(
                grid.error(patch, level),
                grid.error(patch, level + 1),
                out.distance[patch],
            )
        } else {
            1.0
        };
        out.morph.push(f);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coarser_state_is_the_higher_level_then_the_smaller_factor() {
        assert_eq!(coarser((1, 0.2), (2, 0.9)), (2, 0.9));
        assert_eq!(coarser((2, 0.3), (2, 0.9)), (2, 0.3));
        assert_eq!(coarser((2, 0.9), (2, 0.3)), (2, 0.3));
        assert_eq!(coarser((3, 1.0), (1, 0.0)), (3, 1.0));
    }
}
