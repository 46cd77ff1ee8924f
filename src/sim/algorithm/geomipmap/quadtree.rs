//! The quadtree over the patches that culls them (de Boer's, as Lauritsen–Nielsen §2.5 survey
//! it: "the patches are organised in a quadtree for view-frustum culling"): a node covers 2^m ×
//! 2^m patches and keeps their height range, so that a node whose box is outside the view is
//! left with everything below it, and a frame visits O(patches in view · log) nodes, not every
//! patch of the terrain. Built once, O(patches); it chooses no level (`levels.rs`).

use super::super::block_lod::cull::box_outside_view;
use super::super::block_lod::threshold::BlockBox;
use super::patches::PatchGrid;
use crate::sim::view::Camera;

/// What a descent found.
struct Found<'a> {
    patches: &'a mut Vec<u32>,
    culled: &'a mut Vec<((u32, u32), u32)>,
    visited: u64,
}

/// Per quadtree level (0: one node per patch), per node row by row, its lowest and highest
/// sample.
#[derive(Clone, Debug)]
pub(super) struct PatchQuadtree {
    z_ranges: Vec<Vec<(f32, f32)>>,
}

impl PatchQuadtree {
    /// Built bottom-up from the patches' height ranges.
    pub(super) fn new(grid: &PatchGrid) -> PatchQuadtree {
        let mut z_ranges = vec![(0..grid.n_patches()).map(|p| grid.z_range(p)).collect()];
        let mut side = grid.per_side() as usize;
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
        PatchQuadtree { z_ranges }
    }

    /// Pushes onto `out` the patches whose box is not outside `camera`'s view (all of them
    /// without a camera), ascending, and onto `culled` the squares of the nodes culled (their
    /// south-west sample and cells a side), which the mesh declares as culled regions; returns
    /// the nodes visited.
    pub(super) fn visible_patches(
        &self,
        grid: &PatchGrid,
        camera: Option<&Camera>,
        out: &mut Vec<u32>,
        culled: &mut Vec<((u32, u32), u32)>,
    ) -> u64 {
        out.clear();
        culled.clear();
        let Some(camera) = camera else {
            out.extend(0..grid.n_patches() as u32);
            return 0;
        };
        let top = self.z_ranges.len() - 1;
        let mut found = Found {
            patches: out,
            culled,
            visited: 0,
        };
        self.visit(grid, camera, top, 0, 0, &mut found);
        let visited = found.visited;
        out.sort_unstable();
        visited
    }

    fn visit(
        &self,
        grid: &PatchGrid,
        camera: &Camera,
        level: usize,
        x: u32,
        y: u32,
        found: &mut Found,
    ) {
        found.visited += 1;
        let side = grid.per_side() >> level;
        let (low, high) = self.z_ranges[level][(y * side + x) as usize];
        let patches = 1u32 << level;
        let first = grid.block_box((y * patches * grid.per_side() + x * patches) as usize);
        let last = grid.block_box(
            (((y + 1) * patches - 1) * grid.per_side() + (x + 1) * patches - 1) as usize,
        );
        let mut block = BlockBox {
            low: first.low,
            high: last.high,
        };
        (block.low.z, block.high.z) = (f64::from(low), f64::from(high));
        if box_outside_view(camera, &block) {
            let origin = grid.origin(x * patches, y * patches);
            found.culled.push((origin, patches * grid.cells()));
            return;
        }
        if level == 0 {
            found.patches.push(y * grid.per_side() + x);
            return;
        }
        for (cx, cy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            self.visit(grid, camera, level - 1, 2 * x + cx, 2 * y + cy, found);
        }
    }

    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.z_ranges
            .iter()
            .map(|level| level.capacity() * std::mem::size_of::<(f32, f32)>())
            .sum()
    }
}
