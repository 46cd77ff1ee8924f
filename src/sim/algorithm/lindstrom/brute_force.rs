//! SPEC §6's brute-force reference for Lindstrom's criterion: every vertex evaluated exactly, no
//! blocks, no interval tests, closure by activating parents recursively (top-down). Not an entry
//! of its own: tests and `examples/lindstrom_brute_force.rs` compare the algorithm against it.
//!
//! It shares with the algorithm only the criterion itself ([`Tolerance::keeps`]), so it is an
//! independent ground truth. O(samples) per call.

use super::Tolerance;
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::VertexSet;
use glam::DVec3;

/// What the from-scratch evaluation needs: the terrain, every vertex's nested error under the
/// run's nesting rule (indexed by vertex id), the eye, λ and τ.
#[derive(Clone, Copy, Debug)]
pub struct FromScratchView<'a> {
    pub hierarchy: &'a Hierarchy,
    pub nested_errors: &'a [f32],
    pub eye: DVec3,
    pub lambda: f64,
    pub tau_px: f64,
}

/// The mesh Lindstrom's criterion asks for at this view: the closure under parents of every
/// vertex whose vertical-projection error exceeds τ.
pub fn mesh_from_scratch(view: &FromScratchView) -> VertexSet {
    let lattice = view.hierarchy.lattice();
    let field = view.hierarchy.field();
    let tolerance = Tolerance::new(view.lambda, view.tau_px);
    let mut mesh = VertexSet::base_mesh(lattice);
    let mut stack: Vec<GridPoint> = Vec::new();
    for j in 0..lattice.side() {
        for i in 0..lattice.side() {
            let point = GridPoint::new(i, j);
            let delta = view.nested_errors[lattice.id(point) as usize];
            let position = field.position(i as usize, j as usize);
            if !tolerance.keeps(delta, position - view.eye) {
                continue;
            }
            stack.push(point);
            while let Some(vertex) = stack.pop() {
                if mesh.insert(lattice.id(vertex)) {
                    stack.extend(lattice.parents(vertex).as_slice());
                }
            }
        }
    }
    mesh
}
