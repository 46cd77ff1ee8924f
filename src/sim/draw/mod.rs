//! What a GPU draws: the buffers an algorithm keeps on the GPU side and the draw list it issues
//! each frame (issue #31: the study times every algorithm from a new camera to buffers a GPU can
//! draw). A model of GPU memory, not a renderer: no API is called. Its value is in what it
//! counts, the same way for every algorithm: the bytes written into GPU buffers this frame
//! (`upload_bytes`), the draw calls issued (`draw_calls`) and the triangles those calls submit
//! (`triangles_submitted`, degenerate ones included, since the GPU processes them).
//!
//! - [`GpuBuffers`] holds vertex buffers and index buffers by [`BufferId`], and the frame's
//!   draw list of [`DrawCall`]s. Every write is counted: creating or rewriting a buffer or a
//!   range of it, and per-draw constants ([`GpuBuffers::upload_constants`], e.g. a block's
//!   tessellation factors or a chunk's morph blend). Reading is free; so is issuing a draw,
//!   beyond the command itself.
//! - A vertex is a [`DrawVertex`]: its position in the plane and the height it is drawn at, plus
//!   an optional morph target that the vertex shader blends towards by the draw's blend
//!   ([`morph_height`], the one formula used by algorithms and decoder alike, so the drawn
//!   height is bit-exact). A buffer declares its bytes per vertex (12 for x, y, z as `f32`, 16
//!   with a morph target).
//! - [`GpuBuffers::for_each_triangle`] decodes the draw list as a GPU assembles primitives
//!   (lists, strips with the odd triangles' corners swapped, fans, and primitive restart), which
//!   is how the runner checks that **the buffers are the mesh** ([`check`]).
//! - A [`Topology::Patches`] draw is expanded by the tessellator the algorithm registered
//!   ([`patches`]): its patches' words are uploaded, its triangles are the GPU's work.
//!
//! Each algorithm keeps one `GpuBuffers` and maintains it itself inside its frame (in `update`
//! and `LodAlgorithm::prepare_draw`); its module doc says which representation it keeps and why
//! it is its paper's. [`emit`] is the plain way of a rebuilding algorithm: the whole mesh written
//! again each frame; [`incremental`] the leaf buffer of an algorithm that splits and merges
//! (Wu's and ROAM's), changed in place.

pub mod check;
mod decode;
pub mod emit;
pub mod incremental;
pub mod patches;
pub mod strips;

use crate::sim::mesh::{SubgridPoint, SurfacePoint};
use patches::Tessellator;
use std::sync::Arc;

/// Bytes of one index on the GPU (`u32`).
pub const INDEX_BYTES: u64 = 4;
/// Bytes of a vertex drawn at its own height: x, y, z as `f32`.
pub const VERTEX_BYTES: u32 = 12;
/// Bytes of a vertex with a morph target: x, y, z and the target height.
pub const MORPHING_VERTEX_BYTES: u32 = 16;
/// The index that restarts a strip or a fan (primitive restart, as every modern API has it).
pub const RESTART: u32 = u32::MAX;

/// A vertex as it sits in a GPU buffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawVertex {
    pub position: SubgridPoint,
    /// The height drawn at blend 0, metres in the terrain's local frame.
    pub z: f32,
    /// The height drawn at blend 1 (a morph target); equal to `z` for a vertex that does not
    /// morph.
    pub z_target: f32,
}

impl DrawVertex {
    /// A vertex drawn at height `z` whatever the blend.
    pub fn fixed(position: SubgridPoint, z: f32) -> DrawVertex {
        DrawVertex {
            position,
            z,
            z_target: z,
        }
    }

    /// The vertex of a mesh corner, drawn at the corner's height.
    pub fn of(corner: SurfacePoint) -> DrawVertex {
        DrawVertex::fixed(corner.position, corner.z)
    }

    /// The corner this vertex draws at `blend`.
    pub fn drawn(self, blend: f32) -> SurfacePoint {
        SurfacePoint {
            position: self.position,
            z: morph_height(self.z, self.z_target, blend),
        }
    }
}

/// The height a morphing vertex is drawn at: `z + blend·(target − z)` in `f32`, exactly `z` at
/// blend 0 and when `target == z`. Algorithms that morph compute their mesh's heights with this
/// function, so the mesh and the buffers agree to the bit.
pub fn morph_height(z: f32, target: f32, blend: f32) -> f32 {
    if blend == 0.0 || target == z {
        z
    } else {
        z + blend * (target - z)
    }
}

/// How a draw call's indices form triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Topology {
    /// Three indices a triangle.
    TriangleList,
    /// Each index after the second closes a triangle with the two before it; odd triangles'
    /// first two corners are swapped so that every triangle keeps the strip's winding.
    /// [`RESTART`] starts a new strip.
    TriangleStrip,
    /// Each index after the second closes a triangle with the first and the one before it.
    /// [`RESTART`] starts a new fan.
    TriangleFan,
    /// Patches for the tessellation stage: the index buffer holds the patches' words (an
    /// instance buffer, [`patches::Tessellator::words_per_patch`] words a patch) and the
    /// buffers' tessellator ([`GpuBuffers::set_tessellator`]) makes their triangles; the vertex
    /// buffer is not read, nor the blend.
    Patches,
}

/// A buffer on the GPU side, vertex or index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BufferId(u32);

/// One draw command: a range of an index buffer over a vertex buffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawCall {
    pub vertices: BufferId,
    pub indices: BufferId,
    pub first_index: u32,
    pub index_count: u32,
    pub topology: Topology,
    /// The morph blend the vertex shader applies to this draw's vertices (0: none).
    pub blend: f32,
}

/// What one frame wrote and issued.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DrawCounts {
    /// Bytes written into GPU buffers this frame: vertices, indices, per-draw constants.
    pub upload_bytes: u64,
    pub draw_calls: u64,
    /// Triangles the draw calls submit, degenerate ones included.
    pub triangles_submitted: u64,
}

#[derive(Clone, Debug, Default)]
struct VertexBuffer {
    vertices: Vec<DrawVertex>,
    bytes_per_vertex: u32,
}

/// The GPU-side state of one algorithm: its buffers and this frame's draw list.
#[derive(Clone, Debug, Default)]
pub struct GpuBuffers {
    vertex_buffers: Vec<Option<VertexBuffer>>,
    index_buffers: Vec<Option<Vec<u32>>>,
    free_vertex_ids: Vec<u32>,
    free_index_ids: Vec<u32>,
    draws: Vec<DrawCall>,
    upload_bytes: u64,
    /// The tessellation stage that expands [`Topology::Patches`] draws, when one is registered.
    tessellator: Option<Arc<dyn Tessellator>>,
}

impl GpuBuffers {
    pub fn new() -> GpuBuffers {
        GpuBuffers::default()
    }

    /// A new vertex buffer holding `vertices` (counted as uploaded).
    pub fn create_vertices(
        &mut self,
        vertices: Vec<DrawVertex>,
        bytes_per_vertex: u32,
    ) -> BufferId {
        self.upload_bytes += vertices.len() as u64 * u64::from(bytes_per_vertex);
        let buffer = Some(VertexBuffer {
            vertices,
            bytes_per_vertex,
        });
        BufferId(match self.free_vertex_ids.pop() {
            Some(id) => {
                self.vertex_buffers[id as usize] = buffer;
                id
            }
            None => {
                self.vertex_buffers.push(buffer);
                self.vertex_buffers.len() as u32 - 1
            }
        })
    }

    /// A new index buffer holding `indices` (counted as uploaded).
    pub fn create_indices(&mut self, indices: Vec<u32>) -> BufferId {
        self.upload_bytes += indices.len() as u64 * INDEX_BYTES;
        BufferId(match self.free_index_ids.pop() {
            Some(id) => {
                self.index_buffers[id as usize] = Some(indices);
                id
            }
            None => {
                self.index_buffers.push(Some(indices));
                self.index_buffers.len() as u32 - 1
            }
        })
    }

    /// Frees a vertex buffer (nothing is uploaded).
    pub fn release_vertices(&mut self, id: BufferId) {
        self.vertex_buffers[id.0 as usize] = None;
        self.free_vertex_ids.push(id.0);
    }

    /// Frees an index buffer (nothing is uploaded).
    pub fn release_indices(&mut self, id: BufferId) {
        self.index_buffers[id.0 as usize] = None;
        self.free_index_ids.push(id.0);
    }

    /// Writes `vertices` from `offset` on (growing the buffer when they run past its end); the
    /// bytes written are counted.
    pub fn write_vertices(&mut self, id: BufferId, offset: usize, vertices: &[DrawVertex]) {
        let buffer = self.vertex_buffer_mut(id);
        let bytes = vertices.len() as u64 * u64::from(buffer.bytes_per_vertex);
        let end = offset + vertices.len();
        if buffer.vertices.len() < end {
            buffer
                .vertices
                .resize(end, DrawVertex::fixed(SubgridPoint::grid(0, 0), 0.0));
        }
        buffer.vertices[offset..end].copy_from_slice(vertices);
        self.upload_bytes += bytes;
    }

    /// Writes `indices` from `offset` on (growing the buffer when they run past its end); the
    /// bytes written are counted.
    pub fn write_indices(&mut self, id: BufferId, offset: usize, indices: &[u32]) {
        let buffer = self.index_buffer_mut(id);
        let end = offset + indices.len();
        if buffer.len() < end {
            buffer.resize(end, RESTART);
        }
        buffer[offset..end].copy_from_slice(indices);
        self.upload_bytes += indices.len() as u64 * INDEX_BYTES;
    }

    /// Replaces a vertex buffer's whole content (counted as uploaded), keeping its capacity.
    pub fn replace_vertices(&mut self, id: BufferId, fill: impl FnOnce(&mut Vec<DrawVertex>)) {
        let buffer = self.vertex_buffer_mut(id);
        buffer.vertices.clear();
        fill(&mut buffer.vertices);
        let bytes = buffer.vertices.len() as u64 * u64::from(buffer.bytes_per_vertex);
        self.upload_bytes += bytes;
    }

    /// Replaces an index buffer's whole content (counted as uploaded), keeping its capacity.
    pub fn replace_indices(&mut self, id: BufferId, fill: impl FnOnce(&mut Vec<u32>)) {
        let buffer = self.index_buffer_mut(id);
        buffer.clear();
        fill(buffer);
        let bytes = buffer.len() as u64 * INDEX_BYTES;
        self.upload_bytes += bytes;
    }

    /// Counts `bytes` of per-draw or per-block data written this frame (constants, uniforms,
    /// instance data).
    pub fn upload_constants(&mut self, bytes: u64) {
        self.upload_bytes += bytes;
    }

    /// Registers the tessellation stage that [`Topology::Patches`] draws go through (a pipeline
    /// state, set up once: nothing is uploaded).
    pub fn set_tessellator(&mut self, tessellator: Arc<dyn Tessellator>) {
        self.tessellator = Some(tessellator);
    }

    /// Empties the draw list (a new frame's commands follow).
    pub fn clear_draws(&mut self) {
        self.draws.clear();
    }

    /// Adds a draw command to this frame's list.
    pub fn draw(&mut self, call: DrawCall) {
        debug_assert!(
            call.topology != Topology::Patches || self.tessellator.is_some(),
            "a patch draw without a tessellator"
        );
        debug_assert!(
            self.index_buffers[call.indices.0 as usize]
                .as_ref()
                .is_some_and(
                    |indices| (call.first_index + call.index_count) as usize <= indices.len()
                )
        );
        self.draws.push(call);
    }

    /// This frame's draw list.
    pub fn draws(&self) -> &[DrawCall] {
        &self.draws
    }

    /// The vertices of a buffer.
    pub fn vertices(&self, id: BufferId) -> &[DrawVertex] {
        &self.vertex_buffers[id.0 as usize]
            .as_ref()
            .expect("a live vertex buffer")
            .vertices
    }

    /// The indices of a buffer.
    pub fn indices(&self, id: BufferId) -> &[u32] {
        self.index_buffers[id.0 as usize]
            .as_ref()
            .expect("a live index buffer")
    }

    /// Ends the frame: what it uploaded and issued. The upload count starts again from zero.
    pub fn end_frame(&mut self) -> DrawCounts {
        let counts = DrawCounts {
            upload_bytes: self.upload_bytes,
            draw_calls: self.draws.len() as u64,
            triangles_submitted: self
                .draws
                .iter()
                .map(|call| self.call_triangles_submitted(call))
                .sum(),
        };
        self.upload_bytes = 0;
        counts
    }

    /// The triangles one draw call submits.
    fn call_triangles_submitted(&self, call: &DrawCall) -> u64 {
        let indices = self.indices(call.indices);
        if call.topology != Topology::Patches {
            return decode::triangles_submitted(call, indices);
        }
        let tessellator = self.patch_tessellator();
        let range = call.first_index as usize..(call.first_index + call.index_count) as usize;
        patches::patches(tessellator, &indices[range])
            .map(|patch| tessellator.triangles(patch))
            .sum()
    }

    fn patch_tessellator(&self) -> &dyn Tessellator {
        self.tessellator
            .as_deref()
            .expect("a patch draw needs the tessellator its algorithm registered")
    }

    /// Bytes the buffers hold on the GPU (their content, not their capacity).
    pub fn resident_bytes(&self) -> u64 {
        let vertex_bytes: u64 = self
            .vertex_buffers
            .iter()
            .flatten()
            .map(|b| b.vertices.len() as u64 * u64::from(b.bytes_per_vertex))
            .sum();
        let index_bytes: u64 = self
            .index_buffers
            .iter()
            .flatten()
            .map(|b| b.len() as u64 * INDEX_BYTES)
            .sum();
        vertex_bytes + index_bytes
    }

    /// Heap bytes of this model on the CPU side (what `memory_bytes` counts for it).
    pub fn memory_bytes(&self) -> usize {
        let vertex: usize = self
            .vertex_buffers
            .iter()
            .flatten()
            .map(|b| b.vertices.capacity() * size_of::<DrawVertex>())
            .sum();
        let index: usize = self
            .index_buffers
            .iter()
            .flatten()
            .map(|b| b.capacity() * size_of::<u32>())
            .sum();
        vertex + index + self.draws.capacity() * size_of::<DrawCall>()
    }

    /// Calls `visit` on every triangle the draw list makes, as a GPU assembles them: corners in
    /// drawing order at their drawn heights, degenerate triangles included, draws in order.
    pub fn for_each_triangle(&self, mut visit: impl FnMut([SurfacePoint; 3])) {
        for call in &self.draws {
            let vertices = self.vertices(call.vertices);
            let indices = self.indices(call.indices);
            let range = call.first_index as usize..(call.first_index + call.index_count) as usize;
            if call.topology == Topology::Patches {
                let tessellator = self.patch_tessellator();
                for patch in patches::patches(tessellator, &indices[range]) {
                    tessellator.for_each_triangle(patch, &mut visit);
                }
                continue;
            }
            decode::for_each_triangle(call.topology, &indices[range], |corners| {
                visit(corners.map(|k| vertices[k as usize].drawn(call.blend)));
            });
        }
    }

    fn vertex_buffer_mut(&mut self, id: BufferId) -> &mut VertexBuffer {
        self.vertex_buffers[id.0 as usize]
            .as_mut()
            .expect("a live vertex buffer")
    }

    fn index_buffer_mut(&mut self, id: BufferId) -> &mut Vec<u32> {
        self.index_buffers[id.0 as usize]
            .as_mut()
            .expect("a live index buffer")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vertex(i: u32, j: u32) -> DrawVertex {
        DrawVertex::fixed(SubgridPoint::grid(i, j), (i + j) as f32)
    }

    #[test]
    fn writes_are_counted_once_per_frame_and_reading_is_free() {
        let mut gpu = GpuBuffers::new();
        let vb = gpu.create_vertices(vec![vertex(0, 0), vertex(1, 0), vertex(0, 1)], VERTEX_BYTES);
        let ib = gpu.create_indices(vec![0, 1, 2]);
        gpu.draw(DrawCall {
            vertices: vb,
            indices: ib,
            first_index: 0,
            index_count: 3,
            topology: Topology::TriangleList,
            blend: 0.0,
        });
        let first = gpu.end_frame();
        assert_eq!(first.upload_bytes, 3 * 12 + 3 * 4);
        assert_eq!((first.draw_calls, first.triangles_submitted), (1, 1));

        let mut seen = 0;
        gpu.for_each_triangle(|_| seen += 1);
        assert_eq!(seen, 1);
        assert_eq!(
            gpu.end_frame().upload_bytes,
            0,
            "a frame that writes nothing uploads nothing"
        );

        gpu.write_vertices(vb, 2, &[vertex(1, 1)]);
        gpu.upload_constants(8);
        assert_eq!(gpu.end_frame().upload_bytes, 12 + 8);
        assert_eq!(gpu.resident_bytes(), 3 * 12 + 3 * 4);
    }

    #[test]
    fn a_released_buffer_id_is_reused() {
        let mut gpu = GpuBuffers::new();
        let a = gpu.create_indices(vec![0, 1, 2]);
        gpu.release_indices(a);
        let b = gpu.create_indices(vec![]);
        assert_eq!(a, b);
        assert!(gpu.indices(b).is_empty());
    }

    #[test]
    fn a_morphing_vertex_is_drawn_at_its_blend() {
        let v = DrawVertex {
            position: SubgridPoint::grid(0, 0),
            z: 10.0,
            z_target: 20.0,
        };
        assert_eq!(v.drawn(0.0).z, 10.0);
        assert_eq!(v.drawn(0.5).z, 15.0);
        assert_eq!(v.drawn(1.0).z, 20.0);
        assert_eq!(morph_height(3.0, 3.0, 0.7), 3.0);
    }
}
