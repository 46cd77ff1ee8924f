//! Merging a diamond (ROAM'97's merge; SPEC §6): its one or two split parent triangles become
//! leaves again. Topology only: which diamond to merge is the merge queue's (`core/adapt.rs`).
//!
//! A diamond is mergeable when every child of its parents is a leaf. Merging removes the split
//! vertex from the mesh, gives the parents back the children's outer neighbours (relinking those
//! neighbours to the parents) and frees the children's slots. O(1). The children must have left
//! their strips first (`mod.rs` does that); the parents keep their culling flags, which are
//! current.

use super::bintree::{Bintree, TriangleKey};
use crate::sim::hierarchy::GridPoint;

/// The parents of the diamond that `primary` was split in: `primary` and its partner.
pub fn diamond_parents(bintree: &Bintree, primary: TriangleKey) -> [Option<TriangleKey>; 2] {
    [Some(primary), bintree.get(primary).partner]
}

/// Whether the diamond that the split triangle `parent` belongs to can merge.
pub fn is_mergeable(bintree: &Bintree, parent: TriangleKey) -> bool {
    diamond_parents(bintree, parent)
        .into_iter()
        .flatten()
        .all(|p| match bintree.get(p).children {
            None => false,
            Some(children) => children.iter().all(|&c| bintree.get(c).is_leaf()),
        })
}

/// The primary parent of a diamond: the parent with the smaller apex id.
pub fn primary_parent(bintree: &Bintree, parent: TriangleKey) -> TriangleKey {
    let lattice = bintree.lattice();
    match bintree.get(parent).partner {
        Some(partner)
            if lattice.id(bintree.get(partner).shape.apex)
                < lattice.id(bintree.get(parent).shape.apex) =>
        {
            partner
        }
        _ => parent,
    }
}

/// Merges the mergeable diamond of `primary`. Returns the split vertex, or `None` (changing
/// nothing) when the diamond is not mergeable.
pub fn merge(bintree: &mut Bintree, primary: TriangleKey) -> Option<GridPoint> {
    if !is_mergeable(bintree, primary) {
        return None;
    }
    let parents = diamond_parents(bintree, primary);
    let vertex = bintree.get(primary).split_vertex()?;
    for parent in parents.into_iter().flatten() {
        let [c0, c1] = bintree.get(parent).children?;
        let outer_left = bintree.get(c0).base;
        let outer_right = bintree.get(c1).base;
        bintree.relink(outer_left, c0, parent);
        bintree.relink(outer_right, c1, parent);
        let triangle = &mut bintree.triangles[parent];
        triangle.left = outer_left;
        triangle.right = outer_right;
        triangle.children = None;
        bintree.triangles.remove(c0);
        bintree.triangles.remove(c1);
        bintree.n_leaves -= 1;
    }
    if let [Some(a), b] = parents {
        bintree.triangles[a].base = b;
        bintree.triangles[a].partner = None;
        if let Some(b) = b {
            bintree.triangles[b].base = Some(a);
            bintree.triangles[b].partner = None;
        }
    }
    bintree.mesh.remove(bintree.lattice().id(vertex));
    Some(vertex)
}
