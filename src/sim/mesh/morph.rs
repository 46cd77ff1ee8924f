//! Morphed heights of a 4-8 mesh: the vertices an algorithm draws at a height of its own (a
//! geomorph between two levels) instead of their sample's height. Röttger's geomorphing (Röttger
//! et al. 1998 §2.3, SPEC §6) hands them; the block families morph inside their triangle lists
//! instead ([`super::TriangleList`]). It holds the heights; the algorithm computes them.
//!
//! Sparse: only the morphing vertices are held, by vertex id, so a mesh that morphs nothing
//! costs nothing and one that morphs k vertices costs O(k). Lookups are O(1) (a hash map with a
//! fixed hasher: no iteration order is exposed, and none of the results depends on one).
//! Clearing keeps the capacity, so a frame-after-frame rebuild stops allocating.
//!
//! The hasher is a multiply by an odd 64-bit constant (Fibonacci hashing, as rustc's Fx hash
//! folds a word; ROAM's queues use the same), not SipHash: the keys are vertex ids, which no
//! adversary chooses, and an algorithm that rebuilds its morphs every frame (Röttger's) hashes
//! every morphing vertex of every frame.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A fast, fixed hash of vertex ids.
#[derive(Clone, Copy, Debug, Default)]
struct IdHasher {
    state: u64,
}

const ID_HASH_MULTIPLIER: u64 = 0x9e37_79b9_7f4a_7c15;

impl Hasher for IdHasher {
    fn finish(&self) -> u64 {
        // The product's high bits are its best mixed; fold them into the low bits, which pick
        // the bucket.
        self.state ^ (self.state >> 29)
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
        self.state = (self.state.rotate_left(5) ^ value).wrapping_mul(ID_HASH_MULTIPLIER);
    }
}

/// Heights of morphing vertices, by vertex id (the other vertices of the mesh keep their
/// sample's height). Heights are finite (`set` refuses others).
#[derive(Clone, Debug, Default)]
pub struct MorphedHeights {
    heights: HashMap<u32, f32, BuildHasherDefault<IdHasher>>,
}

impl MorphedHeights {
    pub fn new() -> MorphedHeights {
        MorphedHeights::default()
    }

    /// Forgets every morph (keeps the capacity).
    pub fn clear(&mut self) {
        self.heights.clear();
    }

    /// Draws vertex `id` at height `z` (terrain-local metres).
    ///
    /// # Panics
    /// When `z` is not finite: an algorithm that computes such a height has a bug.
    pub fn set(&mut self, id: u32, z: f32) {
        assert!(z.is_finite(), "morphed height {z} of vertex {id}");
        self.heights.insert(id, z);
    }

    /// Stops morphing vertex `id`.
    pub fn remove(&mut self, id: u32) {
        self.heights.remove(&id);
    }

    /// The height vertex `id` is drawn at, when it morphs.
    pub fn get(&self, id: u32) -> Option<f32> {
        self.heights.get(&id).copied()
    }

    /// The number of morphing vertices.
    pub fn len(&self) -> usize {
        self.heights.len()
    }

    pub fn is_empty(&self) -> bool {
        self.heights.is_empty()
    }

    /// Morphing vertex ids in increasing order (allocates; for validators and hashes).
    pub fn sorted_ids(&self) -> Vec<u32> {
        let mut ids: Vec<u32> = self.heights.keys().copied().collect();
        ids.sort_unstable();
        ids
    }

    /// Heap bytes held (the table's slots and control bytes).
    pub fn memory_bytes(&self) -> usize {
        self.heights.capacity() * (std::mem::size_of::<(u32, f32)>() + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_morph_is_found_until_it_is_removed_or_cleared() {
        let mut morphed = MorphedHeights::new();
        morphed.set(7, 1.5);
        morphed.set(3, -2.0);
        assert_eq!(morphed.get(7), Some(1.5));
        assert_eq!(morphed.get(8), None);
        assert_eq!(morphed.sorted_ids(), vec![3, 7]);
        morphed.remove(7);
        assert_eq!(morphed.len(), 1);
        morphed.clear();
        assert!(morphed.is_empty());
    }
}
