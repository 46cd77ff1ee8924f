//! A mesh rebuilt from scratch every frame, double-buffered so that the frame's inserted and
//! deleted vertices can be counted against the previous frame's mesh: what changed on screen,
//! the meaning those counters have for the incremental algorithms too. It is the vertex set of
//! the 4-8 algorithms that rebuild their mesh each frame (SPEC §12): `reference`, `lindstrom`
//! and `rottger`. Incremental algorithms keep their own.
//!
//! Starting a frame swaps the buffers and clears the new current one in O(previous active
//! vertices), not O(grid); it keeps the four corners. Nothing allocates after the first frames.

use super::VertexSet;
use crate::sim::hierarchy::Lattice;

/// The current mesh, its active vertices in insertion order, and the previous frame's.
#[derive(Clone, Debug)]
pub struct RebuiltMesh {
    current: VertexSet,
    active: Vec<u32>,
    previous: VertexSet,
    previous_active: Vec<u32>,
}

impl RebuiltMesh {
    /// The base mesh (the four corners), with the base mesh as its previous frame.
    pub fn new(lattice: &Lattice) -> RebuiltMesh {
        let current = VertexSet::base_mesh(lattice);
        let active: Vec<u32> = current.iter().collect();
        RebuiltMesh {
            previous: current.clone(),
            previous_active: active.clone(),
            current,
            active,
        }
    }

    /// Makes the current mesh the previous one and starts again from the four corners.
    pub fn start_frame(&mut self, lattice: &Lattice) {
        std::mem::swap(&mut self.current, &mut self.previous);
        std::mem::swap(&mut self.active, &mut self.previous_active);
        for &id in &self.active {
            self.current.remove(id);
        }
        self.active.clear();
        for corner in lattice.corners() {
            self.insert(lattice.id(corner));
        }
    }

    /// Inserts a vertex; returns whether it was absent.
    pub fn insert(&mut self, id: u32) -> bool {
        let absent = self.current.insert(id);
        if absent {
            self.active.push(id);
        }
        absent
    }

    pub fn mesh(&self) -> &VertexSet {
        &self.current
    }

    /// The previous frame's mesh.
    pub fn previous(&self) -> &VertexSet {
        &self.previous
    }

    /// Active vertices, in insertion order.
    pub fn active(&self) -> &[u32] {
        &self.active
    }

    /// Vertices active now that were not in the previous frame's mesh.
    pub fn inserted_since_previous(&self) -> u64 {
        self.active
            .iter()
            .filter(|&&id| !self.previous.contains(id))
            .count() as u64
    }

    /// Vertices of the previous frame's mesh that are not active now.
    pub fn deleted_since_previous(&self) -> u64 {
        self.previous_active
            .iter()
            .filter(|&&id| !self.current.contains(id))
            .count() as u64
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        let list = |v: &Vec<u32>| v.capacity() * std::mem::size_of::<u32>();
        self.current.memory_bytes()
            + self.previous.memory_bytes()
            + list(&self.active)
            + list(&self.previous_active)
    }
}
