//! The validator of ROAM's state: the bintree, the mesh it draws, the §7.1 flags, the §7.2
//! strips and the queues with their priorities (eq. 3), each against a recomputation. Only tests
//! call it; no frame of a run does.
//!
//! Checks, in order: parent/child links; every leaf's neighbour links are symmetric, point at
//! leaves and share the right edge; neighbours' depths differ by at most one; the leaf count;
//! the mesh is exactly the corners plus every split vertex, and it passes the shared mesh
//! validator (closure, T = 2 + Σ parents); every triangle's copied corners, thicknesses and tie
//! key equal the terrain's and the tables'; every triangle's culling flags equal a fresh
//! classification with its parent's (with culling flags on; §7.1's labels are exact every
//! frame); the strips are valid (`strips.rs`) and hold exactly the drawn leaves; the split queue
//! holds exactly the splittable leaves and the merge queue exactly the mergeable diamonds, with
//! priorities that equal a recomputation or, under deferral, are stale only where the schedule
//! allows it (a stale split priority and its recomputation both at most the floor G, a stale
//! merge priority and its recomputation both above the ceiling H). Tests call it after every
//! operation; it is O(triangles · log) and allocates.

use super::bintree::Geometry;
use super::bintree::{Bintree, Side};
use super::cull::{self, CullFlags};
use super::merge::{is_mergeable, primary_parent};
use super::priority::PriorityContext;
use super::queues::Queues;
use super::thickness::Thicknesses;
use crate::sim::mesh::VertexSet;
use crate::sim::mesh::validate::validate_reported;
use crate::sim::terrain::Heightfield;
use std::collections::HashSet;

/// How stored priorities must compare with a recomputation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PriorityCheck {
    /// Do not compare (the camera has moved since they were computed).
    Skip,
    /// Equal to a recomputation.
    Exact,
    /// Equal, or stale as deferral allows: both at most the floor G (split queue) or both above
    /// the ceiling H (merge queue). Without deferral, as `Exact`.
    Deferred,
}

/// The first inconsistency found, in words.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("roam bintree: {0}")]
pub struct BintreeError(pub String);

fn fail<T>(message: String) -> Result<T, BintreeError> {
    Err(BintreeError(message))
}

/// What the validator checks a bintree against: the terrain and thickness tables (for every
/// triangle's copied geometry), the frame (flags and priorities), deferral's band, and whether
/// strips are on.
pub struct Expected<'a> {
    pub field: &'a Heightfield,
    pub thicknesses: &'a Thicknesses,
    pub context: PriorityContext<'a>,
    pub check: PriorityCheck,
    /// Deferral's (G, H), for [`PriorityCheck::Deferred`].
    pub band: Option<(f64, f64)>,
    pub strips_on: bool,
}

/// Validates the bintree and its queues against `expected`.
pub fn validate(
    bintree: &Bintree,
    queues: &Queues,
    expected: &Expected,
) -> Result<(), BintreeError> {
    let context = &expected.context;
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
    validate_geometry(bintree, expected)?;
    if context.culling_flags {
        validate_flags(bintree, context)?;
    }
    validate_strips(bintree, context, expected.strips_on)?;
    validate_queues(bintree, queues, context, expected.check, expected.band)
}

/// Every triangle's copied corners and thicknesses against the terrain and the tables.
fn validate_geometry(bintree: &Bintree, expected: &Expected) -> Result<(), BintreeError> {
    for (_, triangle) in bintree.iter() {
        let shape = triangle.shape;
        let fresh = Geometry::of(
            &shape,
            expected.field,
            expected.thicknesses,
            bintree.lattice(),
        );
        if triangle.geometry != fresh {
            return fail(format!(
                "{shape:?}: geometry {:?}, expected {fresh:?}",
                triangle.geometry
            ));
        }
    }
    Ok(())
}

/// Every triangle's flags against a fresh classification from its parent's flags: §7.1's flags
/// are exact every frame, and inheritance is exact because wedgies are nested.
fn validate_flags(bintree: &Bintree, context: &PriorityContext) -> Result<(), BintreeError> {
    for (key, triangle) in bintree.iter() {
        let inherited = triangle
            .parent
            .map_or(0, |parent| bintree.get(parent).flags.in_mask);
        let (corners, e) = cull::wedgie(bintree, key);
        let fresh = context.view.frustum.classify(corners, e, inherited);
        let stored: CullFlags = triangle.flags;
        // Below an `Out` ancestor, `Out` is inherited whatever the wedgie's own test says.
        let ancestor_out = triangle
            .parent
            .is_some_and(|parent| bintree.get(parent).flags.is_out());
        let agrees = if ancestor_out {
            stored.is_out()
        } else {
            stored.label == fresh.label && (stored.is_out() || stored.in_mask == fresh.in_mask)
        };
        if !agrees {
            return fail(format!(
                "{:?}: flags {stored:?}, a fresh classification gives {fresh:?}",
                triangle.shape
            ));
        }
    }
    Ok(())
}

/// The strips are valid and hold exactly the drawn leaves (none with strips off).
fn validate_strips(
    bintree: &Bintree,
    context: &PriorityContext,
    strips_on: bool,
) -> Result<(), BintreeError> {
    super::strips::check(bintree).map_err(|e| BintreeError(format!("strips: {e}")))?;
    for (_, triangle) in bintree.iter() {
        let drawn = strips_on && (!context.culling_flags || !triangle.flags.is_out());
        if (triangle.is_leaf() && drawn) != triangle.strip.is_some() {
            return fail(format!(
                "{:?}: drawn {drawn}, in a strip {}",
                triangle.shape,
                triangle.strip.is_some()
            ));
        }
    }
    Ok(())
}

fn validate_queues(
    bintree: &Bintree,
    queues: &Queues,
    context: &PriorityContext,
    check: PriorityCheck,
    band: Option<(f64, f64)>,
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
    let split_entries = queues.split.entries();
    let merge_entries = queues.merge.entries();
    let queued_split: HashSet<_> = split_entries.iter().map(|(k, _)| *k).collect();
    let queued_merge: HashSet<_> = merge_entries.iter().map(|(k, _)| *k).collect();
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
    let compare = |what: String, stored: f64, recomputed: f64, split: bool| {
        let allowed = match (check, band) {
            (PriorityCheck::Skip, _) => true,
            _ if stored == recomputed => true,
            (PriorityCheck::Deferred, Some((floor, ceiling))) => {
                if split {
                    stored <= floor && recomputed <= floor
                } else {
                    stored > ceiling && recomputed > ceiling
                }
            }
            _ => false,
        };
        if allowed {
            Ok(())
        } else {
            fail(format!(
                "{what}: stored priority {stored}, recomputed {recomputed} ({check:?}, band {band:?})"
            ))
        }
    };
    for (key, priority) in &split_entries {
        let triangle = bintree.get(*key);
        let recomputed = context.priority(triangle);
        compare(
            format!("{:?}", triangle.shape),
            priority.value,
            recomputed,
            true,
        )?;
    }
    for (key, priority) in &merge_entries {
        let recomputed = diamond_priority(bintree, context, *key);
        compare(
            format!("diamond of {:?}", bintree.get(*key).shape),
            priority.value,
            recomputed,
            false,
        )?;
    }
    Ok(())
}

/// A diamond's priority from scratch: the larger of its parents'.
pub fn diamond_priority(
    bintree: &Bintree,
    context: &PriorityContext,
    primary: super::bintree::TriangleKey,
) -> f64 {
    super::merge::diamond_parents(bintree, primary)
        .into_iter()
        .flatten()
        .map(|parent| context.priority(bintree.get(parent)))
        .fold(0.0, f64::max)
}
