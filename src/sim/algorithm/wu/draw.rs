//! Wu's GPU buffers, kept incrementally (issue #31): one vertex buffer with a slot per active
//! vertex and one index buffer with a slot per leaf triangle, drawn by one indexed triangle-list
//! call. Each vertex inserted or deleted by a split or a merge changes them in place, so the
//! upkeep costs O(vertices changed), never O(mesh). It is not the mesh (the vertex set in
//! `mod.rs` is); it only follows it.
//!
//! **What a vertex change does.** Inserting a vertex p of a closed 4-8 mesh (its parents active,
//! its children not) splits the one or two leaf triangles of its diamond (apex a parent of p,
//! hypotenuse the edge p bisects) into two each, with p as their apex; deleting p (its children
//! inactive) merges them back. So an insertion writes p (12 bytes, into a free slot of the vertex
//! buffer), overwrites each diamond triangle's slot with one half and appends the other (12 bytes
//! of indices each): at most 12 + 4·12 = 60 bytes. A deletion writes each merged triangle over one
//! half and removes the other by **swap-remove**: the last triangle moves into the hole (12 bytes)
//! and the list shrinks, so the draw stays one range with no holes; it frees p's vertex slot
//! (nothing written): at most 4·12 = 48 bytes. A Wu split inserts its centre and at most four
//! boundary vertices, a merge deletes as many: at most 5·60 = 300 bytes per split or merge.
//!
//! **Bookkeeping.** The slots themselves, their free list and swap-remove are the shared
//! [`LeafBuffer`] (`sim::draw::incremental`, ROAM's too), keyed here by [`Leaf`]. Per active
//! vertex (a hash map by vertex id, O(mesh), nothing per sample): its vertex slot and the slots
//! of the at most four leaf triangles whose right angle it is, by the direction from it to their
//! hypotenuse (axis directions for block centres, diagonals for edge midpoints and the base
//! corners); per triangle slot, the triangle it holds (apex and direction), so that a moved
//! triangle's owner learns its new slot. Inserting or deleting a vertex looks up its own entry,
//! each parent's and the hypotenuse's two ends once each (plus a moved triangle's apex), never
//! once per corner written. `update` only records each vertex inserted or deleted (a push, in
//! the order the mesh changed); `prepare_draw` replays them, which is the timed buffer upkeep of
//! `frame_ns`. With morphing (`morph.rs`) the drawn mesh's edits replace the vertex set's:
//! insertions at a morph's start height, and height rewrites (12 bytes a morphing vertex a
//! frame).
//!
//! **Why a list, one draw.** The buffers hold the whole mesh, drawn by one call: Wu's in-view
//! refinement (§3.2) already leaves what is outside the cone coarse, so culling blocks on the
//! CPU would buy little and cost a draw call per block and holes in the buffers; the GPU clips
//! the rest. (The in-view count `triangles_in_view_blocks` is the budget's measure, not a
//! culling of the buffers.)
//!
//! **Strips: kept, counted, not drawn.** Wu §7 adopts incremental triangle stripping ("in
//! average there are 3.7 triangles in a strip"); option `strips` keeps them (`strips.rs`: ROAM
//! §7.2's non-generalised strips, updated here per vertex inserted or deleted, so `frame_ns`
//! includes them) and reports `triangles_per_strip`, as ROAM's option does. The buffers still
//! draw the list: with restarts, a 3.7-triangle strip costs 5.7 + 1 indices against 11.1 for a
//! list (40 % fewer indices resident), but a 2001 renderer stripped to send fewer vertices a
//! triangle every frame, which a resident indexed list already achieves (each vertex sent once,
//! when it enters the mesh; nothing for a frame without change), while drawing strips from
//! resident buffers means variable-length index ranges that every split or merge re-links,
//! moves and compacts, its upload no longer a fixed 12 bytes a slot (ROAM's `mod.rs` decides the
//! same for ROAM's strips). The option is off by default, against the paper's words, because it
//! changes nothing drawn: on, every entry's `frame_ns` would pay for strips its buffers do not
//! use, and the study compares the work of drawing. The meshes, counts, uploads and draw calls
//! are the same either way (`tests/wu_strips.rs`). Measured on the first 1000 frames of the
//! Table 1 circle at budget 6000 (`examples/wu_frames.rs` under callgrind, frames 200–499): 3.66
//! triangles a strip (the paper's 3.7), and `prepare_draw` 5.0 times the instructions without
//! strips (110 k against 21.8 k a frame), most of it finding each new leaf's neighbours.

use super::strips::WuStrips;
use crate::sim::draw::incremental::LeafBuffer;
use crate::sim::draw::strips::StripCounts;
use crate::sim::draw::{DrawCounts, DrawVertex, GpuBuffers, VERTEX_BYTES};
use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice};
use crate::sim::mesh::SubgridPoint;
use crate::sim::mesh::triangles::base_triangles;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// No slot.
pub(super) const NO_SLOT: u32 = u32::MAX;

/// A fast, fixed hash of vertex ids (a multiply and a fold: ids are dense integers).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct IdHasher(u64);

impl Hasher for IdHasher {
    fn finish(&self) -> u64 {
        self.0 ^ (self.0 >> 29)
    }

    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.write_u64(u64::from(byte));
        }
    }

    fn write_u32(&mut self, value: u32) {
        self.write_u64(u64::from(value));
    }

    fn write_u64(&mut self, value: u64) {
        self.0 = (self.0.rotate_left(5) ^ value).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
}

/// An active vertex's slots.
#[derive(Clone, Copy, Debug)]
pub(super) struct VertexSlots {
    vertex: u32,
    /// The slots of the leaf triangles with their right angle here, by [`Leaf::direction`].
    pub(super) triangles: [u32; 4],
}

/// The active vertices' slots, by vertex id.
pub(super) type Slots = HashMap<u32, VertexSlots, BuildHasherDefault<IdHasher>>;

/// A leaf triangle as the buffers know it: its right-angle corner and hypotenuse ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Leaf {
    pub(super) apex: GridPoint,
    pub(super) ends: [GridPoint; 2],
}

impl Leaf {
    /// Which of the apex's four triangles this is: the direction from the apex to the
    /// hypotenuse's midpoint, an axis or a diagonal (a vertex has triangles of one kind only).
    pub(super) fn direction(&self) -> usize {
        let d = |end: u32, apex: u32| i64::from(end) - i64::from(apex);
        let di = d(self.ends[0].i, self.apex.i) + d(self.ends[1].i, self.apex.i);
        let dj = d(self.ends[0].j, self.apex.j) + d(self.ends[1].j, self.apex.j);
        match (di.signum(), dj.signum()) {
            (1, 0) | (1, 1) => 0,
            (0, 1) | (-1, 1) => 1,
            (-1, 0) | (-1, -1) => 2,
            _ => 3,
        }
    }

    /// The corners counter-clockwise seen from above (the winding every drawn triangle keeps).
    fn corners(&self) -> [GridPoint; 3] {
        self.ordered([self.apex, self.ends[0], self.ends[1]])
    }

    /// What belongs to the apex and the two ends (in that order), in the order of
    /// [`Leaf::corners`]: the apex first, the ends swapped where the winding needs it.
    fn ordered<T>(&self, [apex, first, second]: [T; 3]) -> [T; 3] {
        let xy = |p: GridPoint| (i64::from(p.i), i64::from(p.j));
        let (a, b, c) = (xy(self.apex), xy(self.ends[0]), xy(self.ends[1]));
        let area2 = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        if area2 >= 0 {
            [apex, first, second]
        } else {
            [apex, second, first]
        }
    }
}

/// A change of the drawn mesh recorded during `update`, applied by `prepare`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Edit {
    /// The vertex joins the mesh, drawn at its sample's height.
    Insert,
    /// The vertex joins the mesh, drawn at this height (a morph's start, `morph.rs`).
    InsertAt(f32),
    /// The vertex leaves the mesh.
    Delete,
    /// The vertex, in the mesh, is drawn at this height from now on (a morph's step).
    Height(f32),
}

/// A vertex and what happens to it.
type Change = (GridPoint, Edit);

/// Wu's buffers (see the module docs).
pub(super) struct WuBuffers {
    buffer: LeafBuffer<Leaf>,
    slots: Slots,
    /// Wu §7's incremental strips over the leaves, when on (`strips.rs`).
    strips: Option<WuStrips>,
    /// The mesh's changes since the last `prepare`, in order.
    pending: Vec<Change>,
    /// Where the vertex set's changes not yet handed to morphing start in `pending`.
    not_taken: usize,
}

impl WuBuffers {
    /// The buffers of the base mesh (the four corners, two triangles), counted as this first
    /// frame's upload.
    /// With `strips`, the leaves are kept in strips too (`strips.rs`).
    pub fn new(lattice: &Lattice, hierarchy: &Hierarchy, strips: bool) -> WuBuffers {
        let mut buffers = WuBuffers {
            buffer: LeafBuffer::new(VERTEX_BYTES),
            slots: HashMap::default(),
            strips: strips.then(WuStrips::default),
            pending: Vec::new(),
            not_taken: 0,
        };
        for corner in lattice.corners() {
            buffers.add_vertex(lattice, corner, hierarchy.height(corner));
        }
        for t in base_triangles(lattice) {
            let leaf = Leaf {
                apex: t.apex,
                ends: [t.left, t.right],
            };
            let corners = buffers.corner_slots(lattice, leaf);
            let slot = buffers.buffer.push_leaf(leaf, corners);
            buffers.remember(lattice, slot, leaf);
            buffers.attach(lattice, &[slot]);
        }
        buffers
    }

    /// Records that the mesh gained (`inserted`) or lost vertex `p`.
    pub fn record(&mut self, p: GridPoint, inserted: bool) {
        self.pending
            .push((p, if inserted { Edit::Insert } else { Edit::Delete }));
    }

    /// Records an edit of the drawn mesh (morphing's, which follows the recorded changes of the
    /// vertex set with its own).
    pub fn record_edit(&mut self, p: GridPoint, edit: Edit) {
        self.pending.push((p, edit));
        self.not_taken = self.pending.len();
    }

    /// Hands over the changes recorded since the last `prepare` (morphing turns the vertex
    /// set's into the drawn mesh's).
    pub fn take_changes(&mut self, into: &mut Vec<(GridPoint, Edit)>) {
        into.extend(self.pending.drain(self.not_taken..));
    }

    /// Applies the recorded changes in order and issues the frame's one draw; what the frame
    /// uploaded and issued.
    pub fn prepare(&mut self, lattice: &Lattice, hierarchy: &Hierarchy) -> DrawCounts {
        let pending = std::mem::take(&mut self.pending);
        for &(p, edit) in &pending {
            match edit {
                Edit::Insert => self.insert(lattice, p, hierarchy.height(p)),
                Edit::InsertAt(z) => self.insert(lattice, p, z),
                Edit::Delete => self.delete(lattice, p),
                Edit::Height(z) => {
                    let slot = self.slots[&lattice.id(p)].vertex;
                    self.buffer
                        .write_vertex(slot, DrawVertex::fixed(SubgridPoint::from(p), z));
                }
            }
        }
        self.pending = pending;
        self.pending.clear();
        self.not_taken = 0;
        self.buffer.prepare(0.0)
    }

    pub fn gpu(&self) -> &GpuBuffers {
        self.buffer.gpu()
    }

    /// Heap bytes on the CPU side: the model of the GPU buffers and the slot bookkeeping.
    pub fn memory_bytes(&self) -> usize {
        self.buffer.memory_bytes()
            + self.slots.capacity()
                * (size_of::<u32>() + size_of::<VertexSlots>() + size_of::<u64>())
            + self.pending.capacity() * size_of::<Change>()
            + self.strips.as_ref().map_or(0, WuStrips::memory_bytes)
    }

    /// The strips' counts, when the leaves are stripped.
    pub fn strip_counts(&self) -> Option<StripCounts> {
        self.strips.as_ref().map(WuStrips::counts)
    }

    /// Checks the strips against the leaves (`strips.rs`); `Ok` when there are none.
    pub fn check_strips(&self, lattice: &Lattice) -> Result<(), String> {
        match &self.strips {
            Some(strips) => strips.check(&self.buffer, &self.slots, lattice),
            None => Ok(()),
        }
    }

    /// The strips, to break them in the validator's tests.
    #[cfg(test)]
    pub(super) fn strips_mut(&mut self) -> Option<&mut WuStrips> {
        self.strips.as_mut()
    }

    /// Takes the leaves in `slots` out of their strips (before they change), when stripping.
    fn detach(&mut self, lattice: &Lattice, slots: &[u32]) {
        if let Some(strips) = &mut self.strips {
            strips.detach(&self.buffer, &self.slots, lattice, slots);
        }
    }

    /// Strips the leaves in `slots` (once the buffers hold them), when stripping.
    fn attach(&mut self, lattice: &Lattice, slots: &[u32]) {
        if let Some(strips) = &mut self.strips {
            strips.attach(&self.buffer, &self.slots, lattice, slots);
        }
    }

    /// Splits the diamond of `p` around it. `p`'s slots are kept in hand and entered once, and
    /// the hypotenuse's ends are looked up once for both parents: five lookups an insertion,
    /// with the buffers written in the same order as one lookup per corner would.
    fn insert(&mut self, lattice: &Lattice, p: GridPoint, z: f32) {
        let ends = lattice
            .bisected_edge(p)
            .expect("a corner is never inserted");
        let vertex = self
            .buffer
            .add_vertex(DrawVertex::fixed(SubgridPoint::from(p), z));
        let mut own = VertexSlots {
            vertex,
            triangles: [NO_SLOT; 4],
        };
        let end_slots = [
            self.vertex_slot(lattice, ends[0]),
            self.vertex_slot(lattice, ends[1]),
        ];
        let parents = lattice.parents(p);
        if self.strips.is_some() {
            let mut diamond = [NO_SLOT; 2];
            for (k, &a) in parents.as_slice().iter().enumerate() {
                let direction = Leaf { apex: a, ends }.direction();
                diamond[k] = self.slots[&lattice.id(a)].triangles[direction];
            }
            self.detach(lattice, &diamond[..parents.as_slice().len()]);
        }
        let mut halves_written = [NO_SLOT; 4];
        for (k, &a) in parents.as_slice().iter().enumerate() {
            let parent = Leaf { apex: a, ends };
            let apex = self.apex_slots(lattice, a);
            let slot = std::mem::replace(&mut apex.triangles[parent.direction()], NO_SLOT);
            debug_assert_ne!(slot, NO_SLOT, "{parent:?} is not a leaf of the buffers");
            let a_slot = apex.vertex;
            // Each half has apex `p` and ends `a` and one end of the parent's hypotenuse.
            let [first, second] = halves(p, parent);
            let corners = first.ordered([vertex, a_slot, end_slots[0]]);
            self.buffer.set_leaf(slot, first, corners);
            own.triangles[first.direction()] = slot;
            let corners = second.ordered([vertex, a_slot, end_slots[1]]);
            let appended = self.buffer.push_leaf(second, corners);
            own.triangles[second.direction()] = appended;
            halves_written[2 * k] = slot;
            halves_written[2 * k + 1] = appended;
        }
        let previous = self.slots.insert(lattice.id(p), own);
        debug_assert!(previous.is_none(), "{p:?} inserted twice");
        self.attach(lattice, &halves_written[..2 * parents.as_slice().len()]);
    }

    /// Merges the diamond of `p` back and frees its vertex slot. As in [`WuBuffers::insert`],
    /// `p`'s slots are taken out once and the ends looked up once.
    fn delete(&mut self, lattice: &Lattice, p: GridPoint) {
        let ends = lattice.bisected_edge(p).expect("a corner is never deleted");
        let mut own = self
            .slots
            .remove(&lattice.id(p))
            .expect("a deleted vertex had a slot");
        let end_slots = [
            self.vertex_slot(lattice, ends[0]),
            self.vertex_slot(lattice, ends[1]),
        ];
        let parents = lattice.parents(p);
        if self.strips.is_some() {
            let mut halves_held = own.triangles;
            halves_held.sort_unstable();
            let held = halves_held.iter().take_while(|&&t| t != NO_SLOT).count();
            self.detach(lattice, &halves_held[..held]);
        }
        let mut merged = [NO_SLOT; 2];
        for (k, &a) in parents.as_slice().iter().enumerate() {
            let parent = Leaf { apex: a, ends };
            let [first, second] = halves(p, parent);
            let slot = std::mem::replace(&mut own.triangles[first.direction()], NO_SLOT);
            debug_assert_ne!(slot, NO_SLOT, "{first:?} is not a leaf of the buffers");
            let apex = self.apex_slots(lattice, a);
            apex.triangles[parent.direction()] = slot;
            let corners = parent.ordered([apex.vertex, end_slots[0], end_slots[1]]);
            self.buffer.set_leaf(slot, parent, corners);
            merged[k] = slot;
            let hole = std::mem::replace(&mut own.triangles[second.direction()], NO_SLOT);
            debug_assert_ne!(hole, NO_SLOT, "{second:?} is not a leaf of the buffers");
            if let Some(strips) = &mut self.strips {
                strips.remove(hole);
                // A merged triangle in the last slot moves into the hole with it.
                for m in &mut merged[..=k] {
                    if *m as usize == self.buffer.leaves() - 1 {
                        *m = hole;
                    }
                }
            }
            if let Some(moved) = self.buffer.remove_leaf(hole) {
                if moved.apex == p {
                    own.triangles[moved.direction()] = hole;
                } else {
                    self.remember(lattice, hole, moved);
                }
            }
        }
        debug_assert!(own.triangles.iter().all(|&t| t == NO_SLOT));
        self.buffer.free_vertex(own.vertex);
        self.attach(lattice, &merged[..parents.as_slice().len()]);
    }

    /// The vertex slot of an active vertex.
    fn vertex_slot(&self, lattice: &Lattice, q: GridPoint) -> u32 {
        self.slots[&lattice.id(q)].vertex
    }

    /// The slots of a leaf's apex (active).
    fn apex_slots(&mut self, lattice: &Lattice, apex: GridPoint) -> &mut VertexSlots {
        self.slots
            .get_mut(&lattice.id(apex))
            .expect("a leaf's apex is active")
    }

    /// Gives `p` a vertex slot and writes it, drawn at height `z`.
    fn add_vertex(&mut self, lattice: &Lattice, p: GridPoint, z: f32) {
        let vertex = DrawVertex::fixed(SubgridPoint::from(p), z);
        let slot = self.buffer.add_vertex(vertex);
        let previous = self.slots.insert(
            lattice.id(p),
            VertexSlots {
                vertex: slot,
                triangles: [NO_SLOT; 4],
            },
        );
        debug_assert!(previous.is_none(), "{p:?} inserted twice");
    }

    /// The vertex slots of a leaf's corners, counter-clockwise.
    fn corner_slots(&self, lattice: &Lattice, leaf: Leaf) -> [u32; 3] {
        leaf.corners()
            .map(|corner| self.slots[&lattice.id(corner)].vertex)
    }

    /// Tells a leaf's apex that the leaf is in triangle slot `slot`.
    fn remember(&mut self, lattice: &Lattice, slot: u32, leaf: Leaf) {
        self.slots
            .get_mut(&lattice.id(leaf.apex))
            .expect("a leaf's apex is active")
            .triangles[leaf.direction()] = slot;
    }
}

/// The two halves of `parent` split at its hypotenuse's midpoint `p`: right-angled at `p`, each
/// with a leg of the parent's as its hypotenuse.
fn halves(p: GridPoint, parent: Leaf) -> [Leaf; 2] {
    [
        Leaf {
            apex: p,
            ends: [parent.apex, parent.ends[0]],
        },
        Leaf {
            apex: p,
            ends: [parent.apex, parent.ends[1]],
        },
    ]
}
