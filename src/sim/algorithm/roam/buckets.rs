//! Duchaineau's bucketed priority queue, made exact at its top: the default kind of ROAM's two
//! queues (`queues.rs`, SPEC §6's split and merge queues). It orders by [`QueueKey`] and nothing
//! else; what goes in and when is the core's (`core/`).
//!
//! Duchaineau's implementation notes for ROAM replace a heap by about 2048 buckets (his own code
//! uses 4096, log-spaced), each an unsorted doubly linked list; an element goes to the bucket of
//! its priority, and the queue tracks the highest (or lowest) non-empty bucket, scanning down
//! when it empties. Insertion, removal and a priority change are O(1). His queue is *approximate*:
//! any element of the top bucket counts as the top. Here the top bucket is scanned for its
//! largest [`QueueKey`] (smallest for a min-queue), so the queue gives exactly the element a heap
//! would; the meshes are those of the `priority-queue` heap, bit for bit, and deferral can keep
//! its promise of identical meshes (an approximate top would depend on the order elements were
//! re-bucketed, which deferral changes).
//!
//! **Buckets.** 4096 of them: bucket 0 holds priority 0 exactly, bucket 4095 holds +∞ (a wedgie
//! behind the near plane), and the 4094 between are log-spaced with 64 per octave, from 2⁻³² to
//! 2³² px (values outside are clamped into the end buckets, still exact). The index comes from the
//! bits of the `f64`, whose order is the order of positive values: no logarithm. Priorities 0 and
//! +∞ are common (culled and zero-thickness triangles, triangles behind the eye) and tie on their
//! value, so those two buckets are ordered maps by [`QueueKey`] (O(log n) there) rather than lists
//! to scan. A bitmap of non-empty buckets makes finding the next one a few word scans.
//!
//! Memory: one entry (key, bucket, two links: about 48 bytes) per slot of the bintree's slot map
//! ([`SecondaryMap`]), plus 4096 bucket heads.

use super::bintree::TriangleKey;
use super::queues::QueueKey;
use slotmap::SecondaryMap;
use std::collections::BTreeMap;

/// Number of buckets.
const N_BUCKETS: usize = 4096;
/// Log-spaced buckets per octave (2⁶).
const BUCKET_BITS_PER_OCTAVE: u32 = 6;
/// The bucket of priority 0.
const ZERO_BUCKET: u16 = 0;
/// The bucket of priority +∞.
const INFINITE_BUCKET: u16 = (N_BUCKETS - 1) as u16;

/// Which end of the queue is its top.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// The largest key first (the split queue).
    LargestFirst,
    /// The smallest key first (the merge queue).
    SmallestFirst,
}

#[derive(Clone, Copy, Debug)]
struct Entry {
    key: QueueKey,
    bucket: u16,
    prev: Option<TriangleKey>,
    next: Option<TriangleKey>,
}

/// An exact priority queue of triangle keys over log-spaced buckets.
pub struct BucketQueue {
    order: Order,
    entries: SecondaryMap<TriangleKey, Entry>,
    heads: Vec<Option<TriangleKey>>,
    occupied: Box<[u64; N_BUCKETS / 64]>,
    /// Buckets 0 and +∞, ordered.
    zero: BTreeMap<QueueKey, TriangleKey>,
    infinite: BTreeMap<QueueKey, TriangleKey>,
}

impl BucketQueue {
    pub fn new(order: Order) -> BucketQueue {
        BucketQueue {
            order,
            entries: SecondaryMap::new(),
            heads: vec![None; N_BUCKETS],
            occupied: Box::new([0; N_BUCKETS / 64]),
            zero: BTreeMap::new(),
            infinite: BTreeMap::new(),
        }
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn contains(&self, key: TriangleKey) -> bool {
        self.entries.contains_key(key)
    }

    pub fn priority(&self, key: TriangleKey) -> Option<QueueKey> {
        self.entries.get(key).map(|entry| entry.key)
    }

    /// Every queued element and its key, in slot order.
    pub fn iter(&self) -> impl Iterator<Item = (TriangleKey, QueueKey)> + '_ {
        self.entries.iter().map(|(k, entry)| (k, entry.key))
    }

    /// Appends every queued key to `out`, in slot order.
    pub fn keys_into(&self, out: &mut Vec<TriangleKey>) {
        out.extend(self.entries.keys());
    }

    pub fn clear(&mut self) {
        self.entries.clear();
        self.heads.fill(None);
        self.occupied.fill(0);
        self.zero.clear();
        self.infinite.clear();
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        let map_entry = size_of::<QueueKey>() + size_of::<TriangleKey>() + 3 * size_of::<usize>();
        self.entries.capacity() * (size_of::<Entry>() + size_of::<u32>())
            + self.heads.capacity() * size_of::<Option<TriangleKey>>()
            + (self.zero.len() + self.infinite.len()) * map_entry
    }

    /// Inserts `key` (or changes its priority if it is queued). O(1), O(log n) in the 0 and +∞
    /// buckets.
    pub fn push(&mut self, key: TriangleKey, priority: QueueKey) {
        let bucket = bucket_of(priority.value);
        if let Some(entry) = self.entries.get_mut(key) {
            if entry.key == priority {
                return;
            }
            if entry.bucket == bucket && !is_ordered(bucket) {
                entry.key = priority;
                return;
            }
            self.remove(key);
        }
        self.entries.insert(
            key,
            Entry {
                key: priority,
                bucket,
                prev: None,
                next: None,
            },
        );
        match bucket {
            ZERO_BUCKET => {
                self.zero.insert(priority, key);
            }
            INFINITE_BUCKET => {
                self.infinite.insert(priority, key);
            }
            _ => {
                let head = self.heads[bucket as usize];
                if let Some(head) = head {
                    self.entries[head].prev = Some(key);
                }
                self.entries[key].next = head;
                self.heads[bucket as usize] = Some(key);
            }
        }
        self.occupied[bucket as usize / 64] |= 1 << (bucket % 64);
    }

    /// Replaces every priority at once with `priorities`, which must hold every queued key
    /// exactly once (a full recomputation): the lists are rebuilt from empty, with no removal,
    /// so no element is unlinked from its old bucket. O(n + buckets).
    pub fn replace_all(&mut self, priorities: &[(TriangleKey, QueueKey)]) {
        assert_eq!(
            priorities.len(),
            self.entries.len(),
            "a full recomputation covers every queued element"
        );
        self.heads.fill(None);
        self.occupied.fill(0);
        let mut zero = Vec::new();
        let mut infinite = Vec::new();
        for &(key, priority) in priorities {
            let bucket = bucket_of(priority.value);
            let mut next = None;
            match bucket {
                ZERO_BUCKET => zero.push((priority, key)),
                INFINITE_BUCKET => infinite.push((priority, key)),
                _ => {
                    next = self.heads[bucket as usize];
                    if let Some(head) = next {
                        self.entries[head].prev = Some(key);
                    }
                    self.heads[bucket as usize] = Some(key);
                }
            }
            self.entries[key] = Entry {
                key: priority,
                bucket,
                prev: None,
                next,
            };
            self.occupied[bucket as usize / 64] |= 1 << (bucket % 64);
        }
        // Built in bulk from sorted runs rather than one insertion at a time.
        self.zero = zero.into_iter().collect();
        self.infinite = infinite.into_iter().collect();
    }

    /// Removes `key`; returns its priority if it was queued. O(1), O(log n) in the 0 and +∞
    /// buckets.
    pub fn remove(&mut self, key: TriangleKey) -> Option<QueueKey> {
        let entry = self.entries.remove(key)?;
        let bucket = entry.bucket as usize;
        let empty = match entry.bucket {
            ZERO_BUCKET => {
                self.zero.remove(&entry.key);
                self.zero.is_empty()
            }
            INFINITE_BUCKET => {
                self.infinite.remove(&entry.key);
                self.infinite.is_empty()
            }
            _ => {
                match entry.prev {
                    Some(prev) => self.entries[prev].next = entry.next,
                    None => self.heads[bucket] = entry.next,
                }
                if let Some(next) = entry.next {
                    self.entries[next].prev = entry.prev;
                }
                self.heads[bucket].is_none()
            }
        };
        if empty {
            self.occupied[bucket / 64] &= !(1 << (bucket % 64));
        }
        Some(entry.key)
    }

    /// The top element: the largest key (or smallest, by [`Order`]), exactly. O(occupied-bitmap
    /// words skipped + elements in the top bucket).
    pub fn peek(&self) -> Option<(TriangleKey, QueueKey)> {
        let bucket = match self.order {
            Order::LargestFirst => self.highest_occupied()?,
            Order::SmallestFirst => self.lowest_occupied()?,
        };
        let largest = self.order == Order::LargestFirst;
        match bucket {
            ZERO_BUCKET | INFINITE_BUCKET => {
                let map = if bucket == ZERO_BUCKET {
                    &self.zero
                } else {
                    &self.infinite
                };
                let (priority, key) = if largest {
                    map.last_key_value()?
                } else {
                    map.first_key_value()?
                };
                Some((*key, *priority))
            }
            _ => {
                let mut best: Option<(TriangleKey, QueueKey)> = None;
                let mut cursor = self.heads[bucket as usize];
                while let Some(key) = cursor {
                    let entry = &self.entries[key];
                    let better = best.is_none_or(|(_, b)| {
                        if largest {
                            entry.key > b
                        } else {
                            entry.key < b
                        }
                    });
                    if better {
                        best = Some((key, entry.key));
                    }
                    cursor = entry.next;
                }
                best
            }
        }
    }

    fn highest_occupied(&self) -> Option<u16> {
        (0..self.occupied.len()).rev().find_map(|word| {
            let bits = self.occupied[word];
            (bits != 0).then(|| (word * 64 + 63 - bits.leading_zeros() as usize) as u16)
        })
    }

    fn lowest_occupied(&self) -> Option<u16> {
        (0..self.occupied.len()).find_map(|word| {
            let bits = self.occupied[word];
            (bits != 0).then(|| (word * 64 + bits.trailing_zeros() as usize) as u16)
        })
    }
}

/// Whether a bucket is one of the two ordered ones.
fn is_ordered(bucket: u16) -> bool {
    bucket == ZERO_BUCKET || bucket == INFINITE_BUCKET
}

/// The bucket of a priority (≥ 0 or +∞): monotone in the value.
fn bucket_of(value: f64) -> u16 {
    if value <= 0.0 {
        return ZERO_BUCKET;
    }
    if value == f64::INFINITY {
        return INFINITE_BUCKET;
    }
    // The bits of a positive f64 are in the order of its value: exponent, then mantissa. Keep
    // the exponent and the top 6 mantissa bits: 64 buckets per octave.
    let shifted = (value.to_bits() >> (52 - BUCKET_BITS_PER_OCTAVE)) as i64;
    // 2^-32 (exponent 1023 − 32) maps to bucket 1.
    let lowest = i64::from(1023 - 32) << BUCKET_BITS_PER_OCTAVE;
    (shifted - lowest + 1).clamp(1, INFINITE_BUCKET as i64 - 1) as u16
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::hierarchy::{GridPoint, Lattice};
    use priority_queue::PriorityQueue;
    use slotmap::SlotMap;
    use std::cmp::Reverse;

    #[test]
    fn buckets_are_monotone_in_the_priority_with_64_per_octave() {
        let mut previous = 0;
        let mut value = 1e-12;
        while value < 1e12 {
            let bucket = bucket_of(value);
            assert!(bucket >= previous, "{value}");
            previous = bucket;
            value *= 1.003;
        }
        assert_eq!(bucket_of(0.0), ZERO_BUCKET);
        assert_eq!(bucket_of(f64::INFINITY), INFINITE_BUCKET);
        assert_eq!(bucket_of(2.0) - bucket_of(1.0), 64);
        assert!(bucket_of(f64::MIN_POSITIVE) >= 1);
        assert!(bucket_of(f64::MAX) < INFINITE_BUCKET);
    }

    /// Random pushes, changes and removals, with many ties at 0 and +∞, against the heap.
    #[test]
    fn the_top_is_always_the_heaps_top() {
        let lattice = Lattice::new(8);
        let mut slots: SlotMap<TriangleKey, ()> = SlotMap::with_key();
        let keys: Vec<TriangleKey> = (0..400).map(|_| slots.insert(())).collect();
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        };
        for order in [Order::LargestFirst, Order::SmallestFirst] {
            let mut buckets = BucketQueue::new(order);
            let mut max_heap: PriorityQueue<TriangleKey, QueueKey> = PriorityQueue::new();
            let mut min_heap: PriorityQueue<TriangleKey, Reverse<QueueKey>> = PriorityQueue::new();
            for step in 0..20_000 {
                let index = next() as usize % keys.len();
                let k = keys[index];
                let value = match next() % 6 {
                    0 => 0.0,
                    1 => f64::INFINITY,
                    2 => (next() % 5) as f64, // exact ties between finite values
                    _ => (next() % 1_000_000) as f64 * 1e-3,
                };
                // One tie key per element, as in the bintree.
                let split = GridPoint::new(index as u32 % 16, index as u32 / 16);
                let priority = QueueKey::triangle(&lattice, value, split, GridPoint::new(0, 0));
                if next() % 4 == 0 {
                    assert_eq!(buckets.remove(k), max_heap.remove(&k).map(|(_, p)| p));
                    min_heap.remove(&k);
                } else {
                    buckets.push(k, priority);
                    max_heap.push(k, priority);
                    min_heap.push(k, Reverse(priority));
                }
                let expected = match order {
                    Order::LargestFirst => max_heap.peek().map(|(k, p)| (*k, *p)),
                    Order::SmallestFirst => min_heap.peek().map(|(k, p)| (*k, p.0)),
                };
                let top = buckets.peek();
                assert_eq!(
                    top.map(|(_, p)| p),
                    expected.map(|(_, p)| p),
                    "{order:?}, step {step}"
                );
                assert_eq!(buckets.len(), max_heap.len());
            }
        }
    }
}
