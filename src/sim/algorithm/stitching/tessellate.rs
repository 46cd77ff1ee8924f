//! The GPU's tessellation of a block, simulated exactly on the CPU (the paper's M-blocks are
//! tessellated by the hardware, §3.1.1, and its strips reuse the "fractional even spacing
//! scheme", §3.2.2): where the tessellator puts the vertices of an edge (fractional-even or equal
//! spacing), the height a vertex gets (the height field resampled bilinearly), and the triangles
//! of a quad patch (an interior grid and an outer ring joining it to the four edges), added to a
//! [`TriangleList`].
//!
//! Positions are fixed-point raw units (1/65 536 of a cell, [`SUBGRID_UNITS_PER_CELL`]); an
//! edge's vertices are computed from its two ends and its spacing alone, always from the low end
//! up, so every block and strip that tessellates the same edge gets bit-identical vertices.
//!
//! Every triangle is added counter-clockwise seen from above ([`add_triangle_or_degenerate`],
//! `sim::mesh::winding`), strips' and P-blocks' too.
//!
//! What it is not: a record of which block is where (the quadtree, `tree.rs`) or of the strips
//! (`strips.rs`), which reuse [`merge_rows`] to triangulate between two parallel rows.

use crate::sim::mesh::{
    SUBGRID_UNITS_PER_CELL, SubgridPoint, TriangleInfo, TriangleList, TriangleRole, Winding,
};
use crate::sim::terrain::Heightfield;

/// The smallest and largest tessellation factors a GPU accepts for fractional-even spacing.
pub const MIN_FACTOR: f64 = 2.0;
pub const MAX_FACTOR: f64 = 64.0;

/// How an edge (or a patch's inner direction) is cut into segments.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EdgeSpacing {
    /// Fractional-even spacing with factor F (clamped to [2, 64]): n = 2⌈F/2⌉ segments, n − 2
    /// of length 1/F and two equal shorter ones, (1 − (n − 2)/F)/2 each, in the middle of the
    /// edge (the OpenGL specification leaves their place to the implementation as long as it is
    /// symmetric; roamsim puts them at the midpoint).
    FractionalEven(f64),
    /// m equal segments (integer spacing, m ≥ 1): Method I's power-of-two factors.
    Equal(u32),
}

impl EdgeSpacing {
    /// The number of segments.
    pub fn segments(self) -> usize {
        match self {
            EdgeSpacing::FractionalEven(f) => {
                let f = f.clamp(MIN_FACTOR, MAX_FACTOR);
                2 * (0.5 * f).ceil() as usize
            }
            EdgeSpacing::Equal(m) => m.max(1) as usize,
        }
    }
}

/// Appends the raw positions of the vertices of the edge from `lo` to `hi` (raw units, lo < hi),
/// both ends included, in increasing order. O(segments).
pub fn edge_positions(lo: i64, hi: i64, spacing: EdgeSpacing, out: &mut Vec<i64>) {
    let n = spacing.segments();
    out.extend((0..=n).map(|k| edge_position(lo, hi, spacing, n, k)));
}

/// The raw position of vertex `k` (0 ..= `n`, n = `spacing.segments()`) of the edge from `lo` to
/// `hi`: the k-th value [`edge_positions`] gives, computed alone. O(1).
#[inline]
pub fn edge_position(lo: i64, hi: i64, spacing: EdgeSpacing, n: usize, k: usize) -> i64 {
    let length = hi - lo;
    match spacing {
        EdgeSpacing::FractionalEven(f) => {
            let f = f.clamp(MIN_FACTOR, MAX_FACTOR);
            let half = n / 2;
            let len = length as f64;
            if k == 0 {
                lo
            } else if k == n {
                hi
            } else if k < half {
                lo + (len * k as f64 / f).round() as i64
            } else if k == half {
                lo + (len * 0.5).round() as i64
            } else {
                hi - (len * (n - k) as f64 / f).round() as i64
            }
        }
        EdgeSpacing::Equal(_) => {
            let (n, k) = (n as i64, k as i64);
            // Nearest, computed from the low end (exact for Method I's dyadic spacings).
            lo + (2 * length * k + n) / (2 * n)
        }
    }
}

/// The height of the field at raw position (x, y): the bilinear interpolation of the four
/// samples of the cell holding it (exact at samples; continuous), rounded to `f32` as a vertex
/// buffer holds it. Points on the east or north border use the last cell.
pub fn resampled_height(field: &Heightfield, x: i64, y: i64) -> f32 {
    let cells = field.side() - 1;
    let locate = |v: i64| {
        let cell = ((v / SUBGRID_UNITS_PER_CELL) as usize).min(cells - 1);
        let fraction =
            (v - cell as i64 * SUBGRID_UNITS_PER_CELL) as f64 / SUBGRID_UNITS_PER_CELL as f64;
        (cell, fraction)
    };
    let ((i, fu), (j, fv)) = (locate(x), locate(y));
    let z = |i: usize, j: usize| f64::from(field.height(i, j));
    let south = z(i, j) * (1.0 - fu) + z(i + 1, j) * fu;
    let north = z(i, j + 1) * (1.0 - fu) + z(i + 1, j + 1) * fu;
    (south * (1.0 - fv) + north * fv) as f32
}

/// An axis-aligned rectangle in raw units, low corner first (x0 < x1, y0 < y1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x0: i64,
    pub y0: i64,
    pub x1: i64,
    pub y1: i64,
}

impl Rect {
    pub fn low(self) -> SubgridPoint {
        SubgridPoint::from_raw(self.x0, self.y0).expect("rectangles lie in the domain")
    }

    pub fn high(self) -> SubgridPoint {
        SubgridPoint::from_raw(self.x1, self.y1).expect("rectangles lie in the domain")
    }
}

/// Sides of a block, in the order of per-side arrays.
pub const SOUTH: usize = 0;
pub const EAST: usize = 1;
pub const NORTH: usize = 2;
pub const WEST: usize = 3;

/// The raw vertex positions of side `side` of `rect` under `spacing`, as (x, y), in increasing
/// order along the side (west to east, south to north).
pub fn side_points(rect: Rect, side: usize, spacing: EdgeSpacing, out: &mut Vec<(i64, i64)>) {
    let mut along = Vec::new();
    let (fixed, horizontal) = match side {
        SOUTH => (rect.y0, true),
        NORTH => (rect.y1, true),
        EAST => (rect.x1, false),
        _ => (rect.x0, false),
    };
    if horizontal {
        edge_positions(rect.x0, rect.x1, spacing, &mut along);
        out.extend(along.iter().map(|&x| (x, fixed)));
    } else {
        edge_positions(rect.y0, rect.y1, spacing, &mut along);
        out.extend(along.iter().map(|&y| (fixed, y)));
    }
}

/// Adds a vertex at raw (x, y) with its resampled height.
pub fn add_resampled_vertex(list: &mut TriangleList, field: &Heightfield, x: i64, y: i64) -> u32 {
    let point = SubgridPoint::from_raw(x, y).expect("tessellated vertices lie in the domain");
    list.add_vertex(point, resampled_height(field, x, y))
}

/// Adds triangle `corners` with `info`, counter-clockwise seen from above (its last two corners
/// swapped when they run clockwise: the rule of `sim::mesh::winding`, which a tessellator's
/// declared output winding keeps), its role degenerate instead when its plane area is zero
/// (two vertices of a fractional tessellation rounded onto one point, as a GPU would draw them;
/// its corners then stay as given). Returns whether it kept its area.
///
/// The triangles of [`merge_rows`] alternate between the two rows, so half of them run each
/// way whatever the rows' order; the interior grid's and the P-blocks' are counter-clockwise as
/// given. Orienting here, with the exact sign, covers every triangle the algorithm draws.
pub fn add_triangle_or_degenerate(
    list: &mut TriangleList,
    corners: [u32; 3],
    info: TriangleInfo,
) -> bool {
    let points = corners.map(|c| list.vertices()[c as usize].position);
    let winding = Winding::of_points(points);
    let (corners, role) = match winding {
        Winding::CounterClockwise => (corners, info.role),
        Winding::Clockwise => ([corners[0], corners[2], corners[1]], info.role),
        Winding::Flat => (corners, TriangleRole::Degenerate),
    };
    list.add_triangle(corners, TriangleInfo { role, ..info });
    winding != Winding::Flat
}

/// Triangulates between two rows of vertices on parallel lines (each row: list indices with
/// their coordinate along the lines, increasing; the first vertices of both rows joined by one
/// end of the region, the last ones by the other) by the perpendicular-bisector rule of the
/// 2019 paper's Algorithm 1: each segment of a row makes a triangle with the vertex of the other
/// row nearest its perpendicular bisector. That is the merge of the two rows' segment midpoints
/// in order; on a tie (a midpoint of each row at the same place) the segment of row `a` goes
/// first, which is the rule "row `a`'s segment takes the lower vertex, row `b`'s the higher" and
/// keeps the triangles from overlapping. Emits len(a) + len(b) − 2 triangles, O(that).
pub fn merge_rows(a: &[(u32, i64)], b: &[(u32, i64)], mut emit: impl FnMut([u32; 3])) {
    let (mut i, mut j) = (0, 0);
    while i + 1 < a.len() || j + 1 < b.len() {
        let take_a = if i + 1 >= a.len() {
            false
        } else if j + 1 >= b.len() {
            true
        } else {
            a[i].1 + a[i + 1].1 <= b[j].1 + b[j + 1].1
        };
        if take_a {
            emit([a[i].0, a[i + 1].0, b[j].0]);
            i += 1;
        } else {
            emit([b[j].0, b[j + 1].0, a[i].0]);
            j += 1;
        }
    }
}

/// Reused buffers of [`add_quad_patch`].
#[derive(Debug, Default)]
pub struct PatchScratch {
    us: Vec<i64>,
    vs: Vec<i64>,
    edge: Vec<(i64, i64)>,
    outer: Vec<(u32, i64)>,
    inner: Vec<(u32, i64)>,
}

impl PatchScratch {
    pub fn memory_bytes(&self) -> usize {
        (self.us.capacity() + self.vs.capacity()) * 8
            + self.edge.capacity() * 16
            + (self.outer.capacity() + self.inner.capacity()) * 16
    }
}

/// Adds the GPU tessellation of the quad patch `rect` (inner spacing `inner` in both directions,
/// outer spacing `outer[side]` on each side) to `list`: the interior grid of the inner
/// spacing's lines 1 ..= n − 1 in each direction, each of its (n − 2)² cells cut along its
/// south-west–north-east diagonal, and the outer ring between that grid's border and the four
/// edges, each side's trapezoid triangulated by [`merge_rows`] (the specification leaves the
/// ring's triangulation to the implementation; its triangle count, outer segments + n − 2 per
/// side, is fixed). With the inner spacing on every side this is the n × n grid, 2n² triangles.
/// Returns (vertices added, triangles added).
pub fn add_quad_patch(
    list: &mut TriangleList,
    field: &Heightfield,
    rect: Rect,
    inner: EdgeSpacing,
    outer: [EdgeSpacing; 4],
    info: TriangleInfo,
    scratch: &mut PatchScratch,
) -> (u64, u64) {
    let vertices_before = list.vertices().len();
    let triangles_before = list.n_triangles();
    let n = inner.segments();
    scratch.us.clear();
    scratch.vs.clear();
    edge_positions(rect.x0, rect.x1, inner, &mut scratch.us);
    edge_positions(rect.y0, rect.y1, inner, &mut scratch.vs);
    // Interior vertices (lines 1 ..= n − 1), row by row.
    let base = list.vertices().len() as u32;
    let side = (n - 1) as u32;
    for b in 1..n {
        for a in 1..n {
            add_resampled_vertex(list, field, scratch.us[a], scratch.vs[b]);
        }
    }
    let interior = |a: usize, b: usize| base + (b as u32 - 1) * side + (a as u32 - 1);
    for b in 1..n - 1 {
        for a in 1..n - 1 {
            let (sw, se, nw, ne) = (
                interior(a, b),
                interior(a + 1, b),
                interior(a, b + 1),
                interior(a + 1, b + 1),
            );
            add_triangle_or_degenerate(list, [sw, se, ne], info);
            add_triangle_or_degenerate(list, [sw, ne, nw], info);
        }
    }
    // The ring: each side's edge against the interior grid's border line on that side.
    for (side_index, &spacing) in outer.iter().enumerate() {
        scratch.edge.clear();
        side_points(rect, side_index, spacing, &mut scratch.edge);
        scratch.outer.clear();
        for &(x, y) in &scratch.edge {
            let index = add_resampled_vertex(list, field, x, y);
            let along = if side_index == SOUTH || side_index == NORTH {
                x
            } else {
                y
            };
            scratch.outer.push((index, along));
        }
        scratch.inner.clear();
        for k in 1..n {
            let (index, along) = match side_index {
                SOUTH => (interior(k, 1), scratch.us[k]),
                NORTH => (interior(k, n - 1), scratch.us[k]),
                EAST => (interior(n - 1, k), scratch.vs[k]),
                _ => (interior(1, k), scratch.vs[k]),
            };
            scratch.inner.push((index, along));
        }
        let (outer_row, inner_row) = (&scratch.outer, &scratch.inner);
        merge_rows(outer_row, inner_row, |corners| {
            add_triangle_or_degenerate(list, corners, info);
        });
    }
    (
        (list.vertices().len() - vertices_before) as u64,
        list.n_triangles() - triangles_before,
    )
}

/// The vertices a quad patch's tessellation adds ([`add_quad_patch`]): (n − 1)² inside, then
/// m_side + 1 on each side.
pub fn quad_patch_vertices(inner: EdgeSpacing, outer: [EdgeSpacing; 4]) -> u64 {
    let n = inner.segments() as u64;
    (n - 1) * (n - 1) + outer.iter().map(|s| s.segments() as u64 + 1).sum::<u64>()
}

/// The triangles a quad patch's tessellation draws for inner spacing `inner` and outer spacings
/// `outer`: 2(n − 2)² + Σ_sides (m_side + n − 2).
pub fn quad_patch_triangles(inner: EdgeSpacing, outer: [EdgeSpacing; 4]) -> u64 {
    let n = inner.segments() as u64;
    2 * (n - 2) * (n - 2)
        + outer
            .iter()
            .map(|s| s.segments() as u64 + n - 2)
            .sum::<u64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    const CELL: i64 = SUBGRID_UNITS_PER_CELL;

    fn positions(spacing: EdgeSpacing) -> Vec<i64> {
        let mut out = Vec::new();
        edge_positions(0, 64 * CELL, spacing, &mut out);
        out
    }

    #[test]
    fn even_factors_cut_an_edge_evenly_and_fractional_ones_shrink_two_middle_segments() {
        let even = positions(EdgeSpacing::FractionalEven(4.0));
        assert_eq!(even, vec![0, 16 * CELL, 32 * CELL, 48 * CELL, 64 * CELL]);
        let three = positions(EdgeSpacing::FractionalEven(3.0));
        // n = 4: two segments of 1/3, two of 1/6 about the midpoint.
        assert_eq!(three.len(), 5);
        assert_eq!(three[2], 32 * CELL);
        assert_eq!(three[1], (64.0 * CELL as f64 / 3.0).round() as i64);
        assert_eq!(three[3], 64 * CELL - three[1]);
        // Just above 2, the two new vertices are born at the midpoint.
        let born = positions(EdgeSpacing::FractionalEven(2.0 + 1e-9));
        assert_eq!(born.len(), 5);
        assert!((born[1] - 32 * CELL).abs() <= 1 && (born[3] - 32 * CELL).abs() <= 1);
        // Clamped to [2, 64].
        assert_eq!(positions(EdgeSpacing::FractionalEven(0.5)).len(), 3);
        assert_eq!(positions(EdgeSpacing::FractionalEven(500.0)).len(), 65);
        assert_eq!(
            positions(EdgeSpacing::Equal(1)),
            vec![0, 64 * CELL],
            "one equal segment"
        );
    }

    #[test]
    fn the_bisector_merge_pairs_each_segment_with_the_nearest_vertex_across() {
        // Row a: 0, 10, 20; row b: 0, 4, 20. Midpoints a: 5, 15; b: 2, 12.
        let a = [(0, 0), (1, 10), (2, 20)];
        let b = [(3, 0), (4, 4), (5, 20)];
        let mut triangles = Vec::new();
        merge_rows(&a, &b, |t| triangles.push(t));
        assert_eq!(triangles, vec![[3, 4, 0], [0, 1, 4], [4, 5, 1], [1, 2, 5]]);
        // A single vertex on one side: a fan.
        let mut fan = Vec::new();
        merge_rows(&a, &[(9, 10)], |t| fan.push(t));
        assert_eq!(fan, vec![[0, 1, 9], [1, 2, 9]]);
    }

    #[test]
    fn a_patch_draws_the_triangles_its_factors_say() {
        let field = Heightfield::new(
            17,
            vec![0.0; 17 * 17],
            crate::sim::terrain::Spacing { dx: 1.0, dy: 1.0 },
        )
        .expect("a flat field");
        let lattice = crate::sim::hierarchy::Lattice::new(4);
        let info = TriangleInfo {
            role: TriangleRole::Surface,
            group: 0,
            level: 0,
        };
        let rect = Rect {
            x0: 0,
            y0: 0,
            x1: 16 * CELL,
            y1: 16 * CELL,
        };
        for (inner, outer) in [
            (2.0, [2.0; 4]),
            (5.5, [5.5; 4]),
            (8.0, [2.0, 64.0, 3.3, 8.0]),
        ] {
            let mut list = TriangleList::new(&lattice, crate::sim::mesh::CrackPolicy::Stitched);
            let inner = EdgeSpacing::FractionalEven(inner);
            let outer = outer.map(EdgeSpacing::FractionalEven);
            let (vertices, triangles) = add_quad_patch(
                &mut list,
                &field,
                rect,
                inner,
                outer,
                info,
                &mut Default::default(),
            );
            assert_eq!(triangles, quad_patch_triangles(inner, outer));
            assert_eq!(vertices, quad_patch_vertices(inner, outer));
            let n = inner.segments() as u64;
            if outer.iter().all(|&o| o == inner) {
                assert_eq!(triangles, 2 * n * n);
            }
            let mut validator = crate::sim::mesh::list_validate::TriangleListValidator::new();
            let hierarchy = crate::sim::hierarchy::Hierarchy::new(field.clone());
            validator
                .validate(&hierarchy, &list, list.n_triangles())
                .expect("one patch tiles the domain");
        }
    }
}
