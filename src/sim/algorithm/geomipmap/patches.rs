//! The geomipmaps, built once (Lauritsen–Nielsen §2.5): the terrain cut into patches of
//! (2^k + 1)² samples, and per patch its height range and the error of each of its levels.
//!
//! Patch (px, py) covers the closed square of 2^k cells from sample (px·2^k, py·2^k); its
//! level ℓ (0 ≤ ℓ ≤ k) is the grid of its samples every 2^ℓ-th (level 0: all of them; level k:
//! its four corners). The error of level ℓ is de Boer's: the largest vertical distance of a
//! sample the level leaves out from the level's surface (the survey's fig. 2.13), i.e. the
//! largest |z − surface_ℓ| over the patch's samples, the surface being the level's grid with
//! each cell split along its south-west–north-east diagonal. Stored **nested**: D_ℓ is the
//! largest error of levels 0..=ℓ, so that D never falls as the level coarsens and the coarsest
//! acceptable level is a function of the distance alone (de Boer's errors usually grow with
//! the level anyway; where one does not, the nesting only keeps a patch finer). Rounded up to
//! `f32`.
//!
//! Build: O(samples · k). Memory: (k + 1) errors and a height range per patch, 4·(k + 3)
//! bytes, about 0.1 B per sample for 17² patches.

use super::super::block_lod::grid::round_up_f32;
use super::super::block_lod::threshold::BlockBox;
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use glam::DVec3;

/// The patches of one terrain and their level errors.
#[derive(Clone, Debug)]
pub(super) struct PatchGrid {
    /// k (clamped to the terrain): patches of 2^k cells a side.
    patch_level: u32,
    /// Patches per side.
    per_side: u32,
    dx: f64,
    dy: f64,
    /// Per patch (row by row): lowest and highest sample.
    z_range: Vec<(f32, f32)>,
    /// Per patch, k + 1 nested errors D_0 (= 0) .. D_k.
    errors: Vec<f32>,
}

impl PatchGrid {
    /// Cuts `hierarchy`'s terrain into patches of (2^`patch_level` + 1)² samples (the level
    /// clamped to [1, terrain level]).
    pub(super) fn new(hierarchy: &Hierarchy, patch_level: u32) -> PatchGrid {
        let terrain_level = hierarchy.lattice().level();
        let patch_level = patch_level.clamp(1, terrain_level);
        let per_side = 1u32 << (terrain_level - patch_level);
        let spacing = hierarchy.field().spacing();
        let mut grid = PatchGrid {
            patch_level,
            per_side,
            dx: spacing.dx,
            dy: spacing.dy,
            z_range: Vec::with_capacity((per_side * per_side) as usize),
            errors: Vec::with_capacity((per_side * per_side * (patch_level + 1)) as usize),
        };
        for py in 0..per_side {
            for px in 0..per_side {
                let (x0, y0) = grid.origin(px, py);
                let cells = grid.cells();
                let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
                for j in y0..=y0 + cells {
                    for i in x0..=x0 + cells {
                        let z = hierarchy.height(GridPoint::new(i, j));
                        low = low.min(z);
                        high = high.max(z);
                    }
                }
                grid.z_range.push((low, high));
                let mut nested: f64 = 0.0;
                grid.errors.push(0.0);
                for level in 1..=patch_level {
                    nested = nested.max(level_error(hierarchy, (x0, y0), cells, level));
                    grid.errors.push(round_up_f32(nested));
                }
            }
        }
        grid
    }

    /// k: patches have 2^k cells a side, levels 0..=k.
    pub(super) fn patch_level(&self) -> u32 {
        self.patch_level
    }

    pub(super) fn per_side(&self) -> u32 {
        self.per_side
    }

    pub(super) fn n_patches(&self) -> usize {
        (self.per_side * self.per_side) as usize
    }

    /// Cells per patch side.
    pub(super) fn cells(&self) -> u32 {
        1 << self.patch_level
    }

    /// The grid sample at patch (px, py)'s south-west corner.
    pub(super) fn origin(&self, px: u32, py: u32) -> (u32, u32) {
        (px * self.cells(), py * self.cells())
    }

    /// Patch `patch`'s nested error D_ℓ at `level`.
    pub(super) fn error(&self, patch: usize, level: u32) -> f32 {
        self.errors[patch * (self.patch_level as usize + 1) + level as usize]
    }

    /// Patch `patch`'s nested errors D_0 .. D_k.
    pub(super) fn errors(&self, patch: usize) -> &[f32] {
        let levels = self.patch_level as usize + 1;
        &self.errors[patch * levels..(patch + 1) * levels]
    }

    /// The patch's box: its square times its samples' height range.
    pub(super) fn block_box(&self, patch: usize) -> BlockBox {
        let (px, py) = (patch as u32 % self.per_side, patch as u32 / self.per_side);
        let (x0, y0) = self.origin(px, py);
        let cells = f64::from(self.cells());
        let (low, high) = self.z_range[patch];
        BlockBox {
            low: DVec3::new(
                f64::from(x0) * self.dx,
                f64::from(y0) * self.dy,
                f64::from(low),
            ),
            high: DVec3::new(
                (f64::from(x0) + cells) * self.dx,
                (f64::from(y0) + cells) * self.dy,
                f64::from(high),
            ),
        }
    }

    /// Patch `patch`'s lowest and highest sample.
    pub(super) fn z_range(&self, patch: usize) -> (f32, f32) {
        self.z_range[patch]
    }

    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.z_range.capacity() * std::mem::size_of::<(f32, f32)>()
            + self.errors.capacity() * std::mem::size_of::<f32>()
    }
}

/// The largest |z − surface| over the samples of the patch whose square starts at `origin` and
/// has `cells` cells a side, the surface being its grid every 2^`level` samples.
pub(super) fn level_error(
    hierarchy: &Hierarchy,
    origin: (u32, u32),
    cells: u32,
    level: u32,
) -> f64 {
    let stride = 1u32 << level;
    let n = cells / stride;
    let (x0, y0) = origin;
    let z = |i: u32, j: u32| f64::from(hierarchy.height(GridPoint::new(i, j)));
    let mut largest: f64 = 0.0;
    for b in 0..n {
        for a in 0..n {
            let (ci, cj) = (x0 + a * stride, y0 + b * stride);
            let (sw, se) = (z(ci, cj), z(ci + stride, cj));
            let (nw, ne) = (z(ci, cj + stride), z(ci + stride, cj + stride));
            let s = f64::from(stride);
            // Every sample of the closed cell (shared edges twice: harmless for a maximum).
            for v in 0..=stride {
                for u in 0..=stride {
                    let (fu, fv) = (f64::from(u), f64::from(v));
                    let surface = if u >= v {
                        sw + (fu * (se - sw) + fv * (ne - se)) / s
                    } else {
                        sw + (fu * (ne - nw) + fv * (nw - sw)) / s
                    };
                    largest = largest.max((z(ci + u, cj + v) - surface).abs());
                }
            }
        }
    }
    largest
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};

    fn terrain(level: u32, height: impl Fn(u32, u32) -> f32) -> Hierarchy {
        let side = (1usize << level) + 1;
        let heights = (0..side * side)
            .map(|k| height((k % side) as u32, (k / side) as u32))
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
    }

    #[test]
    fn a_plane_has_no_error_at_any_level() {
        let hierarchy = terrain(4, |i, j| 2.0 * i as f32 - j as f32);
        let grid = PatchGrid::new(&hierarchy, 2);
        assert_eq!(grid.n_patches(), 16);
        for patch in 0..16 {
            for level in 0..=2 {
                assert_eq!(grid.error(patch, level), 0.0);
            }
        }
    }

    #[test]
    fn a_spike_is_the_error_of_every_level_that_leaves_it_out_and_errors_nest() {
        // 9×9, patches of 5×5: the spike at (1, 1) is in patch (0, 0) only; level 1 (stride 2)
        // leaves it out (6 m), level 2 too.
        let hierarchy = terrain(3, |i, j| if (i, j) == (1, 1) { 6.0 } else { 0.0 });
        let grid = PatchGrid::new(&hierarchy, 2);
        assert_eq!([0, 1, 2].map(|level| grid.error(0, level)), [0.0, 6.0, 6.0]);
        assert_eq!(grid.error(1, 2), 0.0);
        // A bump on a sample level 1 keeps but level 2 drops: (2, 2), the patch's centre. Level
        // 1's surface rises to it, 2 m above the samples halfway; level 2's misses it.
        let hierarchy = terrain(3, |i, j| if (i, j) == (2, 2) { 4.0 } else { 0.0 });
        let grid = PatchGrid::new(&hierarchy, 2);
        assert_eq!([0, 1, 2].map(|level| grid.error(0, level)), [0.0, 2.0, 4.0]);
        let block = grid.block_box(0);
        assert_eq!((block.low.z, block.high.z, block.high.x), (0.0, 4.0, 40.0));
    }
}
