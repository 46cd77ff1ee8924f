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
//! vertices sorted by nested error δ (largest first, ties by id) with their δ, and, for the
//! whole subtree, the largest δ and the number of vertices. Sorting by δ is what lets a frame
//! decide a node's vertices by interval tests without looking at them one by one
//! ([`super::coarse`]). Memory: 8 bytes per sample (a `u32` id and an `f32` δ per vertex) plus
//! about 72 bytes per node. The build sorts no list of every vertex: it counts each node's
//! vertices, puts every id straight into its node's range of the final id array, sorts each range
//! on its own (O(samples · log samples) at most), and turns the nested errors it is given (4 bytes
//! per sample, indexed by id) into the δ array in place. So while it runs it holds the two
//! arrays it keeps, 1/8 byte per sample of visited bits and 8 bytes per node, and nothing more
//! (issue #33: it held 16 bytes per sample, a sorted (node, δ, id) list beside the errors).

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
    owned_deltas: Vec<f32>,
}

impl BlockTree {
    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<BlockNode>()
            + self.owned_ids.capacity() * std::mem::size_of::<u32>()
            + self.owned_deltas.capacity() * std::mem::size_of::<f32>()
    }

    /// Builds the tree for blocks of (2^`block_level` + 1)² samples; a `block_level` beyond the
    /// terrain's level means one block (the root) and 0 is taken as 1. `nested_errors` (indexed
    /// by id) becomes the δ array; the build holds no more than the tree it returns, 8 bytes per
    /// sample, plus 1/8 byte per sample and 8 bytes per node while it runs.
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
        // In place: the nested errors, indexed by id, become the δ of the owned list.
        let owned_deltas = owned_deltas_in_place(
            nested_errors,
            &owned_ids,
            lattice.corners().map(|corner| lattice.id(corner)),
        );
        BlockTree {
            block_level,
            depth,
            nodes,
            owned_ids,
            owned_deltas,
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

    /// The δ of a node's owned vertices, in the order of [`Self::owned_ids`] (non-increasing).
    pub(super) fn owned_deltas(&self, node: &BlockNode) -> &[f32] {
        &self.owned_deltas[node.owned_start..node.owned_end]
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

/// The δ of every owned vertex in the order of `owned_ids`, made from `nested_errors` (indexed
/// by id) in its own buffer: `owned_ids` followed by `corner_ids` is a permutation of the ids,
/// applied cycle by cycle with one visited bit per id; the corners' entries, moved to the end,
/// are then cut off. O(samples), 1/8 byte per sample besides its input.
fn owned_deltas_in_place(
    mut nested_errors: Vec<f32>,
    owned_ids: &[u32],
    corner_ids: [u32; 4],
) -> Vec<f32> {
    let n = nested_errors.len();
    assert_eq!(
        owned_ids.len() + corner_ids.len(),
        n,
        "the owned vertices and the corners are every vertex"
    );
    let source = |position: usize| -> usize {
        match owned_ids.get(position) {
            Some(&id) => id as usize,
            None => corner_ids[position - owned_ids.len()] as usize,
        }
    };
    let mut visited = vec![0u64; n.div_ceil(64)];
    for start in 0..n {
        if visited[start / 64] & (1 << (start % 64)) != 0 {
            continue;
        }
        // Along the cycle through `start`: each position takes the value of its source.
        let first = nested_errors[start];
        let mut position = start;
        loop {
            visited[position / 64] |= 1 << (position % 64);
            let from = source(position);
            if from == start {
                nested_errors[position] = first;
                break;
            }
            nested_errors[position] = nested_errors[from];
            position = from;
        }
    }
    nested_errors.truncate(owned_ids.len());
    nested_errors.shrink_to_fit();
    nested_errors
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

#[cfg(test)]
mod tests {
    use super::owned_deltas_in_place;

    #[test]
    fn the_deltas_made_in_place_are_the_nested_errors_in_the_owned_order() {
        for n in [4usize, 5, 9, 25, 81, 1000] {
            let nested: Vec<f32> = (0..n).map(|id| id as f32 * 1.5 + 0.25).collect();
            let corner_ids = [0, 1, (n / 2) as u32, (n - 1) as u32];
            // The other ids scrambled: cycles of many lengths through the corners' places too.
            let mut owned_ids: Vec<u32> = (0..n as u32)
                .filter(|id| !corner_ids.contains(id))
                .collect();
            owned_ids.sort_by_key(|&id| (u64::from(id) * 2_654_435_761) % 1009);
            let expected: Vec<f32> = owned_ids.iter().map(|&id| nested[id as usize]).collect();
            let deltas = owned_deltas_in_place(nested, &owned_ids, corner_ids);
            assert_eq!(deltas, expected, "{n} ids");
            assert_eq!(deltas.capacity(), owned_ids.len());
        }
    }
}
