//! Triangle strips over the leaves (ROAM §7.2), reported as triangles per strip.
//!
//! The leaves are walked in the bintree's Sierpinski order and cut greedily into strips: a strip
//! (v0 v1 v2)(v1 v2 v3)… goes on while the next leaf holds the strip's last two vertices; the
//! first triangle of a strip is oriented so that the edge it shares with the following leaf
//! comes last. No swaps (degenerate triangles) are used, so this undercounts what ROAM's
//! generalised strips achieve.
//!
//! "Incremental" here is at frame granularity: the strips are recounted, in O(leaves), only on a
//! frame whose splits or merges changed the mesh; an unchanged mesh keeps its count. ROAM's
//! per-diamond strip repair is not modelled. Buffers are reused across frames.

use super::bintree::{Bintree, TriangleKey};
use crate::sim::hierarchy::GridPoint;

/// The strip counter and its reused buffers.
#[derive(Default)]
pub struct StripCounter {
    stack: Vec<(TriangleKey, bool)>,
    leaves: Vec<TriangleKey>,
    triangles_per_strip: f64,
}

impl StripCounter {
    /// Recounts when `changed`, then returns leaves per strip.
    pub fn update(&mut self, bintree: &Bintree, changed: bool) -> f64 {
        if changed || self.triangles_per_strip == 0.0 {
            let strips = self.count_strips(bintree);
            self.triangles_per_strip = self.leaves.len() as f64 / strips.max(1) as f64;
        }
        self.triangles_per_strip
    }

    fn count_strips(&mut self, bintree: &Bintree) -> u64 {
        bintree.leaves_in_curve_order(&mut self.stack, &mut self.leaves);
        let corners = |key: TriangleKey| {
            let t = bintree.get(key).shape;
            [t.apex, t.left, t.right]
        };
        let mut strips = 0;
        // The strip's last two vertices, or `None` before a strip is started.
        let mut last_two: Option<(GridPoint, GridPoint)> = None;
        for (k, &leaf) in self.leaves.iter().enumerate() {
            let vertices = corners(leaf);
            if let Some((a, b)) = last_two
                && vertices.contains(&a)
                && vertices.contains(&b)
            {
                let third = vertices
                    .into_iter()
                    .find(|v| *v != a && *v != b)
                    .unwrap_or(b);
                last_two = Some((b, third));
                continue;
            }
            strips += 1;
            // Start a strip: put the edge shared with the next leaf last, if there is one.
            let next = self.leaves.get(k + 1).map(|&n| corners(n));
            last_two = match next {
                Some(next) => {
                    let shared: Vec<GridPoint> =
                        vertices.into_iter().filter(|v| next.contains(v)).collect();
                    (shared.len() == 2).then(|| (shared[0], shared[1]))
                }
                None => None,
            };
        }
        strips
    }
}
