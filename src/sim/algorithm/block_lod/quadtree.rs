//! The quadtree over a square grid of patches that culls them (de Boer's, as Lauritsen–Nielsen
//! §2.5 survey it: "the patches are organised in a quadtree for view-frustum culling"), shared
//! by `geomipmap` and `vanek`: a node covers 2^m × 2^m patches and keeps their height range, so
//! that a node whose box is outside the view is left with everything below it, and a frame
//! visits O(patches in view · log) nodes, not every patch of the terrain. Built once,
//! O(patches); it chooses no level and knows nothing of what a patch draws.
//!
//! A node's box is its square times its patches' height range, so a patch's (level 0) box is
//! the patch's own and a child's box lies inside its parent's: the per-plane test
//! (`cull.rs`) then culls a node only where it would cull each of its patches (a corner of a
//! child is a convex combination of the parent's corners, and the margin is convex), so the
//! patches left are those the per-patch test keeps.

use super::cull::box_outside_view;
use super::threshold::BlockBox;
use crate::sim::terrain::Spacing;
use crate::sim::view::Camera;
use glam::DVec3;

/// What a descent found.
struct Found<'a> {
    patches: &'a mut Vec<u32>,
    culled: &'a mut Vec<((u32, u32), u32)>,
    visited: u64,
}

/// Per quadtree level (0: one node per patch), per node row by row, its lowest and highest
/// sample; and where the patches lie.
#[derive(Clone, Debug)]
pub(crate) struct PatchQuadtree {
    /// Patches per side (a power of two).
    per_side: u32,
    /// Cells per patch side.
    cells: u32,
    spacing: Spacing,
    z_ranges: Vec<Vec<(f32, f32)>>,
}

impl PatchQuadtree {
    /// Built bottom-up from the patches' height ranges (`z_range(patch)`, patches row by row
    /// from the south-west; patch (px, py) covers `cells` cells a side from sample
    /// (px·cells, py·cells)). `per_side` must be a power of two.
    pub(crate) fn new(
        per_side: u32,
        cells: u32,
        spacing: Spacing,
        z_range: impl Fn(usize) -> (f32, f32),
    ) -> PatchQuadtree {
        assert!(
            per_side.is_power_of_two(),
            "a patch quadtree needs a power-of-two number of patches a side, not {per_side}"
        );
        let n = (per_side * per_side) as usize;
        let mut z_ranges = vec![(0..n).map(z_range).collect::<Vec<_>>()];
        let mut side = per_side as usize;
        while side > 1 {
            let finer: &Vec<(f32, f32)> = z_ranges.last().expect("the patches' level");
            let half = side / 2;
            let mut coarser = Vec::with_capacity(half * half);
            for y in 0..half {
                for x in 0..half {
                    let children = [
                        finer[2 * y * side + 2 * x],
                        finer[2 * y * side + 2 * x + 1],
                        finer[(2 * y + 1) * side + 2 * x],
                        finer[(2 * y + 1) * side + 2 * x + 1],
                    ];
                    coarser.push(children.iter().fold(
                        (f32::INFINITY, f32::NEG_INFINITY),
                        |(low, high), &(l, h)| (low.min(l), high.max(h)),
                    ));
                }
            }
            z_ranges.push(coarser);
            side = half;
        }
        PatchQuadtree {
            per_side,
            cells,
            spacing,
            z_ranges,
        }
    }

    /// Pushes onto `out` the patches whose box is not outside `camera`'s view (all of them
    /// without a camera), ascending, and onto `culled` the squares of the nodes culled (their
    /// south-west sample and cells a side), which the mesh declares as culled regions; returns
    /// the nodes visited.
    pub(crate) fn visible_patches(
        &self,
        camera: Option<&Camera>,
        out: &mut Vec<u32>,
        culled: &mut Vec<((u32, u32), u32)>,
    ) -> u64 {
        out.clear();
        culled.clear();
        let Some(camera) = camera else {
            out.extend(0..self.per_side * self.per_side);
            return 0;
        };
        let top = self.z_ranges.len() - 1;
        let mut found = Found {
            patches: out,
            culled,
            visited: 0,
        };
        self.visit(camera, top, 0, 0, &mut found);
        let visited = found.visited;
        out.sort_unstable();
        visited
    }

    fn visit(&self, camera: &Camera, level: usize, x: u32, y: u32, found: &mut Found) {
        found.visited += 1;
        let side = self.per_side >> level;
        let (low, high) = self.z_ranges[level][(y * side + x) as usize];
        let patches = 1u32 << level;
        let node_cells = patches * self.cells;
        let (x0, y0) = (x * node_cells, y * node_cells);
        let block = BlockBox {
            low: DVec3::new(
                f64::from(x0) * self.spacing.dx,
                f64::from(y0) * self.spacing.dy,
                f64::from(low),
            ),
            high: DVec3::new(
                f64::from(x0 + node_cells) * self.spacing.dx,
                f64::from(y0 + node_cells) * self.spacing.dy,
                f64::from(high),
            ),
        };
        if box_outside_view(camera, &block) {
            found.culled.push(((x0, y0), node_cells));
            return;
        }
        if level == 0 {
            found.patches.push(y * self.per_side + x);
            return;
        }
        for (cx, cy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            self.visit(camera, level - 1, 2 * x + cx, 2 * y + cy, found);
        }
    }

    /// Heap bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.z_ranges
            .iter()
            .map(|level| level.capacity() * std::mem::size_of::<(f32, f32)>())
            .sum()
    }
}
