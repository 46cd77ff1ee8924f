//! The coarse step: per frame, a block-level decision from interval tests on the block's δ range.
//!
//! For a node's box (its square × the height range of its samples) and the eye, the vertical
//! projection factor g = λ·r/(r² + h²) (r the horizontal, h the vertical eye–vertex distance) is
//! bounded over the box ([`ProjectionBounds`]): g is decreasing in h, and in r it rises up to
//! r = h and falls after, so
//! - the largest g is at the smallest h over the box, at the r of [r_min, r_max] closest to h;
//! - the smallest g is at the largest h, at r_min or r_max (whichever is smaller).
//!
//! A vertex of nested error δ in the box then projects to between δ·g_min and δ·g_max pixels.
//! The tests are made conservative against rounding by [`INTERVAL_MARGIN`]: a vertex is decided
//! *removed* by interval only when δ = 0 or δ·g_max·(1 + margin) < τ, *kept* only when δ > 0 and
//! δ·g_min·(1 − margin) ≥ τ; anything between is evaluated exactly. So an interval decision never
//! differs from the exact criterion ([`super::keeps_vertex`]).
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

use super::blocks::{BlockNode, BlockTree};
use super::fine::LevelBuckets;
use super::keeps_vertex;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::metrics::vertical_projection_error_px;
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

    /// Whether every vertex of nested error `delta` in the box projects below τ.
    pub fn removes(&self, delta: f32, tau_px: f64) -> bool {
        delta == 0.0 || f64::from(delta) * self.max * (1.0 + INTERVAL_MARGIN) < tau_px
    }

    /// Whether every vertex of nested error `delta` in the box projects to at least τ.
    pub fn keeps(&self, delta: f32, tau_px: f64) -> bool {
        delta > 0.0 && f64::from(delta) * self.min * (1.0 - INTERVAL_MARGIN) >= tau_px
    }
}

/// Everything a frame's coarse step reads.
pub(super) struct CoarseFrame<'a> {
    pub(super) hierarchy: &'a Hierarchy,
    pub(super) blocks: &'a BlockTree,
    pub(super) eye: DVec3,
    pub(super) lambda: f64,
    pub(super) tau_px: f64,
}

/// Runs the coarse step: decides every node, evaluates what the intervals leave open, and puts
/// every vertex that meets the criterion into `kept` by level. O(nodes visited + log of their
/// sizes + vertices evaluated or kept).
pub(super) fn select_blocks(
    frame: &CoarseFrame,
    stack: &mut Vec<u32>,
    kept: &mut LevelBuckets,
) -> CoarseCounts {
    let mut counts = CoarseCounts::default();
    stack.clear();
    stack.push(0);
    while let Some(index) = stack.pop() {
        let node = frame.blocks.node(index);
        let bounds = node_bounds(frame, node);
        if bounds.removes(node.subtree_delta_max, frame.tau_px) {
            counts.blocks_coarsest += node.subtree_nodes;
            counts.vertices_by_interval += node.subtree_vertices;
            continue;
        }
        decide_owned_vertices(frame, node, &bounds, &mut counts, kept);
        if let Some(children) = frame.blocks.children(index) {
            stack.extend(children.iter().rev());
        }
    }
    counts
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
    counts: &mut CoarseCounts,
    kept: &mut LevelBuckets,
) {
    let ids = frame.blocks.owned_ids(node);
    let deltas = frame.blocks.owned_deltas(node);
    let n_owned = ids.len();
    // δ is non-increasing along the list, and both tests are monotone in δ.
    let kept_end = deltas.partition_point(|&delta| bounds.keeps(delta, frame.tau_px));
    let removed_start = deltas
        .partition_point(|&delta| !bounds.removes(delta, frame.tau_px))
        .max(kept_end);
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
    for (&id, &delta) in ids[kept_end..removed_start]
        .iter()
        .zip(&deltas[kept_end..removed_start])
    {
        let point = lattice.point(id);
        let position = field.position(point.i as usize, point.j as usize);
        let projected =
            vertical_projection_error_px(frame.eye, position, f64::from(delta), frame.lambda);
        if keeps_vertex(delta, projected, frame.tau_px) {
            kept.push(lattice, id);
            counts.vertices_kept += 1;
        }
    }
}
