//! ROAM's GPU-side buffers, changed in place by every split and merge (issue #31): a vertex
//! buffer with one slot per active vertex and an index buffer with one slot (three indices) per
//! leaf triangle, drawn by one `TriangleList` call. What it is not: a strip buffer (the §7.2
//! strips stay counted, see `mod.rs`), nor a culled list (every leaf is drawn, `Out` ones
//! included, since the buffers must draw the mesh the runner culls and checks).
//!
//! - **Vertices.** A split writes its split vertex once, into a slot taken from a free list (or a
//!   new one at the end); a merge gives the slot back. Nothing else is ever written: a vertex's
//!   height does not change while it is in the mesh.
//! - **Indices.** Leaf slot k holds indices 3k..3k+3, the leaf's corners in the order apex, left,
//!   right (the mesh visitor's order, so the winding is the mesh's). A split gives the parent's
//!   slot to its first child and appends one for the second (24 bytes a triangle split); a
//!   merge gives the first child's slot back to the parent and removes the second child's by
//!   moving the last slot into it (swap-remove: one move writes 12 bytes), so the leaves always
//!   fill slots 0..n and one draw of 3n indices draws them.
//!
//! The slots, their free list and swap-remove are the shared [`LeafBuffer`]
//! (`sim::draw::incremental`, Wu's too), keyed here by bintree triangle.
//!
//! Upload per frame: at most [`BYTES_PER_CHANGE`] per diamond split or merged (forced splits
//! included), 0 for a frame that changes nothing; the draw list is issued again each frame,
//! which writes nothing. CPU side: a [`SecondaryMap`] entry per bintree triangle (its corners'
//! vertex slots, and its leaf slot) and the owner of every leaf slot; O(1) per split and merge.
//! `roam-rebuild` resets them with its bintree every frame and so rebuilds them: O(mesh).

use super::bintree::{Bintree, TriangleKey};
use crate::sim::draw::incremental::LeafBuffer;
use crate::sim::draw::{DrawCounts, DrawVertex, GpuBuffers, VERTEX_BYTES};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::SubgridPoint;
use slotmap::SecondaryMap;

/// The most bytes one diamond split or merge uploads: a split writes its vertex (12) and two
/// children per parent (2 × 2 × 12); a merge writes each parent (12) and moves a slot (12).
pub const BYTES_PER_CHANGE: u64 = 12 + 2 * 2 * 12;

/// Marks a triangle that holds no leaf slot (an interior one).
const NO_SLOT: u32 = u32::MAX;

/// A bintree triangle's place in the buffers.
#[derive(Clone, Copy, Debug)]
struct TriangleSlots {
    /// The vertex slots of its apex, left and right corners.
    corners: [u32; 3],
    /// Its leaf slot, or [`NO_SLOT`] while it is split.
    leaf: u32,
}

/// The buffers and the bookkeeping that keeps them equal to the bintree's leaves.
pub(super) struct LeafBuffers {
    buffer: LeafBuffer<TriangleKey>,
    slots: SecondaryMap<TriangleKey, TriangleSlots>,
}

impl LeafBuffers {
    /// Buffers holding the bintree's base mesh (its two roots, unsplit).
    pub fn new(bintree: &Bintree, hierarchy: &Hierarchy) -> LeafBuffers {
        let mut buffers = LeafBuffers {
            buffer: LeafBuffer::new(VERTEX_BYTES),
            slots: SecondaryMap::new(),
        };
        buffers.reset(bintree, hierarchy);
        buffers
    }

    /// Back to the base mesh of a bintree just reset: the four corners and the two roots written
    /// again (the slots of the former mesh are forgotten; what they held is overwritten as the
    /// mesh grows).
    pub fn reset(&mut self, bintree: &Bintree, hierarchy: &Hierarchy) {
        self.slots.clear();
        self.buffer.clear();
        let mut corner_slots: Vec<(GridPoint, u32)> = Vec::with_capacity(4);
        for root in bintree.roots() {
            let shape = bintree.get(root).shape;
            let corners = [shape.apex, shape.left, shape.right].map(|p| {
                match corner_slots.iter().find(|(q, _)| *q == p) {
                    Some(&(_, slot)) => slot,
                    None => {
                        let slot = self.add_vertex(p, hierarchy);
                        corner_slots.push((p, slot));
                        slot
                    }
                }
            });
            let leaf = self.buffer.push_leaf(root, corners);
            self.slots.insert(root, TriangleSlots { corners, leaf });
        }
    }

    /// Follows the split of the diamond of `parents` (already done in the bintree): the split
    /// vertex gets a slot, each parent's leaf slot goes to its first child, its second child gets
    /// a new one. Diamonds must come in the order they were split (a forced split's children may
    /// be the next diamond's parents).
    pub fn split_diamond(
        &mut self,
        bintree: &Bintree,
        parents: [Option<TriangleKey>; 2],
        hierarchy: &Hierarchy,
    ) {
        let Some(mid) = parents[0].and_then(|p| bintree.get(p).split_vertex()) else {
            return;
        };
        let mid_slot = self.add_vertex(mid, hierarchy);
        for parent in parents.into_iter().flatten() {
            let Some([c0, c1]) = bintree.get(parent).children else {
                continue;
            };
            let TriangleSlots { corners, leaf } = self.slots[parent];
            debug_assert_ne!(leaf, NO_SLOT, "a split parent was a leaf");
            self.slots[parent].leaf = NO_SLOT;
            // `Triangle::children`: (mid, apex, left) and (mid, right, apex).
            let [apex, left, right] = corners;
            let first = [mid_slot, apex, left];
            let second = [mid_slot, right, apex];
            self.buffer.set_leaf(leaf, c0, first);
            self.slots.insert(
                c0,
                TriangleSlots {
                    corners: first,
                    leaf,
                },
            );
            let new_leaf = self.buffer.push_leaf(c1, second);
            self.slots.insert(
                c1,
                TriangleSlots {
                    corners: second,
                    leaf: new_leaf,
                },
            );
        }
    }

    /// Follows the merge of the diamond of `parents`, called while their children are still in
    /// the bintree (before `merge::merge`): each parent takes its first child's slot back, its
    /// second child's slot is filled by the last one, and the split vertex's slot is freed.
    pub fn merge_diamond(&mut self, bintree: &Bintree, parents: [Option<TriangleKey>; 2]) {
        let mut mid_slot = None;
        for parent in parents.into_iter().flatten() {
            let Some([c0, c1]) = bintree.get(parent).children else {
                continue;
            };
            let first = self.slots.remove(c0).expect("a leaf has slots");
            let second = self.slots.remove(c1).expect("a leaf has slots");
            mid_slot = Some(first.corners[0]);
            let corners = self.slots[parent].corners;
            self.slots[parent].leaf = first.leaf;
            self.buffer.set_leaf(first.leaf, parent, corners);
            if let Some(moved) = self.buffer.remove_leaf(second.leaf) {
                self.slots[moved].leaf = second.leaf;
            }
        }
        if let Some(slot) = mid_slot {
            self.buffer.free_vertex(slot);
        }
    }

    /// Issues the frame's one draw and ends the frame: what it uploaded and issued.
    pub fn prepare(&mut self) -> DrawCounts {
        self.buffer.prepare(0.0)
    }

    pub fn gpu(&self) -> &GpuBuffers {
        self.buffer.gpu()
    }

    /// Heap bytes of the buffers' model and the bookkeeping.
    pub fn memory_bytes(&self) -> usize {
        self.buffer.memory_bytes()
            + self.slots.capacity() * (size_of::<TriangleSlots>() + size_of::<u32>())
    }

    fn add_vertex(&mut self, p: GridPoint, hierarchy: &Hierarchy) -> u32 {
        self.buffer.add_vertex(DrawVertex::fixed(
            SubgridPoint::from(p),
            hierarchy.height(p),
        ))
    }
}
