//! Splitting a node (Wu et al. 2001 §3.1, Figure 4; SPEC §5): closure first (forced splits, never
//! refused), then the node, its free boundary vertices, and the bookkeeping of the queues. When to
//! split is decided by the frame loop (`mod.rs`); the children of a split are scheduled here, in
//! order of error under block-priority traversal (§3.2).

use super::nodes::NO_NODE;
use super::wheel::Queue;
use super::{NodeLook, Wu};
use crate::sim::hierarchy::{GridPoint, VertexClass};

impl Wu<'_> {
    /// Splits a splittable node chosen by its look (not forced); `chain_depth` is how many splits
    /// of this frame's chain lie above it.
    pub(super) fn split(&mut self, node: u32, look: NodeLook, chain_depth: u32) {
        self.record_for_recentring(node);
        self.activate_with_closure(node, Some(look), chain_depth);
    }

    /// Activates `node` after everything its centre depends on. `known` is its look when it
    /// splits by its own criterion; forced activations have none.
    fn activate_with_closure(&mut self, node: u32, known: Option<NodeLook>, chain_depth: u32) {
        if self.is_active(node) {
            return;
        }
        let (centre, _) = self.nodes.centre(node);
        let parents = self.lattice.parents(centre);
        for &parent in parents.as_slice() {
            self.ensure_vertex_active(parent, chain_depth);
        }
        self.activate(node, known, chain_depth);
    }

    /// Makes a vertex active by forcing the squares it needs.
    fn ensure_vertex_active(&mut self, vertex: GridPoint, chain_depth: u32) {
        if self.mesh.contains_point(&self.lattice, vertex) {
            return;
        }
        match self.lattice.classify(vertex) {
            VertexClass::Corner => {}
            VertexClass::Square { half } => {
                let node = self.nodes.node_of(vertex, half);
                self.activate_with_closure(node, None, chain_depth);
            }
            VertexClass::Rotated { .. } => {
                // A free vertex: active as soon as all its parents are.
                let parents = self.lattice.parents(vertex);
                for &parent in parents.as_slice() {
                    self.ensure_vertex_active(parent, chain_depth);
                }
            }
        }
    }

    /// Activates a node whose parents are active, and updates the queues around it.
    fn activate(&mut self, node: u32, known: Option<NodeLook>, chain_depth: u32) {
        let forced = known.is_none();
        let lattice = self.lattice;
        let (centre, half) = self.nodes.centre(node);
        // An active node's look needs its sight whenever the view is followed.
        let look = match known {
            Some(look) if look.sight.is_some() || !self.active_needs_sight() => look,
            Some(look) => NodeLook {
                sight: self.current_sight(node),
                ..look
            },
            None => self.active_look(node),
        };
        self.wheels.remove(node);
        self.insert_vertex(centre);
        self.node_activated(node, look.sight.is_some_and(|s| s.in_view()));
        self.n_triangles += 2;
        self.counters.inserted += 1;
        self.counters.splits += 1;
        self.counters.forced_splits += u64::from(forced);

        // Free boundary vertices whose parents are now all active.
        for boundary in lattice.boundary_vertices(centre, half) {
            let parents = lattice.parents(boundary);
            if !self.mesh.contains_point(&lattice, boundary)
                && parents
                    .as_slice()
                    .iter()
                    .all(|p| self.mesh.contains_point(&lattice, *p))
            {
                self.insert_vertex(boundary);
                self.n_triangles += parents.len() as u64;
                self.counters.inserted += 1;
            }
        }
        // The nodes this one now depends on are no longer mergeable: they leave the merge queue
        // (for the view queue, in the same link, when the view is followed: a merge key is never
        // later than the view key it includes).
        for parent in lattice.parents(centre).as_slice() {
            for owner in lattice.parents(*parent).as_slice() {
                if let VertexClass::Square { half } = lattice.classify(*owner) {
                    let owner = self.nodes.node_of(*owner, half);
                    if self.wheels.is_in(owner, Queue::Merge) {
                        if self.counts_in_view() {
                            self.wheels.move_to_queue(owner, Queue::View);
                        } else {
                            self.wheels.remove(owner);
                        }
                    }
                }
            }
        }
        // The node itself is mergeable until something depends on it.
        self.schedule_merge(node, look);
        // Its sub-blocks become splittable.
        if let Some(children) = self.nodes.children(node) {
            self.schedule_children(children, forced, chain_depth);
        }
        debug_assert!(
            self.nodes.parent(node) == NO_NODE || self.is_active(self.nodes.parent(node))
        );
    }

    /// Queues the sub-blocks of a newly active node. After a real split they are tested now. With
    /// block-priority traversal they are tested by decreasing error and testing stops at the
    /// first whose life does not let it split: its untested siblings take its life key (the
    /// paper's premise that siblings' errors "are in the same direction"), so they cost no life
    /// computation until that key runs out. This is a heuristic: a sibling can need splitting
    /// before the key it took. (A child kept out only by the view does not stop the test: its
    /// siblings may be in view.) A forced activation is a split too; its sub-blocks start a new
    /// chain (depth 0).
    fn schedule_children(&mut self, children: [u32; 4], forced: bool, chain_depth: u32) {
        let mut order = children;
        let depth = if forced { 0 } else { chain_depth + 1 };
        if self.config.block_priority {
            order.sort_by(|&a, &b| {
                let error = |n: u32| {
                    let (centre, half) = self.nodes.centre(n);
                    self.rule.errors.error(self.hierarchy, centre, half)
                };
                error(b).total_cmp(&error(a)).then(a.cmp(&b))
            });
            for (k, &child) in order.iter().enumerate() {
                let look = self.split_look(child);
                let life_key = look.life - self.base as f64;
                self.schedule_split(child, look, depth);
                if let Some(link) = self.link_for(life_key) {
                    // An infinite key must not park siblings that may have finite lives.
                    let link = if link == self.wheels.parked_link() {
                        self.link_after(1)
                    } else {
                        link
                    };
                    for &rest in &order[k + 1..] {
                        self.wheels.insert(rest, Queue::Split, link);
                    }
                    break;
                }
            }
        } else {
            for child in order {
                let look = self.split_look(child);
                self.schedule_split(child, look, depth);
            }
        }
    }
}
