//! Geomorphing (§2.3): the blend of every drawn vertex and the height it is drawn at.
//!
//! A subdivided block morphs five points of its fan with its blend b = 2(1 − f) clamped to
//! [0, 1] (stored as a byte, `criterion.rs`): its centre, and its edge midpoints, where a shared
//! midpoint takes the **minimum** of the two blocks' blends so that both fans draw it at one
//! height (the paper's crack rule; a border midpoint has one block). In the 4-8 lattice that
//! is: a block centre's blend is its own byte, an edge midpoint's is the smallest byte of its
//! parents (the centres of the blocks beside the edge).
//!
//! A point morphs from "the average of the two corresponding corner points" to its own sample:
//! z = z̄ + b·(z − z̄) = z − (1 − b)·ε, with z̄ the mean of the ends of the edge it bisects in the
//! 4-8 hierarchy and ε = z − z̄ its vertex error. For an edge midpoint those ends are the edge's
//! corners; for a centre they are the corners on the diagonal through its parent block's centre,
//! so a centre at b = 0 lies on the parent's fan, and a block at b → 0 looks exactly like the
//! coarser mesh it replaces. The corners' own heights are the samples'.
//!
//! A vertex **morphs** when it is drawn at a height other than its sample's: blend below 1
//! (byte < 255) and ε ≠ 0.
//!
//! **The mesh output.** With geomorphing on, every frame's mesh output carries the morphed
//! heights ([`MorphedHeights`], as `f32`, the heights' own precision) of exactly the morphing
//! vertices; the others are drawn at their samples. With geomorphing off the output is the plain
//! lattice, with no morphed heights. The map is **rebuilt every frame** by
//! [`rebuild_morphed`], like the mesh itself: one pass over the frame's active vertices, which
//! the frame has just generated anyway (O(mesh vertices), of which O(morphing vertices) are
//! hash-map inserts), with no state to keep consistent between frames. An incremental map would
//! save nothing here: every frame's blends are new, since f moves with the eye. The audit,
//! popping, culling and `triangles`' geometry all read the morphed surface through the output.

use super::criterion::morph_factor;
use super::matrix::QuadtreeMatrix;
use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice, VertexClass};
use crate::sim::mesh::MorphedHeights;

/// The blend byte a vertex is drawn with: a block centre's own, an edge midpoint's the smallest
/// of its parents', 255 (its own height) for a corner. Meaningful for vertices of the mesh.
pub fn vertex_blend_byte(lattice: &Lattice, matrix: &QuadtreeMatrix, p: GridPoint) -> u8 {
    match lattice.classify(p) {
        VertexClass::Corner => u8::MAX,
        VertexClass::Square { .. } => matrix.blend_byte(lattice.id(p)),
        VertexClass::Rotated { .. } => lattice
            .parents(p)
            .as_slice()
            .iter()
            .map(|parent| matrix.blend_byte(lattice.id(*parent)))
            .min()
            .unwrap_or(u8::MAX),
    }
}

/// The height a vertex with this blend byte is drawn at: z − (1 − b)·ε.
pub fn morphed_height(hierarchy: &Hierarchy, p: GridPoint, blend_byte: u8) -> f64 {
    let z = f64::from(hierarchy.height(p));
    if blend_byte == u8::MAX {
        return z;
    }
    z - (1.0 - morph_factor(blend_byte)) * hierarchy.vertex_error(p)
}

/// Whether a vertex with this blend byte is drawn at a height other than its sample's.
pub fn morphs(hierarchy: &Hierarchy, p: GridPoint, blend_byte: u8) -> bool {
    blend_byte < u8::MAX && hierarchy.vertex_error(p) != 0.0
}

/// Clears `morphed` and fills it with the drawn height of every vertex among `active` that
/// morphs (and of no other). O(active); allocates only while the map grows.
pub fn rebuild_morphed(
    hierarchy: &Hierarchy,
    matrix: &QuadtreeMatrix,
    active: &[u32],
    morphed: &mut MorphedHeights,
) {
    let lattice = hierarchy.lattice();
    morphed.clear();
    for &id in active {
        let p = lattice.point(id);
        let byte = vertex_blend_byte(lattice, matrix, p);
        if morphs(hierarchy, p, byte) {
            morphed.set(id, morphed_height(hierarchy, p, byte) as f32);
        }
    }
}
