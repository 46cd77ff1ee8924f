//! A cache of chunks held in sibling groups of four (a quadtree node has four children or
//! none), with least-recently-used eviction (the paper's LRU cache, Lauritsen–Nielsen §3.2.14;
//! dynamic nodes "are also cached, just like the static node", §3.4.3): the synthesised chunks
//! of runtime detail, and the source chunks resident under out-of-core loading.
//!
//! Each entry remembers the frame it was last used and the frame it becomes available (a chunk
//! requested with a latency is held, its room reserved, before it can be drawn). A group is
//! evicted only when none of its chunks has children held and none was used in the current
//! frame or is still on its way (an entry's last use starts at its arrival frame). Iteration
//! and eviction follow chunk ids, so the cache is deterministic. Eviction is O(entries).

use super::tree::ChunkId;
use std::collections::BTreeMap;

/// The order of eviction: least recently used first, then the deeper group, then the lower
/// parent id.
type EvictionKey = (u64, std::cmp::Reverse<u32>, ChunkId);

/// One held chunk.
#[derive(Clone, Debug, PartialEq)]
struct Entry<T> {
    value: T,
    last_used: u64,
    available_from: u64,
}

/// Chunks held in sibling groups, with the frame the cache is at.
#[derive(Clone, Debug)]
pub(super) struct GroupCache<T> {
    entries: BTreeMap<ChunkId, Entry<T>>,
    /// The current frame: chunks arriving later are held but not available.
    now: u64,
}

impl<T> Default for GroupCache<T> {
    fn default() -> Self {
        GroupCache {
            entries: BTreeMap::new(),
            now: 0,
        }
    }
}

impl<T> GroupCache<T> {
    /// Bytes of one map entry besides what its value allocates (a B-tree's per-entry share is
    /// counted as the key and the entry).
    pub(super) const ENTRY_BYTES: usize = std::mem::size_of::<(ChunkId, Entry<T>)>();

    /// Moves the cache to `frame`: chunks due by then become available.
    pub(super) fn set_frame(&mut self, frame: u64) {
        self.now = frame;
    }

    /// The chunk `id` if held and available now.
    pub(super) fn get(&self, id: ChunkId) -> Option<&T> {
        self.entries
            .get(&id)
            .filter(|entry| entry.available_from <= self.now)
            .map(|entry| &entry.value)
    }

    /// The chunk `id` if held, available or on its way.
    pub(super) fn get_any(&self, id: ChunkId) -> Option<&T> {
        self.entries.get(&id).map(|entry| &entry.value)
    }

    /// The chunk `id` if held, available or on its way, to change it.
    pub(super) fn get_any_mut(&mut self, id: ChunkId) -> Option<&mut T> {
        self.entries.get_mut(&id).map(|entry| &mut entry.value)
    }

    /// Chunks held, available or on their way.
    pub(super) fn len(&self) -> usize {
        self.entries.len()
    }

    /// Chunks held that are still on their way.
    pub(super) fn in_flight(&self) -> usize {
        self.entries
            .values()
            .filter(|entry| entry.available_from > self.now)
            .count()
    }

    /// Marks `id` (if held) as used in `frame`.
    pub(super) fn touch(&mut self, id: ChunkId, frame: u64) {
        if let Some(entry) = self.entries.get_mut(&id) {
            entry.last_used = entry.last_used.max(frame);
        }
    }

    /// Holds `id`, made or requested in `frame`, available from `available_from`.
    pub(super) fn insert(&mut self, id: ChunkId, value: T, frame: u64, available_from: u64) {
        self.entries.insert(
            id,
            Entry {
                value,
                last_used: frame.max(available_from),
                available_from,
            },
        );
    }

    /// Evicts the least recently used sibling group none of whose chunks has children held and
    /// none of which was used in `frame` or is on its way; the chunks evicted (4), or 0 when no
    /// group can go. Ties: the deeper group first, then the lower parent id.
    pub(super) fn evict_one(&mut self, frame: u64) -> usize {
        let mut best: Option<(EvictionKey, ChunkId)> = None;
        for &id in self.entries.keys() {
            let Some(parent) = id.parent() else { continue };
            if id != parent.children()[0] {
                continue;
            }
            let mut last_used = 0;
            let mut evictable = true;
            for child in parent.children() {
                match self.entries.get(&child) {
                    Some(entry) => last_used = last_used.max(entry.last_used),
                    None => evictable = false,
                }
                if self.entries.contains_key(&child.children()[0]) {
                    evictable = false;
                }
            }
            if !evictable || last_used >= frame {
                continue;
            }
            let key = (last_used, std::cmp::Reverse(id.level), parent);
            if best.as_ref().is_none_or(|(best_key, _)| key < *best_key) {
                best = Some((key, parent));
            }
        }
        match best {
            Some((_, parent)) => {
                for child in parent.children() {
                    self.entries.remove(&child);
                }
                4
            }
            None => 0,
        }
    }

    /// The available chunks in id order.
    pub(super) fn iter(&self) -> impl Iterator<Item = (ChunkId, &T)> {
        self.entries
            .iter()
            .filter(|(_, entry)| entry.available_from <= self.now)
            .map(|(&id, entry)| (id, &entry.value))
    }

    /// Every chunk held, on its way or not, in id order.
    pub(super) fn iter_all(&self) -> impl Iterator<Item = (ChunkId, &T)> {
        self.entries.iter().map(|(&id, entry)| (id, &entry.value))
    }
}
