//! Wu's in-view flags and in-view triangle count, kept incrementally: what a renderer culling
//! Wu's nodes against the view cone draws (Wu et al. 2001 §3.2 and §7), and what the budget holds
//! with `cone_culling`. It decides nothing about splitting; `visibility.rs` says what is in view.
//!
//! **Not the runner's `triangles_rendered`** (triangles with no frustum plane that has all three
//! corners outside). The cone circumscribes the frustum and a block's sphere is larger than its
//! triangles, so Wu's count is typically the larger of the two (the ratio on the Table 1 flight
//! is in `docs/reproductions/wu-table1.md`). Counting triangle by triangle would make each flag
//! change cost up to eight cone tests instead of one.
//!
//! Every active node carries a flag: its bounding sphere meets this frame's view cone. The flag
//! is set when the node activates and brought up to date whenever a key of the node runs out
//! (its merge key, or its view key in the view queue), which the view keys make happen no later
//! than the frame it can change. The count is Σ over active nodes in view of the triangles each
//! block holds itself (`visibility::owned_triangles`), plus the two base triangles while the root
//! is inactive (counted by the root's flag, refreshed every frame then). It changes:
//! - when a flag changes: by ± the node's own triangles;
//! - when an edge midpoint is inserted (deleted): each of the one or two blocks beside it trades
//!   the quarter on that edge for two halves (or back): ±1 per block in view;
//! - when a block centre is inserted (deleted): the block gains its four quarters and its quadtree
//!   parent loses the two halves that tiled it (or the reverse; for the root, the base
//!   triangles).
//!
//! All O(1) per change. `validate.rs` recounts it from scratch.

use super::Wu;
use super::cull::Cone;
use super::nodes::NO_NODE;
use super::visibility::{ConeMotion, Sight, owned_triangles};
use super::wheel::Queue;
use crate::sim::hierarchy::{GridPoint, VertexClass};

/// What Wu keeps to follow the view cone.
pub(super) struct ViewTracking {
    pub motion: ConeMotion,
    /// This frame's cone (`None` before the first frame).
    pub cone: Option<Cone>,
    /// Whether the flags and the count are kept (`cone_culling`); in-view refinement alone
    /// needs only the cone.
    pub counting: bool,
    /// One bit per node: in view (meaningful for active nodes, and for the root while inactive);
    /// empty when not counting.
    in_view: Vec<u64>,
    /// Triangles of the active blocks in view (see the module docs).
    pub in_view_triangles: u64,
}

impl ViewTracking {
    pub fn new(n_nodes: usize, motion: ConeMotion, counting: bool) -> ViewTracking {
        ViewTracking {
            motion,
            cone: None,
            counting,
            in_view: if counting {
                vec![0; n_nodes.div_ceil(64)]
            } else {
                Vec::new()
            },
            in_view_triangles: 0,
        }
    }

    pub fn memory_bytes(&self) -> usize {
        self.in_view.capacity() * std::mem::size_of::<u64>()
    }

    pub fn is_in_view(&self, node: u32) -> bool {
        self.counting && self.in_view[node as usize / 64] & (1 << (node % 64)) != 0
    }

    fn set(&mut self, node: u32, in_view: bool) {
        let word = &mut self.in_view[node as usize / 64];
        let bit = 1 << (node % 64);
        if in_view {
            *word |= bit;
        } else {
            *word &= !bit;
        }
    }
}

impl Wu<'_> {
    /// Whether the in-view flags and count are kept.
    pub(super) fn counts_in_view(&self) -> bool {
        self.view.as_ref().is_some_and(|view| view.counting)
    }

    /// Whether the node's flag says it is in view (false when the view is not followed).
    pub(super) fn flagged_in_view(&self, node: u32) -> bool {
        self.view.as_ref().is_some_and(|view| view.is_in_view(node))
    }

    /// The triangles a node's flag stands for: an active block's own, the base triangles for the
    /// inactive root, nothing for another inactive node.
    pub(super) fn triangles_flagged_by(&self, node: u32) -> u64 {
        let (centre, half) = self.nodes.centre(node);
        if self.mesh.contains_point(&self.lattice, centre) {
            owned_triangles(&self.lattice, &self.mesh, centre, half)
        } else if node == self.nodes.root() {
            2
        } else {
            0
        }
    }

    /// Sets a node's flag, moving its triangles in or out of the count.
    fn set_in_view(&mut self, node: u32, in_view: bool) {
        if !self.counts_in_view() || self.flagged_in_view(node) == in_view {
            return;
        }
        let triangles = self.triangles_flagged_by(node);
        let Some(view) = self.view.as_mut() else {
            return;
        };
        view.set(node, in_view);
        if in_view {
            view.in_view_triangles += triangles;
        } else {
            view.in_view_triangles -= triangles;
        }
    }

    /// Applies a freshly computed sight of an active node (or the inactive root) to its flag.
    pub(super) fn apply_sight(&mut self, node: u32, sight: Option<Sight>) {
        if let Some(sight) = sight {
            self.set_in_view(node, sight.in_view());
        }
    }

    /// A node's sight against this frame's cone (`None` when the view cone is not followed).
    pub(super) fn current_sight(&mut self, node: u32) -> Option<Sight> {
        let cone = self.view.as_ref()?.cone?;
        self.counters.cone_tests += 1;
        Some(self.rule.sight(self.hierarchy, &self.nodes, node, &cone))
    }

    /// Computes a node's sight against this frame's cone and applies it.
    pub(super) fn refresh_sight(&mut self, node: u32) -> Option<Sight> {
        let sight = self.current_sight(node)?;
        self.set_in_view(node, sight.in_view());
        Some(sight)
    }

    /// Brings an active, non-mergeable node's flag up to date and queues it in the view queue
    /// until its view can change.
    pub(super) fn refresh_view(&mut self, node: u32) {
        let Some(sight) = self.refresh_sight(node) else {
            return;
        };
        let motion = self.view.as_ref().map(|view| view.motion);
        let key = motion.map_or(f64::INFINITY, |m| sight.frames_until_view_changes(&m));
        let link = self.link_for(key).unwrap_or_else(|| self.link_after(1));
        self.wheels.insert(node, Queue::View, link);
    }

    /// While the root is inactive, the base triangles' flag is refreshed every frame.
    pub(super) fn refresh_base_view(&mut self) {
        let root = self.nodes.root();
        if self.counts_in_view() && !self.is_active(root) {
            self.refresh_sight(root);
        }
    }

    /// An edge midpoint `m` was inserted or is about to be deleted: the blocks beside it (its
    /// parents, all active) trade a quarter for two halves or back.
    pub(super) fn boundary_vertex_changed(&mut self, m: GridPoint, inserted: bool) {
        if !self.counts_in_view() {
            return;
        }
        let mut change = 0;
        for parent in self.lattice.parents(m).as_slice() {
            if let VertexClass::Square { half } = self.lattice.classify(*parent) {
                change += u64::from(self.flagged_in_view(self.nodes.node_of(*parent, half)));
            }
        }
        if let Some(view) = self.view.as_mut() {
            if inserted {
                view.in_view_triangles += change;
            } else {
                view.in_view_triangles -= change;
            }
        }
    }

    /// A node's centre was just inserted (its boundary vertices are still inactive): it holds its
    /// four quarters, flagged `in_view`; its quadtree parent (or, for the root, the base) loses the
    /// two triangles that tiled its block.
    pub(super) fn node_activated(&mut self, node: u32, in_view: bool) {
        if !self.counts_in_view() {
            return;
        }
        let parent = self.nodes.parent(node);
        let lost = if parent == NO_NODE {
            self.flagged_in_view(node)
        } else {
            self.flagged_in_view(parent)
        };
        if let Some(view) = self.view.as_mut() {
            view.in_view_triangles =
                view.in_view_triangles + 4 * u64::from(in_view) - 2 * u64::from(lost);
            view.set(node, in_view);
        }
    }

    /// A node's centre was just deleted (after its boundary vertices): its four quarters go, the
    /// two triangles of its block return to its quadtree parent (or to the base, flagged like the
    /// root was). An inactive node other than the root carries no flag.
    pub(super) fn node_deactivated(&mut self, node: u32) {
        if !self.counts_in_view() {
            return;
        }
        let parent = self.nodes.parent(node);
        let was_in_view = self.flagged_in_view(node);
        let regained = if parent == NO_NODE {
            was_in_view
        } else {
            self.flagged_in_view(parent)
        };
        if let Some(view) = self.view.as_mut() {
            view.in_view_triangles =
                view.in_view_triangles + 2 * u64::from(regained) - 4 * u64::from(was_in_view);
            if parent != NO_NODE {
                view.set(node, false);
            }
        }
    }
}
