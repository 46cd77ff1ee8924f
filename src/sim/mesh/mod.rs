//! Meshes: what an algorithm draws, in the two forms of [`MeshOutput`], and what checks them
//! (SPEC §3: the 4-8 family, and the families beyond it). Not an algorithm's own mesh structure:
//! bintrees, block trees and queues stay with each algorithm, which hands its mesh over in one of
//! these two forms.
//!
//! - The 4-8 form: [`VertexSet`], a set of active vertices closed under parents, one bit per
//!   grid vertex (2^28 vertices of a 16385² grid take 32 MiB) plus a count. Triangles are not
//!   stored; they follow from the set ([`triangles::for_each_triangle`]). [`validate::validate`]
//!   checks what makes a set a mesh. Optional [`MorphedHeights`] draw some vertices at heights
//!   of their own ([`morph`]).
//! - The general form: [`TriangleList`] ([`triangle_list`]), positions ([`position`]) and
//!   heights of its own, a role, group and level per triangle, a declared [`CrackPolicy`];
//!   [`list_validate`] checks it.
//! - [`check`]: what `--check` runs on either form; [`winding`]: the rule both validators hold
//!   every drawn triangle to (counter-clockwise seen from above, flat ones excepted).
//! - [`output`]: [`MeshOutput`], the one type algorithms hand the runner, and its triangle
//!   visitor; [`raster`]: the rasterisers the audit and the validators share.

pub mod check;
pub mod list_validate;
pub mod morph;
pub mod output;
pub mod position;
pub mod raster;
pub mod rebuilt;
pub mod triangle_list;
pub mod triangles;
pub mod validate;
pub mod winding;

pub use morph::MorphedHeights;
pub use output::{DrawnTriangle, LatticeMesh, MeshOutput};
pub use position::{SUBGRID_BITS, SUBGRID_UNITS_PER_CELL, SubgridPoint, SurfacePoint};
pub use triangle_list::{CrackPolicy, TriangleInfo, TriangleList, TriangleRole};
pub use winding::Winding;

use crate::sim::hierarchy::{GridPoint, Lattice};

/// A set of grid vertices, by vertex id. Inserting and removing are O(1); clearing is O(grid/64).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VertexSet {
    words: Vec<u64>,
    len: usize,
}

impl VertexSet {
    /// The empty set over a lattice's vertices.
    pub fn new(lattice: &Lattice) -> VertexSet {
        VertexSet {
            words: vec![0; lattice.n_vertices().div_ceil(64)],
            len: 0,
        }
    }

    /// The set holding only the four corners: the base mesh of two triangles.
    pub fn base_mesh(lattice: &Lattice) -> VertexSet {
        let mut set = VertexSet::new(lattice);
        for corner in lattice.corners() {
            set.insert(lattice.id(corner));
        }
        set
    }

    pub fn contains(&self, id: u32) -> bool {
        self.words[(id / 64) as usize] & (1 << (id % 64)) != 0
    }

    /// Inserts `id`; returns whether it was absent.
    pub fn insert(&mut self, id: u32) -> bool {
        let word = &mut self.words[(id / 64) as usize];
        let bit = 1 << (id % 64);
        let absent = *word & bit == 0;
        *word |= bit;
        // Not `self.len += usize::from(absent)`: rustc 1.95 at opt-level >= 2 miscompiles that
        // form inside insertion loops (the count stays 0 while the bits are set; compare
        // rust-lang/rust#158206). The branch is what release builds get right; the regression
        // test `vertex_set_len_matches_its_bits_in_an_insertion_loop` guards it.
        if absent {
            self.len += 1;
        }
        absent
    }

    /// Removes `id`; returns whether it was present.
    pub fn remove(&mut self, id: u32) -> bool {
        let word = &mut self.words[(id / 64) as usize];
        let bit = 1 << (id % 64);
        let present = *word & bit != 0;
        *word &= !bit;
        // A branch, not `-= usize::from(present)`: see `insert`.
        if present {
            self.len -= 1;
        }
        present
    }

    pub fn len(&self) -> usize {
        self.len
    }

    /// Heap bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.words.capacity() * std::mem::size_of::<u64>()
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Ids in increasing order.
    pub fn iter(&self) -> impl Iterator<Item = u32> + '_ {
        self.words.iter().enumerate().flat_map(|(w, &word)| {
            let mut bits = word;
            std::iter::from_fn(move || {
                (bits != 0).then(|| {
                    let bit = bits.trailing_zeros();
                    bits &= bits - 1;
                    w as u32 * 64 + bit
                })
            })
        })
    }

    /// Whether every member of `self` is in `other`.
    pub fn is_subset(&self, other: &VertexSet) -> bool {
        self.words
            .iter()
            .zip(&other.words)
            .all(|(a, b)| a & !b == 0)
    }

    /// T = 2 + Σ over active non-corner vertices of their number of parents: the triangle count
    /// of a closed set.
    pub fn triangle_count(&self, lattice: &Lattice) -> u64 {
        2 + self
            .iter()
            .map(|id| lattice.parents(lattice.point(id)).len() as u64)
            .sum::<u64>()
    }

    pub fn contains_point(&self, lattice: &Lattice, p: GridPoint) -> bool {
        self.contains(lattice.id(p))
    }
}
