//! Merging a node: delete its boundary vertices and its centre, then the bookkeeping of the
//! queues (its sub-blocks stop being splittable, it becomes splittable, the nodes it depended on
//! may become mergeable and merge at once if their key has run out).

use super::Wu;
use super::wheel::Queue;
use crate::sim::hierarchy::VertexClass;

impl Wu<'_> {
    /// Merges a mergeable node whose life is `life`.
    pub(super) fn merge(&mut self, node: u32, life: f64) {
        let lattice = self.lattice;
        let (centre, half) = self.nodes.centre(node);
        self.wheels.remove(node);
        for boundary in lattice.boundary_vertices(centre, half) {
            if self.remove_vertex(boundary) {
                self.n_triangles -= lattice.parents(boundary).len() as u64;
                self.counters.deleted += 1;
            }
        }
        self.remove_vertex(centre);
        self.n_triangles -= 2;
        self.counters.deleted += 1;
        self.counters.merges += 1;
        if let Some(children) = self.nodes.children(node) {
            for child in children {
                self.wheels.remove(child);
            }
        }
        self.schedule_split(node, life, 0);
        // The nodes owning this node's parents may now have no dependent left.
        for parent in lattice.parents(centre).as_slice() {
            for owner in lattice.parents(*parent).as_slice() {
                if let VertexClass::Square { half } = lattice.classify(*owner) {
                    let owner = self.nodes.node_of(*owner, half);
                    if !self.wheels.is_in(owner, Queue::Merge) && self.is_mergeable(owner) {
                        let owner_life = self.life(owner);
                        self.schedule_merge(owner, owner_life);
                    }
                }
            }
        }
    }
}
