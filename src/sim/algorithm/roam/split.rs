//! Splitting a leaf triangle, with ROAM's recursive forced split of a coarser base neighbour
//! (ROAM'97; SPEC §6). Topology only: which triangle to split is the split queue's
//! (`core/adapt.rs`).
//!
//! A triangle splits together with its base neighbour when that neighbour is at the same level
//! (the two form a diamond); when the neighbour is one level coarser it is split first
//! (recursively: it may force its own base neighbour), after which the triangle's base neighbour
//! is the coarser triangle's child that shares its hypotenuse. Each diamond split inserts its
//! split vertex in the mesh and is recorded in a [`SplitLog`] so that the queues, the culling
//! flags and the strips can follow (in `mod.rs`). O(depth) per split, no allocation besides the
//! new slots and the log. New children start with unknown culling flags, no strip and unset
//! geometry: the core fills those in.

use super::bintree::{BinTriangle, Bintree, Geometry, TriangleKey};
use super::cull::CullFlags;
use crate::sim::hierarchy::GridPoint;

/// A diamond that was split: its one or two parent triangles.
#[derive(Clone, Copy, Debug)]
pub struct DiamondSplit {
    pub parents: [Option<TriangleKey>; 2],
}

/// What splits did, in order.
#[derive(Default)]
pub struct SplitLog {
    pub diamonds: Vec<DiamondSplit>,
    /// Triangles split only because a finer neighbour needed it.
    pub forced: u64,
}

/// Leaves the split of `key` would add, forced splits included (0 when it cannot split).
pub fn split_cost(bintree: &Bintree, key: TriangleKey) -> u64 {
    let mut cost = 0;
    let mut current = key;
    loop {
        let triangle = bintree.get(current);
        if !triangle.is_leaf() || triangle.split_vertex().is_none() {
            return cost;
        }
        match triangle.base {
            None => return cost + 1,
            Some(base) if bintree.get(base).base == Some(current) => return cost + 2,
            Some(base) => {
                cost += 2;
                current = base;
            }
        }
    }
}

/// Splits the leaf `key` (forcing coarser neighbours first). Returns `false`, changing nothing,
/// when the triangle is at the finest level; an interior triangle is left as it is.
pub fn split(bintree: &mut Bintree, key: TriangleKey, log: &mut SplitLog) -> bool {
    let triangle = bintree.get(key);
    if !triangle.is_leaf() {
        return true;
    }
    if triangle.split_vertex().is_none() {
        return false;
    }
    if let Some(base) = triangle.base
        && bintree.get(base).base != Some(key)
    {
        log.forced += 1;
        split(bintree, base, log);
    }
    let base = bintree.get(key).base;
    split_diamond(bintree, key, base, log);
    true
}

/// Splits `key` and its same-level base neighbour `partner` (if any) at their shared midpoint.
fn split_diamond(
    bintree: &mut Bintree,
    key: TriangleKey,
    partner: Option<TriangleKey>,
    log: &mut SplitLog,
) {
    let Some(mid) = bintree.get(key).split_vertex() else {
        return;
    };
    let [c0, c1] = add_children(bintree, key, mid);
    if let Some(partner) = partner {
        let [b0, b1] = add_children(bintree, partner, mid);
        // The shared hypotenuse runs left→right in `key` and right→left in `partner`.
        bintree.triangles[c0].right = Some(b1);
        bintree.triangles[c1].left = Some(b0);
        bintree.triangles[b0].right = Some(c1);
        bintree.triangles[b1].left = Some(c0);
    }
    bintree.triangles[key].partner = partner;
    if let Some(partner) = partner {
        bintree.triangles[partner].partner = Some(key);
    }
    bintree.mesh.insert(bintree.lattice.id(mid));
    log.diamonds.push(DiamondSplit {
        parents: [Some(key), partner],
    });
}

/// Creates the two children of leaf `key`, links them to its left and right neighbours and to
/// each other, and counts the new leaf.
fn add_children(bintree: &mut Bintree, key: TriangleKey, mid: GridPoint) -> [TriangleKey; 2] {
    let parent = bintree.get(key).clone();
    let [shape0, shape1] = parent.shape.children(mid);
    let child = |shape, base| BinTriangle {
        shape,
        depth: parent.depth + 1,
        parent: Some(key),
        children: None,
        base,
        left: None,
        right: None,
        partner: None,
        flags: CullFlags::UNKNOWN,
        strip: None,
        due: u64::MAX,
        geometry: Geometry::UNSET,
    };
    let c0 = bintree.triangles.insert(child(shape0, parent.left));
    let c1 = bintree.triangles.insert(child(shape1, parent.right));
    bintree.triangles[c0].left = Some(c1);
    bintree.triangles[c1].right = Some(c0);
    bintree.relink(parent.left, key, c0);
    bintree.relink(parent.right, key, c1);
    bintree.triangles[key].children = Some([c0, c1]);
    bintree.n_leaves += 1;
    [c0, c1]
}
