//! Merging a node (Wu et al. 2001 §3.1, Figure 4): delete its boundary vertices and its centre,
//! then the bookkeeping of the queues (its sub-blocks stop being splittable, it becomes
//! splittable, the nodes it depended on may become mergeable — leaving the view queue — and merge
//! at once if their key has run out). When to merge is decided by the frame loop (`mod.rs`).

use super::wheel::Queue;
use super::{NodeLook, Wu};
use crate::sim::hierarchy::VertexClass;

impl Wu<'_> {
    /// Merges a mergeable node whose look is `look`.
    pub(super) fn merge(&mut self, node: u32, look: NodeLook) {
        if look.life >= self.base as f64 + 1.0 {
            self.record_for_recentring(node);
        }
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
        self.node_deactivated(node);
        self.n_triangles -= 2;
        self.counters.deleted += 1;
        self.counters.merges += 1;
        if let Some(children) = self.nodes.children(node) {
            for child in children {
                self.wheels.remove(child);
            }
        }
        // Its look as a splittable node: in-view refinement needs its sight, which an active
        // node's look has whenever the view is followed.
        self.schedule_split(node, look, 0);
        // The nodes owning this node's parents may now have no dependent left.
        for parent in lattice.parents(centre).as_slice() {
            for owner in lattice.parents(*parent).as_slice() {
                if let VertexClass::Square { half } = lattice.classify(*owner) {
                    let owner = self.nodes.node_of(*owner, half);
                    if !self.wheels.is_in(owner, Queue::Merge) && self.is_mergeable(owner) {
                        self.wheels.remove(owner);
                        let owner_look = self.active_look(owner);
                        self.apply_sight(owner, owner_look.sight);
                        self.schedule_merge(owner, owner_look);
                    }
                }
            }
        }
    }
}
