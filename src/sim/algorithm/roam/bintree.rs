//! ROAM's triangle bintree (ROAM'97; SPEC §6): right triangles in a `SlotMap`, linked to parent,
//! children and their three neighbours. The data structure only: no priorities, no queues.
//!
//! Every triangle is a [`Triangle`] of the shared 4-8 family (apex = right-angle corner,
//! left–right = hypotenuse). Its children split the hypotenuse at its midpoint, the *split
//! vertex*: child 0 covers the leg apex–left, child 1 the leg apex–right (the order of
//! [`Triangle::children`]). Neighbour links are kept exact for leaves only:
//! - `base`: across the hypotenuse (the same level, forming a diamond, or one level coarser);
//! - `left`: across the leg apex–left; `right`: across the leg apex–right
//!   (the same level or one level finer-or-coarser, as ROAM's bintree allows).
//!
//! A split triangle keeps `partner`, the other half of the diamond it was split with (`None` on
//! the border), until it is merged. Each triangle also carries what the effects keep on it: its
//! §7.1 culling flags (`cull.rs`), its place in a §7.2 triangle strip (`strips.rs`, leaves only)
//! and the frame its priority is next due (`deferral.rs`), and a copy of its corners and
//! thicknesses ([`Geometry`], filled in by the core). The structure does no priority work;
//! `split.rs` and `merge.rs` change its topology, `validate.rs` checks it. Memory: one slot
//! (about 200 bytes) per triangle, leaves and interior nodes alike.

use super::cull::CullFlags;
use crate::sim::draw::strips::{self, StripCounts};
use crate::sim::hierarchy::{GridPoint, Lattice};
use crate::sim::mesh::VertexSet;
use crate::sim::mesh::triangles::{Triangle, base_triangles};
use slotmap::{SlotMap, new_key_type};

new_key_type! {
    /// A triangle of the bintree. Keys are never used to order anything (see `queues.rs`).
    pub struct TriangleKey;
}

/// Which side of a triangle a neighbour lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Base,
    Left,
    Right,
}

/// One triangle of the bintree.
#[derive(Clone, Debug)]
pub struct BinTriangle {
    pub shape: Triangle,
    /// 0 for the two base triangles.
    pub depth: u32,
    pub parent: Option<TriangleKey>,
    pub children: Option<[TriangleKey; 2]>,
    pub base: Option<TriangleKey>,
    pub left: Option<TriangleKey>,
    pub right: Option<TriangleKey>,
    /// For a split triangle: the other triangle split at the same vertex.
    pub partner: Option<TriangleKey>,
    /// The §7.1 frustum flags of the triangle's wedgie (kept only with culling flags on).
    pub flags: CullFlags,
    /// The leaf's place in a §7.2 strip (`None` when it is in none: strips off, not drawn, or an
    /// interior triangle).
    pub strip: Option<StripLinks>,
    /// The frame at which the queued priority of this triangle (a leaf's, or the diamond's it is
    /// the primary parent of) is due for recomputation under deferral; `u64::MAX` when none.
    pub due: u64,
    /// What eq. (3) and the frustum tests read, copied in when the triangle is created.
    pub geometry: Geometry,
}

/// A triangle's corners and thicknesses, copied from the terrain and the thickness tables when
/// the triangle is created so that a priority or a frustum test reads one slot and nothing else
/// (the per-frame recomputation walks the slot map in order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometry {
    /// Apex, left, right, in terrain-local coordinates.
    pub corners: [glam::DVec3; 3],
    /// e_T for the priority (0 when the triangle cannot split).
    pub thickness: f32,
    /// e_T for the culling flags (a nested bound).
    pub culling_thickness: f32,
    /// The triangle's tie key in the split queue (`queues.rs`); 0 when it cannot split.
    pub tie: u64,
}

impl Geometry {
    /// Before the core fills it in.
    pub const UNSET: Geometry = Geometry {
        corners: [glam::DVec3::ZERO; 3],
        thickness: f32::NAN,
        culling_thickness: f32::NAN,
        tie: 0,
    };

    /// The geometry of the triangle `shape` from the terrain and the thickness tables.
    pub fn of(
        shape: &Triangle,
        field: &crate::sim::terrain::Heightfield,
        thicknesses: &super::thickness::Thicknesses,
        lattice: &Lattice,
    ) -> Geometry {
        let position = |p: GridPoint| field.position(p.i as usize, p.j as usize);
        let (thickness, culling_thickness, tie) = match shape.split_vertex() {
            Some(mid) => (
                thicknesses.priority(mid, shape.apex),
                thicknesses.culling(mid, shape.apex),
                super::queues::QueueKey::triangle_tie(lattice, mid, shape.apex),
            ),
            None => (0.0, 0.0, 0),
        };
        Geometry {
            corners: [
                position(shape.apex),
                position(shape.left),
                position(shape.right),
            ],
            thickness,
            culling_thickness,
            tie,
        }
    }
}

/// A leaf's place in a triangle strip (`sim::draw::strips`): its neighbours in the strip and
/// the order of its corners (0 apex, 1 left, 2 right) in the strip's vertex sequence.
pub type StripLinks = strips::StripLinks<TriangleKey>;

impl BinTriangle {
    pub fn is_leaf(&self) -> bool {
        self.children.is_none()
    }

    pub fn neighbour(&self, side: Side) -> Option<TriangleKey> {
        match side {
            Side::Base => self.base,
            Side::Left => self.left,
            Side::Right => self.right,
        }
    }

    /// The midpoint of the hypotenuse, or `None` at the finest level.
    pub fn split_vertex(&self) -> Option<GridPoint> {
        self.shape.split_vertex()
    }

    /// The edge on `side`, as an unordered pair (smaller point first).
    pub fn edge(&self, side: Side) -> [GridPoint; 2] {
        let t = &self.shape;
        let (a, b) = match side {
            Side::Base => (t.left, t.right),
            Side::Left => (t.apex, t.left),
            Side::Right => (t.apex, t.right),
        };
        [a.min(b), a.max(b)]
    }
}

/// The bintree over one lattice. Invariants (checked by `validate.rs`): leaves tile the square;
/// leaf links are symmetric and geometric; `mesh` holds the corners plus the split vertex of
/// every split triangle; `n_leaves` counts the leaves; the strip links form valid strips whose
/// numbers `strips.rs` keeps in `strip_counts`.
pub struct Bintree {
    pub(super) lattice: Lattice,
    pub(super) triangles: SlotMap<TriangleKey, BinTriangle>,
    pub(super) roots: [TriangleKey; 2],
    pub(super) mesh: VertexSet,
    pub(super) n_leaves: u64,
    /// Strips and the triangles in them (`strips.rs`).
    pub(super) strip_counts: StripCounts,
}

impl Bintree {
    /// The base mesh: two triangles sharing the diagonal from (0, 0) to (2^n, 2^n).
    pub fn new(lattice: &Lattice) -> Bintree {
        let mut bintree = Bintree {
            lattice: *lattice,
            triangles: SlotMap::with_key(),
            roots: [TriangleKey::default(); 2],
            mesh: VertexSet::base_mesh(lattice),
            n_leaves: 2,
            strip_counts: StripCounts::default(),
        };
        bintree.reset();
        bintree
    }

    /// Back to the base mesh, keeping the allocations. O(triangles + active vertices).
    pub fn reset(&mut self) {
        for triangle in self.triangles.values() {
            if let Some(mid) = triangle.split_vertex()
                && triangle.children.is_some()
            {
                self.mesh.remove(self.lattice.id(mid));
            }
        }
        self.triangles.clear();
        let [first, second] = base_triangles(&self.lattice);
        let root = |shape| BinTriangle {
            shape,
            depth: 0,
            parent: None,
            children: None,
            base: None,
            left: None,
            right: None,
            partner: None,
            flags: CullFlags::UNKNOWN,
            strip: None,
            due: u64::MAX,
            geometry: Geometry::UNSET,
        };
        let a = self.triangles.insert(root(first));
        let b = self.triangles.insert(root(second));
        self.triangles[a].base = Some(b);
        self.triangles[b].base = Some(a);
        self.roots = [a, b];
        self.n_leaves = 2;
        self.strip_counts = StripCounts::default();
    }

    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    pub fn get(&self, key: TriangleKey) -> &BinTriangle {
        &self.triangles[key]
    }

    pub fn roots(&self) -> [TriangleKey; 2] {
        self.roots
    }

    pub fn mesh(&self) -> &VertexSet {
        &self.mesh
    }

    pub fn n_leaves(&self) -> u64 {
        self.n_leaves
    }

    /// Strips and the triangles in them.
    pub fn strip_counts(&self) -> StripCounts {
        self.strip_counts
    }

    /// Every triangle, leaves and interior, in slot order.
    pub fn iter(&self) -> impl Iterator<Item = (TriangleKey, &BinTriangle)> {
        self.triangles.iter()
    }

    pub(super) fn get_mut(&mut self, key: TriangleKey) -> &mut BinTriangle {
        &mut self.triangles[key]
    }

    /// Points `neighbour`'s link that referred to `old` at `new` instead.
    pub(super) fn relink(
        &mut self,
        neighbour: Option<TriangleKey>,
        old: TriangleKey,
        new: TriangleKey,
    ) {
        let Some(n) = neighbour else {
            return;
        };
        let triangle = &mut self.triangles[n];
        if triangle.base == Some(old) {
            triangle.base = Some(new);
        } else if triangle.left == Some(old) {
            triangle.left = Some(new);
        } else if triangle.right == Some(old) {
            triangle.right = Some(new);
        }
    }
}
