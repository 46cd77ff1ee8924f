//! The chunked selection decided chunk by chunk from the definitions (eq. 3.1's errors, the
//! test of listing 3.2), for differential tests: no top-down traversal, and errors recomputed
//! another way.
//!
//! Every chunk's surface is evaluated at the samples by interpolation in its cell (the
//! triangle (SW, SE, NE) or (SW, NE, NW) the sample falls in), δ_m is the largest vertical
//! distance between a chunk's surface and its children's at the vertices of their grids, δ_c
//! follows eq. 3.1 bottom-up, and a chunk is drawn when every ancestor wants refining and is
//! not culled, and it neither wants refining (or is a leaf) nor is culled. What is shared with
//! the algorithm is the arithmetic of the test itself (the box distance, C, the culling test,
//! the rounding of stored errors), which `block_lod` tests on its own.

use super::super::block_lod::cull::box_outside_view;
use super::super::block_lod::grid::round_up_f32;
use super::super::block_lod::threshold::{BlockBox, DetailThreshold};
use super::{ChunkId, ChunkedConfig};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::view::Camera;
use glam::DVec3;
use std::collections::HashMap;

/// The chunks `chunked` with `config` draws from `camera` at tolerance `tau_px`, sorted by id.
/// O(samples · levels + chunks · levels).
pub fn chunks_from_scratch(
    hierarchy: &Hierarchy,
    config: &ChunkedConfig,
    camera: &Camera,
    tau_px: f64,
) -> Vec<ChunkId> {
    let terrain_level = hierarchy.lattice().level();
    let chunk_level = config.chunk_level.clamp(1, terrain_level);
    let leaf_level = terrain_level - chunk_level;
    let cells = 1u32 << chunk_level;
    let spacing = hierarchy.field().spacing();
    let square = |id: ChunkId| {
        let side = cells << (leaf_level - id.level);
        (id.x * side, id.y * side, side)
    };
    // The chunk's surface at sample (i, j) of its closed square.
    let surface = |id: ChunkId, i: u32, j: u32| -> f64 {
        let (x0, y0, side) = square(id);
        let stride = side / cells;
        let (a, b) = (
            ((i - x0) / stride).min(cells - 1),
            ((j - y0) / stride).min(cells - 1),
        );
        let (ci, cj) = (x0 + a * stride, y0 + b * stride);
        let z = |di: u32, dj: u32| f64::from(hierarchy.height(GridPoint::new(ci + di, cj + dj)));
        let (sw, se, nw, ne) = (z(0, 0), z(stride, 0), z(0, stride), z(stride, stride));
        let (u, v) = (
            f64::from(i - ci) / f64::from(stride),
            f64::from(j - cj) / f64::from(stride),
        );
        if u >= v {
            sw + u * (se - sw) + v * (ne - se)
        } else {
            sw + u * (ne - nw) + v * (nw - sw)
        }
    };
    let mut errors: HashMap<ChunkId, f32> = HashMap::new();
    let mut boxes: HashMap<ChunkId, BlockBox> = HashMap::new();
    for level in (0..=leaf_level).rev() {
        let per_side = 1u32 << level;
        for y in 0..per_side {
            for x in 0..per_side {
                let id = ChunkId { level, x, y };
                let (x0, y0, side) = square(id);
                let (mut z_min, mut z_max) = (f64::INFINITY, f64::NEG_INFINITY);
                for j in y0..=y0 + side {
                    for i in x0..=x0 + side {
                        let z = f64::from(hierarchy.height(GridPoint::new(i, j)));
                        z_min = z_min.min(z);
                        z_max = z_max.max(z);
                    }
                }
                boxes.insert(
                    id,
                    BlockBox {
                        low: DVec3::new(
                            f64::from(x0) * spacing.dx,
                            f64::from(y0) * spacing.dy,
                            z_min,
                        ),
                        high: DVec3::new(
                            f64::from(x0 + side) * spacing.dx,
                            f64::from(y0 + side) * spacing.dy,
                            z_max,
                        ),
                    },
                );
                let error = if level == leaf_level {
                    0.0
                } else {
                    let half = side / cells / 2;
                    let mut own: f64 = 0.0;
                    for j in (y0..=y0 + side).step_by(half as usize) {
                        for i in (x0..=x0 + side).step_by(half as usize) {
                            let z = f64::from(hierarchy.height(GridPoint::new(i, j)));
                            own = own.max((z - surface(id, i, j)).abs());
                        }
                    }
                    let children = id.children().map(|c| f64::from(errors[&c]));
                    round_up_f32(children.into_iter().fold(0.0, f64::max) + own)
                };
                errors.insert(id, error);
            }
        }
    }
    let threshold = DetailThreshold::new(camera.settings.pixels_per_unit(), tau_px);
    let culled = |id: ChunkId| config.culling && box_outside_view(camera, &boxes[&id]);
    let refines = |id: ChunkId| {
        id.level < leaf_level
            && threshold.refines(
                errors[&id],
                boxes[&id].lod_distance(camera.eye, config.projection),
            )
    };
    let mut drawn: Vec<ChunkId> = boxes
        .keys()
        .copied()
        .filter(|&id| {
            let ancestors_refine = (0..id.level).all(|level| {
                let ancestor = id.ancestor_at(level).unwrap_or(ChunkId::ROOT);
                !culled(ancestor) && refines(ancestor)
            });
            ancestors_refine && !culled(id) && !refines(id)
        })
        .collect();
    drawn.sort_unstable();
    drawn
}
