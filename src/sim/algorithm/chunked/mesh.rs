//! A drawn chunk as triangles (Lauritsen–Nielsen §3.2.3, §3.2.6, §3.2.8): its regular grid,
//! morphed as the selection says, and its skirt. It chooses nothing: which chunks are drawn,
//! and their morph factors, are the selection's (`select.rs`).
//!
//! - **Surface**: the chunk's (2^c + 1)² vertices, its cells split along their south-west–
//!   north-east diagonal (`block_lod::grid`). With a morph factor f < 1 every vertex the
//!   parent lacks (odd in the chunk's grid), border vertices included, is drawn between z and
//!   z_c, z_c on the parent's surface (eq. 3.4), as a morphing vertex: at
//!   `draw::morph_height(z, z_c, 1 − f)`, the formula the vertex shader applies to the chunk's
//!   buffer (z with z_c as its morph target, 1 − f the draw's blend).
//! - **Skirt** (§3.2.6): below each of the 4·2^c border edges, two vertical triangles down to
//!   the chunk's skirt depth ([`super::tree::SkirtDepth`]), from every border vertex as drawn
//!   (morphed or not). A skirt of depth 0 (the paper's, at a leaf) is drawn all the same: the
//!   triangle count does not depend on the depth, and the audit measures what it covers.
//!
//! Every triangle has the chunk's breadth-first number as its group (one draw batch per
//! chunk) and the chunk's quadtree level as its level. The vertices are the chunk's own: a
//! border vertex is added once per chunk that draws it, as each chunk's vertex buffer holds it.
//! The mesh is built from the buffers `buffers.rs` keeps ([`add_chunk`] reads a chunk's vertex
//! buffer, [`chunk_vertices`], and the one index buffer all chunks share, [`chunk_indices`]),
//! so they draw exactly this mesh.

use super::super::block_lod::grid::{cell_triangles, coarser_neighbours};
use super::select::DrawnChunk;
use super::tree::{ChunkGeometry, ChunkId, ChunkRecord, ChunkSource};
use crate::sim::draw::DrawVertex;
use crate::sim::mesh::{TriangleInfo, TriangleList, TriangleRole};

/// Vertices a chunk of `cells` cells adds: its grid and one skirt bottom per border vertex.
pub(super) fn vertices_per_chunk(cells: u32) -> u64 {
    let side = u64::from(cells) + 1;
    side * side + 4 * u64::from(cells)
}

/// Triangles a chunk of `cells` cells adds: two per cell, two per border edge.
pub(super) fn triangles_per_chunk(cells: u32) -> u64 {
    2 * u64::from(cells) * u64::from(cells) + 8 * u64::from(cells)
}

/// The blend a drawn chunk's vertices are drawn at (its per-draw constant): 1 − f while it
/// morphs (f < 1), 0 at full detail.
pub(super) fn blend(morph: f64) -> f32 {
    if morph < 1.0 {
        (1.0 - morph) as f32
    } else {
        0.0
    }
}

/// The border vertex `k` of a chunk of `cells` cells, counter-clockwise from the south-west
/// corner.
fn ring(cells: u32, k: u32) -> (u32, u32) {
    let (edge, t) = (k / cells, k % cells);
    match edge {
        0 => (t, 0),
        1 => (cells, t),
        2 => (cells - t, cells),
        _ => (0, cells - t),
    }
}

/// Writes into `out` the vertex buffer of chunk `id` (whose record is `record`): its
/// (2^c + 1)² grid vertices row by row, then one skirt bottom per border vertex
/// counter-clockwise from the south-west corner. With `morph`, every vertex the parent lacks
/// (odd in the chunk's grid, border vertices included) carries its height on the parent's
/// surface, z_c (eq. 3.4), as its morph target, and a skirt bottom carries its top's target less
/// the skirt depth; the other vertices' target is their height. The buffer does not depend on
/// the frame: the morph factor is the draw's blend ([`blend`]).
pub(super) fn chunk_vertices<S: ChunkSource>(
    source: &S,
    geometry: &ChunkGeometry,
    id: ChunkId,
    record: &ChunkRecord,
    morph: bool,
    out: &mut Vec<DrawVertex>,
) {
    let cells = geometry.cells;
    let side = cells + 1;
    out.clear();
    for b in 0..=cells {
        for a in 0..=cells {
            let z = source.height(id, a, b);
            let z_target = match coarser_neighbours(a, b) {
                Some([p, q]) if morph => {
                    let ends = [source.height(id, p.0, p.1), source.height(id, q.0, q.1)];
                    (0.5 * (f64::from(ends[0]) + f64::from(ends[1]))) as f32
                }
                _ => z,
            };
            out.push(DrawVertex {
                position: geometry.vertex(id, a, b),
                z,
                z_target,
            });
        }
    }
    let depth = f64::from(record.skirt_depth);
    for k in 0..4 * cells {
        let (a, b) = ring(cells, k);
        let top = out[(b * side + a) as usize];
        out.push(DrawVertex {
            position: top.position,
            z: (f64::from(top.z) - depth) as f32,
            z_target: (f64::from(top.z_target) - depth) as f32,
        });
    }
}

/// Calls `visit` on every triangle of a chunk of `cells` cells, as indices into its vertex
/// buffer ([`chunk_vertices`]): two per cell, split along the south-west–north-east diagonal,
/// then two per border edge for the skirt. Every chunk has this topology, so one index buffer
/// serves them all.
pub(super) fn for_each_chunk_triangle(cells: u32, mut visit: impl FnMut([u32; 3])) {
    let side = cells + 1;
    let at = |a: u32, b: u32| b * side + a;
    for b in 0..cells {
        for a in 0..cells {
            let (sw, se) = (at(a, b), at(a + 1, b));
            let (nw, ne) = (at(a, b + 1), at(a + 1, b + 1));
            for corners in cell_triangles(sw, se, nw, ne) {
                visit(corners);
            }
        }
    }
    let n_ring = 4 * cells;
    let top = |k: u32| {
        let (a, b) = ring(cells, k);
        at(a, b)
    };
    let bottom = |k: u32| side * side + k;
    for k in 0..n_ring {
        let next = (k + 1) % n_ring;
        visit([top(k), top(next), bottom(next)]);
        visit([top(k), bottom(next), bottom(k)]);
    }
}

/// The index buffer every chunk of `cells` cells is drawn with (a triangle list).
pub(super) fn chunk_indices(cells: u32) -> Vec<u32> {
    let mut indices = Vec::with_capacity(3 * triangles_per_chunk(cells) as usize);
    for_each_chunk_triangle(cells, |corners| indices.extend(corners));
    indices
}

/// Adds `chunk` to `list`: `vertices`, its vertex buffer ([`chunk_vertices`], kept by
/// `buffers.rs`), at the heights the GPU draws them at this frame's blend
/// ([`DrawVertex::drawn`], so the mesh and the buffers agree to the bit), and its triangles,
/// `indices` ([`chunk_indices`], the shared index buffer). Reads no height: O(chunk's vertices
/// and triangles).
pub(super) fn add_chunk(
    list: &mut TriangleList,
    geometry: &ChunkGeometry,
    chunk: &DrawnChunk,
    vertices: &[DrawVertex],
    indices: &[u32],
) {
    let id = chunk.id;
    let cells = geometry.cells;
    let side = cells + 1;
    let grid = (side * side) as usize;
    debug_assert_eq!(vertices.len() as u64, vertices_per_chunk(cells));
    debug_assert_eq!(indices.len() as u64, 3 * triangles_per_chunk(cells));
    let blend = blend(chunk.morph);
    let morphing = chunk.morph < 1.0;
    let base = list.vertices().len() as u32;
    // The grid row by row (a vertex the parent lacks, odd in a or b, morphs), then the skirt
    // bottoms, which do not.
    for (b, row) in vertices[..grid].chunks_exact(side as usize).enumerate() {
        for (a, vertex) in row.iter().enumerate() {
            let drawn = vertex.drawn(blend);
            if morphing && (a | b) % 2 == 1 {
                list.add_morphing_vertex(drawn.position, drawn.z);
            } else {
                list.add_vertex(drawn.position, drawn.z);
            }
        }
    }
    for vertex in &vertices[grid..] {
        let drawn = vertex.drawn(blend);
        list.add_vertex(drawn.position, drawn.z);
    }
    let info = |role| TriangleInfo {
        role,
        group: id.breadth_first_index(),
        level: id.level,
    };
    let surface = 3 * 2 * (cells * cells) as usize;
    for (k, corners) in indices.chunks_exact(3).enumerate() {
        let role = if 3 * k < surface {
            TriangleRole::Surface
        } else {
            TriangleRole::Skirt
        };
        list.add_triangle(
            [base + corners[0], base + corners[1], base + corners[2]],
            info(role),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::super::tree::{ChunkId, ChunkTree, SkirtDepth};
    use super::*;
    use crate::sim::hierarchy::Hierarchy;
    use crate::sim::mesh::raster::SampleRaster;
    use crate::sim::mesh::{CrackPolicy, MeshOutput, SUBGRID_UNITS_PER_CELL};
    use crate::sim::terrain::{Heightfield, Spacing};

    /// The drawn height at every sample of the terrain (NaN where no surface triangle owns it).
    fn drawn_heights(hierarchy: &Hierarchy, list: &TriangleList) -> Vec<f64> {
        let lattice = hierarchy.lattice();
        let side = lattice.side() as usize;
        let raster = SampleRaster::new(
            SUBGRID_UNITS_PER_CELL,
            side,
            i64::from(lattice.cells()) * SUBGRID_UNITS_PER_CELL,
        );
        let mut heights = vec![f64::NAN; side * side];
        MeshOutput::triangles(list).for_each_triangle(hierarchy, |t| {
            if t.info.role == TriangleRole::Surface {
                raster.for_each_covered_sample(&t.corners, |sample| {
                    if sample.owned {
                        heights[sample.index] = sample.height;
                    }
                });
            }
        });
        heights
    }

    #[test]
    fn children_at_morph_factor_zero_draw_exactly_their_parents_surface() {
        let side = 17;
        let heights = (0..side * side)
            .map(|k| ((k * 2654435761usize) % 97) as f32 * 0.25 + (k % side) as f32)
            .collect();
        let hierarchy =
            Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 3.0, dy: 3.0 }).unwrap());
        let tree = ChunkTree::new(&hierarchy, 2, SkirtDepth::ChunkError, true, 0.0);
        let geometry = *tree.geometry();
        let drawn = |id: ChunkId, morph: f64| DrawnChunk {
            id,
            distance: 0.0,
            morph,
        };
        let mut vertices = Vec::new();
        let indices = chunk_indices(geometry.cells);
        for parent in [
            ChunkId::ROOT,
            ChunkId {
                level: 1,
                x: 1,
                y: 0,
            },
        ] {
            let mut whole = TriangleList::new(hierarchy.lattice(), CrackPolicy::Skirted);
            let mut split = TriangleList::new(hierarchy.lattice(), CrackPolicy::Skirted);
            let record = *tree.record(parent);
            chunk_vertices(&tree, &geometry, parent, &record, true, &mut vertices);
            add_chunk(
                &mut whole,
                &geometry,
                &drawn(parent, 1.0),
                &vertices,
                &indices,
            );
            for child in parent.children() {
                let record = *tree.record(child);
                chunk_vertices(&tree, &geometry, child, &record, true, &mut vertices);
                add_chunk(
                    &mut split,
                    &geometry,
                    &drawn(child, 0.0),
                    &vertices,
                    &indices,
                );
            }
            let (a, b) = (
                drawn_heights(&hierarchy, &whole),
                drawn_heights(&hierarchy, &split),
            );
            let mut compared = 0;
            for (k, (x, y)) in a.iter().zip(&b).enumerate() {
                if !x.is_nan() {
                    assert!((x - y).abs() < 1e-4, "{parent:?}, sample {k}: {x} vs {y}");
                    compared += 1;
                }
            }
            assert!(compared >= 25, "{parent:?}: {compared} samples");
        }
    }

    #[test]
    fn a_65_by_65_chunk_has_8192_surface_and_512_skirt_triangles() {
        assert_eq!(triangles_per_chunk(64), 8192 + 512);
        assert_eq!(vertices_per_chunk(64), 65 * 65 + 256);
        // 65² − 33² odd vertices, and half the 256 border vertices' bottoms.
    }
}
