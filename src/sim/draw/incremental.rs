//! An incremental leaf buffer: the GPU-side buffers of a mesh changed in place by splits and
//! merges (issue #31; Wu's and ROAM's, which keep the same shape of bookkeeping). One vertex
//! buffer with a slot per active vertex and one index buffer with a slot (three indices) per
//! leaf triangle, drawn by one indexed triangle-list call. It is not the mesh and knows nothing
//! of its geometry: the algorithm says which vertex goes into a slot, which corners a leaf has,
//! and keeps its own map from its ids (a vertex, a bintree triangle) to the slots handed out.
//!
//! - **Vertex slots** come from a free list (or a new slot at the end); writing a vertex uploads
//!   its bytes (12, or 16 for a morphing vertex); freeing a slot writes nothing (its content is
//!   never drawn again until the slot is reused and overwritten).
//! - **Leaf slots** always fill 0..n, so one draw of 3n indices draws them: a leaf is appended
//!   (12 bytes) or overwrites a slot (12 bytes); removing one moves the last leaf into the hole
//!   (**swap-remove**: its indices copied, 12 bytes, and its owner reported so that the algorithm
//!   learns its new slot).
//!
//! Every write goes through [`GpuBuffers`], so the upload is counted where it happens; a frame
//! that changes nothing uploads 0 bytes (re-issuing the draw writes nothing). O(1) per call.

use super::{BufferId, DrawCall, DrawCounts, DrawVertex, GpuBuffers, Topology};

/// The buffers and the owner (the algorithm's id) of every leaf slot.
#[derive(Clone, Debug)]
pub struct LeafBuffer<T> {
    gpu: GpuBuffers,
    vertices: BufferId,
    indices: BufferId,
    /// The leaf in each leaf slot; its length is the number of triangles drawn.
    owners: Vec<T>,
    free_vertex_slots: Vec<u32>,
    vertex_slots_used: u32,
}

impl<T: Copy> LeafBuffer<T> {
    /// Empty buffers whose vertices take `bytes_per_vertex` each (12 or 16).
    pub fn new(bytes_per_vertex: u32) -> LeafBuffer<T> {
        let mut gpu = GpuBuffers::new();
        let vertices = gpu.create_vertices(Vec::new(), bytes_per_vertex);
        let indices = gpu.create_indices(Vec::new());
        LeafBuffer {
            gpu,
            vertices,
            indices,
            owners: Vec::new(),
            free_vertex_slots: Vec::new(),
            vertex_slots_used: 0,
        }
    }

    /// Forgets every slot (what they held is overwritten as the mesh grows again); writes
    /// nothing.
    pub fn clear(&mut self) {
        self.owners.clear();
        self.free_vertex_slots.clear();
        self.vertex_slots_used = 0;
    }

    /// Gives `vertex` a slot and writes it there; the slot.
    pub fn add_vertex(&mut self, vertex: DrawVertex) -> u32 {
        let slot = self.free_vertex_slots.pop().unwrap_or_else(|| {
            self.vertex_slots_used += 1;
            self.vertex_slots_used - 1
        });
        self.write_vertex(slot, vertex);
        slot
    }

    /// Rewrites the vertex in `slot` (a morphing vertex's new heights).
    pub fn write_vertex(&mut self, slot: u32, vertex: DrawVertex) {
        debug_assert!(slot < self.vertex_slots_used);
        self.gpu
            .write_vertices(self.vertices, slot as usize, &[vertex]);
    }

    /// Frees a vertex slot (nothing is written).
    pub fn free_vertex(&mut self, slot: u32) {
        debug_assert!(slot < self.vertex_slots_used && !self.free_vertex_slots.contains(&slot));
        self.free_vertex_slots.push(slot);
    }

    /// Appends a leaf with corners `corners` (vertex slots, in drawing order); its slot.
    pub fn push_leaf(&mut self, owner: T, corners: [u32; 3]) -> u32 {
        let slot = self.owners.len() as u32;
        self.owners.push(owner);
        self.write_indices(slot, corners);
        slot
    }

    /// Puts a leaf into an existing leaf slot, over what it held.
    pub fn set_leaf(&mut self, slot: u32, owner: T, corners: [u32; 3]) {
        self.owners[slot as usize] = owner;
        self.write_indices(slot, corners);
    }

    /// Removes the leaf in `slot`: the last leaf moves into it, and is returned (its new slot
    /// is `slot`); `None` when the removed leaf was the last.
    pub fn remove_leaf(&mut self, slot: u32) -> Option<T> {
        let last = self.owners.len() as u32 - 1;
        let moved = self.owners.pop().expect("a leaf to remove");
        if slot == last {
            return None;
        }
        self.owners[slot as usize] = moved;
        let corners = self.corners(last);
        self.write_indices(slot, corners);
        Some(moved)
    }

    /// The leaf in `slot`.
    pub fn owner(&self, slot: u32) -> T {
        self.owners[slot as usize]
    }

    /// The vertex slots of the leaf in `slot`, in drawing order (read back: free).
    pub fn corners(&self, slot: u32) -> [u32; 3] {
        let from = 3 * slot as usize;
        self.gpu.indices(self.indices)[from..from + 3]
            .try_into()
            .expect("three indices a leaf")
    }

    /// The number of leaves drawn.
    pub fn leaves(&self) -> usize {
        self.owners.len()
    }

    /// Issues the frame's one draw (at morph blend `blend`) and ends the frame: what it uploaded
    /// and issued.
    pub fn prepare(&mut self, blend: f32) -> DrawCounts {
        self.gpu.clear_draws();
        self.gpu.draw(DrawCall {
            vertices: self.vertices,
            indices: self.indices,
            first_index: 0,
            index_count: 3 * self.owners.len() as u32,
            topology: Topology::TriangleList,
            blend,
        });
        self.gpu.end_frame()
    }

    pub fn gpu(&self) -> &GpuBuffers {
        &self.gpu
    }

    /// Heap bytes of the buffers' model and the slot lists.
    pub fn memory_bytes(&self) -> usize {
        self.gpu.memory_bytes()
            + self.owners.capacity() * size_of::<T>()
            + self.free_vertex_slots.capacity() * size_of::<u32>()
    }

    fn write_indices(&mut self, slot: u32, corners: [u32; 3]) {
        self.gpu
            .write_indices(self.indices, 3 * slot as usize, &corners);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::draw::VERTEX_BYTES;
    use crate::sim::mesh::SubgridPoint;

    fn vertex(i: u32, j: u32) -> DrawVertex {
        DrawVertex::fixed(SubgridPoint::grid(i, j), (i + j) as f32)
    }

    /// The triangles drawn, as corner positions.
    fn drawn(buffer: &LeafBuffer<char>) -> Vec<[(i64, i64); 3]> {
        let mut triangles = Vec::new();
        buffer
            .gpu()
            .for_each_triangle(|t| triangles.push(t.map(|c| c.position.raw())));
        triangles
    }

    /// A unit square as two leaves, 'a' and 'b'.
    fn square() -> (LeafBuffer<char>, [u32; 4]) {
        let mut buffer = LeafBuffer::new(VERTEX_BYTES);
        let v = [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(i, j)| buffer.add_vertex(vertex(i, j)));
        buffer.push_leaf('a', [v[0], v[1], v[2]]);
        buffer.push_leaf('b', [v[0], v[2], v[3]]);
        (buffer, v)
    }

    #[test]
    fn the_first_frame_uploads_what_was_written_and_a_quiet_frame_nothing() {
        let (mut buffer, _) = square();
        let first = buffer.prepare(0.0);
        assert_eq!(first.upload_bytes, 4 * 12 + 2 * 12);
        assert_eq!((first.draw_calls, first.triangles_submitted), (1, 2));
        let quiet = buffer.prepare(0.0);
        assert_eq!(quiet.upload_bytes, 0);
        assert_eq!(quiet.triangles_submitted, 2);
    }

    #[test]
    fn removing_a_leaf_moves_the_last_into_the_hole_and_names_it() {
        let (mut buffer, v) = square();
        let c = buffer.push_leaf('c', [v[1], v[2], v[3]]);
        buffer.prepare(0.0);
        assert_eq!(buffer.remove_leaf(0), Some('c'));
        assert_eq!(buffer.owner(0), 'c');
        assert_eq!(buffer.corners(0), [v[1], v[2], v[3]]);
        assert_eq!(buffer.leaves(), 2);
        assert_eq!(
            buffer.remove_leaf(c - 1),
            None,
            "the last leaf moves nothing"
        );
        let counts = buffer.prepare(0.0);
        assert_eq!(counts.upload_bytes, 12, "only the moved leaf's indices");
        assert_eq!(drawn(&buffer).len(), 1);
    }

    #[test]
    fn a_freed_vertex_slot_is_reused_and_overwritten() {
        let (mut buffer, v) = square();
        buffer.remove_leaf(1);
        buffer.free_vertex(v[3]);
        buffer.prepare(0.0);
        let slot = buffer.add_vertex(vertex(0, 2));
        assert_eq!(slot, v[3]);
        buffer.set_leaf(0, 'd', [v[0], v[2], slot]);
        assert_eq!(buffer.prepare(0.0).upload_bytes, 12 + 12);
        assert_eq!(
            drawn(&buffer),
            vec![[(0, 0), (1, 1), (0, 2)].map(|(i, j)| { SubgridPoint::grid(i, j).raw() })]
        );
    }
}
