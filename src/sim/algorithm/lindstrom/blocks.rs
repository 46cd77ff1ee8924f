//! Lindstrom's quadtree of blocks (Lindstrom et al. 1996's discrete block levels; SPEC §6), built
//! once: who owns which vertex, and each block's δ range. It decides nothing per frame; the
//! coarse step (`coarse.rs`) reads it.
//!
//! The grid of side 2^n + 1 is covered by a complete quadtree of depth D = n − k (k the effective
//! block level, 1 ≤ k ≤ n). A node at depth d covers a square of side S_d = 2^(n−d) cells and is
//! a block of (2^k + 1)² samples at stride σ_d = S_d / 2^k = 2^(D−d); the leaves are blocks of
//! (2^k + 1)² samples at full resolution. A node *owns* the vertices that its sample grid adds
//! to its parent's, i.e. the 4-8 vertices of half-size exactly σ_d in its closed square; the root
//! owns every vertex of half-size ≥ σ_0 (the coarsest 2k levels of the 4-8 hierarchy). A vertex
//! on an edge shared by two nodes of the same depth belongs to the node on its east (north)
//! side, except on the grid's east (north) border. So the owned sets partition the non-corner
//! vertices, and every owned vertex lies in its node's closed square.
//!
//! Per node the build stores its square, the height range of the samples in it, its owned
//! vertices sorted by nested error δ (largest first, ties by id), and, for the whole subtree,
//! the largest δ and the number of vertices; the δ themselves stay in the nested errors it is
//! given, indexed by vertex id, read through the ids. Sorting by δ is what lets a frame
//! decide a node's vertices by interval tests without looking at them one by one
//! ([`super::coarse`]). Memory: 8 bytes per sample (a `u32` id per owned vertex and the `f32`
//! nested errors by id) plus about 72 bytes per node. The build sorts no list of every vertex:
//! it counts each node's vertices, puts every id straight into its node's range of the final id
//! array and sorts each range on its own (O(samples · log samples) at most). So while it runs it
//! holds the two arrays it keeps and 8 bytes per node, nothing more (issue #33: it held 16 bytes
//! per sample, a sorted (node, δ, id) list beside the errors; a δ array in the ids' order, made
//! from the errors in place, cost a cache miss a vertex, three times the build's time).

use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice, VertexClass};

/// One block of the quadtree.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct BlockNode {
    /// South-west corner of the node's square, in grid coordinates.
    pub(super) i0: u32,
    pub(super) j0: u32,
    /// Side of the square, in cells.
    pub(super) side: u32,
    pub(super) depth: u32,
    /// Lowest and highest sample height in the closed square.
    pub(super) z_min: f64,
    pub(super) z_max: f64,
    /// Range of the node's owned vertices in [`BlockTree::owned_ids`] / `owned_deltas`.
    pub(super) owned_start: usize,
    pub(super) owned_end: usize,
    /// The largest δ of any vertex owned by the node or its descendants.
    pub(super) subtree_delta_max: f32,
    /// Vertices owned by the node and its descendants.
    pub(super) subtree_vertices: u64,
    /// Nodes in the subtree, the node included.
    pub(super) subtree_nodes: u64,
}

/// The quadtree of blocks, nodes in breadth-first order (root first, then each depth row-major),
/// so a node's four children are found by index arithmetic.
#[derive(Clone, Debug)]
pub(super) struct BlockTree {
    block_level: u32,
    depth: u32,
    nodes: Vec<BlockNode>,
    owned_ids: Vec<u32>,
    /// δ of every vertex, indexed by id (0 at the corners, which no node owns).
    nested_errors: Vec<f32>,
}

impl BlockTree {
    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<BlockNode>()
            + self.owned_ids.capacity() * std::mem::size_of::<u32>()
            + self.nested_errors.capacity() * std::mem::size_of::<f32>()
    }

    /// Builds the tree for blocks of (2^`block_level` + 1)² samples; a `block_level` beyond the
    /// terrain's level means one block (the root) and 0 is taken as 1. `nested_errors` (indexed
    /// by id) is kept as the δ of every vertex; the build holds no more than the tree it
    /// returns, 8 bytes per sample, plus 8 bytes per node while it runs.
    pub(super) fn new(
        hierarchy: &Hierarchy,
        nested_errors: Vec<f32>,
        block_level: u32,
    ) -> BlockTree {
        let lattice = hierarchy.lattice();
        let block_level = block_level.clamp(1, lattice.level());
        let depth = lattice.level() - block_level;
        let n_nodes = nodes_in_complete_tree(depth);

        // Each node's range of the owned list: count its vertices, then prefix sums.
        let mut starts = vec![0usize; n_nodes as usize + 1];
        for_each_owned_vertex(lattice, depth, |node, _| starts[node as usize + 1] += 1);
        for index in 1..starts.len() {
            starts[index] += starts[index - 1];
        }
        let n_owned = starts[n_nodes as usize];
        // Every id into its node's range (filled from the range's end, so `ends` is back at the
        // starts when done), then each range sorted by δ, largest first, ties by id.
        let mut owned_ids = vec![0u32; n_owned];
        let mut ends = starts[1..].to_vec();
        for_each_owned_vertex(lattice, depth, |node, id| {
            let end = &mut ends[node as usize];
            *end -= 1;
            owned_ids[*end] = id;
        });
        drop(ends);
        for range in starts.windows(2) {
            owned_ids[range[0]..range[1]].sort_unstable_by(|&a, &b| {
                nested_errors[b as usize]
                    .total_cmp(&nested_errors[a as usize])
                    .then(a.cmp(&b))
            });
        }

        let mut nodes = Vec::with_capacity(n_nodes as usize);
        for node_depth in 0..=depth {
            let per_side = 1u32 << node_depth;
            let side = lattice.cells() >> node_depth;
            for b in 0..per_side {
                for a in 0..per_side {
                    let index = nodes.len();
                    let (owned_start, owned_end) = (starts[index], starts[index + 1]);
                    let (i0, j0) = (a * side, b * side);
                    let centre = GridPoint::new(i0 + side / 2, j0 + side / 2);
                    let (z_min, z_max) = hierarchy.node_height_range(centre, side / 2);
                    let own_max = if owned_start < owned_end {
                        nested_errors[owned_ids[owned_start] as usize]
                    } else {
                        0.0
                    };
                    nodes.push(BlockNode {
                        i0,
                        j0,
                        side,
                        depth: node_depth,
                        z_min: f64::from(z_min),
                        z_max: f64::from(z_max),
                        owned_start,
                        owned_end,
                        subtree_delta_max: own_max,
                        subtree_vertices: (owned_end - owned_start) as u64,
                        subtree_nodes: nodes_in_complete_tree(depth - node_depth),
                    });
                }
            }
        }
        // Children come after their parents: accumulate the subtree data backwards.
        for index in (1..nodes.len()).rev() {
            let parent = parent_index(&nodes[index]) as usize;
            let (delta, vertices) = (
                nodes[index].subtree_delta_max,
                nodes[index].subtree_vertices,
            );
            let parent_node = &mut nodes[parent];
            parent_node.subtree_delta_max = parent_node.subtree_delta_max.max(delta);
            parent_node.subtree_vertices += vertices;
        }
        BlockTree {
            block_level,
            depth,
            nodes,
            owned_ids,
            nested_errors,
        }
    }

    /// The effective k: blocks of (2^k + 1)² samples.
    pub(super) fn block_level(&self) -> u32 {
        self.block_level
    }

    /// D: the depth of the leaves.
    pub(super) fn depth(&self) -> u32 {
        self.depth
    }

    pub(super) fn nodes(&self) -> &[BlockNode] {
        &self.nodes
    }

    pub(super) fn node(&self, index: u32) -> &BlockNode {
        &self.nodes[index as usize]
    }

    /// The four children of a node (none for a leaf).
    pub(super) fn children(&self, index: u32) -> Option<[u32; 4]> {
        let node = self.node(index);
        (node.depth < self.depth).then(|| {
            let per_side = 1u32 << node.depth;
            let local = index - nodes_in_complete_tree_above(node.depth);
            let (a, b) = (local % per_side, local / per_side);
            let child = |da: u32, db: u32| {
                nodes_in_complete_tree_above(node.depth + 1)
                    + (2 * b + db) * (2 * per_side)
                    + 2 * a
                    + da
            };
            [child(0, 0), child(1, 0), child(0, 1), child(1, 1)]
        })
    }

    /// A node's owned vertex ids, largest δ first.
    pub(super) fn owned_ids(&self, node: &BlockNode) -> &[u32] {
        &self.owned_ids[node.owned_start..node.owned_end]
    }

    /// The nested error δ of the vertex `id`.
    pub(super) fn delta(&self, id: u32) -> f32 {
        self.nested_errors[id as usize]
    }

    /// The δ of a node's owned vertices, in the order of [`Self::owned_ids`] (non-increasing).
    pub(super) fn owned_deltas(&self, node: &BlockNode) -> impl Iterator<Item = f32> + '_ {
        self.owned_ids(node).iter().map(|&id| self.delta(id))
    }
}

/// Calls `visit(node, id)` for every non-corner vertex with the node that owns it, row by row.
fn for_each_owned_vertex(lattice: &Lattice, depth: u32, mut visit: impl FnMut(u32, u32)) {
    for j in 0..lattice.side() {
        for i in 0..lattice.side() {
            let point = GridPoint::new(i, j);
            let half = match lattice.classify(point) {
                VertexClass::Corner => continue,
                VertexClass::Square { half } | VertexClass::Rotated { half, .. } => half,
            };
            visit(
                owner(lattice.level(), depth, point, half),
                lattice.id(point),
            );
        }
    }
}

/// Nodes of a complete quadtree whose leaves are at `depth`: (4^(depth+1) − 1)/3.
fn nodes_in_complete_tree(depth: u32) -> u64 {
    ((1u64 << (2 * (depth + 1))) - 1) / 3
}

/// Index of the first node at `depth` in breadth-first order.
fn nodes_in_complete_tree_above(depth: u32) -> u32 {
    (((1u64 << (2 * depth)) - 1) / 3) as u32
}

fn parent_index(node: &BlockNode) -> u32 {
    let parent_depth = node.depth - 1;
    let parent_side = 2 * node.side;
    let per_side = 1u32 << parent_depth;
    nodes_in_complete_tree_above(parent_depth)
        + (node.j0 / parent_side) * per_side
        + node.i0 / parent_side
}

/// The node owning a non-corner vertex of half-size `half`: the depth whose stride is `half`
/// (the root for every half-size ≥ its stride), then the square holding the point, a shared edge
/// going to the east (north) square except on the grid's border.
fn owner(level: u32, depth: u32, point: GridPoint, half: u32) -> u32 {
    let log_half = half.trailing_zeros();
    let node_depth = depth.saturating_sub(log_half);
    let per_side = 1u32 << node_depth;
    let side = 1u32 << (level - node_depth);
    let a = (point.i / side).min(per_side - 1);
    let b = (point.j / side).min(per_side - 1);
    nodes_in_complete_tree_above(node_depth) + b * per_side + a
}
