//! The rebuilding way to keep buffers: the whole mesh written again every frame, as one indexed
//! triangle list. What an algorithm that rebuilds its mesh from scratch each frame pays to make
//! it drawable when its paper names no cheaper form; algorithms whose papers draw fans or strips
//! emit those instead. Not an incremental path: its upload is O(mesh) every frame by design.

use super::{
    BufferId, DrawCall, DrawVertex, GpuBuffers, MORPHING_VERTEX_BYTES, Topology, VERTEX_BYTES,
};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::MeshOutput;

/// One vertex buffer and one index buffer, rewritten whole each frame.
#[derive(Clone, Debug)]
pub struct WholeMeshEmitter {
    vertices: BufferId,
    indices: BufferId,
}

impl WholeMeshEmitter {
    /// Allocates the two (empty) buffers.
    pub fn new(gpu: &mut GpuBuffers) -> WholeMeshEmitter {
        WholeMeshEmitter {
            vertices: gpu.create_vertices(Vec::new(), VERTEX_BYTES),
            indices: gpu.create_indices(Vec::new()),
        }
    }

    /// Writes `mesh` into the buffers and issues its one draw. A triangle list keeps its own
    /// vertex sharing; a 4-8 mesh is written three corners a triangle (no vertex table: a
    /// rebuilding algorithm keeps none from frame to frame).
    pub fn emit(&self, gpu: &mut GpuBuffers, mesh: MeshOutput, hierarchy: &Hierarchy) {
        let mut index_count = 0;
        match mesh {
            MeshOutput::Triangles(list) => {
                gpu.replace_vertices(self.vertices, |out| {
                    out.extend(list.vertices().iter().map(|&v| DrawVertex::of(v)));
                });
                gpu.replace_indices(self.indices, |out| {
                    out.extend(list.triangles().iter().flatten());
                    index_count = out.len();
                });
            }
            MeshOutput::Lattice(_) => {
                gpu.replace_vertices(self.vertices, |out| {
                    mesh.for_each_triangle(hierarchy, |t| {
                        out.extend(t.corners.map(DrawVertex::of));
                    });
                    index_count = out.len();
                });
                gpu.replace_indices(self.indices, |out| out.extend(0..index_count as u32));
            }
        }
        gpu.clear_draws();
        gpu.draw(DrawCall {
            vertices: self.vertices,
            indices: self.indices,
            first_index: 0,
            index_count: index_count as u32,
            topology: Topology::TriangleList,
            blend: 0.0,
        });
    }
}

/// Bytes per vertex of a buffer whose vertices may morph.
pub const fn vertex_bytes(morphs: bool) -> u32 {
    if morphs {
        MORPHING_VERTEX_BYTES
    } else {
        VERTEX_BYTES
    }
}

/// The GPU-side state of an algorithm that rebuilds its buffers every frame: its buffers and the
/// emitter that fills them.
#[derive(Clone, Debug)]
pub struct RebuiltBuffers {
    gpu: GpuBuffers,
    emitter: WholeMeshEmitter,
}

impl Default for RebuiltBuffers {
    fn default() -> RebuiltBuffers {
        RebuiltBuffers::new()
    }
}

impl RebuiltBuffers {
    pub fn new() -> RebuiltBuffers {
        let mut gpu = GpuBuffers::new();
        let emitter = WholeMeshEmitter::new(&mut gpu);
        RebuiltBuffers { gpu, emitter }
    }

    /// Writes this frame's mesh and issues its draw; what the frame uploaded and issued.
    pub fn prepare(&mut self, mesh: MeshOutput, hierarchy: &Hierarchy) -> super::DrawCounts {
        self.emitter.emit(&mut self.gpu, mesh, hierarchy);
        self.gpu.end_frame()
    }

    pub fn gpu(&self) -> &GpuBuffers {
        &self.gpu
    }
}
