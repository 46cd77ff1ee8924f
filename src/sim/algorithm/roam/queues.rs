//! ROAM's two priority queues: leaf triangles to split, mergeable diamonds to merge.
//!
//! Priorities need a total order that does not depend on how the slot map happened to allocate
//! keys, so a [`QueueKey`] is the priority value (by `f64::total_cmp`) followed by a tie key
//! derived from grid coordinates only:
//! - a triangle: its split vertex id, then its apex id (two triangles share a split vertex, never
//!   an apex as well);
//! - a diamond: its split vertex id, then `u32::MAX`, so a diamond ranks at or above each of its
//!   parent triangles when their values are equal (its value is the larger of theirs). The
//!   oscillation guard in `mod.rs` relies on that.
//!
//! The split queue is a max-queue; the merge queue a min-queue (`Reverse`). Both are
//! `priority_queue::PriorityQueue`s: O(log n) push, pop and remove by key. Their index of keys is
//! hashed with [`KeyHasher`], a fixed multiplicative hash of the slot map key's two words, not
//! the standard library's SipHash (keyed against hostile input, which slot keys are not; the
//! profile showed it among ROAM's hot spots). Order never depends on the hash: only on
//! [`QueueKey`].

use super::bintree::TriangleKey;
use crate::sim::hierarchy::{GridPoint, Lattice};
use priority_queue::PriorityQueue;
use std::cmp::{Ordering, Reverse};
use std::hash::{BuildHasherDefault, Hasher};

/// A fast, fixed hash of slot map keys (two `u32` words): each word folded in by a rotate, xor
/// and multiply by an odd 64-bit constant (the Fx hash of rustc).
#[derive(Clone, Copy, Debug, Default)]
pub struct KeyHasher {
    state: u64,
}

const KEY_HASH_MULTIPLIER: u64 = 0x51_7c_c1_b7_27_22_0a_95;

impl KeyHasher {
    fn fold(&mut self, word: u64) {
        self.state = (self.state.rotate_left(5) ^ word).wrapping_mul(KEY_HASH_MULTIPLIER);
    }
}

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.state
    }

    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.fold(u64::from_le_bytes(word));
        }
    }

    fn write_u32(&mut self, value: u32) {
        self.fold(u64::from(value));
    }

    fn write_u64(&mut self, value: u64) {
        self.fold(value);
    }
}

type KeyHash = BuildHasherDefault<KeyHasher>;

/// A priority with its deterministic tie rule.
#[derive(Clone, Copy, Debug)]
pub struct QueueKey {
    /// The priority in pixels (+∞ for a wedgie reaching behind the near plane).
    pub value: f64,
    tie: u64,
}

impl QueueKey {
    /// The key of the triangle with split vertex `split` and apex `apex`.
    pub fn triangle(lattice: &Lattice, value: f64, split: GridPoint, apex: GridPoint) -> QueueKey {
        QueueKey {
            value,
            tie: (u64::from(lattice.id(split)) << 32) | u64::from(lattice.id(apex)),
        }
    }

    /// The key of the diamond split at `split`.
    pub fn diamond(lattice: &Lattice, value: f64, split: GridPoint) -> QueueKey {
        QueueKey {
            value,
            tie: (u64::from(lattice.id(split)) << 32) | u64::from(u32::MAX),
        }
    }
}

impl PartialEq for QueueKey {
    fn eq(&self, other: &QueueKey) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for QueueKey {}

impl PartialOrd for QueueKey {
    fn partial_cmp(&self, other: &QueueKey) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for QueueKey {
    fn cmp(&self, other: &QueueKey) -> Ordering {
        self.value
            .total_cmp(&other.value)
            .then(self.tie.cmp(&other.tie))
    }
}

/// The split queue (largest first) and the merge queue (smallest first). A diamond is queued
/// under its *primary* parent: of its one or two parent triangles, the one with the smaller
/// apex id.
#[derive(Default)]
pub struct Queues {
    pub split: PriorityQueue<TriangleKey, QueueKey, KeyHash>,
    pub merge: PriorityQueue<TriangleKey, Reverse<QueueKey>, KeyHash>,
}

impl Queues {
    pub fn clear(&mut self) {
        self.split.clear();
        self.merge.clear();
    }

    pub fn top_split(&self) -> Option<(TriangleKey, QueueKey)> {
        self.split.peek().map(|(k, p)| (*k, *p))
    }

    pub fn bottom_merge(&self) -> Option<(TriangleKey, QueueKey)> {
        self.merge.peek().map(|(k, p)| (*k, p.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_values_are_ordered_by_grid_position_and_diamonds_rank_above_their_parents() {
        let lattice = Lattice::new(3);
        let mid = GridPoint::new(4, 4);
        let a = QueueKey::triangle(&lattice, 1.0, mid, GridPoint::new(8, 0));
        let b = QueueKey::triangle(&lattice, 1.0, mid, GridPoint::new(0, 8));
        let diamond = QueueKey::diamond(&lattice, 1.0, mid);
        assert!(a < b);
        assert!(b < diamond);
        let infinite = QueueKey::triangle(&lattice, f64::INFINITY, GridPoint::new(2, 2), mid);
        assert!(infinite > diamond);
    }
}
