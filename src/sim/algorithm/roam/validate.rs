//! The bintree validator: what makes ROAM's state consistent.
//!
//! Checks, in order: parent/child links; every leaf's neighbour links are symmetric, point at
//! leaves and share the right edge; neighbours' depths differ by at most one; the leaf count;
//! the mesh is exactly the corners plus every split vertex, and it passes the shared mesh
//! validator (closure, T = 2 + Σ parents); with strips on, the curve-order list holds every leaf
//! in the order of a walk from the roots and the joined-junction count equals a recount; the
//! split queue holds exactly the splittable leaves
//! and the merge queue exactly the mergeable diamonds, with priorities that equal a
//! recomputation (or, under deferral, lie on the same side of τ). Tests call it after every
//! operation; it is O(triangles · log) and allocates.

use super::bintree::{Bintree, CullFlag, Side};
use super::merge::{is_mergeable, primary_parent};
use super::priority::PriorityContext;
use super::queues::Queues;
use super::strips::count_strips;
use crate::sim::mesh::VertexSet;
use crate::sim::mesh::validate::validate_reported;
use std::collections::HashSet;

/// How stored priorities must compare with a recomputation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PriorityCheck {
    /// Do not compare (the camera has moved since they were computed).
    Skip,
    /// Equal to a recomputation.
    Exact,
    /// On the same side of τ as a recomputation (deferral).
    SameSideOf(f64),
}

/// The first inconsistency found, in words.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("roam bintree: {0}")]
pub struct BintreeError(pub String);

fn fail<T>(message: String) -> Result<T, BintreeError> {
    Err(BintreeError(message))
}

/// Validates the bintree and its queues; `context` recomputes priorities and flags.
pub fn validate(
    bintree: &Bintree,
    queues: &Queues,
    context: &PriorityContext,
    check: PriorityCheck,
) -> Result<(), BintreeError> {
    let mut n_leaves = 0;
    let mut expected_mesh = VertexSet::base_mesh(bintree.lattice());
    for (key, triangle) in bintree.iter() {
        if let Some(parent) = triangle.parent {
            let Some(children) = bintree.get(parent).children else {
                return fail(format!("{:?}: parent is a leaf", triangle.shape));
            };
            if !children.contains(&key) || triangle.depth != bintree.get(parent).depth + 1 {
                return fail(format!("{:?}: parent does not list it", triangle.shape));
            }
        } else if !bintree.roots().contains(&key) {
            return fail(format!("{:?}: orphan", triangle.shape));
        }
        if let Some(children) = triangle.children {
            let Some(mid) = triangle.split_vertex() else {
                return fail(format!("{:?}: split at the finest level", triangle.shape));
            };
            expected_mesh.insert(bintree.lattice().id(mid));
            for child in children {
                if bintree.get(child).parent != Some(key) {
                    return fail(format!("{:?}: child does not point back", triangle.shape));
                }
            }
            continue;
        }
        n_leaves += 1;
        for side in [Side::Base, Side::Left, Side::Right] {
            let Some(neighbour_key) = triangle.neighbour(side) else {
                let [a, b] = triangle.edge(side);
                let cells = bintree.lattice().cells();
                let on_border = (a.i == b.i && (a.i == 0 || a.i == cells))
                    || (a.j == b.j && (a.j == 0 || a.j == cells));
                if !on_border {
                    return fail(format!(
                        "{:?}: no {side:?} neighbour across an inner edge",
                        triangle.shape
                    ));
                }
                continue;
            };
            let neighbour = bintree.get(neighbour_key);
            if !neighbour.is_leaf() {
                return fail(format!("{:?}: {side:?} neighbour is split", triangle.shape));
            }
            let back = [Side::Base, Side::Left, Side::Right]
                .into_iter()
                .find(|&s| neighbour.neighbour(s) == Some(key));
            let Some(back) = back else {
                return fail(format!(
                    "{:?}: {side:?} neighbour does not link back",
                    triangle.shape
                ));
            };
            // The mesh is conforming: neighbours share whole edges (a leg of one level is the
            // hypotenuse of the next), and their depths differ by at most one.
            let (mine, theirs) = (triangle.edge(side), neighbour.edge(back));
            let consistent = mine == theirs && triangle.depth.abs_diff(neighbour.depth) <= 1;
            if !consistent {
                return fail(format!(
                    "{:?}: {side:?} neighbour {:?} does not share the edge (depths {} and {})",
                    triangle.shape, neighbour.shape, triangle.depth, neighbour.depth
                ));
            }
        }
    }
    if n_leaves != bintree.n_leaves() {
        return fail(format!(
            "{n_leaves} leaves, but the count says {}",
            bintree.n_leaves()
        ));
    }
    if &expected_mesh != bintree.mesh() {
        return fail("the mesh is not the set of split vertices".into());
    }
    validate_reported(bintree.lattice(), bintree.mesh(), bintree.n_leaves())
        .map_err(|e| BintreeError(e.to_string()))?;
    validate_strips(bintree)?;
    validate_queues(bintree, queues, context, check)
}

/// The curve-order list against a walk from the roots, the joined junctions against a recount.
fn validate_strips(bintree: &Bintree) -> Result<(), BintreeError> {
    if !bintree.tracks_strips() {
        return Ok(());
    }
    let (mut stack, mut leaves) = (Vec::new(), Vec::new());
    let strips = count_strips(bintree, &mut stack, &mut leaves);
    let mut previous = None;
    let mut key = leaves.first().copied();
    for (position, &expected) in leaves.iter().enumerate() {
        let Some(current) = key else {
            return fail(format!("the curve-order list ends after {position} leaves"));
        };
        if current != expected || bintree.get(current).prev != previous {
            return fail(format!(
                "curve-order list differs from a walk at leaf {position}: {:?}",
                bintree.get(expected).shape
            ));
        }
        previous = key;
        key = bintree.get(current).next;
    }
    if key.is_some() {
        return fail("the curve-order list goes on past the last leaf".into());
    }
    let incremental = bintree.n_leaves() - bintree.joined_junctions().min(bintree.n_leaves());
    if incremental != strips {
        return fail(format!(
            "{incremental} strips counted incrementally, {strips} recounted"
        ));
    }
    Ok(())
}

fn validate_queues(
    bintree: &Bintree,
    queues: &Queues,
    context: &PriorityContext,
    check: PriorityCheck,
) -> Result<(), BintreeError> {
    let mut splittable = HashSet::new();
    let mut mergeable = HashSet::new();
    for (key, triangle) in bintree.iter() {
        if triangle.is_leaf() && triangle.split_vertex().is_some() {
            splittable.insert(key);
        }
        if !triangle.is_leaf() && is_mergeable(bintree, key) {
            mergeable.insert(primary_parent(bintree, key));
        }
    }
    let queued_split: HashSet<_> = queues.split.iter().map(|(k, _)| *k).collect();
    let queued_merge: HashSet<_> = queues.merge.iter().map(|(k, _)| *k).collect();
    if queued_split != splittable {
        return fail(format!(
            "split queue holds {} triangles, {} leaves can split",
            queued_split.len(),
            splittable.len()
        ));
    }
    if queued_merge != mergeable {
        return fail(format!(
            "merge queue holds {} diamonds, {} are mergeable",
            queued_merge.len(),
            mergeable.len()
        ));
    }
    let compare = |what: String, stored: f64, recomputed: f64| match check {
        PriorityCheck::Skip => Ok(()),
        PriorityCheck::Exact if stored == recomputed => Ok(()),
        PriorityCheck::SameSideOf(tau) if (stored <= tau) == (recomputed <= tau) => Ok(()),
        _ => fail(format!(
            "{what}: stored priority {stored}, recomputed {recomputed} ({check:?})"
        )),
    };
    for (key, priority) in queues.split.iter() {
        let triangle = bintree.get(*key);
        let recomputed = context.priority(triangle, flag_now(context, triangle));
        compare(format!("{:?}", triangle.shape), priority.value, recomputed)?;
    }
    for (key, priority) in queues.merge.iter() {
        let recomputed = super::diamond_priority_fresh(bintree, context, *key);
        compare(
            format!("diamond of {:?}", bintree.get(*key).shape),
            priority.0.value,
            recomputed,
        )?;
    }
    Ok(())
}

/// A freshly tested flag (the validator never trusts inherited ones).
fn flag_now(context: &PriorityContext, triangle: &super::bintree::BinTriangle) -> CullFlag {
    if context.culling_flags {
        context.classify(triangle)
    } else {
        CullFlag::DontKnow
    }
}
