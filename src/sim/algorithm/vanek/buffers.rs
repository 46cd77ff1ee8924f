//! A Vaněk frame's GPU side (issue #31, §2–3): one shared index buffer per level, the paper's
//! strip made on first use, and per patch a vertex buffer holding its level's vertices as drawn
//! (collapsed ones moved), rewritten only when the patch's shape changes; one strip draw per
//! drawn patch. It reads the triangle list `mesh.rs` built and changes nothing in it.

use super::{Vanek, strip};
use crate::sim::draw::{DrawCall, DrawCounts, DrawVertex, Topology, VERTEX_BYTES};

impl Vanek<'_> {
    /// Brings the buffers to this frame's drawn patches and records their draws (what
    /// [`LodAlgorithm::prepare_draw`](super::super::LodAlgorithm::prepare_draw) does).
    pub(super) fn write_buffers(&mut self) -> DrawCounts {
        self.gpu.clear_draws();
        self.patches_rewritten = 0;
        for &(patch, base, shape) in &self.drawn {
            let k = shape[0];
            let m = (1u32 << k) + 1;
            let (indices, index_count) = *self.level_strips[k as usize].get_or_insert_with(|| {
                // The paper's strip, after one repeated first index: a GPU then reads it with
                // the parity roamsim draws it with (counter-clockwise, `strip.rs`), at the cost
                // of one more degenerate triangle per draw.
                let mut indices = strip::degenerate_strip(m, m);
                indices.insert(0, indices[0]);
                let count = indices.len() as u32;
                (self.gpu.create_indices(indices), count)
            });
            let patch_vertices = &self.list.vertices()[base as usize..(base + m * m) as usize];
            let vertices = match self.patch_vertices[patch] {
                Some((buffer, held)) if held == shape => buffer,
                Some((buffer, _)) => {
                    self.gpu.replace_vertices(buffer, |out| {
                        out.extend(patch_vertices.iter().map(|&v| DrawVertex::of(v)));
                    });
                    self.patch_vertices[patch] = Some((buffer, shape));
                    self.patches_rewritten += 1;
                    buffer
                }
                None => {
                    let buffer = self.gpu.create_vertices(
                        patch_vertices.iter().map(|&v| DrawVertex::of(v)).collect(),
                        VERTEX_BYTES,
                    );
                    self.patch_vertices[patch] = Some((buffer, shape));
                    self.patches_rewritten += 1;
                    buffer
                }
            };
            self.gpu.draw(DrawCall {
                vertices,
                indices,
                first_index: 0,
                index_count,
                topology: Topology::TriangleStrip,
                blend: 0.0,
            });
        }
        self.gpu.end_frame()
    }
}
