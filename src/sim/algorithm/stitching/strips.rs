//! The dynamic stitching strips (DSS, §3.1.3 and §3.2) and the P-blocks of one split node: the
//! cross of four strips between its children's regions, and the square at its centre.
//!
//! A strip lies between two sibling subtrees. Each of its two long sides gathers the vertices
//! that subtree shows along it (§3.2.2): a leaf contributes its M-block's edge, tessellated by
//! the same function and factor as the block itself; a split node its two children's sides in
//! order (the ends of its own strips appear as the gap between them, two corners and nothing
//! between). The two rows are then triangulated by the perpendicular-bisector rule
//! (Algorithm 1, [`merge_rows`]). So every strip vertex is one of a neighbouring M-block's
//! edge vertices, bit for bit, and the strip closes both edges.
//!
//! The P-block (§3.1.2) is the square where the four strips meet: its sides are the strips'
//! inner ends, so two triangles close it ([`PBlockShape::TwoTriangles`]); the option
//! [`PBlockShape::Fan`] adds its centre, resampled, and draws four.

use super::tessellate::{
    EAST, EdgeSpacing, NORTH, Rect, SOUTH, WEST, add_resampled_vertex, add_triangle_or_degenerate,
    merge_rows, side_points,
};
use super::tree::{NE, NW, NodeId, SE, SW, Tree};
use crate::sim::mesh::{TriangleInfo, TriangleList, TriangleRole};
use crate::sim::terrain::Heightfield;

/// What a P-block is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PBlockShape {
    /// Its four corners, two triangles (the south-west–north-east diagonal).
    TwoTriangles,
    /// Its four corners and its centre: four triangles.
    Fan,
}

/// The four strips of a split node, in drawing order.
pub const ARMS: [Arm; 4] = [Arm::South, Arm::East, Arm::North, Arm::West];

/// One strip of a node's cross, named by the side of the centre it lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arm {
    South,
    East,
    North,
    West,
}

impl Arm {
    /// The two subtrees it stitches, each with the side facing the strip: (child, side) for the
    /// lower row (west or south of the strip) and the upper row.
    pub fn rows(self) -> [(usize, usize); 2] {
        match self {
            Arm::South => [(SW, EAST), (SE, WEST)],
            Arm::North => [(NW, EAST), (NE, WEST)],
            Arm::West => [(SW, NORTH), (NW, SOUTH)],
            Arm::East => [(SE, NORTH), (NE, SOUTH)],
        }
    }

    /// Whether the strip runs south–north (its rows' coordinate along it is y).
    pub fn vertical(self) -> bool {
        matches!(self, Arm::South | Arm::North)
    }

    /// The strip's rectangle inside the split node `id`.
    pub fn rect(self, tree: &Tree, id: NodeId) -> Rect {
        let (region, square) = (tree.region(id), tree.square(id));
        let (cx, cy) = ((square.x0 + square.x1) / 2, (square.y0 + square.y1) / 2);
        let h = tree.half_width();
        match self {
            Arm::South => Rect {
                x0: cx - h,
                x1: cx + h,
                y0: region.y0,
                y1: cy - h,
            },
            Arm::North => Rect {
                x0: cx - h,
                x1: cx + h,
                y0: cy + h,
                y1: region.y1,
            },
            Arm::West => Rect {
                x0: region.x0,
                x1: cx - h,
                y0: cy - h,
                y1: cy + h,
            },
            Arm::East => Rect {
                x0: cx + h,
                x1: region.x1,
                y0: cy - h,
                y1: cy + h,
            },
        }
    }
}

/// The P-block of split node `id`.
pub fn p_block_rect(tree: &Tree, id: NodeId) -> Rect {
    let square = tree.square(id);
    let (cx, cy) = ((square.x0 + square.x1) / 2, (square.y0 + square.y1) / 2);
    let h = tree.half_width();
    Rect {
        x0: cx - h,
        y0: cy - h,
        x1: cx + h,
        y1: cy + h,
    }
}

/// Appends the vertices subtree `id` shows along its side `side`, in increasing order:
/// `factor(id)` is `Some(F)` for a leaf (its M-block's factor), `None` for a split node.
pub fn collect_side(
    tree: &Tree,
    factor: &impl Fn(NodeId) -> Option<f64>,
    id: NodeId,
    side: usize,
    out: &mut Vec<(i64, i64)>,
) {
    match factor(id) {
        Some(f) => side_points(tree.region(id), side, EdgeSpacing::FractionalEven(f), out),
        None => {
            let children = id.children();
            let (first, second) = match side {
                SOUTH => (SW, SE),
                NORTH => (NW, NE),
                WEST => (SW, NW),
                _ => (SE, NE),
            };
            collect_side(tree, factor, children[first], side, out);
            collect_side(tree, factor, children[second], side, out);
        }
    }
}

/// Reused buffers of [`add_strip`].
#[derive(Debug, Default)]
pub struct StripScratch {
    points: [Vec<(i64, i64)>; 2],
    rows: [Vec<(u32, i64)>; 2],
}

impl StripScratch {
    pub fn memory_bytes(&self) -> usize {
        self.points.iter().map(|p| p.capacity() * 16).sum::<usize>()
            + self.rows.iter().map(|r| r.capacity() * 16).sum::<usize>()
    }
}

/// Adds strip `arm` of split node `id`: its two rows' vertices and the bisector rule's
/// triangles (role stitch, counter-clockwise; degenerate where two rounded vertices coincide).
/// Returns (vertices, triangles) added.
#[allow(
    clippy::too_many_arguments,
    reason = "the strip's context, each needed once"
)]
pub fn add_strip(
    list: &mut TriangleList,
    field: &Heightfield,
    tree: &Tree,
    factor: &impl Fn(NodeId) -> Option<f64>,
    id: NodeId,
    arm: Arm,
    group: u32,
    scratch: &mut StripScratch,
) -> (u64, u64) {
    let vertices_before = list.vertices().len();
    let triangles_before = list.n_triangles();
    let children = id.children();
    for (row, (child, side)) in arm.rows().into_iter().enumerate() {
        let points = &mut scratch.points[row];
        points.clear();
        collect_side(tree, factor, children[child], side, points);
        let indices = &mut scratch.rows[row];
        indices.clear();
        for &(x, y) in points.iter() {
            let index = add_resampled_vertex(list, field, x, y);
            indices.push((index, if arm.vertical() { y } else { x }));
        }
    }
    let info = TriangleInfo {
        role: TriangleRole::Stitch,
        group,
        level: id.depth,
    };
    let [lower, upper] = &scratch.rows;
    merge_rows(lower, upper, |corners| {
        add_triangle_or_degenerate(list, corners, info);
    });
    (
        (list.vertices().len() - vertices_before) as u64,
        list.n_triangles() - triangles_before,
    )
}

/// Adds the P-block `rect` (role surface). Returns (vertices, triangles) added.
pub fn add_p_block(
    list: &mut TriangleList,
    field: &Heightfield,
    rect: Rect,
    shape: PBlockShape,
    info: TriangleInfo,
) -> (u64, u64) {
    let sw = add_resampled_vertex(list, field, rect.x0, rect.y0);
    let se = add_resampled_vertex(list, field, rect.x1, rect.y0);
    let nw = add_resampled_vertex(list, field, rect.x0, rect.y1);
    let ne = add_resampled_vertex(list, field, rect.x1, rect.y1);
    match shape {
        PBlockShape::TwoTriangles => {
            add_triangle_or_degenerate(list, [sw, se, ne], info);
            add_triangle_or_degenerate(list, [sw, ne, nw], info);
            (4, 2)
        }
        PBlockShape::Fan => {
            let centre = add_resampled_vertex(
                list,
                field,
                (rect.x0 + rect.x1) / 2,
                (rect.y0 + rect.y1) / 2,
            );
            for [a, b] in [[sw, se], [se, ne], [ne, nw], [nw, sw]] {
                add_triangle_or_degenerate(list, [a, b, centre], info);
            }
            (5, 4)
        }
    }
}
