//! Incremental triangle strips as ROAM'97 §7.2 describes them, kept over the drawn leaves.
//! Counted, not drawn (`mod.rs` says why): they feed only `triangles_per_strip`; the mesh the
//! runner reads and the buffers a GPU draws (`draw.rs`) are the bintree's leaves, whatever the
//! strips.
//!
//! The linking itself ("New triangles are first inserted as singleton strips, which we
//! subsequently attempt to glue to each of the neighboring strip ends") is shared with Wu's
//! strips in `sim::draw::strips`; this module says where a bintree keeps it: the links on each
//! leaf (`BinTriangle::strip`), the counts on the bintree, the neighbours from the leaf links,
//! tried in the order base, left, right. The caller strips the *drawn* leaves only: every leaf
//! with culling flags off, every leaf not labelled `Out` with them on.
//!
//! `triangles_per_strip` = stripped triangles / strips; the paper reports about 4 to 5 for its
//! strips. Each operation is O(1) apart from a reversal, so strips cost O(splits + merges +
//! culling changes) per frame.

use super::bintree::{Bintree, Side, StripLinks, TriangleKey};
use crate::sim::draw::strips::{self, StripCounts, StripMesh};
use crate::sim::hierarchy::GridPoint;

impl StripMesh for Bintree {
    type Key = TriangleKey;

    /// Apex, left, right.
    fn corners(&self, key: TriangleKey) -> [GridPoint; 3] {
        let shape = self.get(key).shape;
        [shape.apex, shape.left, shape.right]
    }

    fn neighbour(&self, key: TriangleKey, side: usize) -> Option<(TriangleKey, [GridPoint; 2])> {
        let side = [Side::Base, Side::Left, Side::Right][side];
        let triangle = self.get(key);
        Some((triangle.neighbour(side)?, triangle.edge(side)))
    }

    fn links(&self, key: TriangleKey) -> Option<StripLinks> {
        self.get(key).strip
    }

    fn links_mut(&mut self, key: TriangleKey) -> Option<&mut StripLinks> {
        self.get_mut(key).strip.as_mut()
    }

    fn set_links(&mut self, key: TriangleKey, links: Option<StripLinks>) {
        self.get_mut(key).strip = links;
    }

    fn counts_mut(&mut self) -> &mut StripCounts {
        &mut self.strip_counts
    }
}

/// Triangles per strip from the counts (0 when nothing is stripped).
pub fn triangles_per_strip(bintree: &Bintree) -> f64 {
    bintree.strip_counts().triangles_per_strip()
}

/// Takes the leaf `key` out of its strip (if it is in one).
pub fn detach(bintree: &mut Bintree, key: TriangleKey) {
    strips::detach(bintree, key);
}

/// Strips the leaf `key` and glues it to the strips around it.
pub fn attach(bintree: &mut Bintree, key: TriangleKey) {
    strips::attach(bintree, key);
}

/// Checks the strips: every stripped triangle is a leaf, and the shared checks
/// (`sim::draw::strips::check`). O(triangles).
pub fn check(bintree: &Bintree) -> Result<(), String> {
    let mut stripped = Vec::new();
    for (key, triangle) in bintree.iter() {
        if triangle.strip.is_none() {
            continue;
        }
        if !triangle.is_leaf() {
            return Err(format!("{:?}: split, yet in a strip", triangle.shape));
        }
        stripped.push(key);
    }
    strips::check(bintree, stripped, bintree.strip_counts(), |key| {
        format!("{:?}", bintree.get(key).shape)
    })
}
