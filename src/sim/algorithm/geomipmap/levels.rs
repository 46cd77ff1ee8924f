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

/// One frame's drawn patches, and their levels, factors and distances. Indexed by patch (row
/// by row) and sized once for every patch; only the entries of this frame's drawn patches
/// ([`PatchLevels::drawn`]) are this frame's, so that a frame touches only what it draws (with
/// box culling, the patches in view, not the whole terrain).
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
    /// This frame's drawn patches, ascending.
    pub(super) drawn: Vec<u32>,
    /// Per patch, the number of the last frame that drew it.
    drawn_in: Vec<u32>,
    /// This frame's number (from 1).
    frame: u32,
    /// Per level, the patches whose level is being relaxed (reused).
    buckets: Vec<Vec<u32>>,
}

impl PatchLevels {
    /// Room for every patch of `grid`; nothing drawn yet.
    pub(super) fn new(grid: &PatchGrid) -> PatchLevels {
        let n = grid.n_patches();
        PatchLevels {
            distance: vec![0.0; n],
            own: vec![0; n],
            level: vec![0; n],
            morph: vec![1.0; n],
            drawn: Vec::new(),
            drawn_in: vec![0; n],
            frame: 0,
            buckets: vec![Vec::new(); grid.patch_level() as usize + 1],
        }
    }

    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        (self.distance.capacity() + self.morph.capacity()) * std::mem::size_of::<f64>()
            + (self.own.capacity()
                + self.level.capacity()
                + self.drawn.capacity()
                + self.drawn_in.capacity())
                * std::mem::size_of::<u32>()
            + self
                .buckets
                .iter()
                .map(|b| b.capacity() * std::mem::size_of::<u32>())
                .sum::<usize>()
    }

    /// Whether `patch` is drawn this frame.
    pub(super) fn is_drawn(&self, patch: usize) -> bool {
        self.drawn_in[patch] == self.frame
    }

    /// This frame's number (from 1).
    pub(super) fn frame(&self) -> u32 {
        self.frame
    }

    /// The drawn neighbours of `patch` (WEST, EAST, SOUTH, NORTH); `None` at the terrain's
    /// edge and where the neighbour is not drawn (a culled neighbour needs no stitch).
    pub(super) fn neighbours(&self, grid: &PatchGrid, patch: usize) -> [Option<usize>; 4] {
        let per_side = grid.per_side() as usize;
        let (px, py) = (patch % per_side, patch / per_side);
        [
            (px > 0).then(|| patch - 1),
            (px + 1 < per_side).then(|| patch + 1),
            (py > 0).then(|| patch - per_side),
            (py + 1 < per_side).then(|| patch + per_side),
        ]
        .map(|q| q.filter(|&q| self.is_drawn(q)))
    }

    /// The level and factor each side (WEST, EAST, SOUTH, NORTH) of patch `patch` is drawn at:
    /// its own, or its drawn neighbour's where that looks coarser.
    pub(super) fn sides(&self, grid: &PatchGrid, patch: usize) -> [(u32, f64); 4] {
        let own = (self.level[patch], self.morph[patch]);
        self.neighbours(grid, patch)
            .map(|neighbour| match neighbour {
                None => own,
                Some(q) => coarser(own, (self.level[q], self.morph[q])),
            })
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

/// Starts a frame drawing the patches `drawn` (ascending) and measures their distances.
pub(super) fn measure(drawn: &[u32], distance: impl Fn(usize) -> f64, out: &mut PatchLevels) {
    out.frame += 1;
    out.drawn.clear();
    out.drawn.extend_from_slice(drawn);
    for &patch in drawn {
        out.drawn_in[patch as usize] = out.frame;
        out.distance[patch as usize] = distance(patch as usize);
    }
}

/// Chooses every drawn patch's level for `threshold` (steps 1 and 2); returns the level tests
/// made. O(drawn patches · levels).
pub(super) fn choose_levels(
    grid: &PatchGrid,
    threshold: &DetailThreshold,
    difference: LevelDifference,
    out: &mut PatchLevels,
) -> u64 {
    let k = grid.patch_level();
    let mut tests = 0;
    for &patch in &out.drawn {
        let patch = patch as usize;
        let errors = grid.errors(patch);
        let d = out.distance[patch];
        let mut level = k;
        loop {
            tests += 1;
            if level == 0 || !threshold.refines(errors[level as usize], d) {
                break;
            }
            level -= 1;
        }
        out.own[patch] = level;
        out.level[patch] = level;
    }
    if difference == LevelDifference::AtMostOne {
        // ℓ(P) = min over drawn Q of ℓ_own(Q) + |P − Q|₁ along drawn patches: a breadth-first
        // relaxation by level (every patch drawn: the city-block distance transform).
        let mut buckets = std::mem::take(&mut out.buckets);
        for &patch in &out.drawn {
            buckets[out.level[patch as usize] as usize].push(patch);
        }
        for l in 0..buckets.len() {
            while let Some(patch) = buckets[l].pop() {
                if out.level[patch as usize] != l as u32 {
                    continue;
                }
                for q in out.neighbours(grid, patch as usize).into_iter().flatten() {
                    if out.level[q] > l as u32 + 1 {
                        out.level[q] = l as u32 + 1;
                        buckets[l + 1].push(q as u32);
                    }
                }
            }
        }
        out.buckets = buckets;
    }
    tests
}

/// Sets every drawn patch's morph factor from its level (step 3).
pub(super) fn set_morph_factors(
    grid: &PatchGrid,
    threshold: &DetailThreshold,
    morph: bool,
    out: &mut PatchLevels,
) {
    let k = grid.patch_level();
    for &patch in &out.drawn {
        let patch = patch as usize;
        let level = out.level[patch];
        out.morph[patch] = if morph && level < k {
            threshold.morph_factor(
                grid.error(patch, level),
                grid.error(patch, level + 1),
                out.distance[patch],
            )
        } else {
            1.0
        };
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
