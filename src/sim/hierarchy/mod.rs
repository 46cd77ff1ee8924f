//! The 4-8 hierarchy of a height field (SPEC §3) and the data preprocessing attaches to it: Wu's
//! node errors and height ranges (Wu et al. 2001 §4.2), and the other papers' nested errors on
//! demand. It is built once per terrain and shared, read-only, by the algorithms; the index
//! arithmetic is `lattice.rs`.
//!
//! [`Hierarchy::new`] is one O(samples) bottom-up pass that computes, for every square node
//! (Wu's quadtree block): the node error δ under Wu's rule (max of the sub-blocks' δ, the centre's
//! |ε| and the four boundary vertices' |ε|) and the block's height range. The finest blocks count
//! their boundary vertices too, as the paper says (§3.1: the vertices that depend on a leaf node
//! are its children). Both are stored, 12 bytes per node, in a dense array ([`SquareIndex`]
//! order) for every level but the finest. The finest blocks (half-size 1), three quarters of all
//! nodes, store nothing: their δ and height range are computed on demand from the block's 9
//! samples, O(1) and bit-identical to what storing them would give. That is 12 bytes per 12
//! samples, i.e. 1 byte per sample on top of the 4-byte heights.
//!
//! **The node table is built when first read.** Only some algorithms read it (Wu's, the reference,
//! Lindstrom's block ranges, Röttger's clipping boxes: `AlgorithmConfig::reads_node_table`); a
//! run of the others never pays its byte per sample. [`Hierarchy::build_node_table`] builds it
//! up front (the session does, inside the terrain's timed preprocessing, when an entry reads it);
//! any reader that comes first builds it itself, so what is read never depends on when it was
//! built. The heights are held by an [`Arc`], so a run shares the experiment's one copy.
//!
//! Other papers' nested errors over
//! all vertices ([`NestingRule`]) are built on demand by [`Hierarchy::nested_vertex_errors`], so a
//! run pays only for the rules its algorithms use.
//! Errors are rounded up to `f32`, never down, so they stay bounds.

mod lattice;

pub use lattice::{Few, GridPoint, Lattice, VertexClass};

use crate::sim::terrain::Heightfield;
use std::sync::{Arc, OnceLock};

/// How a vertex's error is nested over its descendants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NestingRule {
    /// e(v) = max(|ε(v)|, e(children)): Wu's and Lindstrom's rule. Monotone, but not a bound of
    /// the surface's distance from the mesh.
    Max,
    /// e(v) = |ε(v)| + max e(children): ROAM's nested wedgie thickness, a true bound.
    MaxPlusOwn,
}

/// Dense indices of square nodes, coarsest level first, row-major within a level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SquareIndex {
    cells: u32,
}

impl SquareIndex {
    pub fn n_squares(&self) -> usize {
        ((self.cells as usize).pow(2) - 1) / 3
    }

    /// Index of the square node centred at `p` with the given half-size.
    pub fn index(&self, p: GridPoint, half: u32) -> usize {
        let per_side = (self.cells / (2 * half)) as usize;
        let level_offset = (per_side * per_side - 1) / 3;
        let a = (p.i / (2 * half)) as usize;
        let b = (p.j / (2 * half)) as usize;
        level_offset + b * per_side + a
    }
}

/// A height field with its 4-8 hierarchy and Wu's per-node data.
#[derive(Clone, Debug)]
pub struct Hierarchy {
    field: Arc<Heightfield>,
    lattice: Lattice,
    square_index: SquareIndex,
    /// Per square node of half-size ≥ 2 (the first `nodes.len()` indices of [`SquareIndex`]),
    /// contiguous so that one node's data is one cache access. The finest level is not stored.
    /// Built when first read (the module docs).
    nodes: OnceLock<Vec<NodeData>>,
}

/// What preprocessing stores per square node.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct NodeData {
    error: f32,
    z_min: f32,
    z_max: f32,
}

impl Hierarchy {
    /// The hierarchy of a height field, sharing it (a `Heightfield` given by value is moved in,
    /// not copied). O(1): Wu's node table (O(samples) time, 12 bytes per square node above the
    /// finest level) is built by [`Hierarchy::build_node_table`] or by its first reader.
    pub fn new(field: impl Into<Arc<Heightfield>>) -> Hierarchy {
        let field = field.into();
        // A `Heightfield`'s level is within the lattice's (`terrain::MAX_PAGED_LEVEL`).
        let lattice = Lattice::new(field.level());
        Hierarchy {
            field,
            lattice,
            square_index: SquareIndex {
                cells: lattice.cells(),
            },
            nodes: OnceLock::new(),
        }
    }

    /// Builds Wu's node table now (once: later calls do nothing). O(samples).
    pub fn build_node_table(&self) {
        self.node_table();
    }

    /// Whether Wu's node table has been built.
    pub fn has_node_table(&self) -> bool {
        self.nodes.get().is_some()
    }

    pub fn field(&self) -> &Heightfield {
        &self.field
    }

    /// The height field, shared (e.g. with a GPU-side stage that samples it as a texture).
    pub fn shared_field(&self) -> Arc<Heightfield> {
        Arc::clone(&self.field)
    }

    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    pub fn square_index(&self) -> SquareIndex {
        self.square_index
    }

    pub fn height(&self, p: GridPoint) -> f32 {
        self.field.height(p.i as usize, p.j as usize)
    }

    /// ε(v) = z(v) − (z(a) + z(b))/2 for the edge (a, b) that v bisects; 0 for corners.
    pub fn vertex_error(&self, p: GridPoint) -> f64 {
        match self.lattice.bisected_edge(p) {
            None => 0.0,
            Some([a, b]) => {
                f64::from(self.height(p))
                    - 0.5 * (f64::from(self.height(a)) + f64::from(self.height(b)))
            }
        }
    }

    /// Wu's node error δ of the square node at `p`. O(1).
    pub fn node_error(&self, p: GridPoint, half: u32) -> f32 {
        self.node_data(p, half).error
    }

    /// Lowest and highest sample height in the closed block of the square node at `p`. O(1).
    pub fn node_height_range(&self, p: GridPoint, half: u32) -> (f32, f32) {
        let node = self.node_data(p, half);
        (node.z_min, node.z_max)
    }

    /// Wu's node error δ and the block's height range of the square node at `p`, in one access.
    pub fn node_error_and_range(&self, p: GridPoint, half: u32) -> (f32, f32, f32) {
        let node = self.node_data(p, half);
        (node.error, node.z_min, node.z_max)
    }

    /// Bytes per sample of the heights (a paged field's cache at its bound and records) and
    /// Wu's node data if built (the heap capacity held).
    pub fn bytes_per_sample(&self) -> f64 {
        let heights = self.field.paged_samples().map_or_else(
            || std::mem::size_of_val(self.field.heights()),
            |paged| paged.memory_bytes(),
        );
        let nodes = self.nodes.get().map_or(0, |nodes| {
            nodes.capacity() * std::mem::size_of::<NodeData>()
        });
        (heights + nodes) as f64 / self.field.n_samples() as f64
    }

    /// The stored data of a node above the finest level, or the finest node's data computed from
    /// its 9 samples.
    #[inline]
    fn node_data(&self, p: GridPoint, half: u32) -> NodeData {
        if half == 1 {
            self.finest_node_data(p)
        } else {
            self.node_table()[self.square_index.index(p, half)]
        }
    }

    /// Wu's node table, built on first use.
    #[inline]
    fn node_table(&self) -> &[NodeData] {
        self.nodes.get_or_init(|| self.compute_node_table())
    }

    /// δ and height range of the finest block centred at `p` (half-size 1), from its 3 × 3 samples:
    /// the same values, rounded the same way, as the generic rule (centre and boundary vertex
    /// errors by [`Hierarchy::vertex_error`]) gives; `tests` check it on every block.
    fn finest_node_data(&self, p: GridPoint) -> NodeData {
        let side = self.lattice.side() as usize;
        let heights = self.field.heights();
        let base = (p.j as usize - 1) * side + p.i as usize - 1;
        let row = |r: usize| -> [f32; 3] {
            let start = base + r * side;
            match heights.get(start..start + 3) {
                Some(&[a, b, c]) => [a, b, c],
                _ => unreachable!("a finest block lies inside the grid"),
            }
        };
        // z[row][column], row 0 to the south, column 0 to the west.
        let z = [row(0), row(1), row(2)];
        // Heights are finite (a `Heightfield` invariant), so plain comparisons are exact; they
        // give the values `f32::min`/`max` folded in row-major order give.
        let mut z_min = z[0][0];
        let mut z_max = z[0][0];
        for value in z.as_flattened() {
            z_min = if *value < z_min { *value } else { z_min };
            z_max = if *value > z_max { *value } else { z_max };
        }
        let z64 = |r: usize, c: usize| f64::from(z[r][c]);
        let midpoint_error = |v: f64, a: f64, b: f64| (v - 0.5 * (a + b)).abs();
        // The centre bisects the block's diagonal that does not join its parents (see
        // `Lattice::bisected_edge`): the parents are on the main diagonal exactly when the
        // south-west corner's coordinates, in units of 2, have mixed parity.
        let odd = |x: u32| (x / 2) % 2 == 1;
        let centre = if odd(p.i - 1) != odd(p.j - 1) {
            midpoint_error(z64(1, 1), z64(0, 2), z64(2, 0))
        } else {
            midpoint_error(z64(1, 1), z64(0, 0), z64(2, 2))
        };
        // West and east midpoints bisect vertical edges, south and north ones horizontal edges.
        let west = midpoint_error(z64(1, 0), z64(0, 0), z64(2, 0));
        let east = midpoint_error(z64(1, 2), z64(0, 2), z64(2, 2));
        let south = midpoint_error(z64(0, 1), z64(0, 0), z64(0, 2));
        let north = midpoint_error(z64(2, 1), z64(2, 0), z64(2, 2));
        NodeData {
            error: round_up(max_of_finite(&[centre, west, east, south, north])),
            z_min,
            z_max,
        }
    }

    /// Every vertex's nested error under `rule`, indexed by vertex id (0 at corners). O(samples);
    /// holds nothing but its result (4 bytes per sample).
    pub fn nested_vertex_errors(&self, rule: NestingRule) -> Vec<f32> {
        let lattice = &self.lattice;
        let mut nested = vec![0.0f32; lattice.n_vertices()];
        for p in vertices_finest_first(lattice) {
            nested[lattice.id(p) as usize] = self.nest(p, rule, &nested);
        }
        nested
    }

    fn nest(&self, p: GridPoint, rule: NestingRule, nested: &[f32]) -> f32 {
        let own = self.vertex_error(p).abs();
        let children = self
            .lattice
            .children(p)
            .as_slice()
            .iter()
            .map(|c| f64::from(nested[self.lattice.id(*c) as usize]))
            .fold(0.0, f64::max);
        round_up(match rule {
            NestingRule::Max => own.max(children),
            NestingRule::MaxPlusOwn => own + children,
        })
    }

    /// The stored levels (half-size ≥ 2), finest first; their sub-blocks are stored or, at
    /// half-size 2, computed from samples.
    fn compute_node_table(&self) -> Vec<NodeData> {
        // The finest level is the last of the index: everything before it is stored.
        let n_stored = self.square_index.n_squares() - (self.lattice.cells() as usize / 2).pow(2);
        let mut nodes = vec![NodeData::default(); n_stored];
        let mut half = 2;
        while half < self.lattice.cells() {
            for p in square_points(&self.lattice, half) {
                let k = self.square_index.index(p, half);
                let mut error = self.vertex_error(p).abs();
                for boundary in self.lattice.boundary_vertices(p, half) {
                    error = error.max(self.vertex_error(boundary).abs());
                }
                let (mut z_min, mut z_max) = (f32::INFINITY, f32::NEG_INFINITY);
                if let Some(sub_blocks) = self.lattice.sub_blocks(p, half) {
                    for sub in sub_blocks {
                        let sub = if half == 2 {
                            self.finest_node_data(sub)
                        } else {
                            nodes[self.square_index.index(sub, half / 2)]
                        };
                        error = error.max(f64::from(sub.error));
                        z_min = z_min.min(sub.z_min);
                        z_max = z_max.max(sub.z_max);
                    }
                }
                nodes[k] = NodeData {
                    error: round_up(error),
                    z_min,
                    z_max,
                };
            }
            half *= 2;
        }
        nodes
    }
}

/// All square centres of half-size `half`.
pub fn square_points(lattice: &Lattice, half: u32) -> impl Iterator<Item = GridPoint> + use<> {
    let cells = lattice.cells();
    (half..cells).step_by(2 * half as usize).flat_map(move |j| {
        (half..cells)
            .step_by(2 * half as usize)
            .map(move |i| GridPoint::new(i, j))
    })
}

/// Every non-corner vertex, level by level from the finest: the rotated vertices of half-size 1,
/// the squares of half-size 1, the rotated vertices of half-size 2, and so on. A vertex's
/// children (rotated(h)'s are squares of half-size h/2, square(h)'s are rotated(h)) come before
/// it, so a bottom-up table can be filled in one pass. Generated as read: O(1) memory.
pub fn vertices_finest_first(lattice: &Lattice) -> impl Iterator<Item = GridPoint> + use<> {
    let lattice = *lattice;
    std::iter::successors(Some(1u32), |half| half.checked_mul(2))
        .take_while(move |&half| half < lattice.cells())
        .flat_map(move |half| {
            rotated_points(&lattice, half, true)
                .chain(rotated_points(&lattice, half, false))
                .chain(square_points(&lattice, half))
        })
}

/// All rotated vertices of half-size `half` on horizontal (or vertical) edges, row by row,
/// generated as they are read (nothing is collected: at half-size 1 they are half the samples).
fn rotated_points(
    lattice: &Lattice,
    half: u32,
    horizontal: bool,
) -> impl Iterator<Item = GridPoint> + use<> {
    let cells = lattice.cells();
    let step = 2 * half as usize;
    // Odd multiples of `half` strictly inside, even ones from border to border.
    let odd = move || (half..cells).step_by(step);
    let even = move || (0..cells + 1).step_by(step);
    let (rows, columns) = if horizontal {
        (even(), odd())
    } else {
        (odd(), even())
    };
    rows.flat_map(move |j| columns.clone().map(move |i| GridPoint::new(i, j)))
}

/// The largest of finite values.
fn max_of_finite(values: &[f64; 5]) -> f64 {
    let mut largest = values[0];
    for value in &values[1..] {
        largest = if *value > largest { *value } else { largest };
    }
    largest
}

/// The smallest `f32` not below `value` (stored errors stay bounds).
pub(crate) fn round_up(value: f64) -> f32 {
    let rounded = value as f32;
    if f64::from(rounded) < value {
        rounded.next_up()
    } else {
        rounded
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::Spacing;

    fn hierarchy(side: usize, height: impl Fn(usize, usize) -> f32) -> Hierarchy {
        let heights = (0..side * side)
            .map(|k| height(k % side, k / side))
            .collect();
        let field = Heightfield::new(side, heights, Spacing { dx: 1.0, dy: 1.0 }).unwrap();
        Hierarchy::new(field)
    }

    #[test]
    fn square_indices_are_dense_and_distinct() {
        let h = hierarchy(17, |_, _| 0.0);
        let index = h.square_index();
        let mut seen = vec![false; index.n_squares()];
        let mut half = 1;
        while half < 16 {
            for p in square_points(h.lattice(), half) {
                let k = index.index(p, half);
                assert!(!seen[k], "index {k} used twice");
                seen[k] = true;
            }
            half *= 2;
        }
        assert!(seen.iter().all(|&s| s));
        assert_eq!(index.index(h.lattice().root(), 8), 0);
    }

    #[test]
    fn a_single_spike_sets_the_error_of_every_node_whose_block_holds_it() {
        // A 10 m spike at (5, 5) of a flat 9×9 field.
        let h = hierarchy(9, |i, j| if (i, j) == (5, 5) { 10.0 } else { 0.0 });
        assert_eq!(h.node_error(GridPoint::new(5, 5), 1), 10.0);
        assert_eq!(h.node_error(GridPoint::new(6, 6), 2), 10.0);
        assert_eq!(h.node_error(h.lattice().root(), 4), 10.0);
        assert_eq!(h.node_error(GridPoint::new(2, 2), 2), 0.0);
        assert_eq!(h.node_height_range(GridPoint::new(2, 2), 2), (0.0, 0.0));
        assert_eq!(h.node_height_range(h.lattice().root(), 4), (0.0, 10.0));
        // (7, 7)'s block [6,8]² does not hold the spike.
        assert_eq!(h.node_error(GridPoint::new(7, 7), 1), 0.0);
    }

    #[test]
    fn a_plane_has_zero_error_everywhere() {
        let h = hierarchy(17, |i, j| 3.0 * i as f32 - 2.0 * j as f32 + 7.0);
        let mut half = 1;
        while half < 16 {
            assert!(square_points(h.lattice(), half).all(|p| h.node_error(p, half) == 0.0));
            half *= 2;
        }
        let nested = h.nested_vertex_errors(NestingRule::MaxPlusOwn);
        assert!(nested.iter().all(|&e| e == 0.0));
    }

    #[test]
    fn nesting_rules_are_monotone_and_max_plus_own_dominates_max() {
        let h = hierarchy(17, |i, j| ((i * 7 + j * 13) % 11) as f32);
        let max = h.nested_vertex_errors(NestingRule::Max);
        let plus = h.nested_vertex_errors(NestingRule::MaxPlusOwn);
        let lattice = h.lattice();
        for id in 0..lattice.n_vertices() as u32 {
            let p = lattice.point(id);
            if lattice.classify(p) == VertexClass::Corner {
                continue; // Corners are always active; their nested error is 0 by definition.
            }
            for c in &lattice.children(p) {
                let c = lattice.id(*c) as usize;
                assert!(max[id as usize] >= max[c]);
                assert!(plus[id as usize] >= plus[c]);
            }
            assert!(plus[id as usize] >= max[id as usize]);
            assert!(f64::from(max[id as usize]) >= h.vertex_error(p).abs());
        }
    }

    #[test]
    fn wu_node_error_covers_its_centre_and_boundary_vertices() {
        let h = hierarchy(17, |i, j| ((i * 5 + j * 3) % 7) as f32);
        let lattice = h.lattice();
        let mut half = 1;
        while half < 16 {
            for p in square_points(lattice, half) {
                let delta = f64::from(h.node_error(p, half));
                assert!(delta >= h.vertex_error(p).abs());
                for b in lattice.boundary_vertices(p, half) {
                    assert!(delta >= h.vertex_error(b).abs());
                }
            }
            half *= 2;
        }
    }

    /// The finest blocks' data, computed from samples, equals Wu's rule applied through the
    /// generic lattice functions, bit for bit.
    #[test]
    fn finest_blocks_computed_on_demand_equal_the_generic_rule() {
        // Pseudo-random heights with fractional parts, so that rounding matters.
        let h = hierarchy(33, |i, j| {
            let seed = (i as u64 * 33 + j as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            ((seed >> 40) as f32) / 977.0 - 3000.0
        });
        let lattice = h.lattice();
        for p in square_points(lattice, 1) {
            let mut error = h.vertex_error(p).abs();
            for b in lattice.boundary_vertices(p, 1) {
                error = error.max(h.vertex_error(b).abs());
            }
            let block = (0..3).flat_map(|dj| (0..3).map(move |di| (p.i + di - 1, p.j + dj - 1)));
            let heights = block.map(|(i, j)| h.height(GridPoint::new(i, j)));
            let z_min = heights.clone().fold(f32::INFINITY, f32::min);
            let z_max = heights.fold(f32::NEG_INFINITY, f32::max);
            assert_eq!(
                h.node_error_and_range(p, 1),
                (round_up(error), z_min, z_max),
                "finest block at {p:?}"
            );
        }
    }

    #[test]
    fn the_node_table_is_built_only_when_read_and_reads_the_same_either_way() {
        let height = |i: usize, j: usize| ((i * 7 + j * 13) % 11) as f32;
        let lazy = hierarchy(65, height);
        assert!(!lazy.has_node_table());
        assert_eq!(lazy.bytes_per_sample(), 4.0);
        let eager = hierarchy(65, height);
        eager.build_node_table();
        assert!(eager.has_node_table());
        // Reading builds it, with the values building it first gives.
        let root = lazy.lattice().root();
        assert_eq!(
            lazy.node_error_and_range(root, 32),
            eager.node_error_and_range(root, 32)
        );
        assert!(lazy.has_node_table());
        assert_eq!(lazy.node_table(), eager.node_table());
        assert!(lazy.bytes_per_sample() > 4.0);
    }

    #[test]
    fn a_hierarchy_shares_its_field_rather_than_copying_it() {
        let field = Arc::new(
            Heightfield::new(17, vec![1.0; 17 * 17], Spacing { dx: 1.0, dy: 1.0 }).unwrap(),
        );
        let h = Hierarchy::new(Arc::clone(&field));
        assert!(std::ptr::eq(h.field(), field.as_ref()));
    }

    #[test]
    fn only_the_levels_above_the_finest_are_stored() {
        let h = hierarchy(129, |i, j| ((i * 7 + j * 13) % 11) as f32);
        assert_eq!(h.node_table().len(), (64 * 64 - 1) / 3);
        // 4 bytes of height per sample, 12 bytes per stored node: one node per 12 samples.
        assert!(h.bytes_per_sample() < 5.0, "{}", h.bytes_per_sample());
    }
}
