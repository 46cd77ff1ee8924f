//! Mesh generation for one frame (§2.2): the top-down traversal from the root, the forced
//! subdivisions that keep the mesh conforming, and the edge midpoints the fans draw.
//!
//! 1. **Top-down.** A block reached by the traversal (the root, or a child of a block that
//!    subdivided by the criterion) is tested: with clipping on, a block whose box three times as
//!    large cannot be seen is not subdivided; otherwise it subdivides when f < 1. A subdivided
//!    block stores its blend byte in the matrix, its centre enters the mesh, and its children
//!    (if it has any: the finest blocks, 3 × 3 samples, have none) are tested next.
//! 2. **Forced subdivisions.** A block centre entering the mesh needs its 4-8 parents (two edge
//!    midpoints of its parent block), which need the centres of the blocks on both sides of those
//!    edges: a subdivided block needs the blocks of twice its size beside it subdivided too — the
//!    paper's level-difference rule. Where the criterion did not already subdivide them (the
//!    d2 propagation guarantees it only in 2D), they are subdivided here, recursively, with the
//!    smallest blend byte; their children are not tested (the criterion declined them). These
//!    are the frame's forced subdivisions.
//! 3. **Midpoints.** A block's edge midpoint is drawn iff every block sharing that edge at the
//!    block's size is subdivided (the paper's "neighbour refined to the same level"; a border
//!    edge has only the block itself).
//!
//! O(blocks visited + mesh) per frame; the stack and lists are reused.

use super::clip::{ViewFrustum, generation_may_see};
use super::criterion::{Criterion, SMALLEST_BLEND_BYTE, blend_byte, subdivides};
use super::matrix::QuadtreeMatrix;
use crate::sim::hierarchy::{GridPoint, Hierarchy, VertexClass};
use crate::sim::mesh::rebuilt::RebuiltMesh;
use crate::sim::view::Camera;

/// What one frame's generation reads.
#[derive(Clone, Copy)]
pub(super) struct GenerationInput<'a> {
    pub hierarchy: &'a Hierarchy,
    pub criterion: Criterion,
    pub camera: &'a Camera,
    /// The frame's frustum when clipping is on.
    pub clipping: Option<&'a ViewFrustum>,
}

/// What one frame's generation writes: the mesh, the matrix's blend bytes, the subdivided block
/// centres (in the order they entered), the traversal stack, the triangle count.
pub(super) struct GenerationState<'a> {
    pub mesh: &'a mut RebuiltMesh,
    pub matrix: &'a mut QuadtreeMatrix,
    pub subdivided: &'a mut Vec<u32>,
    pub stack: &'a mut Vec<(GridPoint, u32)>,
    pub triangles: u64,
}

/// The traversal's counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct TraversalCounts {
    /// Blocks the traversal reached.
    pub visited: u64,
    /// Reached blocks whose f was evaluated.
    pub evaluated: u64,
    /// Reached blocks left undivided because their enlarged box cannot be seen.
    pub clipped: u64,
    /// Blocks subdivided by the criterion.
    pub by_criterion: u64,
}

impl GenerationState<'_> {
    /// Clears the previous frame's blend bytes and starts the mesh again from the corners.
    pub(super) fn start_frame(&mut self, hierarchy: &Hierarchy) {
        for &id in self.subdivided.iter() {
            self.matrix.set_blend_byte(id, 0);
        }
        self.subdivided.clear();
        self.mesh.start_frame(hierarchy.lattice());
        self.triangles = 2;
    }

    /// Puts `p` in the mesh and, first, its parents (recursively). A block centre put in the
    /// mesh is subdivided with the smallest blend byte until the traversal stores its own.
    fn activate_closed(&mut self, hierarchy: &Hierarchy, p: GridPoint) {
        let lattice = hierarchy.lattice();
        let id = lattice.id(p);
        if self.mesh.mesh().contains(id) {
            return;
        }
        let parents = lattice.parents(p);
        for parent in &parents {
            self.activate_closed(hierarchy, *parent);
        }
        self.mesh.insert(id);
        self.triangles += parents.len() as u64;
        if matches!(lattice.classify(p), VertexClass::Square { .. }) {
            self.matrix.set_blend_byte(id, SMALLEST_BLEND_BYTE);
            self.subdivided.push(id);
        }
    }
}

/// Step 1 and 2: the traversal from the root, with forced subdivisions as closure needs them.
pub(super) fn subdivide_top_down(
    input: &GenerationInput,
    state: &mut GenerationState,
) -> TraversalCounts {
    let hierarchy = input.hierarchy;
    let lattice = hierarchy.lattice();
    let eye = input.camera.eye;
    let mut counts = TraversalCounts::default();
    state.stack.clear();
    state.stack.push((lattice.root(), lattice.cells() / 2));
    while let Some((centre, half)) = state.stack.pop() {
        counts.visited += 1;
        if let Some(frustum) = input.clipping
            && !generation_may_see(hierarchy, frustum, centre, half)
        {
            counts.clipped += 1;
            continue;
        }
        counts.evaluated += 1;
        let d2 = state.matrix.d2(centre, half);
        let f = input
            .criterion
            .decision_variable(hierarchy, centre, half, d2, eye);
        if !subdivides(f) {
            continue;
        }
        counts.by_criterion += 1;
        state.activate_closed(hierarchy, centre);
        state
            .matrix
            .set_blend_byte(lattice.id(centre), blend_byte(f));
        if let Some(children) = lattice.sub_blocks(centre, half) {
            state
                .stack
                .extend(children.iter().rev().map(|&child| (child, half / 2)));
        }
    }
    counts
}

/// Step 3: every edge midpoint of a subdivided block whose parents (the blocks on both sides of
/// the edge) are all subdivided.
pub(super) fn add_drawn_midpoints(hierarchy: &Hierarchy, state: &mut GenerationState) {
    let lattice = hierarchy.lattice();
    for k in 0..state.subdivided.len() {
        let centre = lattice.point(state.subdivided[k]);
        let VertexClass::Square { half } = lattice.classify(centre) else {
            unreachable!("only block centres are subdivided");
        };
        for midpoint in lattice.boundary_vertices(centre, half) {
            let parents = lattice.parents(midpoint);
            if parents
                .as_slice()
                .iter()
                .all(|q| state.mesh.mesh().contains_point(lattice, *q))
                && state.mesh.insert(lattice.id(midpoint))
            {
                state.triangles += parents.len() as u64;
            }
        }
    }
}
