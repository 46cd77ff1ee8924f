//! A patch as triangles: its level's regular grid, with the borders it shares with coarser
//! neighbours stitched (de Boer's gap avoidance, not in `papers/`, as Lauritsen–Nielsen §2.5
//! surveys it). It chooses nothing: the levels and factors it draws at are `levels.rs`'s, the
//! grid's triangles and morphed heights `block_lod::grid`'s.
//!
//! A patch at level ℓ (stride s = 2^ℓ, n = 2^(k−ℓ) cells a side) whose four sides are drawn at
//! levels ℓ_W, ℓ_E, ℓ_S, ℓ_N ≥ ℓ (`levels.rs`): a side drawn coarser than the patch is
//! **stitched**: its border keeps only the vertices every 2^ℓ_side samples, the ones the
//! coarser neighbour has (de Boer's scheme, the survey's fig. 2.14), so the two patches share
//! every border edge and the surface is closed. The patch is drawn as
//!
//! - its cells that touch no stitched side, as regular cells split along the south-west–
//!   north-east diagonal (role surface);
//! - per stitched side, the strip between the border and the line of vertices one cell
//!   inwards, triangulated by zipping the two polylines (each triangle advances along one of
//!   them; the nearer next vertex first, ties broken so that equal steps would give the regular
//!   diagonal), role stitch. At a corner where both sides are stitched the corner cell is split
//!   between the two strips along the diagonal from the corner to the first inner vertex.
//!
//! Every triangle is listed counter-clockwise seen from above (`sim::mesh::winding`): the
//! regular cells as `block_lod::grid` splits them; a stitch triangle as (outer vertex, next
//! outer, inner) or (outer, next inner, inner) on the south and east sides, where the inner
//! polyline lies to the left of the border walked from its start corner, and with its last two
//! corners swapped on the west and north sides, where it lies to the right.
//!
//! Heights: the patch's interior vertices morph with its own factor, its border vertices with
//! the factor their side is drawn at, each odd vertex towards the line between its two even
//! neighbours at the same step (`block_lod::grid`); a neighbour computes its shared border
//! vertices the same way, bit for bit. Corners never morph (they are in every level).
//!
//! Triangles per patch: 2 per regular cell, plus per stitched side the segments of its two
//! polylines ([`patch_triangles`], which the algorithm uses to count without building).

use super::super::block_lod::grid::{cell_triangles, coarser_neighbours, morphed_height};
use super::levels::{EAST, NORTH, SOUTH, WEST};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::{SubgridPoint, TriangleInfo, TriangleList, TriangleRole};

/// How one patch is drawn this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PatchDraw {
    /// The sample at the patch's south-west corner, and its cells a side (2^k).
    pub(super) origin: (u32, u32),
    pub(super) patch_cells: u32,
    /// The patch's level and morph factor.
    pub(super) level: u32,
    pub(super) morph: f64,
    /// Per side (WEST, EAST, SOUTH, NORTH): the level and morph factor it is drawn at.
    pub(super) sides: [(u32, f64); 4],
    /// The triangle list group (the patch's number) and level (0 = coarsest).
    pub(super) group: u32,
    pub(super) list_level: u32,
}

impl PatchDraw {
    /// Cells a side at the patch's level.
    pub(super) fn n(&self) -> u32 {
        self.patch_cells >> self.level
    }

    /// For a stitched side, its step in the patch's cells; `None` for a side drawn at the
    /// patch's own level.
    fn stitch_step(&self, side: usize) -> Option<u32> {
        let side_level = self.sides[side].0;
        (side_level > self.level).then(|| 1 << (side_level - self.level))
    }
}

/// Triangles of a patch of `n` cells a side whose sides have the stitch steps `stitched`
/// (WEST, EAST, SOUTH, NORTH; `None`: not stitched).
pub(super) fn patch_triangles(n: u32, stitched: [Option<u32>; 4]) -> u64 {
    2 * regular_cells(n, stitched) + stitch_triangles(n, stitched)
}

/// The patch's cells that touch no stitched side.
pub(super) fn regular_cells(n: u32, stitched: [Option<u32>; 4]) -> u64 {
    let n = u64::from(n);
    let is = |side: usize| u64::from(stitched[side].is_some());
    let strips: u64 = (0..4).map(|side| n * is(side)).sum();
    let shared_corners: u64 = [(WEST, SOUTH), (WEST, NORTH), (EAST, SOUTH), (EAST, NORTH)]
        .iter()
        .map(|&(a, b)| is(a) * is(b))
        .sum();
    n * n - (strips - shared_corners)
}

/// The stitch triangles: per stitched side, the segments of its outer and inner polylines.
pub(super) fn stitch_triangles(n: u32, stitched: [Option<u32>; 4]) -> u64 {
    let n = u64::from(n);
    let is = |side: usize| u64::from(stitched[side].is_some());
    stitched
        .iter()
        .enumerate()
        .filter_map(|(side, step)| {
            let (start, end) = corner_sides(side);
            step.map(|step| n / u64::from(step) + n - is(start) - is(end))
        })
        .sum()
}

/// The sides meeting `side` at its start corner (south or west) and its end corner.
fn corner_sides(side: usize) -> (usize, usize) {
    match side {
        WEST | EAST => (SOUTH, NORTH),
        _ => (WEST, EAST),
    }
}

/// Scratch space of [`add_patch`], reused between patches.
#[derive(Debug, Default)]
pub(super) struct PatchScratch {
    /// Per vertex (a, b) of the patch's grid, its index in the list (`u32::MAX`: not added).
    indices: Vec<u32>,
}

impl PatchScratch {
    pub(super) fn memory_bytes(&self) -> usize {
        self.indices.capacity() * std::mem::size_of::<u32>()
    }
}

/// What [`add_patch`] added.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct PatchAdded {
    pub(super) vertices: u64,
    pub(super) morphing_vertices: u64,
}

/// One primitive of a patch, in the patch's grid steps (a, b) at its level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum PatchPrimitive {
    /// A regular cell, its corners in the order its vertices are first taken (south-west,
    /// south-east, north-west, north-east); two triangles by [`cell_triangles`].
    Cell([(u32, u32); 4]),
    /// A stitch triangle: its corners in the zip's order and whether its last two corners
    /// are swapped to run counter-clockwise.
    Stitch([(u32, u32); 3], bool),
}

impl PatchPrimitive {
    /// The triangles of the primitive (counter-clockwise), given each corner's index.
    pub(super) fn triangles(
        self,
        mut index: impl FnMut((u32, u32)) -> u32,
    ) -> ([[u32; 3]; 2], usize) {
        match self {
            PatchPrimitive::Cell(corners) => {
                let [sw, se, nw, ne] = corners.map(&mut index);
                (cell_triangles(sw, se, nw, ne), 2)
            }
            PatchPrimitive::Stitch(corners, swapped) => {
                let [first, second, third] = corners.map(&mut index);
                let triangle = if swapped {
                    [first, third, second]
                } else {
                    [first, second, third]
                };
                ([triangle, triangle], 1)
            }
        }
    }
}

/// Walks the primitives of a patch of `n` cells a side whose sides are stitched at the steps
/// `stitched` (WEST, EAST, SOUTH, NORTH; `None`: not stitched), in drawing order: the regular
/// cells row by row, then each stitched side's zipped strip. The one walk both the mesh
/// ([`add_patch`]) and the shared index buffers (`buffers.rs`) are made from, so that they
/// list the same triangles with the same corners and winding.
pub(super) fn for_each_patch_primitive(
    n: u32,
    stitched: [Option<u32>; 4],
    mut visit: impl FnMut(PatchPrimitive),
) {
    for b in 0..n {
        for a in 0..n {
            let touches_stitch = (a == 0 && stitched[WEST].is_some())
                || (a + 1 == n && stitched[EAST].is_some())
                || (b == 0 && stitched[SOUTH].is_some())
                || (b + 1 == n && stitched[NORTH].is_some());
            if touches_stitch {
                continue;
            }
            visit(PatchPrimitive::Cell([
                (a, b),
                (a + 1, b),
                (a, b + 1),
                (a + 1, b + 1),
            ]));
        }
    }
    for side in [WEST, EAST, SOUTH, NORTH] {
        let Some(step) = stitched[side] else {
            continue;
        };
        // Along the side t runs from its start corner (south or west) to its end corner.
        let (start_other, end_other) = corner_sides(side);
        // The regular diagonal runs from the cell's south-west corner: on the west and south
        // sides that is the border vertex, whose inner neighbour comes first.
        let inner_first = side == WEST || side == SOUTH;
        // Walked from the start corner, the inner polyline lies to the left of the border on
        // the south and east sides, to the right on the west and north sides: there a triangle
        // (outer vertex, next outer, inner) runs counter-clockwise, here clockwise, and one
        // that advances along the inner polyline the other way round.
        let inner_on_the_right = side == WEST || side == NORTH;
        let point = |t: u32, inner: bool| -> (u32, u32) {
            let across = match (side, inner) {
                (WEST, false) | (SOUTH, false) => 0,
                (WEST, true) | (SOUTH, true) => 1,
                (_, false) => n,
                (_, true) => n - 1,
            };
            if side == WEST || side == EAST {
                (across, t)
            } else {
                (t, across)
            }
        };
        let last_outer = n / step;
        let first_inner = u32::from(stitched[start_other].is_some());
        let last_inner = n - u32::from(stitched[end_other].is_some());
        let (mut outer, mut inner) = (0, first_inner);
        while outer < last_outer || inner < last_inner {
            let advance_outer = if inner == last_inner {
                true
            } else if outer == last_outer {
                false
            } else {
                let (next_outer, next_inner) = ((outer + 1) * step, inner + 1);
                next_outer < next_inner || (next_outer == next_inner && !inner_first)
            };
            let o = point(outer * step, false);
            let i = point(inner, true);
            let corners = if advance_outer {
                let next = point((outer + 1) * step, false);
                outer += 1;
                [o, next, i]
            } else {
                let next = point(inner + 1, true);
                inner += 1;
                [o, i, next]
            };
            visit(PatchPrimitive::Stitch(
                corners,
                advance_outer == inner_on_the_right,
            ));
        }
    }
}

/// The stitch steps of `patch`'s sides (WEST, EAST, SOUTH, NORTH).
pub(super) fn stitch_steps_of(patch: &PatchDraw) -> [Option<u32>; 4] {
    [WEST, EAST, SOUTH, NORTH].map(|side| patch.stitch_step(side))
}

/// Adds `patch` to `list`.
pub(super) fn add_patch(
    list: &mut TriangleList,
    hierarchy: &Hierarchy,
    patch: &PatchDraw,
    scratch: &mut PatchScratch,
) -> PatchAdded {
    let n = patch.n();
    scratch.indices.clear();
    scratch
        .indices
        .resize(((n + 1) * (n + 1)) as usize, u32::MAX);
    let mut added = PatchAdded::default();
    let info = |role| TriangleInfo {
        role,
        group: patch.group,
        level: patch.list_level,
    };
    for_each_patch_primitive(n, stitch_steps_of(patch), |primitive| {
        // The vertices are added in the walk's order.
        let (triangles, count) = primitive.triangles(|(a, b)| {
            let slot = (b * (n + 1) + a) as usize;
            if scratch.indices[slot] == u32::MAX {
                let (position, z, morphing) = vertex_at(hierarchy, patch, a, b);
                scratch.indices[slot] = if morphing {
                    added.morphing_vertices += 1;
                    list.add_morphing_vertex(position, z)
                } else {
                    list.add_vertex(position, z)
                };
                added.vertices += 1;
            }
            scratch.indices[slot]
        });
        let role = match primitive {
            PatchPrimitive::Cell(_) => TriangleRole::Surface,
            PatchPrimitive::Stitch(..) => TriangleRole::Stitch,
        };
        for corners in &triangles[..count] {
            list.add_triangle(*corners, info(role));
        }
    });
    added
}

/// Vertex (a, b) of the patch's grid: its position, its height (morphed or not), and whether
/// it is morphing.
pub(super) fn vertex_at(
    hierarchy: &Hierarchy,
    patch: &PatchDraw,
    a: u32,
    b: u32,
) -> (SubgridPoint, f32, bool) {
    let n = patch.n();
    let stride = 1u32 << patch.level;
    let (x0, y0) = patch.origin;
    let (i, j) = (x0 + a * stride, y0 + b * stride);
    let position = SubgridPoint::grid(i, j);
    let sample = |i: u32, j: u32| hierarchy.height(GridPoint::new(i, j));
    let z = sample(i, j);
    let on_side = [a == 0, a == n, b == 0, b == n];
    let corner = (a == 0 || a == n) && (b == 0 || b == n);
    if corner {
        return (position, z, false);
    }
    if let Some(side) = (0..4).find(|&side| on_side[side]) {
        // A border vertex: the side's level and factor, along the side.
        let (side_level, f) = patch.sides[side];
        let side_stride = 1u32 << side_level;
        let vertical = side == WEST || side == EAST;
        let t = if vertical { j - y0 } else { i - x0 };
        if f < 1.0 && (t / side_stride) % 2 == 1 {
            let ends = if vertical {
                [sample(i, j - side_stride), sample(i, j + side_stride)]
            } else {
                [sample(i - side_stride, j), sample(i + side_stride, j)]
            };
            return (position, morphed_height(z, ends, f), true);
        }
        return (position, z, false);
    }
    match coarser_neighbours(a, b) {
        Some([p, q]) if patch.morph < 1.0 => {
            let at = |(pa, pb): (u32, u32)| sample(x0 + pa * stride, y0 + pb * stride);
            (
                position,
                morphed_height(z, [at(p), at(q)], patch.morph),
                true,
            )
        }
        _ => (position, z, false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mesh::raster::SampleRaster;
    use crate::sim::mesh::{CrackPolicy, MeshOutput, SUBGRID_UNITS_PER_CELL};
    use crate::sim::terrain::{Heightfield, Spacing};

    fn rough(side: usize) -> Hierarchy {
        let heights = (0..side * side)
            .map(|k| ((k * 2654435761usize) % 89) as f32 * 0.5 + (k / side) as f32)
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 2.0, dy: 2.0 }).unwrap())
    }

    /// The height every sample is drawn at (NaN where nothing is drawn).
    fn drawn_heights(hierarchy: &Hierarchy, patch: &PatchDraw) -> Vec<f64> {
        let mut list = TriangleList::new(hierarchy.lattice(), CrackPolicy::Stitched);
        add_patch(&mut list, hierarchy, patch, &mut PatchScratch::default());
        let lattice = hierarchy.lattice();
        let side = lattice.side() as usize;
        let raster = SampleRaster::new(
            SUBGRID_UNITS_PER_CELL,
            side,
            i64::from(lattice.cells()) * SUBGRID_UNITS_PER_CELL,
        );
        let mut heights = vec![f64::NAN; side * side];
        MeshOutput::triangles(&list).for_each_triangle(hierarchy, |t| {
            raster.for_each_covered_sample(&t.corners, |sample| {
                if sample.owned {
                    heights[sample.index] = sample.height;
                }
            });
        });
        heights
    }

    #[test]
    fn a_patch_morphed_to_zero_draws_exactly_its_next_coarser_level_stitched_or_not() {
        let hierarchy = rough(9);
        let patch = |level: u32, morph: f64, sides: [(u32, f64); 4]| PatchDraw {
            origin: (0, 0),
            patch_cells: 8,
            level,
            morph,
            sides,
            group: 0,
            list_level: 3 - level,
        };
        let coarse = drawn_heights(&hierarchy, &patch(2, 1.0, [(2, 1.0); 4]));
        for sides in [
            [(1, 0.0); 4],
            [(2, 1.0), (1, 0.0), (2, 1.0), (1, 0.0)],
            [(2, 1.0); 4],
        ] {
            let fine = drawn_heights(&hierarchy, &patch(1, 0.0, sides));
            for (k, (a, b)) in coarse.iter().zip(&fine).enumerate() {
                assert!(
                    (a - b).abs() < 1e-4 || (a.is_nan() && b.is_nan()),
                    "{sides:?}, sample {k}: {a} vs {b}"
                );
            }
        }
    }

    #[test]
    fn unstitched_patches_have_two_triangles_per_cell() {
        assert_eq!(patch_triangles(4, [None; 4]), 32);
        assert_eq!(patch_triangles(1, [None; 4]), 2);
    }

    #[test]
    fn stitched_sides_replace_their_strips_by_zipped_polylines() {
        // 2×2 cells, west side at twice the step: 2 regular cells (4 triangles), and a strip of
        // one outer segment and two inner ones.
        assert_eq!(patch_triangles(2, [Some(2), None, None, None]), 7);
        // Every side stitched: a fan of 4 around the centre.
        assert_eq!(patch_triangles(2, [Some(2); 4]), 4);
        // 4×4 cells, west at step 4 and south at step 2, sharing the south-west corner cell:
        // 16 − 4 − 4 + 1 = 9 regular cells; west 1 + 3, south 2 + 3 segments.
        assert_eq!(
            patch_triangles(4, [Some(4), None, Some(2), None]),
            18 + 4 + 5
        );
    }
}
