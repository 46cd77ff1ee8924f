//! ROAM's per-frame loops over the two queues: split above τ and merge at or below it, or the
//! paper's dual-queue loop towards a triangle target with the oscillation guard and the tie rule
//! (`../mod.rs` states them), and the literal loop without the guard that a unit test runs. The
//! queues' ends are made exact first where deferral could hide a stale priority. Not here: the
//! splits and merges themselves (`mod.rs` of this folder).

use super::super::RoamGoal;
use super::super::bintree::TriangleKey;
use super::super::queues::QueueKey;
use super::super::split::split_cost;
use super::{Core, Scheduling};

impl Core<'_> {
    // ----- The dual-queue loops -------------------------------------------------------------

    /// An upper bound on split/merge iterations in one frame: under the guard each vertex is
    /// inserted at most once and removed at most once per frame.
    pub fn iteration_cap(&self) -> u64 {
        2 * self.bintree.lattice().n_vertices() as u64 + 64
    }

    /// The split queue's top, exact: under deferral in target mode, a top at or below the floor
    /// G might hide a stale priority, so the split queue is recomputed first.
    fn known_top_split(&mut self) -> Option<(TriangleKey, QueueKey)> {
        let top = self.queues.top_split();
        if let Some(deferral) = &self.deferral
            && self.scheduling[0] == Scheduling::Scheduled
            && top.is_some_and(|(_, key)| key.value <= deferral.floor)
        {
            self.counters.revalidations += 1;
            self.recompute_queue(0, false);
            return self.queues.top_split();
        }
        top
    }

    /// The merge queue's bottom, exact (see [`Self::known_top_split`]): a bottom above the
    /// ceiling H might hide a stale one below it.
    fn known_bottom_merge(&mut self) -> Option<(TriangleKey, QueueKey)> {
        let bottom = self.queues.bottom_merge();
        if let Some(deferral) = &self.deferral
            && self.scheduling[1] == Scheduling::Scheduled
            && bottom.is_some_and(|(_, key)| key.value > deferral.ceiling)
        {
            self.counters.revalidations += 1;
            self.recompute_queue(1, false);
            return self.queues.bottom_merge();
        }
        bottom
    }

    /// The bottom diamond if its priority *value* is below `key`'s (a tie in value, +∞ against
    /// +∞ behind the near plane above all, never makes room: trading equals only moves the mesh
    /// from frame to frame). Under deferral, when every stale merge priority is above H and `key`
    /// is at most H, there is none, and the merge queue need not be recomputed.
    fn merge_below(&mut self, key: QueueKey) -> Option<(TriangleKey, QueueKey)> {
        if let Some(deferral) = &self.deferral
            && self.scheduling[1] == Scheduling::Scheduled
            && key.value <= deferral.ceiling
            && self
                .queues
                .bottom_merge()
                .is_none_or(|(_, bottom)| bottom.value > deferral.ceiling)
        {
            return None;
        }
        self.known_bottom_merge()
            .filter(|(_, bottom)| bottom.value < key.value)
    }

    /// Fixed τ: split above τ, merge at or below. Under deferral every stale split priority is
    /// at most τ and every stale merge priority above it, so the queues' ends decide exactly.
    pub fn adapt_to_tolerance(&mut self, tau: f64, split_only: bool) {
        let mut remaining = self.iteration_cap();
        loop {
            if remaining == 0 {
                self.counters.guard_stops += 1;
                break;
            }
            remaining -= 1;
            if let Some((key, priority)) = self.queues.top_split()
                && priority.value > tau
            {
                self.split(key);
                continue;
            }
            if !split_only
                && let Some((key, priority)) = self.queues.bottom_merge()
                && priority.value <= tau
            {
                self.merge(key);
                continue;
            }
            break;
        }
    }

    /// Target count: the dual-queue loop with the oscillation guard (see `mod.rs`).
    pub fn adapt_to_target(&mut self, target: u64, split_only: bool) {
        if !self.oscillation_guard {
            self.adapt_to_target_unguarded(target);
            return;
        }
        let mut lowest_split: Option<QueueKey> = None;
        let mut highest_merge: Option<QueueKey> = None;
        let mut remaining = self.iteration_cap();
        loop {
            if remaining == 0 {
                self.counters.guard_stops += 1;
                break;
            }
            remaining -= 1;
            let may_merge = |key: QueueKey| lowest_split.is_none_or(|s| key < s);
            if self.bintree.n_leaves() > target {
                let bottom = if split_only {
                    None
                } else {
                    self.known_bottom_merge()
                };
                match bottom {
                    Some((diamond, key)) if may_merge(key) => {
                        self.merge(diamond);
                        highest_merge = highest_merge.max(Some(key));
                        continue;
                    }
                    Some(_) => self.counters.guard_stops += 1,
                    None => {}
                }
                break;
            }
            let Some((triangle, key)) = self.known_top_split() else {
                break;
            };
            if key.value <= 0.0 {
                break;
            }
            if highest_merge.is_some_and(|m| key <= m) {
                self.counters.guard_stops += 1;
                break;
            }
            if self.bintree.n_leaves() + split_cost(&self.bintree, triangle) <= target {
                self.split(triangle);
                lowest_split = Some(lowest_split.map_or(key, |s| s.min(key)));
                continue;
            }
            if split_only {
                break;
            }
            // It does not fit: make room if it beats the least useful diamond.
            if let Some((diamond, bottom_key)) = self.merge_below(key) {
                if may_merge(bottom_key) {
                    self.merge(diamond);
                    highest_merge = highest_merge.max(Some(bottom_key));
                    continue;
                }
                self.counters.guard_stops += 1;
            }
            break;
        }
    }

    /// The paper's loop as written, without the guard: while too large merge, while too small
    /// or the top split beats the bottom merge split. Only the iteration cap stops it.
    fn adapt_to_target_unguarded(&mut self, target: u64) {
        let mut remaining = self.iteration_cap();
        loop {
            if remaining == 0 {
                self.counters.guard_stops += 1;
                break;
            }
            remaining -= 1;
            let top = self.queues.top_split().filter(|(_, key)| key.value > 0.0);
            let bottom = self.queues.bottom_merge();
            if self.bintree.n_leaves() > target {
                let Some((diamond, _)) = bottom else {
                    break;
                };
                self.merge(diamond);
                continue;
            }
            let beats = matches!((top, bottom), (Some((_, t)), Some((_, b))) if t > b);
            match top {
                Some((triangle, _)) if self.bintree.n_leaves() < target || beats => {
                    self.split(triangle);
                }
                _ => break,
            }
        }
    }

    pub fn adapt(&mut self, split_only: bool) {
        match self.config.goal {
            RoamGoal::TolerancePx(tau) => self.adapt_to_tolerance(tau, split_only),
            RoamGoal::TargetTriangles(n) => self.adapt_to_target(n, split_only),
        }
    }
}
