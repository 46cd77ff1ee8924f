//! What geomipmapping keeps on the GPU side, as de Boer draws it (as Lauritsen–Nielsen §2.5
//! survey it): per patch one **static vertex buffer** of its full-resolution samples, and one
//! **index buffer per (level, stitched sides)** shared by every patch, since a patch's level
//! and its stitching choose which of its vertices are drawn, never where they are. A frame
//! issues one indexed draw per drawn patch; a level change only picks another index buffer.
//!
//! - **Vertex buffers** hold (2^k + 1)² vertices of 12 bytes each, written when the patch is
//!   first drawn and kept (not at construction: a 16385² terrain would hold 268 M vertices
//!   for patches no flight comes near; a streaming renderer does the same).
//! - **Index buffers** list the patch's triangles at a level with its sides stitched at the
//!   neighbours' levels, made the first time that (level, sides) is drawn, from the same walk as
//!   the mesh (`stitch::for_each_patch_primitive`), so the buffers and the mesh list the same
//!   triangles with the same winding.
//! - **Geomorphing** (decision): the heights are written by the CPU, de Boer's way (his
//!   geomorphing moves the vertices of a patch in transition, "which requires the vertices to be
//!   updated"; a vertex shader blend cannot express the border rule, where a border vertex
//!   morphs by its coarser-looking side's factor, not the patch's). A patch whose level, sides
//!   or factors changed while it morphs has its level's grid rewritten with the drawn heights
//!   (`stitch::vertex_at`, the mesh's own function, so they agree to the bit); once it stops
//!   morphing, the grid it morphed is written back to the samples. Without morphing a vertex
//!   buffer is never written again.
//!
//! Per frame: O(drawn patches), plus the writes a level or morph change asks for.

use super::stitch::{PatchDraw, for_each_patch_primitive, stitch_steps_of, vertex_at};
use crate::sim::draw::{BufferId, DrawCall, DrawVertex, GpuBuffers, Topology, VERTEX_BYTES};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::SubgridPoint;
use std::collections::HashMap;

/// A patch's drawn heights as last written: its level and sides, and the factors' bits.
pub(super) type MorphKey = ([u32; 5], [u64; 5]);

/// One patch's vertex buffer and what its heights are.
#[derive(Clone, Copy, Debug, Default)]
struct PatchVertices {
    buffer: Option<BufferId>,
    /// The morph state the buffer's heights were last written for, while morphing.
    written: Option<MorphKey>,
    /// Levels whose grid may hold morphed heights (bit ℓ).
    morphed_levels: u32,
}

/// The patches' buffers and the shared index buffers.
#[derive(Debug, Default)]
pub(super) struct PatchBuffers {
    gpu: GpuBuffers,
    patches: Vec<PatchVertices>,
    /// Per (level, stitch steps), the shared index buffer and its index count.
    indices: HashMap<(u32, [u32; 4]), (BufferId, u32)>,
    /// Vertex buffers written whole (made) and patches whose heights were rewritten this frame.
    pub(super) made: u64,
    pub(super) rewritten: u64,
    scratch: Vec<u32>,
}

impl PatchBuffers {
    pub(super) fn new(n_patches: usize) -> PatchBuffers {
        PatchBuffers {
            patches: vec![PatchVertices::default(); n_patches],
            ..PatchBuffers::default()
        }
    }

    pub(super) fn gpu(&self) -> &GpuBuffers {
        &self.gpu
    }

    /// Starts a frame's draw list.
    pub(super) fn begin_frame(&mut self) {
        self.gpu.clear_draws();
        self.made = 0;
        self.rewritten = 0;
    }

    /// Makes sure `patch`'s buffers draw it as `draw` says, and issues its draw.
    pub(super) fn draw_patch(
        &mut self,
        hierarchy: &Hierarchy,
        patch: usize,
        draw: &PatchDraw,
        morph: Option<MorphKey>,
    ) {
        let cells = draw.patch_cells;
        let row = cells + 1;
        let (x0, y0) = draw.origin;
        let state = &mut self.patches[patch];
        let vertices = match state.buffer {
            Some(buffer) => buffer,
            None => {
                let mut vertices = Vec::with_capacity((row * row) as usize);
                for j in y0..=y0 + cells {
                    for i in x0..=x0 + cells {
                        let z = hierarchy.height(GridPoint::new(i, j));
                        vertices.push(DrawVertex::fixed(SubgridPoint::grid(i, j), z));
                    }
                }
                self.made += 1;
                let buffer = self.gpu.create_vertices(vertices, VERTEX_BYTES);
                state.buffer = Some(buffer);
                buffer
            }
        };
        let stride = 1u32 << draw.level;
        let n = draw.n();
        let slot = |a: u32, b: u32| (b * stride * row + a * stride) as usize;
        match morph {
            Some(key) if state.written != Some(key) => {
                let steps = stitch_steps_of(draw).map(|step| step.unwrap_or(1));
                // A stitched side's vertices between its neighbour's are never drawn.
                let drawn = |a: u32, b: u32| {
                    (a != 0 || b.is_multiple_of(steps[0]))
                        && (a != n || b.is_multiple_of(steps[1]))
                        && (b != 0 || a.is_multiple_of(steps[2]))
                        && (b != n || a.is_multiple_of(steps[3]))
                };
                for b in 0..=n {
                    for a in (0..=n).filter(|&a| drawn(a, b)) {
                        let (position, z, _) = vertex_at(hierarchy, draw, a, b);
                        self.gpu.write_vertices(
                            vertices,
                            slot(a, b),
                            &[DrawVertex::fixed(position, z)],
                        );
                    }
                }
                state.written = Some(key);
                state.morphed_levels |= 1 << draw.level;
                self.rewritten += 1;
            }
            None if state.morphed_levels != 0 => {
                // Back to the samples: the finest morphed grid holds every coarser one.
                let finest = state.morphed_levels.trailing_zeros();
                let stride = 1u32 << finest;
                for j in (0..=cells).step_by(stride as usize) {
                    for i in (0..=cells).step_by(stride as usize) {
                        let (gi, gj) = (x0 + i, y0 + j);
                        let z = hierarchy.height(GridPoint::new(gi, gj));
                        self.gpu.write_vertices(
                            vertices,
                            (j * row + i) as usize,
                            &[DrawVertex::fixed(SubgridPoint::grid(gi, gj), z)],
                        );
                    }
                }
                state.written = None;
                state.morphed_levels = 0;
                self.rewritten += 1;
            }
            _ => {}
        }
        let steps = stitch_steps_of(draw);
        let key = (draw.level, steps.map(|s| s.unwrap_or(0)));
        let (indices, count) = match self.indices.get(&key) {
            Some(&found) => found,
            None => {
                let scratch = &mut self.scratch;
                scratch.clear();
                for_each_patch_primitive(n, steps, |primitive| {
                    let (triangles, count) =
                        primitive.triangles(|(a, b)| b * stride * row + a * stride);
                    for corners in &triangles[..count] {
                        scratch.extend_from_slice(corners);
                    }
                });
                let made = (
                    self.gpu.create_indices(scratch.clone()),
                    scratch.len() as u32,
                );
                self.indices.insert(key, made);
                made
            }
        };
        self.gpu.draw(DrawCall {
            vertices,
            indices,
            first_index: 0,
            index_count: count,
            topology: Topology::TriangleList,
            blend: 0.0,
        });
    }

    /// Ends the frame: what it uploaded and issued.
    pub(super) fn end_frame(&mut self) -> crate::sim::draw::DrawCounts {
        self.gpu.end_frame()
    }

    /// Heap bytes held (the GPU model's included).
    pub(super) fn memory_bytes(&self) -> usize {
        self.gpu.memory_bytes()
            + self.patches.capacity() * std::mem::size_of::<PatchVertices>()
            + self.indices.capacity() * std::mem::size_of::<((u32, [u32; 4]), (BufferId, u32))>()
            + self.scratch.capacity() * std::mem::size_of::<u32>()
    }
}
