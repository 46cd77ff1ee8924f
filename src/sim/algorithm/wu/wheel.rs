//! The split and merge queues: timing wheels of intrusive doubly linked links.
//!
//! Each queue is an array of `W` links indexed by frame modulo `W` (the head is the link of the
//! current frame, so it rotates once per frame and nothing is decremented node by node), plus an
//! **overflow** link for keys of `W` frames or more, re-examined whenever the wheel wraps, and a
//! **parked** link for infinite keys (nodes without error, or a zero speed bound), which is only
//! re-examined when the speed bounds were broken. A node is in at most one link of one queue; the
//! per-node `prev`/`next`/`slot` arrays (12 bytes per node) make insertion and removal O(1).
//! Taking a link empties it in O(its length).

use super::nodes::NO_NODE;

/// Which queue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Queue {
    Split,
    Merge,
}

/// Where a node is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Slot {
    pub queue: Queue,
    pub link: u32,
}

const NOT_QUEUED: u32 = u32::MAX;
const MERGE_BIT: u32 = 1 << 31;

/// Both queues over the same nodes.
pub(super) struct Wheels {
    n_links: u32,
    /// First node of each link: split links, then merge links; each queue has `n_links` wheel
    /// links, then overflow, then parked.
    heads: Vec<u32>,
    counts: Vec<u32>,
    prev: Vec<u32>,
    next: Vec<u32>,
    slot: Vec<u32>,
}

impl Wheels {
    /// Empty queues over `n_nodes` nodes with `n_links` wheel links each (n_links ≥ 2).
    pub fn new(n_nodes: usize, n_links: u32) -> Wheels {
        let per_queue = (n_links + 2) as usize;
        Wheels {
            n_links,
            heads: vec![NO_NODE; 2 * per_queue],
            counts: vec![0; 2 * per_queue],
            prev: vec![NO_NODE; n_nodes],
            next: vec![NO_NODE; n_nodes],
            slot: vec![NOT_QUEUED; n_nodes],
        }
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        (self.heads.capacity()
            + self.counts.capacity()
            + self.prev.capacity()
            + self.next.capacity()
            + self.slot.capacity())
            * std::mem::size_of::<u32>()
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
        let base = match queue {
            Queue::Split => 0,
            Queue::Merge => self.n_links + 2,
        };
        (base + link) as usize
    }

    pub fn slot(&self, node: u32) -> Option<Slot> {
        let raw = self.slot[node as usize];
        (raw != NOT_QUEUED).then_some(Slot {
            queue: if raw & MERGE_BIT != 0 {
                Queue::Merge
            } else {
                Queue::Split
            },
            link: raw & !MERGE_BIT,
        })
    }

    pub fn is_in(&self, node: u32, queue: Queue) -> bool {
        self.slot(node).is_some_and(|s| s.queue == queue)
    }

    /// Puts `node` (not queued) at the front of a link.
    pub fn insert(&mut self, node: u32, queue: Queue, link: u32) {
        debug_assert_eq!(
            self.slot[node as usize], NOT_QUEUED,
            "node {node} queued twice"
        );
        let h = self.head_index(queue, link);
        let first = self.heads[h];
        self.next[node as usize] = first;
        self.prev[node as usize] = NO_NODE;
        if first != NO_NODE {
            self.prev[first as usize] = node;
        }
        self.heads[h] = node;
        self.counts[h] += 1;
        self.slot[node as usize] = match queue {
            Queue::Split => link,
            Queue::Merge => link | MERGE_BIT,
        };
    }

    /// Takes `node` out of whatever link holds it; returns where it was.
    pub fn remove(&mut self, node: u32) -> Option<Slot> {
        let slot = self.slot(node)?;
        let h = self.head_index(slot.queue, slot.link);
        let (prev, next) = (self.prev[node as usize], self.next[node as usize]);
        if prev == NO_NODE {
            self.heads[h] = next;
        } else {
            self.next[prev as usize] = next;
        }
        if next != NO_NODE {
            self.prev[next as usize] = prev;
        }
        self.counts[h] -= 1;
        self.slot[node as usize] = NOT_QUEUED;
        self.prev[node as usize] = NO_NODE;
        self.next[node as usize] = NO_NODE;
        Some(slot)
    }

    /// Empties a link into `out` (front to back), leaving its nodes unqueued.
    pub fn take_link(&mut self, queue: Queue, link: u32, out: &mut Vec<u32>) {
        let h = self.head_index(queue, link);
        let mut node = self.heads[h];
        while node != NO_NODE {
            out.push(node);
            let next = self.next[node as usize];
            self.slot[node as usize] = NOT_QUEUED;
            self.prev[node as usize] = NO_NODE;
            self.next[node as usize] = NO_NODE;
            node = next;
        }
        self.heads[h] = NO_NODE;
        self.counts[h] = 0;
    }

    /// Nodes in a queue (all links).
    pub fn len(&self, queue: Queue) -> u64 {
        let start = self.head_index(queue, 0);
        self.counts[start..start + (self.n_links + 2) as usize]
            .iter()
            .map(|&c| u64::from(c))
            .sum()
    }

    pub fn link_len(&self, queue: Queue, link: u32) -> u32 {
        self.counts[self.head_index(queue, link)]
    }

    /// The nodes of a link, front to back (for validation).
    pub fn link_nodes(&self, queue: Queue, link: u32) -> Vec<u32> {
        let mut nodes = Vec::new();
        let mut node = self.heads[self.head_index(queue, link)];
        while node != NO_NODE {
            nodes.push(node);
            node = self.next[node as usize];
        }
        nodes
    }

    /// Checks the link structure itself: prev/next symmetry, slots agree with membership,
    /// counts agree with a recount. Returns the first inconsistency.
    pub fn check_structure(&self) -> Result<(), String> {
        let mut seen = vec![false; self.slot.len()];
        for queue in [Queue::Split, Queue::Merge] {
            for link in 0..self.n_links + 2 {
                let nodes = self.link_nodes(queue, link);
                if nodes.len() as u32 != self.link_len(queue, link) {
                    return Err(format!(
                        "{queue:?} link {link}: count {} but {} nodes linked",
                        self.link_len(queue, link),
                        nodes.len()
                    ));
                }
                let mut previous = NO_NODE;
                for &node in &nodes {
                    if seen[node as usize] {
                        return Err(format!("node {node} is linked twice"));
                    }
                    seen[node as usize] = true;
                    if self.slot(node) != Some(Slot { queue, link }) {
                        return Err(format!(
                            "node {node} is in {queue:?} link {link} but its slot says {:?}",
                            self.slot(node)
                        ));
                    }
                    if self.prev[node as usize] != previous {
                        return Err(format!("node {node}: prev link broken"));
                    }
                    previous = node;
                }
            }
        }
        for (node, &raw) in self.slot.iter().enumerate() {
            if raw != NOT_QUEUED && !seen[node] {
                return Err(format!("node {node} has a slot but is in no link"));
            }
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
}
