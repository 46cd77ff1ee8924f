//! What Röttger et al. send to the graphics hardware each frame (§2.1, §3): the triangle fans of
//! the subdivided blocks, each fan's vertices sent in fan order (centre, then the ring
//! counter-clockwise), one draw per fan. Rebuilt every frame, like the mesh: upload is O(mesh)
//! per frame by design (the paper generates and sends its fans anew every frame: "approximately
//! 1600 triangle fans, or a total of roughly 15000 vertices per frame", §3).
//!
//! **A draw per fan**, not one draw with primitive restart: a renderer of 1998 drew a fan as one
//! `glBegin(GL_TRIANGLE_FAN)` … `glEnd()` (primitive restart came to OpenGL in 2009), so
//! `draw_calls` counts the fans the paper sends. Each fan's vertices are written into one vertex
//! buffer, as immediate mode sends them (shared vertices sent once per fan that uses them,
//! t + 2 vertices for a fan of t triangles: the paper's vertex count); the draws index it
//! through a static identity index buffer (0, 1, 2, …), written only when it must grow, which
//! stands for a non-indexed draw.
//!
//! **Heights**: the drawn heights of the mesh output, morphed on the CPU when geomorphing is on
//! (the paper's hardware had no vertex programs): a vertex's `z` is the `f32` the mesh output
//! carries, bit for bit. Every fan of the mesh is drawn, clipped blocks' too: the buffers draw
//! the mesh the runner culls and checks (the `fans` columns count what clipping would send).

use super::fans::{self, FanRun};
use crate::sim::draw::{
    BufferId, DrawCall, DrawCounts, DrawVertex, GpuBuffers, Topology, VERTEX_BYTES,
};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::{MorphedHeights, SubgridPoint, VertexSet};

/// The fans' buffers: one vertex buffer rewritten each frame, one identity index buffer.
#[derive(Clone, Debug)]
pub(super) struct FanBuffers {
    gpu: GpuBuffers,
    vertices: BufferId,
    identity: BufferId,
    /// Length of the identity index buffer.
    identity_len: usize,
    /// This frame's fans (reused).
    runs: Vec<FanRun>,
}

impl FanBuffers {
    pub fn new() -> FanBuffers {
        let mut gpu = GpuBuffers::new();
        let vertices = gpu.create_vertices(Vec::new(), VERTEX_BYTES);
        let identity = gpu.create_indices(Vec::new());
        FanBuffers {
            gpu,
            vertices,
            identity,
            identity_len: 0,
            runs: Vec::new(),
        }
    }

    /// Writes this frame's fans and issues one draw per fan. `morphed`: the mesh output's
    /// morphed heights (geomorphing on). O(mesh).
    pub fn prepare(
        &mut self,
        hierarchy: &Hierarchy,
        mesh: &VertexSet,
        subdivided: &[u32],
        morphed: Option<&MorphedHeights>,
    ) -> DrawCounts {
        let lattice = hierarchy.lattice();
        let height = |p: GridPoint| {
            morphed
                .and_then(|m| m.get(lattice.id(p)))
                .unwrap_or_else(|| hierarchy.height(p))
        };
        self.runs.clear();
        let runs = &mut self.runs;
        let mut n_vertices = 0;
        self.gpu.replace_vertices(self.vertices, |out| {
            fans::for_each_fan(lattice, mesh, subdivided, |points| {
                runs.push(FanRun {
                    first: out.len() as u32,
                    count: points.len() as u32,
                });
                out.extend(
                    points
                        .iter()
                        .map(|&p| DrawVertex::fixed(SubgridPoint::from(p), height(p))),
                );
            });
            n_vertices = out.len();
        });
        if self.identity_len < n_vertices {
            let grown: Vec<u32> = (self.identity_len as u32..n_vertices as u32).collect();
            self.gpu
                .write_indices(self.identity, self.identity_len, &grown);
            self.identity_len = n_vertices;
        }
        self.gpu.clear_draws();
        for run in &self.runs {
            self.gpu.draw(DrawCall {
                vertices: self.vertices,
                indices: self.identity,
                first_index: run.first,
                index_count: run.count,
                topology: Topology::TriangleFan,
                blend: 0.0,
            });
        }
        self.gpu.end_frame()
    }

    pub fn gpu(&self) -> &GpuBuffers {
        &self.gpu
    }

    pub fn memory_bytes(&self) -> usize {
        self.gpu.memory_bytes() + self.runs.capacity() * size_of::<FanRun>()
    }
}
