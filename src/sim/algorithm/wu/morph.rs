//! Wu §7's geometry morphing, an option (`morph_frames`): the drawn mesh, which follows the
//! vertex set over a few frames instead of at once. It is not the refinement (the vertex set in
//! `mod.rs` decides every split and merge, the budget counts it) and not the buffers (`draw.rs`
//! applies the drawn mesh's edits).
//!
//! **What the paper says, and the reading taken.** Wu et al. 2001 §7: "we also adopt simple
//! geometry morphing similar to [2, 5]" — no parameters, no formula. Refs [2, 5] are
//! Lindstrom et al. 1996 and ROAM 1997; both morph a vertex in time between its parent edge's
//! interpolated height and its own. roamsim takes ROAM's reading, both ways:
//! - a vertex the refinement **inserts** is drawn at once, at the height of its bisected edge's
//!   midpoint (the mean of the edge ends' samples: the coarse surface there), and rises to its own
//!   sample over N frames: drawn at `morph_height(z_mid, z, k / N)` on its k-th frame, fixed
//!   from frame N on;
//! - a vertex the refinement **deletes** stays drawn and sinks back the same way (k = N … 0),
//!   and leaves the drawn mesh one frame after it reached the midpoint, once no drawn vertex
//!   depends on it (its children sink first: the drawn mesh stays a closed 4-8 mesh, a superset
//!   of the vertex set). A vertex inserted again while it sinks turns round and rises from
//!   where it is.
//!
//! The first frame is drawn as refined (there is no earlier frame to pop from). So nothing pops
//! as the refinement changes, except where an edge end itself is morphing (its
//! midpoint is taken from the samples) and at a teleport (morphs run on at their pace: a jump
//! of the camera pops anyway). Heights are computed with `sim::draw::morph_height` and written as
//! the vertices' drawn heights (12-byte vertices, blend 0: every vertex morphs at its own
//! phase, so the blend cannot be per draw; writing the drawn height is the CPU-side morph the
//! draw framework allows), and the same `f32` is the mesh output's morphed height: buffers and
//! mesh agree to the bit.
//!
//! **Why off by default.** The paper gives no N, and the study compares every incremental
//! algorithm without morphing by default (Röttger's and chunked LOD's morphing are options too);
//! the audit and the popping columns measure what it costs (a mesh larger than the budget's by
//! the sinking vertices, a rewrite of 12 bytes per morphing vertex a frame) and what it saves.
//!
//! Cost: O(morphing vertices) a frame (each is stepped), O(1) per edit; memory O(morphing
//! vertices) plus a second vertex set (0.125 bytes per sample).

use super::draw::{Edit, WuBuffers};
use crate::sim::draw::morph_height;
use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice};
use crate::sim::mesh::{MeshOutput, MorphedHeights, VertexSet};
use std::collections::BTreeMap;

/// A morphing vertex: drawn at `morph_height(low, high, level / N)`.
#[derive(Clone, Copy, Debug)]
struct Morph {
    level: u32,
    rising: bool,
    /// Its bisected edge's midpoint height (level 0).
    low: f32,
    /// Its sample's height (level N).
    high: f32,
}

/// The drawn mesh and its morphs (see the module docs).
pub(super) struct Morphing {
    frames: u32,
    drawn: VertexSet,
    heights: MorphedHeights,
    /// Morphing vertices by id (ordered, so that every run steps them alike).
    morphs: BTreeMap<u32, Morph>,
    n_triangles: u64,
    changes: Vec<(GridPoint, Edit)>,
    finished: Vec<u32>,
}

impl Morphing {
    /// The base mesh, morphing over `frames` frames (≥ 1).
    pub fn new(lattice: &Lattice, frames: u32) -> Morphing {
        assert!(frames >= 1, "morphing over {frames} frames");
        Morphing {
            frames,
            drawn: VertexSet::base_mesh(lattice),
            heights: MorphedHeights::new(),
            morphs: BTreeMap::new(),
            n_triangles: 2,
            changes: Vec::new(),
            finished: Vec::new(),
        }
    }

    /// One frame: steps every morph, removes the vertices that have sunk, then follows the
    /// vertex set's changes recorded in `draw` (replacing them there by the drawn mesh's edits).
    /// `at_once`: the first frame, drawn as refined (no earlier frame to pop from).
    pub fn advance(
        &mut self,
        lattice: &Lattice,
        hierarchy: &Hierarchy,
        draw: &mut WuBuffers,
        at_once: bool,
    ) {
        let mut changes = std::mem::take(&mut self.changes);
        draw.take_changes(&mut changes);
        if at_once {
            debug_assert!(
                self.morphs.is_empty(),
                "the first frame starts from the base mesh"
            );
            for &(p, edit) in &changes {
                let parents = lattice.parents(p).len() as u64;
                if edit == Edit::Insert {
                    self.drawn.insert(lattice.id(p));
                    self.n_triangles += parents;
                } else {
                    self.drawn.remove(lattice.id(p));
                    self.n_triangles -= parents;
                }
                draw.record_edit(p, edit);
            }
            changes.clear();
            self.changes = changes;
            return;
        }
        self.step(lattice, hierarchy, draw);
        for &(p, edit) in &changes {
            match edit {
                Edit::Insert => self.follow(lattice, hierarchy, p, true, draw),
                Edit::Delete => self.follow(lattice, hierarchy, p, false, draw),
                Edit::InsertAt(_) | Edit::Height(_) => {
                    unreachable!("the vertex set records inserts and deletes only")
                }
            }
        }
        changes.clear();
        self.changes = changes;
    }

    /// The drawn mesh, at its morphed heights.
    pub fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::morphed_lattice(&self.drawn, &self.heights)
    }

    /// The drawn mesh's triangles.
    pub fn triangle_count(&self) -> u64 {
        self.n_triangles
    }

    pub fn memory_bytes(&self) -> usize {
        self.drawn.memory_bytes()
            + self.heights.memory_bytes()
            + self.morphs.len() * (size_of::<u32>() + size_of::<Morph>() + 16)
            + self.changes.capacity() * size_of::<(GridPoint, Edit)>()
            + self.finished.capacity() * size_of::<u32>()
    }

    /// Moves every morph one level on; a vertex that has risen is drawn at its sample, one that
    /// has sunk (drawn a frame at the midpoint) leaves the mesh when nothing drawn depends on it.
    fn step(&mut self, lattice: &Lattice, hierarchy: &Hierarchy, draw: &mut WuBuffers) {
        let n = self.frames;
        self.finished.clear();
        for (&id, morph) in &mut self.morphs {
            if morph.rising {
                morph.level += 1;
            } else if morph.level > 0 {
                morph.level -= 1;
            } else {
                self.finished.push(id);
                continue;
            }
            let p = lattice.point(id);
            if morph.rising && morph.level >= n {
                self.finished.push(id);
                draw.record_edit(p, Edit::Height(hierarchy.height(p)));
            } else {
                let z = drawn_height(morph, n);
                self.heights.set(id, z);
                draw.record_edit(p, Edit::Height(z));
            }
        }
        for k in 0..self.finished.len() {
            let id = self.finished[k];
            let p = lattice.point(id);
            if self.morphs[&id].rising {
                self.morphs.remove(&id);
                self.heights.remove(id);
            } else if !lattice
                .children(p)
                .as_slice()
                .iter()
                .any(|&c| self.drawn.contains_point(lattice, c))
            {
                self.morphs.remove(&id);
                self.heights.remove(id);
                self.drawn.remove(id);
                self.n_triangles -= lattice.parents(p).len() as u64;
                draw.record_edit(p, Edit::Delete);
            }
        }
    }

    /// The vertex set gained (`rising`) or lost `p`: a vertex already morphing turns round
    /// where it is; a new one joins the drawn mesh at its edge's midpoint and rises; one leaving
    /// starts sinking from its sample.
    fn follow(
        &mut self,
        lattice: &Lattice,
        hierarchy: &Hierarchy,
        p: GridPoint,
        rising: bool,
        draw: &mut WuBuffers,
    ) {
        let id = lattice.id(p);
        if let Some(morph) = self.morphs.get_mut(&id) {
            morph.rising = rising;
            return;
        }
        let morph = Morph {
            level: if rising { 0 } else { self.frames },
            rising,
            low: edge_midpoint_height(lattice, hierarchy, p),
            high: hierarchy.height(p),
        };
        let z = drawn_height(&morph, self.frames);
        self.morphs.insert(id, morph);
        self.heights.set(id, z);
        if rising {
            self.drawn.insert(id);
            self.n_triangles += lattice.parents(p).len() as u64;
            draw.record_edit(p, Edit::InsertAt(z));
        } else {
            draw.record_edit(p, Edit::Height(z));
        }
    }
}

/// The height of the coarse surface at `p`: the mean of its bisected edge's ends' samples.
fn edge_midpoint_height(lattice: &Lattice, hierarchy: &Hierarchy, p: GridPoint) -> f32 {
    let [a, b] = lattice
        .bisected_edge(p)
        .expect("a corner is never inserted or deleted");
    (hierarchy.height(a) + hierarchy.height(b)) * 0.5
}

/// The height a morph draws its vertex at.
fn drawn_height(morph: &Morph, frames: u32) -> f32 {
    morph_height(morph.low, morph.high, morph.level as f32 / frames as f32)
}
