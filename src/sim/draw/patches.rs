//! Patches: draws whose triangles the GPU's tessellation stage makes ([`Topology::Patches`]).
//! The CPU writes only each patch's data (a few words: where the patch lies and its
//! tessellation factors, an instance buffer); the tessellator expands every patch into
//! triangles on the GPU side, so those triangles are submitted and drawn but never uploaded.
//!
//! An algorithm that draws patches registers its tessellation stage with its buffers
//! ([`GpuBuffers::set_tessellator`]): a pure [`Tessellator`] that says, from a patch's words
//! alone (and what the GPU holds resident, e.g. the height map as a texture), how many
//! triangles it makes and which. [`GpuBuffers::for_each_triangle`] and
//! [`GpuBuffers::end_frame`] ask it, so `--check` and `triangles_submitted` see the tessellated
//! triangles exactly as the mesh has them.
//!
//! What it is not: a tessellator (each algorithm brings its own) or a model of a texture upload
//! (the height map is resident before the first frame, like every algorithm's terrain).
//!
//! [`Topology::Patches`]: super::Topology::Patches
//! [`GpuBuffers::set_tessellator`]: super::GpuBuffers::set_tessellator
//! [`GpuBuffers::for_each_triangle`]: super::GpuBuffers::for_each_triangle
//! [`GpuBuffers::end_frame`]: super::GpuBuffers::end_frame

use crate::sim::mesh::SurfacePoint;

/// The tessellation stage of a pipeline that draws patches: what it makes of one patch's words.
/// Pure: the same words give the same triangles.
pub trait Tessellator: std::fmt::Debug + Send + Sync {
    /// Words (`u32`) of one patch's data, in the draw's index buffer (its instance buffer).
    fn words_per_patch(&self) -> usize;

    /// The triangles the tessellator makes of `patch` (its words), degenerate ones included,
    /// counted without making them.
    fn triangles(&self, patch: &[u32]) -> u64;

    /// Calls `visit` on every triangle it makes of `patch`: corners in drawing order at their
    /// drawn heights, degenerate triangles included.
    fn for_each_triangle(&self, patch: &[u32], visit: &mut dyn FnMut([SurfacePoint; 3]));
}

/// The patches of a draw's words, `tessellator.words_per_patch()` words each (a trailing partial
/// patch is not drawn, as a GPU ignores an incomplete one).
pub(super) fn patches<'a>(
    tessellator: &dyn Tessellator,
    words: &'a [u32],
) -> impl Iterator<Item = &'a [u32]> {
    words.chunks_exact(tessellator.words_per_patch().max(1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::draw::{DrawCall, GpuBuffers, Topology, VERTEX_BYTES};
    use crate::sim::mesh::SubgridPoint;
    use std::sync::Arc;

    /// A patch (i, j) is the unit cell at grid point (i, j), two triangles at height 0.
    #[derive(Debug)]
    struct Cells;

    impl Tessellator for Cells {
        fn words_per_patch(&self) -> usize {
            2
        }

        fn triangles(&self, _: &[u32]) -> u64 {
            2
        }

        fn for_each_triangle(&self, patch: &[u32], visit: &mut dyn FnMut([SurfacePoint; 3])) {
            let corner = |di, dj| SurfacePoint {
                position: SubgridPoint::grid(patch[0] + di, patch[1] + dj),
                z: 0.0,
            };
            visit([corner(0, 0), corner(1, 0), corner(1, 1)]);
            visit([corner(0, 0), corner(1, 1), corner(0, 1)]);
        }
    }

    #[test]
    fn a_patch_draw_uploads_its_words_and_submits_what_the_tessellator_makes() {
        let mut gpu = GpuBuffers::new();
        gpu.set_tessellator(Arc::new(Cells));
        let unused = gpu.create_vertices(Vec::new(), VERTEX_BYTES);
        let patches = gpu.create_indices(vec![0, 0, 3, 1, 2, 2]);
        gpu.draw(DrawCall {
            vertices: unused,
            indices: patches,
            first_index: 2,
            index_count: 4,
            topology: Topology::Patches,
            blend: 0.0,
        });
        let counts = gpu.end_frame();
        assert_eq!(
            counts.upload_bytes,
            6 * 4,
            "the words, nothing of the triangles"
        );
        assert_eq!((counts.draw_calls, counts.triangles_submitted), (1, 4));
        let mut drawn = Vec::new();
        gpu.for_each_triangle(|t| drawn.push(t[2].position));
        assert_eq!(
            drawn,
            vec![
                SubgridPoint::grid(4, 2),
                SubgridPoint::grid(3, 2),
                SubgridPoint::grid(3, 3),
                SubgridPoint::grid(2, 3)
            ]
        );
        assert_eq!(
            gpu.end_frame().upload_bytes,
            0,
            "drawing again uploads nothing"
        );
    }
}
