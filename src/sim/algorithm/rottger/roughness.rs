//! Preprocessing: every block's d2 roughness (eq. 2), propagated bottom-up (§2.2), stored as
//! one-byte codes in the quadtree matrix.
//!
//! **Local d2** of a block = max of its six elevation differences |dh| over its edge length d:
//! each edge midpoint against the mean of the edge's ends (four), and the centre against the mean
//! of each diagonal's ends (two). Computed from the block's nine samples, O(1).
//!
//! **Propagation.** Finest blocks first, each block's d2 becomes the maximum of its local value
//! and K = C/(2(C − 1)) times the (stored, decoded) d2 of every adjacent block one level finer:
//! its own four children, and the two children of each edge neighbour that touch its edge (the
//! blocks the paper's condition (4) relates it to). Propagating the rounded-up stored values
//! keeps the inequality d2(block) ≥ K · d2(adjacent finer block) exact on what the criterion
//! reads. With propagation off (an option, to measure what it buys) the codes hold the local
//! values.
//!
//! Two passes over the blocks, O(samples) time; nothing is allocated besides the matrix (the
//! local values are recomputed in the second pass rather than stored).

use super::criterion::{block_edge_m, propagation_factor};
use super::matrix::{D2Scale, QuadtreeMatrix};
use crate::sim::hierarchy::{GridPoint, Hierarchy, square_points};

/// The largest of a block's six elevation differences over its edge length.
pub fn local_d2(hierarchy: &Hierarchy, centre: GridPoint, half: u32) -> f64 {
    let z = |di: i32, dj: i32| {
        let i = (centre.i as i64 + i64::from(di) * i64::from(half)) as u32;
        let j = (centre.j as i64 + i64::from(dj) * i64::from(half)) as u32;
        f64::from(hierarchy.height(GridPoint::new(i, j)))
    };
    let difference = |v: f64, a: f64, b: f64| (v - 0.5 * (a + b)).abs();
    let differences = [
        difference(z(-1, 0), z(-1, -1), z(-1, 1)),
        difference(z(1, 0), z(1, -1), z(1, 1)),
        difference(z(0, -1), z(-1, -1), z(1, -1)),
        difference(z(0, 1), z(-1, 1), z(1, 1)),
        difference(z(0, 0), z(-1, -1), z(1, 1)),
        difference(z(0, 0), z(1, -1), z(-1, 1)),
    ];
    let largest = differences.into_iter().fold(0.0, f64::max);
    largest / block_edge_m(hierarchy, half)
}

/// The blocks of half-size `half / 2` adjacent to the block at `centre` (half-size `half` ≥ 2)
/// that lie inside the grid: its four children and the children of its edge neighbours that
/// touch its edges (up to twelve).
pub fn adjacent_finer_blocks(
    cells: u32,
    centre: GridPoint,
    half: u32,
) -> impl Iterator<Item = GridPoint> {
    debug_assert!(half >= 2);
    let quarter = i64::from(half / 2);
    let offsets = [-3i64, -1, 1, 3];
    offsets
        .into_iter()
        .flat_map(move |a| offsets.into_iter().map(move |b| (a, b)))
        // (±3, ±3) would be a diagonal neighbour's child: it touches only a corner.
        .filter(|&(a, b)| a.abs() + b.abs() < 6)
        .filter_map(move |(a, b)| {
            let i = i64::from(centre.i) + a * quarter;
            let j = i64::from(centre.j) + b * quarter;
            let inside = |x: i64| x - quarter >= 0 && x + quarter <= i64::from(cells);
            (inside(i) && inside(j)).then(|| GridPoint::new(i as u32, j as u32))
        })
}

/// Builds the matrix: every block's d2 code, propagated with K for this `minimum_resolution` C
/// when `propagate`, local otherwise. Blend entries start at 0.
pub fn build_matrix(
    hierarchy: &Hierarchy,
    minimum_resolution: f64,
    propagate: bool,
) -> QuadtreeMatrix {
    let lattice = hierarchy.lattice();
    let mut d2_max: f64 = 0.0;
    let mut half = 1;
    while half < lattice.cells() {
        for centre in square_points(lattice, half) {
            d2_max = d2_max.max(local_d2(hierarchy, centre, half));
        }
        half *= 2;
    }
    let mut matrix = QuadtreeMatrix::new(lattice, D2Scale::new(d2_max));
    let k = propagation_factor(minimum_resolution);
    let mut half = 1;
    while half < lattice.cells() {
        for centre in square_points(lattice, half) {
            let mut d2 = local_d2(hierarchy, centre, half);
            if propagate && half >= 2 {
                for finer in adjacent_finer_blocks(lattice.cells(), centre, half) {
                    d2 = d2.max(k * matrix.d2(finer, half / 2));
                }
            }
            let code = matrix.scale().encode(d2);
            matrix.set_d2_code(centre, half, code);
        }
        half *= 2;
    }
    matrix
}
