//! ROAM's two priority queues (SPEC §6): leaf triangles to split, mergeable diamonds to merge,
//! and the total order both kinds share. What enters them and when is the core's (`core/`).
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
//! The split queue is a max-queue; the merge queue a min-queue. Two implementations give the same
//! order, chosen by [`QueueKind`]:
//! - `buckets` (the default): Duchaineau's bucketed queue, exact at its top (`buckets.rs`): O(1)
//!   insertion, removal and priority change, the top found by scanning its bucket;
//! - `heap`: `priority_queue::PriorityQueue`s, O(log n) push, pop and remove by key, their index
//!   of keys hashed with [`KeyHasher`], a fixed multiplicative hash of the slot map key's two
//!   words (not SipHash: every queue operation hashes, and the keys come from the slot map, not
//!   from outside, so they need no protection against crafted collisions).
//!
//! Order never depends on the hash or the buckets: only on [`QueueKey`], so both kinds give the
//! same meshes bit for bit (a test runs both side by side).

use super::bintree::TriangleKey;
use super::buckets::{BucketQueue, Order};
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
            tie: Self::triangle_tie(lattice, split, apex),
        }
    }

    /// The tie key of the triangle with split vertex `split` and apex `apex`.
    pub fn triangle_tie(lattice: &Lattice, split: GridPoint, apex: GridPoint) -> u64 {
        (u64::from(lattice.id(split)) << 32) | u64::from(lattice.id(apex))
    }

    /// A key with a tie computed before (see [`Self::triangle_tie`]).
    pub fn with_tie(value: f64, tie: u64) -> QueueKey {
        QueueKey { value, tie }
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

/// Which priority queue implementation ROAM runs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueueKind {
    /// Duchaineau's 4096 log-spaced buckets, exact at the top (the default).
    Buckets,
    /// The `priority-queue` crate's indexed binary heap.
    Heap,
}

/// One priority queue of triangle keys, largest or smallest first.
pub enum Queue {
    Buckets(BucketQueue),
    HeapLargestFirst(PriorityQueue<TriangleKey, QueueKey, KeyHash>),
    HeapSmallestFirst(PriorityQueue<TriangleKey, Reverse<QueueKey>, KeyHash>),
}

impl Queue {
    fn new(kind: QueueKind, order: Order) -> Queue {
        match (kind, order) {
            (QueueKind::Buckets, _) => Queue::Buckets(BucketQueue::new(order)),
            (QueueKind::Heap, Order::LargestFirst) => {
                Queue::HeapLargestFirst(PriorityQueue::default())
            }
            (QueueKind::Heap, Order::SmallestFirst) => {
                Queue::HeapSmallestFirst(PriorityQueue::default())
            }
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Queue::Buckets(q) => q.len(),
            Queue::HeapLargestFirst(q) => q.len(),
            Queue::HeapSmallestFirst(q) => q.len(),
        }
    }

    pub fn contains(&self, key: TriangleKey) -> bool {
        match self {
            Queue::Buckets(q) => q.contains(key),
            Queue::HeapLargestFirst(q) => q.contains(&key),
            Queue::HeapSmallestFirst(q) => q.contains(&key),
        }
    }

    pub fn priority(&self, key: TriangleKey) -> Option<QueueKey> {
        match self {
            Queue::Buckets(q) => q.priority(key),
            Queue::HeapLargestFirst(q) => q.get_priority(&key).copied(),
            Queue::HeapSmallestFirst(q) => q.get_priority(&key).map(|p| p.0),
        }
    }

    /// Inserts `key`, or changes its priority if it is queued.
    pub fn push(&mut self, key: TriangleKey, priority: QueueKey) {
        match self {
            Queue::Buckets(q) => q.push(key, priority),
            Queue::HeapLargestFirst(q) => {
                q.push(key, priority);
            }
            Queue::HeapSmallestFirst(q) => {
                q.push(key, Reverse(priority));
            }
        }
    }

    /// Replaces every priority at once (a full recomputation: `priorities` holds every queued
    /// key exactly once). O(n): the buckets are relinked from empty, the heap is rebuilt.
    pub fn replace_all(&mut self, priorities: &[(TriangleKey, QueueKey)]) {
        match self {
            Queue::Buckets(q) => q.replace_all(priorities),
            Queue::HeapLargestFirst(q) => {
                q.clear();
                q.extend(priorities.iter().copied());
            }
            Queue::HeapSmallestFirst(q) => {
                q.clear();
                q.extend(priorities.iter().map(|&(k, p)| (k, Reverse(p))));
            }
        }
    }

    /// Removes `key`; returns its priority if it was queued.
    pub fn remove(&mut self, key: TriangleKey) -> Option<QueueKey> {
        match self {
            Queue::Buckets(q) => q.remove(key),
            Queue::HeapLargestFirst(q) => q.remove(&key).map(|(_, p)| p),
            Queue::HeapSmallestFirst(q) => q.remove(&key).map(|(_, p)| p.0),
        }
    }

    /// The first element (largest or smallest key).
    pub fn peek(&self) -> Option<(TriangleKey, QueueKey)> {
        match self {
            Queue::Buckets(q) => q.peek(),
            Queue::HeapLargestFirst(q) => q.peek().map(|(k, p)| (*k, *p)),
            Queue::HeapSmallestFirst(q) => q.peek().map(|(k, p)| (*k, p.0)),
        }
    }

    /// Appends every queued key to `out`.
    pub fn keys_into(&self, out: &mut Vec<TriangleKey>) {
        match self {
            Queue::Buckets(q) => q.keys_into(out),
            Queue::HeapLargestFirst(q) => out.extend(q.iter().map(|(k, _)| *k)),
            Queue::HeapSmallestFirst(q) => out.extend(q.iter().map(|(k, _)| *k)),
        }
    }

    /// Every queued key with its priority.
    pub fn entries(&self) -> Vec<(TriangleKey, QueueKey)> {
        match self {
            Queue::Buckets(q) => q.iter().collect(),
            Queue::HeapLargestFirst(q) => q.iter().map(|(k, p)| (*k, *p)).collect(),
            Queue::HeapSmallestFirst(q) => q.iter().map(|(k, p)| (*k, p.0)).collect(),
        }
    }

    pub fn clear(&mut self) {
        match self {
            Queue::Buckets(q) => q.clear(),
            Queue::HeapLargestFirst(q) => q.clear(),
            Queue::HeapSmallestFirst(q) => q.clear(),
        }
    }

    /// Heap bytes held (the heap's index estimated from its length and element sizes).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        let heap_entry = size_of::<TriangleKey>() + size_of::<QueueKey>() + 3 * size_of::<usize>();
        match self {
            Queue::Buckets(q) => q.memory_bytes(),
            Queue::HeapLargestFirst(q) => q.capacity() * heap_entry,
            Queue::HeapSmallestFirst(q) => q.capacity() * heap_entry,
        }
    }
}

/// The split queue (largest first) and the merge queue (smallest first). A diamond is queued
/// under its *primary* parent: of its one or two parent triangles, the one with the smaller
/// apex id.
pub struct Queues {
    pub split: Queue,
    pub merge: Queue,
}

impl Queues {
    pub fn new(kind: QueueKind) -> Queues {
        Queues {
            split: Queue::new(kind, Order::LargestFirst),
            merge: Queue::new(kind, Order::SmallestFirst),
        }
    }

    pub fn clear(&mut self) {
        self.split.clear();
        self.merge.clear();
    }

    pub fn top_split(&self) -> Option<(TriangleKey, QueueKey)> {
        self.split.peek()
    }

    pub fn bottom_merge(&self) -> Option<(TriangleKey, QueueKey)> {
        self.merge.peek()
    }

    pub fn memory_bytes(&self) -> usize {
        self.split.memory_bytes() + self.merge.memory_bytes()
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
