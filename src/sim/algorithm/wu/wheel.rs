//! Wu's split, merge and view queues: timing wheels of linked links (Wu et al. 2001 §6, "the
//! data structure of split and merge queue are all defined as arrays" of links; SPEC §5, a
//! timing wheel with a rotating head, not a heap). The wheels only hold nodes; keys and what to
//! do when a link comes due are the frame loop's (`mod.rs`).
//!
//! The split queue holds splittable nodes, the merge queue mergeable ones; the view queue, kept
//! only when Wu tracks the view cone, holds the other active nodes, each due when its view may
//! change (`visibility.rs`). Each queue is an array of `W` links indexed by frame modulo `W` (the
//! head is the link of the current frame, so it rotates once per frame and nothing is decremented
//! node by node), plus an **overflow** link for keys of `W` frames or more, re-examined whenever
//! the wheel wraps, and a **parked** link for infinite keys (nodes without error, or a zero speed
//! bound), which is only re-examined when the speed bounds were broken. A node is in at most one
//! link of one queue.
//!
//! **Memory.** Only queued nodes (the frontier: splittable and mergeable nodes, O(mesh size)) hold
//! a link entry (node, next, slot: 12 bytes) in a slab whose freed entries are reused; every node
//! holds a 4-byte handle to its entry. That is 4 bytes per node (a node per 3 samples) plus 12
//! bytes per queued node at the peak, instead of 12 bytes of intrusive links per node.
//!
//! **Singly linked, removal by tombstone.** A link is a singly linked list, new nodes at its
//! front. Removing a node marks its entry dead and drops its handle; the entry stays in its link
//! until the link is taken, deferred or compacted, which frees it. So an insertion writes its own
//! entry and the link's head, and a removal its own entry and handle: neither touches a
//! neighbouring entry (a doubly linked list wrote the old front's `prev` on every insertion and
//! both neighbours on every removal, three scattered cache lines over the slab; issue #31 item 6,
//! `docs/performance.md`). Every walk skips dead entries, so what a link hands out, and in which
//! order, is what a doubly linked list would hand out. A link whose dead entries outnumber its
//! live ones is compacted at once (O(its length), paid for by the removals that made them), so
//! the slab holds at most two entries per queued node, plus the free ones.
//!
//! Insertion and removal are O(1) (amortised, with compaction); taking a link empties it in O(its
//! length). Only the slab grows (by doubling, amortised O(1)), to the largest number of entries
//! held at once rounded up to a power of two.

use super::nodes::NO_NODE;

/// Which queue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Queue {
    Split,
    Merge,
    /// Active nodes that are not mergeable, queued by their view keys only.
    View,
}

impl Queue {
    const ALL: [Queue; 3] = [Queue::Split, Queue::Merge, Queue::View];

    fn index(self) -> u32 {
        match self {
            Queue::Split => 0,
            Queue::Merge => 1,
            Queue::View => 2,
        }
    }

    fn from_index(index: u32) -> Queue {
        Queue::ALL[index as usize]
    }
}

/// Where a node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Slot {
    pub queue: Queue,
    pub link: u32,
}

/// Sentinel for "no entry" (end of a link, an unqueued node, an empty free list).
const NO_ENTRY: u32 = u32::MAX;
/// A slot is the link number with the queue's index in its top two bits and a mark below them
/// (links < 2^29).
const QUEUE_SHIFT: u32 = 30;
const MARK_BIT: u32 = 1 << 29;
const LINK_MASK: u32 = MARK_BIT - 1;

/// One queued node's place in its link. `next` is an entry index. A dead entry (its node
/// removed, the entry not yet unlinked) has `node` [`NO_NODE`].
#[derive(Clone, Copy, Debug)]
struct Entry {
    node: u32,
    next: u32,
    /// The link, with the queue's index above [`QUEUE_SHIFT`] and the caller's mark in
    /// [`MARK_BIT`]. For a free entry, unused.
    slot: u32,
}

impl Entry {
    fn is_dead(&self) -> bool {
        self.node == NO_NODE
    }
}

/// The three queues over the same nodes.
pub(super) struct Wheels {
    n_links: u32,
    /// First entry of each link: split links, then merge links, then view links; each queue has
    /// `n_links` wheel links, then overflow, then parked.
    heads: Vec<u32>,
    /// Live nodes in each link.
    counts: Vec<u32>,
    /// Dead entries still in each link (at most its live count, see [`Wheels::remove`]).
    dead: Vec<u32>,
    /// Nodes in each queue.
    totals: [u64; 3],
    /// Per node, its entry, or [`NO_ENTRY`] when it is not queued.
    entry_of: Vec<u32>,
    /// The entries of queued nodes, dead entries not yet unlinked, and free ones chained through
    /// `next` from `free`.
    entries: Vec<Entry>,
    free: u32,
}

impl Wheels {
    /// Empty queues over `n_nodes` nodes with `n_links` wheel links each (n_links ≥ 2).
    pub fn new(n_nodes: usize, n_links: u32) -> Wheels {
        assert!(
            n_links + 2 <= LINK_MASK,
            "{n_links} links do not fit a slot"
        );
        let per_queue = (n_links + 2) as usize;
        Wheels {
            n_links,
            heads: vec![NO_ENTRY; 3 * per_queue],
            counts: vec![0; 3 * per_queue],
            dead: vec![0; 3 * per_queue],
            totals: [0; 3],
            entry_of: vec![NO_ENTRY; n_nodes],
            entries: Vec::new(),
            free: NO_ENTRY,
        }
    }

    /// Heap bytes held (capacities, not lengths).
    pub fn memory_bytes(&self) -> usize {
        (self.heads.capacity()
            + self.counts.capacity()
            + self.dead.capacity()
            + self.entry_of.capacity())
            * std::mem::size_of::<u32>()
            + self.entries.capacity() * std::mem::size_of::<Entry>()
    }

    pub fn n_links(&self) -> u32 {
        self.n_links
    }

    pub fn overflow_link(&self) -> u32 {
        self.n_links
    }

    pub fn parked_link(&self) -> u32 {
        self.n_links + 1
    }

    fn head_index(&self, queue: Queue, link: u32) -> usize {
        (queue.index() * (self.n_links + 2) + link) as usize
    }

    fn head_index_of_slot(&self, raw: u32) -> usize {
        self.head_index(Queue::from_index(raw >> QUEUE_SHIFT), raw & LINK_MASK)
    }

    pub fn slot(&self, node: u32) -> Option<Slot> {
        let entry = self.entry_of[node as usize];
        (entry != NO_ENTRY).then(|| {
            let raw = self.entries[entry as usize].slot;
            Slot {
                queue: Queue::from_index(raw >> QUEUE_SHIFT),
                link: raw & LINK_MASK,
            }
        })
    }

    pub fn is_in(&self, node: u32, queue: Queue) -> bool {
        self.slot(node).is_some_and(|s| s.queue == queue)
    }

    /// Puts `node` (not queued) at the front of a link.
    pub fn insert(&mut self, node: u32, queue: Queue, link: u32) {
        self.insert_marked(node, queue, link, false);
    }

    /// Puts `node` (not queued) at the front of a link with a mark that [`Wheels::defer`]
    /// gives back (Wu marks the merge entries that came due by a view key).
    pub fn insert_marked(&mut self, node: u32, queue: Queue, link: u32, marked: bool) {
        debug_assert_eq!(
            self.entry_of[node as usize], NO_ENTRY,
            "node {node} queued twice"
        );
        let h = self.head_index(queue, link);
        let entry = Entry {
            node,
            next: self.heads[h],
            slot: link | (queue.index() << QUEUE_SHIFT) | if marked { MARK_BIT } else { 0 },
        };
        let e = self.allocate(entry);
        self.heads[h] = e;
        self.counts[h] += 1;
        self.totals[queue.index() as usize] += 1;
        self.entry_of[node as usize] = e;
    }

    /// Takes `node` out of whatever link holds it; returns where it was. Its entry stays in the
    /// link, dead, until the link is walked; a link whose dead entries now outnumber its live
    /// ones is compacted.
    pub fn remove(&mut self, node: u32) -> Option<Slot> {
        let e = self.entry_of[node as usize];
        if e == NO_ENTRY {
            return None;
        }
        let entry = &mut self.entries[e as usize];
        let raw = entry.slot;
        entry.node = NO_NODE;
        let slot = Slot {
            queue: Queue::from_index(raw >> QUEUE_SHIFT),
            link: raw & LINK_MASK,
        };
        let h = self.head_index(slot.queue, slot.link);
        self.counts[h] -= 1;
        self.dead[h] += 1;
        self.totals[slot.queue.index() as usize] -= 1;
        self.entry_of[node as usize] = NO_ENTRY;
        if self.dead[h] > self.counts[h] {
            self.compact(h);
        }
        Some(slot)
    }

    /// Moves `node` from whatever queue holds it to the same link of `queue`: the link comes due
    /// when it did, which stays safe when the new queue's key is no sooner than the old one's.
    pub fn move_to_queue(&mut self, node: u32, queue: Queue) {
        if let Some(slot) = self.remove(node) {
            self.insert(node, queue, slot.link);
        }
    }

    /// Unlinks and frees the dead entries of a link, keeping its live ones in order.
    fn compact(&mut self, h: usize) {
        let mut last_live = NO_ENTRY;
        let mut e = self.heads[h];
        self.heads[h] = NO_ENTRY;
        while e != NO_ENTRY {
            let Entry { next, .. } = self.entries[e as usize];
            if self.entries[e as usize].is_dead() {
                self.release(e);
            } else {
                self.entries[e as usize].next = NO_ENTRY;
                if last_live == NO_ENTRY {
                    self.heads[h] = e;
                } else {
                    self.entries[last_live as usize].next = e;
                }
                last_live = e;
            }
            e = next;
        }
        self.dead[h] = 0;
    }

    /// An entry from the free list (growing the slab when it is empty), holding `entry`.
    fn allocate(&mut self, entry: Entry) -> u32 {
        if self.free == NO_ENTRY {
            self.grow();
        }
        let e = self.free;
        let free_entry = &mut self.entries[e as usize];
        self.free = free_entry.next;
        *free_entry = entry;
        e
    }

    /// Doubles the slab (at least 64 entries) and chains the new entries into the free list.
    #[cold]
    #[inline(never)]
    fn grow(&mut self) {
        let old_len = self.entries.len();
        let new_len = (2 * old_len).max(64);
        assert!(
            new_len < NO_ENTRY as usize,
            "more queued nodes than entry indices"
        );
        self.entries.reserve_exact(new_len - old_len);
        // The free list is empty: chain the new entries in order, the last ending it.
        for e in old_len + 1..=new_len {
            let next = if e == new_len { NO_ENTRY } else { e as u32 };
            self.entries.push(Entry {
                node: NO_NODE,
                next,
                slot: 0,
            });
        }
        self.free = old_len as u32;
    }

    /// Returns an entry to the free list.
    fn release(&mut self, e: u32) {
        self.entries[e as usize] = Entry {
            node: NO_NODE,
            next: self.free,
            slot: 0,
        };
        self.free = e;
    }

    /// Empties a link into `out` (front to back), leaving its nodes unqueued.
    pub fn take_link(&mut self, queue: Queue, link: u32, out: &mut Vec<u32>) {
        self.drain_link(queue, link, |node| out.push(node));
    }

    /// Moves every node of link `from` to the front of link `to` of the same queue, marked when
    /// `mark`, and hands the nodes that were marked to `marked` (front to back): the same links
    /// as taking `from` and inserting its nodes one by one, front to back, at the front of `to`
    /// (so `from`'s nodes end up reversed before `to`'s), in one walk that allocates no entry
    /// (it frees `from`'s dead ones). O(the link's length), a few instructions a node.
    pub fn defer(&mut self, queue: Queue, from: u32, to: u32, mark: bool, marked: &mut Vec<u32>) {
        let (h_from, h_to) = (self.head_index(queue, from), self.head_index(queue, to));
        let slot = to | (queue.index() << QUEUE_SHIFT) | if mark { MARK_BIT } else { 0 };
        let mut front = self.heads[h_to];
        let mut e = self.heads[h_from];
        while e != NO_ENTRY {
            let entry = &mut self.entries[e as usize];
            let next = entry.next;
            if entry.is_dead() {
                self.release(e);
                e = next;
                continue;
            }
            if entry.slot & MARK_BIT != 0 {
                marked.push(entry.node);
            }
            entry.slot = slot;
            entry.next = front;
            front = e;
            e = next;
        }
        self.heads[h_to] = front;
        self.counts[h_to] += self.counts[h_from];
        self.heads[h_from] = NO_ENTRY;
        self.counts[h_from] = 0;
        self.dead[h_from] = 0;
    }

    /// Empties a link, front to back, handing each live node to `each` and freeing every entry.
    fn drain_link(&mut self, queue: Queue, link: u32, mut each: impl FnMut(u32)) {
        let h = self.head_index(queue, link);
        let mut e = self.heads[h];
        while e != NO_ENTRY {
            let Entry { node, next, .. } = self.entries[e as usize];
            if node != NO_NODE {
                each(node);
                self.entry_of[node as usize] = NO_ENTRY;
            }
            self.release(e);
            e = next;
        }
        self.totals[queue.index() as usize] -= u64::from(self.counts[h]);
        self.heads[h] = NO_ENTRY;
        self.counts[h] = 0;
        self.dead[h] = 0;
    }

    /// Nodes in a queue (all links). O(1).
    pub fn len(&self, queue: Queue) -> u64 {
        self.totals[queue.index() as usize]
    }

    pub fn link_len(&self, queue: Queue, link: u32) -> u32 {
        self.counts[self.head_index(queue, link)]
    }

    /// Checks the link structure itself: handles and slots agree with membership, live and dead
    /// counts agree with a recount and dead entries never outnumber live ones in a link, every
    /// entry is linked or free. Returns the first inconsistency.
    pub fn check_structure(&self) -> Result<(), String> {
        let mut seen = vec![false; self.entry_of.len()];
        let mut linked_entries = 0usize;
        for queue in Queue::ALL {
            let mut n_in_queue = 0u64;
            for link in 0..self.n_links + 2 {
                let h = self.head_index(queue, link);
                let mut e = self.heads[h];
                let (mut n_linked, mut n_dead) = (0u32, 0u32);
                while e != NO_ENTRY {
                    let Some(entry) = self.entries.get(e as usize) else {
                        return Err(format!("{queue:?} link {link}: entry {e} out of range"));
                    };
                    if n_linked as usize + n_dead as usize > self.entries.len() {
                        return Err(format!("{queue:?} link {link}: a cycle"));
                    }
                    e = entry.next;
                    if entry.is_dead() {
                        n_dead += 1;
                        continue;
                    }
                    let node = entry.node;
                    if seen.get(node as usize).copied().unwrap_or(true) {
                        return Err(format!("node {node} is linked twice or out of range"));
                    }
                    seen[node as usize] = true;
                    if self.entry_of[node as usize] == NO_ENTRY
                        || self.entries[self.entry_of[node as usize] as usize].node != node
                    {
                        return Err(format!("node {node}: handle does not name its entry"));
                    }
                    if self.head_index_of_slot(entry.slot) != h {
                        return Err(format!(
                            "node {node} is in {queue:?} link {link} but its slot says {:?}",
                            self.slot(node)
                        ));
                    }
                    n_linked += 1;
                }
                if n_linked != self.link_len(queue, link) {
                    return Err(format!(
                        "{queue:?} link {link}: count {} but {n_linked} nodes linked",
                        self.link_len(queue, link),
                    ));
                }
                if n_dead != self.dead[h] || n_dead > n_linked {
                    return Err(format!(
                        "{queue:?} link {link}: {n_dead} dead entries (recorded {}) for \
                         {n_linked} live ones",
                        self.dead[h]
                    ));
                }
                linked_entries += n_linked as usize + n_dead as usize;
                n_in_queue += u64::from(n_linked);
            }
            if n_in_queue != self.len(queue) {
                return Err(format!(
                    "{queue:?}: total {} but {n_in_queue} nodes linked",
                    self.len(queue)
                ));
            }
        }
        for (node, &e) in self.entry_of.iter().enumerate() {
            if e != NO_ENTRY && !seen[node] {
                return Err(format!("node {node} has an entry but is in no link"));
            }
        }
        let mut n_free = 0usize;
        let mut e = self.free;
        while e != NO_ENTRY && n_free <= self.entries.len() {
            n_free += 1;
            e = self.entries[e as usize].next;
        }
        if linked_entries + n_free != self.entries.len() {
            return Err(format!(
                "{} entries but {linked_entries} linked and {n_free} free",
                self.entries.len()
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insert_remove_and_take_keep_the_links_consistent() {
        let mut wheels = Wheels::new(10, 4);
        for node in 0..6 {
            wheels.insert(node, Queue::Split, node % 3);
        }
        wheels.insert(7, Queue::Merge, wheels.overflow_link());
        wheels.check_structure().unwrap();
        assert_eq!(wheels.len(Queue::Split), 6);
        assert_eq!(
            wheels.remove(4),
            Some(Slot {
                queue: Queue::Split,
                link: 1
            })
        );
        assert_eq!(wheels.remove(4), None);
        wheels.check_structure().unwrap();
        let mut taken = Vec::new();
        wheels.take_link(Queue::Split, 0, &mut taken);
        assert_eq!(taken, vec![3, 0]);
        assert_eq!(wheels.len(Queue::Split), 3);
        assert_eq!(wheels.len(Queue::Merge), 1);
        assert!(wheels.is_in(7, Queue::Merge));
        wheels.check_structure().unwrap();
    }

    #[test]
    fn deferring_a_link_leaves_the_links_that_taking_and_reinserting_it_leaves() {
        // Both ways: link 1 of the merge queue (some entries marked) onto link 2, which already
        // holds nodes. The links, their order and the marks handed back must be the same.
        let fill = |wheels: &mut Wheels| {
            for node in 0..5 {
                wheels.insert_marked(node, Queue::Merge, 1, node % 2 == 0);
            }
            wheels.insert(8, Queue::Merge, 2);
            wheels.insert(9, Queue::Merge, 2);
        };
        let mut by_hand = Wheels::new(10, 4);
        fill(&mut by_hand);
        let mut taken = Vec::new();
        let mut marked_by_hand = Vec::new();
        let h = by_hand.head_index(Queue::Merge, 1);
        let mut e = by_hand.heads[h];
        while e != NO_ENTRY {
            let entry = by_hand.entries[e as usize];
            if !entry.is_dead() && entry.slot & MARK_BIT != 0 {
                marked_by_hand.push(entry.node);
            }
            e = entry.next;
        }
        by_hand.take_link(Queue::Merge, 1, &mut taken);
        for &node in &taken {
            by_hand.insert_marked(node, Queue::Merge, 2, true);
        }
        let mut deferred = Wheels::new(10, 4);
        fill(&mut deferred);
        let mut marked = Vec::new();
        deferred.defer(Queue::Merge, 1, 2, true, &mut marked);
        deferred.check_structure().unwrap();
        assert_eq!(marked, marked_by_hand);
        assert_eq!(marked, vec![4, 2, 0]);
        for wheels in [&mut by_hand, &mut deferred] {
            assert_eq!(wheels.link_len(Queue::Merge, 1), 0);
            assert_eq!(wheels.len(Queue::Merge), 7);
        }
        let (mut a, mut b) = (Vec::new(), Vec::new());
        by_hand.take_marked_for_test(Queue::Merge, 2, &mut a);
        deferred.take_marked_for_test(Queue::Merge, 2, &mut b);
        assert_eq!(a, b);
        assert_eq!(
            b.iter().map(|&(n, _)| n).collect::<Vec<_>>(),
            [0, 1, 2, 3, 4, 9, 8]
        );
    }

    impl Wheels {
        /// A link's nodes, front to back, with their marks, emptying it.
        fn take_marked_for_test(&mut self, queue: Queue, link: u32, out: &mut Vec<(u32, bool)>) {
            let h = self.head_index(queue, link);
            let mut e = self.heads[h];
            while e != NO_ENTRY {
                let entry = self.entries[e as usize];
                if !entry.is_dead() {
                    out.push((entry.node, entry.slot & MARK_BIT != 0));
                }
                e = entry.next;
            }
            let mut nodes = Vec::new();
            self.take_link(queue, link, &mut nodes);
        }
    }

    #[test]
    fn removed_nodes_leave_the_links_in_the_order_a_doubly_linked_list_keeps() {
        // Link 0 of the split queue front to back: 9 8 7 6 5 4 3 2 1 0. Removing 8, 5 and 0
        // leaves their entries dead in the link; removing four more makes the dead outnumber the
        // live ones on the way, which compacts it. Deferring and taking hand out the live nodes in order.
        let mut wheels = Wheels::new(16, 4);
        for node in 0..10 {
            wheels.insert(node, Queue::Split, 0);
        }
        for node in [8, 5, 0] {
            wheels.remove(node);
        }
        wheels.check_structure().unwrap();
        assert_eq!(wheels.dead[wheels.head_index(Queue::Split, 0)], 3);
        assert_eq!(wheels.link_len(Queue::Split, 0), 7);
        for node in [9, 2, 4, 6] {
            wheels.remove(node);
        }
        wheels.check_structure().unwrap();
        assert_eq!(wheels.link_len(Queue::Split, 0), 3);
        assert!(wheels.dead[wheels.head_index(Queue::Split, 0)] <= 3);
        wheels.insert(11, Queue::Split, 1);
        wheels.insert(12, Queue::Split, 1);
        wheels.remove(11);
        let mut marked = Vec::new();
        wheels.defer(Queue::Split, 0, 1, false, &mut marked);
        wheels.check_structure().unwrap();
        let mut taken = Vec::new();
        wheels.take_link(Queue::Split, 1, &mut taken);
        // 0's live nodes 7 3 1 reversed before 1's live node 12.
        assert_eq!(taken, vec![1, 3, 7, 12]);
        assert_eq!(wheels.len(Queue::Split), 0);
        wheels.check_structure().unwrap();
    }

    #[test]
    fn the_slab_grows_only_to_the_most_nodes_queued_at_once() {
        let mut wheels = Wheels::new(1000, 8);
        let mut taken = Vec::new();
        for round in 0..50u32 {
            for node in 0..20 {
                let queue = if node % 2 == 0 {
                    Queue::Split
                } else {
                    Queue::Merge
                };
                wheels.insert(round * 20 + node, queue, (round + node) % 8);
            }
            wheels.check_structure().unwrap();
            for node in (0..20).step_by(3) {
                wheels.remove(round * 20 + node);
            }
            wheels.check_structure().unwrap();
            for link in 0..8 {
                wheels.take_link(Queue::Split, link, &mut taken);
                wheels.take_link(Queue::Merge, link, &mut taken);
            }
            assert_eq!(wheels.len(Queue::Split) + wheels.len(Queue::Merge), 0);
        }
        assert_eq!(taken.len(), 50 * 13);
        // At most 20 nodes were queued at once: the slab never grew past its first 64 entries.
        assert!(
            wheels.entries.capacity() <= 64,
            "{}",
            wheels.entries.capacity()
        );
        wheels.check_structure().unwrap();
    }
}
