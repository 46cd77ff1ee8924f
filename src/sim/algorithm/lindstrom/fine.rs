//! Lindstrom et al. 1996's fine, vertex-based step (SPEC §6): bottom-up, finest level first, a
//! vertex stays when it meets the criterion or when something that depends on it stayed. It
//! evaluates no metric: the coarse step hands it the kept vertices.
//!
//! The 4-8 levels are numbered from the finest: rotated vertices of half-size t are level
//! 2·log₂t, square ones 2·log₂t + 1, and every vertex's parents are exactly one level coarser
//! (rotated(t) depends on squares of half t, square(t) on rotated vertices of half 2t or on
//! corners). Starting from the full-resolution grid, Lindstrom's bottom-up simplification removes
//! a vertex when its projected error is below τ *and* none of its dependents is left; that is the
//! same as keeping, level by level from the finest, every vertex that met the criterion plus
//! every parent of a vertex kept one level below. Walking only the kept vertices, not the whole
//! grid, gives that mesh in O(mesh) per frame. Dependencies cross block borders freely: a parent
//! is activated wherever it lies, and those activations are the `forced_activations`.

use crate::sim::hierarchy::{Lattice, VertexClass};
use crate::sim::mesh::rebuilt::RebuiltMesh;

/// Vertex ids waiting for the fine step, one list per 4-8 level. The lists are reused across
/// frames: after the first frames nothing allocates.
#[derive(Clone, Debug)]
pub(super) struct LevelBuckets {
    levels: Vec<Vec<u32>>,
}

impl LevelBuckets {
    /// Empty buckets for a lattice of level n (2n levels).
    pub(super) fn new(lattice: &Lattice) -> LevelBuckets {
        LevelBuckets {
            levels: vec![Vec::new(); 2 * lattice.level() as usize],
        }
    }

    /// Queues a non-corner vertex at its level; corners are always active and are ignored.
    pub(super) fn push(&mut self, lattice: &Lattice, id: u32) {
        if let Some(level) = level_of(lattice.classify(lattice.point(id))) {
            self.levels[level].push(id);
        }
    }

    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.levels
            .iter()
            .map(|l| l.capacity() * std::mem::size_of::<u32>())
            .sum()
    }

    pub(super) fn clear(&mut self) {
        for level in &mut self.levels {
            level.clear();
        }
    }
}

/// Activates every queued vertex and, level by level upwards, the parents of every vertex
/// activated. Inserts them into `mesh` and returns the triangles they add (their parents,
/// summed). Leaves the buckets empty.
pub(super) fn activate_bottom_up(
    lattice: &Lattice,
    buckets: &mut LevelBuckets,
    mesh: &mut RebuiltMesh,
) -> u64 {
    let mut triangles_added = 0;
    for level in 0..buckets.levels.len() {
        let mut pending = std::mem::take(&mut buckets.levels[level]);
        for &id in &pending {
            if !mesh.insert(id) {
                continue;
            }
            let parents = lattice.parents(lattice.point(id));
            triangles_added += parents.len() as u64;
            if let Some(above) = buckets.levels.get_mut(level + 1) {
                above.extend(
                    parents
                        .as_slice()
                        .iter()
                        .filter(|parent| !matches!(lattice.classify(**parent), VertexClass::Corner))
                        .map(|parent| lattice.id(*parent)),
                );
            }
        }
        pending.clear();
        buckets.levels[level] = pending;
    }
    triangles_added
}

/// A vertex's level counted from the finest; `None` for corners.
fn level_of(class: VertexClass) -> Option<usize> {
    match class {
        VertexClass::Corner => None,
        VertexClass::Rotated { half, .. } => Some(2 * half.trailing_zeros() as usize),
        VertexClass::Square { half } => Some(2 * half.trailing_zeros() as usize + 1),
    }
}
