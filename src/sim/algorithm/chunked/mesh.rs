//! A drawn chunk as triangles (Lauritsen–Nielsen §3.2.3, §3.2.6, §3.2.8): its regular grid,
//! morphed as the selection says, and its skirt. It chooses nothing: which chunks are drawn,
//! and their morph factors, are the selection's (`select.rs`).
//!
//! - **Surface**: the chunk's (2^c + 1)² vertices, its cells split along their south-west–
//!   north-east diagonal (`block_lod::grid`). With a morph factor f < 1 every vertex the
//!   parent lacks (odd in the chunk's grid), border vertices included, is drawn at
//!   z_c + f·(z − z_c), z_c on the parent's surface (eq. 3.4), as a morphing vertex.
//! - **Skirt** (§3.2.6): below each of the 4·2^c border edges, two vertical triangles down to
//!   the chunk's skirt depth ([`super::tree::SkirtDepth`]), from every border vertex as drawn
//!   (morphed or not). A skirt of depth 0 (the paper's, at a leaf) is drawn all the same: the
//!   triangle count does not depend on the depth, and the audit measures what it covers.
//!
//! Every triangle has the chunk's breadth-first number as its group (one draw batch per
//! chunk) and the chunk's quadtree level as its level. The vertices are the chunk's own: a
//! border vertex is added once per chunk that draws it, as each chunk's vertex buffer holds it.

use super::super::block_lod::grid::{cell_triangles, coarser_neighbours, morphed_height};
use super::select::DrawnChunk;
use super::tree::{ChunkGeometry, ChunkRecord, ChunkSource};
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

/// Adds `chunk` (whose record is `record`) to `list`. `indices` is scratch space.
pub(super) fn add_chunk<S: ChunkSource>(
    list: &mut TriangleList,
    source: &S,
    geometry: &ChunkGeometry,
    chunk: &DrawnChunk,
    record: &ChunkRecord,
    indices: &mut Vec<u32>,
) {
    let id = chunk.id;
    let cells = geometry.cells;
    let side = cells + 1;
    let at = |a: u32, b: u32| (b * side + a) as usize;
    indices.clear();
    for b in 0..=cells {
        for a in 0..=cells {
            let position = geometry.vertex(id, a, b);
            let z = source.height(id, a, b);
            let index = match coarser_neighbours(a, b) {
                Some([p, q]) if chunk.morph < 1.0 => {
                    let ends = [source.height(id, p.0, p.1), source.height(id, q.0, q.1)];
                    list.add_morphing_vertex(position, morphed_height(z, ends, chunk.morph))
                }
                _ => list.add_vertex(position, z),
            };
            indices.push(index);
        }
    }
    let info = |role| TriangleInfo {
        role,
        group: id.breadth_first_index(),
        level: id.level,
    };
    for b in 0..cells {
        for a in 0..cells {
            let (sw, se) = (indices[at(a, b)], indices[at(a + 1, b)]);
            let (nw, ne) = (indices[at(a, b + 1)], indices[at(a + 1, b + 1)]);
            for corners in cell_triangles(sw, se, nw, ne) {
                list.add_triangle(corners, info(TriangleRole::Surface));
            }
        }
    }
    // The border, counter-clockwise from the south-west corner, one skirt bottom per vertex
    // (the bottoms' indices appended to `indices` after the grid's: no allocation per chunk).
    let ring = |k: u32| -> (u32, u32) {
        let (edge, t) = (k / cells, k % cells);
        match edge {
            0 => (t, 0),
            1 => (cells, t),
            2 => (cells - t, cells),
            _ => (0, cells - t),
        }
    };
    let n_ring = 4 * cells;
    let depth = f64::from(record.skirt_depth);
    let bottoms_from = indices.len();
    for k in 0..n_ring {
        let (a, b) = ring(k);
        let vertex = list.vertices()[indices[at(a, b)] as usize];
        let bottom = list.add_vertex(vertex.position, (f64::from(vertex.z) - depth) as f32);
        indices.push(bottom);
    }
    let (grid, bottoms) = indices.split_at(bottoms_from);
    let top = |k: u32| {
        let (a, b) = ring(k);
        grid[at(a, b)]
    };
    for k in 0..n_ring {
        let next = (k + 1) % n_ring;
        let (top_k, top_next) = (top(k), top(next));
        let (bottom_k, bottom_next) = (bottoms[k as usize], bottoms[next as usize]);
        list.add_triangle([top_k, top_next, bottom_next], info(TriangleRole::Skirt));
        list.add_triangle([top_k, bottom_next, bottom_k], info(TriangleRole::Skirt));
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
        let mut indices = Vec::new();
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
            add_chunk(
                &mut whole,
                &tree,
                &geometry,
                &drawn(parent, 1.0),
                &record,
                &mut indices,
            );
            for child in parent.children() {
                let record = *tree.record(child);
                add_chunk(
                    &mut split,
                    &tree,
                    &geometry,
                    &drawn(child, 0.0),
                    &record,
                    &mut indices,
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
