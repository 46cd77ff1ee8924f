//! The full quadtree of M-blocks, built once before the first frame (the paper builds the whole
//! tree in advance and selects nodes from it each frame, §3.3.1): where each node's block lies,
//! its height range, and its 32 object-space errors δ_i.
//!
//! Geometry (raw units, 1/65 536 of a cell): node (depth d, ix, iy) owns the square of side
//! 2^(N − d) cells at (ix, iy)·side. Its **region** is that square less half a strip width on
//! every side that is not on the domain's border: every such side lies on the centre line of an
//! ancestor's split, where the cross of strips (and the P-block at its centre) sits. A leaf's
//! M-block is its region; a split node's region is its children's regions, its own cross of four
//! strips and its P-block, with nothing left over. With strip width 0 (Methods I and II)
//! regions are the squares.
//!
//! δ_i (i = 1 ..= 32) is the mean, over the grid samples of the node's square, of the absolute
//! difference between the sample and the square tessellated at F = 2i (the regular 2i × 2i
//! grid, heights resampled bilinearly, cells cut along their south-west–north-east diagonal).
//! The square, not the region: the errors, and so the quadtree a view selects, are the same
//! whatever the strip width, and the same for the strips and Method I (the paper's figure 18
//! compares the two on one quadtree); a block narrower by a strip differs from it by a sliver.
//! Cost: O(Σ_nodes Σ_i (samples in the region + (2i + 1)²)), once; memory 136 bytes a node.

use super::tessellate::{EdgeSpacing, Rect, edge_positions, resampled_height};
use crate::sim::mesh::SUBGRID_UNITS_PER_CELL;
use crate::sim::terrain::Heightfield;

/// Object-space errors per node: δ_i for F = 2i, i = 1 ..= 32.
pub const LEVELS: usize = 32;

/// A node of the quadtree: its depth (0 = the whole terrain) and its column and row at that
/// depth, from the south-west.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct NodeId {
    pub depth: u32,
    pub ix: u32,
    pub iy: u32,
}

impl NodeId {
    pub const ROOT: NodeId = NodeId {
        depth: 0,
        ix: 0,
        iy: 0,
    };

    /// The four children: south-west, south-east, north-west, north-east.
    pub fn children(self) -> [NodeId; 4] {
        let (x, y) = (2 * self.ix, 2 * self.iy);
        let d = self.depth + 1;
        [(x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1)].map(|(ix, iy)| NodeId { depth: d, ix, iy })
    }
}

/// Children order of [`NodeId::children`].
pub const SW: usize = 0;
pub const SE: usize = 1;
pub const NW: usize = 2;
pub const NE: usize = 3;

/// The quadtree and its per-node data.
#[derive(Debug)]
pub struct Tree {
    terrain_level: u32,
    /// L: the deepest depth (its blocks are 2^(N − L) cells a side).
    depth_max: u32,
    /// Half the strip width, raw units.
    half_width: i64,
    domain: i64,
    errors: Vec<[f32; LEVELS]>,
    z_range: Vec<(f32, f32)>,
}

impl Tree {
    /// Builds the tree of `field` down to blocks of 2^`block_level` cells (1 ≤ block_level ≤ N)
    /// with strips `2 · half_width` raw units wide (less than half the smallest block).
    pub fn new(field: &Heightfield, block_level: u32, half_width: i64) -> Tree {
        let terrain_level = field.level();
        assert!(
            (1..=terrain_level).contains(&block_level),
            "block level {block_level} outside 1 ..= {terrain_level}"
        );
        let depth_max = terrain_level - block_level;
        let domain = (1i64 << terrain_level) * SUBGRID_UNITS_PER_CELL;
        assert!(
            half_width >= 0 && 4 * half_width <= (1i64 << block_level) * SUBGRID_UNITS_PER_CELL,
            "strips of {half_width}·2 raw units do not fit blocks of 2^{block_level} cells"
        );
        let n_nodes = ((1usize << (2 * (depth_max + 1))) - 1) / 3;
        let mut tree = Tree {
            terrain_level,
            depth_max,
            half_width,
            domain,
            errors: vec![[0.0; LEVELS]; n_nodes],
            z_range: vec![(0.0, 0.0); n_nodes],
        };
        let mut scratch = ErrorScratch::default();
        for depth in 0..=depth_max {
            for iy in 0..1u32 << depth {
                for ix in 0..1u32 << depth {
                    let id = NodeId { depth, ix, iy };
                    let index = tree.index(id);
                    tree.z_range[index] = square_height_range(field, tree.square(id));
                    let square = tree.square(id);
                    for (i, error) in tree.errors[index].iter_mut().enumerate() {
                        *error = mean_error(field, square, 2 * (i as u32 + 1), &mut scratch);
                    }
                }
            }
        }
        tree
    }

    pub fn depth_max(&self) -> u32 {
        self.depth_max
    }

    pub fn half_width(&self) -> i64 {
        self.half_width
    }

    pub fn n_nodes(&self) -> usize {
        self.errors.len()
    }

    /// The node's position in the dense arrays: depth by depth, row by row.
    pub fn index(&self, id: NodeId) -> usize {
        ((1usize << (2 * id.depth)) - 1) / 3 + ((id.iy as usize) << id.depth) + id.ix as usize
    }

    /// The node's square, raw units.
    pub fn square(&self, id: NodeId) -> Rect {
        let side = (1i64 << (self.terrain_level - id.depth)) * SUBGRID_UNITS_PER_CELL;
        let (x0, y0) = (i64::from(id.ix) * side, i64::from(id.iy) * side);
        Rect {
            x0,
            y0,
            x1: x0 + side,
            y1: y0 + side,
        }
    }

    /// The node's region: its square less half a strip on every side inside the domain.
    pub fn region(&self, id: NodeId) -> Rect {
        let s = self.square(id);
        let h = self.half_width;
        let inside = |v: i64| v > 0 && v < self.domain;
        Rect {
            x0: s.x0 + if inside(s.x0) { h } else { 0 },
            y0: s.y0 + if inside(s.y0) { h } else { 0 },
            x1: s.x1 - if inside(s.x1) { h } else { 0 },
            y1: s.y1 - if inside(s.y1) { h } else { 0 },
        }
    }

    /// δ_1 ..= δ_32 of the node.
    pub fn errors(&self, id: NodeId) -> &[f32; LEVELS] {
        &self.errors[self.index(id)]
    }

    /// The lowest and highest sample of the node's square (every resampled height inside it
    /// lies between them).
    pub fn z_range(&self, id: NodeId) -> (f32, f32) {
        self.z_range[self.index(id)]
    }

    pub fn memory_bytes(&self) -> usize {
        self.errors.capacity() * std::mem::size_of::<[f32; LEVELS]>()
            + self.z_range.capacity() * std::mem::size_of::<(f32, f32)>()
    }
}

fn square_height_range(field: &Heightfield, square: Rect) -> (f32, f32) {
    let cell = SUBGRID_UNITS_PER_CELL;
    let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
    for j in (square.y0 / cell) as usize..=(square.y1 / cell) as usize {
        for i in (square.x0 / cell) as usize..=(square.x1 / cell) as usize {
            let z = field.height(i, j);
            low = low.min(z);
            high = high.max(z);
        }
    }
    (low, high)
}

#[derive(Debug, Default)]
struct ErrorScratch {
    us: Vec<i64>,
    vs: Vec<i64>,
    heights: Vec<f64>,
}

/// The mean absolute vertical difference between the samples inside `region` and the region
/// tessellated as the regular n × n grid (n even).
fn mean_error(field: &Heightfield, region: Rect, n: u32, scratch: &mut ErrorScratch) -> f32 {
    let cell = SUBGRID_UNITS_PER_CELL;
    let spacing = EdgeSpacing::FractionalEven(f64::from(n));
    scratch.us.clear();
    scratch.vs.clear();
    edge_positions(region.x0, region.x1, spacing, &mut scratch.us);
    edge_positions(region.y0, region.y1, spacing, &mut scratch.vs);
    let side = n as usize + 1;
    scratch.heights.clear();
    for &y in &scratch.vs {
        for &x in &scratch.us {
            scratch
                .heights
                .push(f64::from(resampled_height(field, x, y)));
        }
    }
    let locate = |positions: &[i64], v: i64| {
        // The cell holding v: positions are increasing, n + 1 of them.
        let k = positions.partition_point(|&p| p <= v).clamp(1, n as usize) - 1;
        let fraction = (v - positions[k]) as f64 / (positions[k + 1] - positions[k]) as f64;
        (k, fraction)
    };
    let (mut sum, mut count) = (0.0, 0u64);
    let (i0, i1) = ((region.x0 + cell - 1) / cell, region.x1 / cell);
    let (j0, j1) = ((region.y0 + cell - 1) / cell, region.y1 / cell);
    for j in j0..=j1 {
        let (b, fv) = locate(&scratch.vs, j * cell);
        for i in i0..=i1 {
            let (a, fu) = locate(&scratch.us, i * cell);
            let z = |a: usize, b: usize| scratch.heights[b * side + a];
            let (z00, z10, z01, z11) = (z(a, b), z(a + 1, b), z(a, b + 1), z(a + 1, b + 1));
            let drawn = if fu >= fv {
                z00 + fu * (z10 - z00) + fv * (z11 - z10)
            } else {
                z00 + fv * (z01 - z00) + fu * (z11 - z01)
            };
            sum += (f64::from(field.height(i as usize, j as usize)) - drawn).abs();
            count += 1;
        }
    }
    if count == 0 {
        0.0
    } else {
        (sum / count as f64) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::Spacing;

    fn field(side: usize, f: impl Fn(usize, usize) -> f32) -> Heightfield {
        let heights = (0..side * side).map(|k| f(k % side, k / side)).collect();
        Heightfield::new(side, heights, Spacing { dx: 1.0, dy: 1.0 }).expect("a field")
    }

    #[test]
    fn regions_tile_the_parent_with_its_cross() {
        let tree = Tree::new(&field(33, |_, _| 0.0), 2, SUBGRID_UNITS_PER_CELL / 2);
        let root = tree.region(NodeId::ROOT);
        assert_eq!(
            root,
            tree.square(NodeId::ROOT),
            "the root touches the border all round"
        );
        let c = NodeId::ROOT.children();
        let h = SUBGRID_UNITS_PER_CELL / 2;
        let mid = 16 * SUBGRID_UNITS_PER_CELL;
        assert_eq!(tree.region(c[SW]).x1, mid - h);
        assert_eq!(tree.region(c[SE]).x0, mid + h);
        assert_eq!(tree.region(c[NW]).y0, mid + h);
        assert_eq!(tree.n_nodes(), 1 + 4 + 16 + 64);
        assert_eq!(
            tree.index(NodeId {
                depth: 3,
                ix: 7,
                iy: 7
            }),
            84
        );
    }

    #[test]
    fn planes_have_no_error_and_a_spike_has_less_error_at_finer_factors() {
        let plane = Tree::new(&field(17, |i, j| (3 * i + j) as f32), 1, 0);
        assert!(plane.errors.iter().flatten().all(|&e| e.abs() < 1e-5));
        let spike = Tree::new(
            &field(17, |i, j| if (i, j) == (5, 7) { 9.0 } else { 0.0 }),
            1,
            0,
        );
        let root = spike.errors(NodeId::ROOT);
        assert!(root[0] > 0.0);
        // At F = 16 (and every multiple of 16) the grid holds every sample: no error.
        assert_eq!(root[7], 0.0);
        assert_eq!(root[15], 0.0);
    }
}
