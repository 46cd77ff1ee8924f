//! Index arithmetic of the 4-8 (longest-edge bisection) hierarchy over a (2^n+1)² grid (SPEC §3):
//! vertex classes, parents, children, the edge a vertex bisects, and Wu's sub-blocks and boundary
//! vertices (Wu et al. 2001 §3.1, Figure 2). Positions only: heights and errors are `mod.rs`'s.
//!
//! Every non-corner grid vertex is the centre of exactly one diamond, and its class follows from
//! its coordinates alone. Let t be the largest power of two dividing both i and j (the vertex's
//! *half-size*):
//! - if i/t and j/t are both odd, the vertex is the centre of the square block
//!   [i−t, i+t]×[j−t, j+t] (a **square** diamond, one of Wu's quadtree nodes). Its two parents are
//!   the block corners whose coordinates, in units of 2t, have mixed parity; the hypotenuse it
//!   bisects joins the other two corners. Its four children are the block's edge midpoints.
//! - otherwise exactly one of i/t, j/t is odd, and the vertex is the midpoint of a block edge of
//!   length 2t (a **rotated** diamond). Its parents are the centres of the (one or two) blocks
//!   that share the edge; its children are the centres of the (two or four) half-size blocks
//!   touching it, and it has none when t = 1.
//!
//! No tables are stored: parents and children are computed in O(1). Vertex ids are
//! `j · side + i` as `u32` (a 16385² grid has 2^28 vertices).

use crate::sim::terrain::{MAX_LEVEL, MAX_PAGED_LEVEL};

/// A vertex of the grid, by column and row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct GridPoint {
    pub i: u32,
    pub j: u32,
}

impl GridPoint {
    pub const fn new(i: u32, j: u32) -> GridPoint {
        GridPoint { i, j }
    }
}

/// What kind of vertex a grid point is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexClass {
    /// One of the four grid corners: always in every mesh, no parents.
    Corner,
    /// Centre of a square block of side 2·`half`.
    Square { half: u32 },
    /// Midpoint of a block edge of length 2·`half`; `horizontal` when the edge runs along x.
    Rotated { half: u32, horizontal: bool },
}

/// Up to four vertices, without allocation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Few {
    points: [GridPoint; 4],
    len: u8,
}

impl Few {
    const EMPTY: Few = Few {
        points: [GridPoint::new(0, 0); 4],
        len: 0,
    };

    fn push(&mut self, point: GridPoint) {
        self.points[self.len as usize] = point;
        self.len += 1;
    }

    pub fn as_slice(&self) -> &[GridPoint] {
        &self.points[..self.len as usize]
    }

    pub fn len(&self) -> usize {
        self.len as usize
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl<'a> IntoIterator for &'a Few {
    type Item = &'a GridPoint;
    type IntoIter = std::slice::Iter<'a, GridPoint>;

    fn into_iter(self) -> Self::IntoIter {
        self.as_slice().iter()
    }
}

/// The 4-8 hierarchy of a grid of side 2^n + 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Lattice {
    level: u32,
    /// 2^n: the largest coordinate.
    cells: u32,
}

impl Lattice {
    /// The lattice of a grid of side 2^level + 1 (1 ≤ level ≤ [`MAX_PAGED_LEVEL`]). Vertex ids
    /// are `u32`, so [`Lattice::id`] and what numbers vertices by it (vertex sets, the
    /// algorithms of the 4-8 hierarchy) hold only up to [`MAX_LEVEL`] (65 537² is above 2^32);
    /// level 16 is a paged terrain's, whose coordinates (`cells`, `side`, `level`) chunked LOD
    /// reads and whose ids nothing computes (the run refuses every other entry before it
    /// starts). Not reachable from an input with another level: a `Heightfield`, whose level a
    /// hierarchy's lattice takes, refuses a larger side with an error; the panic is for code
    /// that asks for a lattice of a level it made up.
    pub fn new(level: u32) -> Lattice {
        assert!(
            (1..=MAX_PAGED_LEVEL).contains(&level),
            "lattice level {level} outside 1..={MAX_PAGED_LEVEL}"
        );
        Lattice {
            level,
            cells: 1 << level,
        }
    }

    pub fn level(&self) -> u32 {
        self.level
    }

    pub fn side(&self) -> u32 {
        self.cells + 1
    }

    /// 2^n, the largest coordinate.
    pub fn cells(&self) -> u32 {
        self.cells
    }

    pub fn n_vertices(&self) -> usize {
        (self.side() as usize).pow(2)
    }

    pub fn id(&self, p: GridPoint) -> u32 {
        debug_assert!(
            self.level <= MAX_LEVEL,
            "no 32-bit vertex ids at level {}",
            self.level
        );
        p.j * self.side() + p.i
    }

    pub fn point(&self, id: u32) -> GridPoint {
        GridPoint::new(id % self.side(), id / self.side())
    }

    pub fn corners(&self) -> [GridPoint; 4] {
        let c = self.cells;
        [
            GridPoint::new(0, 0),
            GridPoint::new(c, 0),
            GridPoint::new(0, c),
            GridPoint::new(c, c),
        ]
    }

    /// The root block centre (Wu's root node).
    pub fn root(&self) -> GridPoint {
        GridPoint::new(self.cells / 2, self.cells / 2)
    }

    pub fn classify(&self, p: GridPoint) -> VertexClass {
        let both = p.i | p.j;
        if (p.i == 0 || p.i == self.cells) && (p.j == 0 || p.j == self.cells) {
            return VertexClass::Corner;
        }
        let half = both & both.wrapping_neg();
        let odd_i = (p.i / half) % 2 == 1;
        let odd_j = (p.j / half) % 2 == 1;
        if odd_i && odd_j {
            VertexClass::Square { half }
        } else {
            VertexClass::Rotated {
                half,
                horizontal: odd_i,
            }
        }
    }

    /// The vertices `p` depends on (2 inside, 1 on the border, none for corners).
    pub fn parents(&self, p: GridPoint) -> Few {
        let mut out = Few::EMPTY;
        match self.classify(p) {
            VertexClass::Corner => {}
            VertexClass::Square { half } => {
                let [a, b] = square_parents(p, half);
                out.push(a);
                out.push(b);
            }
            VertexClass::Rotated { half, horizontal } => {
                let (a, b) = if horizontal {
                    (
                        self.offset(p, 0, -(half as i64)),
                        self.offset(p, 0, half as i64),
                    )
                } else {
                    (
                        self.offset(p, -(half as i64), 0),
                        self.offset(p, half as i64, 0),
                    )
                };
                out.extend_options(a, b);
            }
        }
        out
    }

    /// The vertices that depend on `p` (the two corners that are the root's parents have the root
    /// as their child).
    pub fn children(&self, p: GridPoint) -> Few {
        let mut out = Few::EMPTY;
        match self.classify(p) {
            VertexClass::Corner => {
                let root = self.root();
                if self.parents(root).as_slice().contains(&p) {
                    out.push(root);
                }
            }
            VertexClass::Square { half } => {
                for point in block_edge_midpoints(p, half) {
                    out.push(point);
                }
            }
            VertexClass::Rotated { half, .. } => {
                if half >= 2 {
                    let q = (half / 2) as i64;
                    for (di, dj) in [(-q, -q), (q, -q), (-q, q), (q, q)] {
                        if let Some(child) = self.offset(p, di, dj) {
                            out.push(child);
                        }
                    }
                }
            }
        }
        out
    }

    /// The ends of the edge that `p` bisects (the hypotenuse of its diamond), or `None` for a
    /// corner.
    pub fn bisected_edge(&self, p: GridPoint) -> Option<[GridPoint; 2]> {
        match self.classify(p) {
            VertexClass::Corner => None,
            VertexClass::Square { half } => {
                let [a, b] = square_parents(p, half);
                // The hypotenuse is the block's other diagonal: swap one coordinate of each
                // parent.
                let ends = [GridPoint::new(a.i, b.j), GridPoint::new(b.i, a.j)];
                Some([ends[0].min(ends[1]), ends[0].max(ends[1])])
            }
            VertexClass::Rotated { half, horizontal } => Some(if horizontal {
                [
                    GridPoint::new(p.i - half, p.j),
                    GridPoint::new(p.i + half, p.j),
                ]
            } else {
                [
                    GridPoint::new(p.i, p.j - half),
                    GridPoint::new(p.i, p.j + half),
                ]
            }),
        }
    }

    /// Wu's quadtree children of a square node: the centres of its four sub-blocks (none for the
    /// finest blocks, half = 1).
    pub fn sub_blocks(&self, square: GridPoint, half: u32) -> Option<[GridPoint; 4]> {
        (half >= 2).then(|| {
            let q = half / 2;
            [
                GridPoint::new(square.i - q, square.j - q),
                GridPoint::new(square.i + q, square.j - q),
                GridPoint::new(square.i - q, square.j + q),
                GridPoint::new(square.i + q, square.j + q),
            ]
        })
    }

    /// The edge midpoints of a square block (its boundary vertices): west, east, south, north.
    pub fn boundary_vertices(&self, square: GridPoint, half: u32) -> [GridPoint; 4] {
        block_edge_midpoints(square, half)
    }

    fn offset(&self, p: GridPoint, di: i64, dj: i64) -> Option<GridPoint> {
        let i = p.i as i64 + di;
        let j = p.j as i64 + dj;
        let limit = self.cells as i64;
        ((0..=limit).contains(&i) && (0..=limit).contains(&j))
            .then(|| GridPoint::new(i as u32, j as u32))
    }
}

impl Few {
    fn extend_options(&mut self, a: Option<GridPoint>, b: Option<GridPoint>) {
        for point in [a, b].into_iter().flatten() {
            self.push(point);
        }
    }
}

/// The two corners of a square block that are its parents: those whose coordinates, in units of
/// 2·half, have mixed parity (they are diagonally opposite).
fn square_parents(centre: GridPoint, half: u32) -> [GridPoint; 2] {
    let (i0, i1) = (centre.i - half, centre.i + half);
    let (j0, j1) = (centre.j - half, centre.j + half);
    let odd = |x: u32| (x / (2 * half)) % 2 == 1;
    // (i0, j0) has mixed parity exactly when the main diagonal holds the parents.
    if odd(i0) != odd(j0) {
        [GridPoint::new(i0, j0), GridPoint::new(i1, j1)]
    } else {
        [GridPoint::new(i1, j0), GridPoint::new(i0, j1)]
    }
}

fn block_edge_midpoints(centre: GridPoint, half: u32) -> [GridPoint; 4] {
    [
        GridPoint::new(centre.i - half, centre.j),
        GridPoint::new(centre.i + half, centre.j),
        GridPoint::new(centre.i, centre.j - half),
        GridPoint::new(centre.i, centre.j + half),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_root_of_a_9_by_9_grid_depends_on_the_off_diagonal_corners() {
        let lattice = Lattice::new(3);
        let root = lattice.root();
        assert_eq!(lattice.classify(root), VertexClass::Square { half: 4 });
        let parents = lattice.parents(root);
        assert_eq!(
            parents.as_slice(),
            &[GridPoint::new(8, 0), GridPoint::new(0, 8)]
        );
        assert_eq!(
            lattice.bisected_edge(root),
            Some([GridPoint::new(0, 0), GridPoint::new(8, 8)])
        );
    }

    #[test]
    fn a_border_midpoint_has_one_parent_and_two_children() {
        let lattice = Lattice::new(3);
        let south = GridPoint::new(4, 0);
        assert_eq!(
            lattice.classify(south),
            VertexClass::Rotated {
                half: 4,
                horizontal: true
            }
        );
        assert_eq!(lattice.parents(south).as_slice(), &[GridPoint::new(4, 4)]);
        assert_eq!(
            lattice.children(south).as_slice(),
            &[GridPoint::new(2, 2), GridPoint::new(6, 2)]
        );
    }

    #[test]
    fn parent_and_child_relations_are_mutual_on_a_33_by_33_grid() {
        let lattice = Lattice::new(5);
        for j in 0..lattice.side() {
            for i in 0..lattice.side() {
                let p = GridPoint::new(i, j);
                for parent in &lattice.parents(p) {
                    assert!(
                        lattice.children(*parent).as_slice().contains(&p),
                        "{p:?} lists parent {parent:?} which does not list it back"
                    );
                }
                for child in &lattice.children(p) {
                    assert!(lattice.parents(*child).as_slice().contains(&p));
                }
                let expected_parents = match lattice.classify(p) {
                    VertexClass::Corner => 0,
                    VertexClass::Square { .. } => 2,
                    VertexClass::Rotated { .. } => {
                        let border =
                            i == 0 || j == 0 || i == lattice.cells() || j == lattice.cells();
                        if border { 1 } else { 2 }
                    }
                };
                assert_eq!(lattice.parents(p).len(), expected_parents, "{p:?}");
            }
        }
    }

    #[test]
    fn every_bisected_edge_has_its_vertex_as_midpoint_and_parents_as_apexes() {
        let lattice = Lattice::new(4);
        for j in 0..lattice.side() {
            for i in 0..lattice.side() {
                let p = GridPoint::new(i, j);
                let Some([a, b]) = lattice.bisected_edge(p) else {
                    continue;
                };
                assert_eq!((a.i + b.i, a.j + b.j), (2 * i, 2 * j), "{p:?}");
                for parent in &lattice.parents(p) {
                    // Each apex is equidistant from both ends (a right isosceles triangle).
                    let d = |q: GridPoint| {
                        (q.i as i64 - parent.i as i64).pow(2)
                            + (q.j as i64 - parent.j as i64).pow(2)
                    };
                    assert_eq!(d(a), d(b), "{p:?} parent {parent:?}");
                    assert_ne!(*parent, a);
                }
            }
        }
    }
}
