//! Lindstrom et al. 1996's coarse, block-based step (SPEC §6): per frame, a block-level decision
//! from interval tests on the block's δ range. Vertices the intervals leave undecided are
//! evaluated exactly here; closure is the fine step's (`fine.rs`).
//!
//! For a node's box (its square × the height range of its samples) and the eye, the vertical
//! projection factor g = λ·r/(r² + h²) (r the horizontal, h the vertical eye–vertex distance) is
//! bounded over the box ([`ProjectionBounds`]): g is decreasing in h, and in r it rises up to
//! r = h and falls after, so
//! - the largest g is at the smallest h over the box, at the r of [r_min, r_max] closest to h;
//! - the smallest g is at the largest h, at r_min or r_max (whichever is smaller).
//!
//! A vertex of nested error δ in the box then projects to between δ·g_min and δ·g_max pixels.
//! The paper keeps a vertex only when its error *exceeds* τ, so a vertex is decided *removed* by
//! interval when δ·g_max·(1 + margin) ≤ τ and *kept* when δ·g_min·(1 − margin) > τ; anything
//! between is evaluated exactly by the paper's squared comparison ([`super::Tolerance::keeps`]).
//! The [`INTERVAL_MARGIN`] makes the interval tests conservative against rounding, so an interval
//! decision never differs from the exact criterion.
//!
//! **Block state kept between frames.** ROAM'97 §2 on Lindstrom et al.: "The block-LOD updates
//! are incremental, taking advantage of frame-to-frame and object-space coherence." Each node
//! keeps a [`BlockState`]: whether its subtree was open (visited) in the previous frame and where
//! its δ-sorted list was cut into kept / evaluated / removed. A frame starts each node's two
//! searches from last frame's cuts (galloping: O(log of how far a cut moved) probes instead of
//! O(log of the list)), and when a subtree that was open closes, only its previously open part is
//! walked to close it. The per-vertex decisions themselves are redone every frame, as in the
//! paper's bottom-up vertex step (no deferral: the paper has no speed bound). `interval_probes`
//! counts the searches' predicate evaluations, `blocks_changed` the nodes that opened or closed.
//!
//! Traversal, top-down from the root with a reused stack:
//! - if the subtree's largest δ is removed by interval over the node's box (which holds the
//!   whole subtree), every block of the subtree is at its lowest resolution: the subtree is
//!   skipped, its vertices count as decided by interval and its nodes as `blocks_coarsest`;
//! - otherwise the node's own vertices, sorted by δ (largest first), split into a prefix kept by
//!   interval, a suffix removed by interval (both found by binary search, the tests being
//!   monotone in δ) and a middle evaluated exactly. The node is *finest* when the prefix is
//!   everything, *coarsest* when the suffix is, *partial* otherwise; then its children are
//!   visited.
//!
//! Kept vertices are handed to the fine step by level ([`super::fine::LevelBuckets`]).

use super::Tolerance;
use super::blocks::{BlockNode, BlockTree};
use super::fine::LevelBuckets;
use crate::sim::hierarchy::Hierarchy;
use glam::DVec3;

/// Relative margin by which an interval test must clear τ before it decides a vertex without
/// evaluating it. Rounding in the bounds and in the exact metric is a few ulps (~10⁻¹⁵); this
/// is far above that and far below any difference that matters on screen.
pub const INTERVAL_MARGIN: f64 = 1e-9;

/// What the coarse step did this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct CoarseCounts {
    pub(super) blocks_coarsest: u64,
    pub(super) blocks_finest: u64,
    pub(super) blocks_partial: u64,
    /// Vertices whose projected error was computed exactly.
    pub(super) vertices_evaluated: u64,
    /// Vertices decided by a block's interval test, without evaluation.
    pub(super) vertices_by_interval: u64,
    /// Vertices that meet the criterion themselves (before closure).
    pub(super) vertices_kept: u64,
    /// Predicate evaluations of the searches that cut the δ-sorted lists.
    pub(super) interval_probes: u64,
    /// Nodes whose subtree opened or closed since the previous frame.
    pub(super) blocks_changed: u64,
}

/// What a node of the block quadtree remembers from the previous frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct BlockState {
    /// The node's subtree was visited (not removed by interval) in the previous frame.
    open: bool,
    /// Where the previous frame cut the node's δ-sorted list: `[0, kept_end)` kept by interval,
    /// `[removed_start, n)` removed by interval (meaningful only when `open`).
    kept_end: u32,
    removed_start: u32,
}

/// Bounds of the vertical projection factor λ·r/(r² + h²) over an axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectionBounds {
    pub min: f64,
    pub max: f64,
}

impl ProjectionBounds {
    /// The bounds over the box [`low`, `high`] seen from `eye`, with λ = `lambda`. The maximum
    /// is +∞ when the eye is in the box; the minimum is 0 when the eye is above or below it.
    pub fn over_box(eye: DVec3, low: DVec3, high: DVec3, lambda: f64) -> ProjectionBounds {
        let gap = |e: f64, lo: f64, hi: f64| {
            if e < lo {
                lo - e
            } else if e > hi {
                e - hi
            } else {
                0.0
            }
        };
        let far = |e: f64, lo: f64, hi: f64| (e - lo).abs().max((hi - e).abs());
        let (gx, gy) = (gap(eye.x, low.x, high.x), gap(eye.y, low.y, high.y));
        let (fx, fy) = (far(eye.x, low.x, high.x), far(eye.y, low.y, high.y));
        let r_min = (gx * gx + gy * gy).sqrt();
        let r_max = (fx * fx + fy * fy).sqrt();
        let h_min = gap(eye.z, low.z, high.z);
        let h_max = far(eye.z, low.z, high.z);
        let factor = |r: f64, h: f64| r / (r * r + h * h);

        let max = if h_min == 0.0 {
            if r_min == 0.0 {
                f64::INFINITY
            } else {
                1.0 / r_min
            }
        } else if r_max <= h_min {
            factor(r_max, h_min)
        } else if r_min >= h_min {
            factor(r_min, h_min)
        } else {
            0.5 / h_min
        };
        let min = if r_min == 0.0 {
            0.0
        } else {
            factor(r_min, h_max).min(factor(r_max, h_max))
        };
        ProjectionBounds {
            min: lambda * min,
            max: lambda * max,
        }
    }

    /// Whether every vertex of nested error `delta` in the box projects to at most τ (the paper
    /// removes those).
    pub fn removes(&self, delta: f32, tau_px: f64) -> bool {
        delta == 0.0 || f64::from(delta) * self.max * (1.0 + INTERVAL_MARGIN) <= tau_px
    }

    /// Whether every vertex of nested error `delta` in the box projects to more than τ (the
    /// paper keeps those).
    pub fn keeps(&self, delta: f32, tau_px: f64) -> bool {
        f64::from(delta) * self.min * (1.0 - INTERVAL_MARGIN) > tau_px
    }
}

/// Everything a frame's coarse step reads.
pub(super) struct CoarseFrame<'a> {
    pub(super) hierarchy: &'a Hierarchy,
    pub(super) blocks: &'a BlockTree,
    pub(super) eye: DVec3,
    pub(super) lambda: f64,
    pub(super) tau_px: f64,
    pub(super) tolerance: Tolerance,
}

/// Runs the coarse step: decides every node, evaluates what the intervals leave open, and puts
/// every vertex that meets the criterion into `kept` by level. `state` (one entry per node) is
/// last frame's state on entry and this frame's on return. O(nodes visited + log of how far their
/// cuts moved + vertices evaluated or kept + nodes that closed).
pub(super) fn select_blocks(
    frame: &CoarseFrame,
    state: &mut [BlockState],
    stacks: &mut (Vec<u32>, Vec<u32>),
    kept: &mut LevelBuckets,
) -> CoarseCounts {
    let (stack, closing) = stacks;
    let mut counts = CoarseCounts::default();
    stack.clear();
    stack.push(0);
    while let Some(index) = stack.pop() {
        let node = frame.blocks.node(index);
        let bounds = node_bounds(frame, node);
        if bounds.removes(node.subtree_delta_max, frame.tau_px) {
            counts.blocks_coarsest += node.subtree_nodes;
            counts.vertices_by_interval += node.subtree_vertices;
            if state[index as usize].open {
                close_subtree(frame.blocks, state, index, closing, &mut counts);
            }
            continue;
        }
        let node_state = &mut state[index as usize];
        counts.blocks_changed += u64::from(!node_state.open);
        decide_owned_vertices(frame, node, &bounds, node_state, &mut counts, kept);
        if let Some(children) = frame.blocks.children(index) {
            stack.extend(children.iter().rev());
        }
    }
    counts
}

/// Marks the previously open part of the subtree of `root` closed. O(nodes that were open).
fn close_subtree(
    blocks: &BlockTree,
    state: &mut [BlockState],
    root: u32,
    pending: &mut Vec<u32>,
    counts: &mut CoarseCounts,
) {
    pending.clear();
    pending.push(root);
    while let Some(index) = pending.pop() {
        let node_state = &mut state[index as usize];
        if !node_state.open {
            continue;
        }
        node_state.open = false;
        counts.blocks_changed += 1;
        pending.extend(blocks.children(index).into_iter().flatten());
    }
}

fn node_bounds(frame: &CoarseFrame, node: &BlockNode) -> ProjectionBounds {
    let spacing = frame.hierarchy.field().spacing();
    let low = DVec3::new(
        f64::from(node.i0) * spacing.dx,
        f64::from(node.j0) * spacing.dy,
        node.z_min,
    );
    let high = DVec3::new(
        f64::from(node.i0 + node.side) * spacing.dx,
        f64::from(node.j0 + node.side) * spacing.dy,
        node.z_max,
    );
    ProjectionBounds::over_box(frame.eye, low, high, frame.lambda)
}

fn decide_owned_vertices(
    frame: &CoarseFrame,
    node: &BlockNode,
    bounds: &ProjectionBounds,
    state: &mut BlockState,
    counts: &mut CoarseCounts,
    kept: &mut LevelBuckets,
) {
    let blocks = frame.blocks;
    let ids = blocks.owned_ids(node);
    let n_owned = ids.len();
    // δ is non-increasing along the list, and both tests are monotone in δ; last frame's cuts
    // (when the node was open) are where the searches start.
    let (kept_hint, removed_hint) = if state.open {
        (state.kept_end as usize, state.removed_start as usize)
    } else {
        (0, n_owned)
    };
    let kept_end = partition_point_from(
        ids,
        kept_hint,
        |&id| bounds.keeps(blocks.delta(id), frame.tau_px),
        &mut counts.interval_probes,
    );
    let removed_start = partition_point_from(
        ids,
        removed_hint,
        |&id| !bounds.removes(blocks.delta(id), frame.tau_px),
        &mut counts.interval_probes,
    )
    .max(kept_end);
    *state = BlockState {
        open: true,
        kept_end: kept_end as u32,
        removed_start: removed_start as u32,
    };
    if kept_end == n_owned && n_owned > 0 {
        counts.blocks_finest += 1;
    } else if removed_start == 0 {
        counts.blocks_coarsest += 1;
    } else {
        counts.blocks_partial += 1;
    }
    counts.vertices_by_interval += (kept_end + n_owned - removed_start) as u64;
    counts.vertices_evaluated += (removed_start - kept_end) as u64;

    let lattice = frame.hierarchy.lattice();
    let field = frame.hierarchy.field();
    for &id in &ids[..kept_end] {
        kept.push(lattice, id);
    }
    counts.vertices_kept += kept_end as u64;
    for &id in &ids[kept_end..removed_start] {
        let delta = blocks.delta(id);
        let point = lattice.point(id);
        let position = field.position(point.i as usize, point.j as usize);
        if frame.tolerance.keeps(delta, position - frame.eye) {
            kept.push(lattice, id);
            counts.vertices_kept += 1;
        }
    }
}

/// The partition point of `slice` under `pred` (true on a prefix, false after it), found by
/// galloping from `hint` outwards and then bisecting: O(log |answer − hint|) evaluations of
/// `pred`, each counted in `probes`.
fn partition_point_from<T>(
    slice: &[T],
    hint: usize,
    pred: impl Fn(&T) -> bool,
    probes: &mut u64,
) -> usize {
    let n = slice.len();
    let hint = hint.min(n);
    let mut test = |k: usize| {
        *probes += 1;
        pred(&slice[k])
    };
    // The answer p satisfies lo ≤ p ≤ hi.
    let (mut lo, mut hi);
    if hint > 0 && !test(hint - 1) {
        // p < hint: gallop to the left.
        hi = hint - 1;
        let mut step = 1;
        loop {
            if hi < step {
                lo = 0;
                break;
            }
            if test(hi - step) {
                lo = hi - step + 1;
                break;
            }
            hi -= step;
            step *= 2;
        }
    } else {
        // p ≥ hint: gallop to the right.
        lo = hint;
        let mut step = 1;
        loop {
            if lo + step > n {
                hi = n;
                break;
            }
            if !test(lo + step - 1) {
                hi = lo + step - 1;
                break;
            }
            lo += step;
            step *= 2;
        }
    }
    while lo < hi {
        let middle = lo + (hi - lo) / 2;
        if test(middle) {
            lo = middle + 1;
        } else {
            hi = middle;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::partition_point_from;

    #[test]
    fn galloping_from_any_hint_finds_the_partition_point_of_every_prefix() {
        for n in 0..40usize {
            let values: Vec<usize> = (0..n).collect();
            for point in 0..=n {
                for hint in 0..=n + 2 {
                    let mut probes = 0;
                    let found = partition_point_from(&values, hint, |&v| v < point, &mut probes);
                    assert_eq!(found, point, "n {n}, point {point}, hint {hint}");
                    if hint == point && n > 0 {
                        assert!(probes <= 2, "a right hint costs at most two probes");
                    }
                }
            }
        }
    }
}
