//! ROAM's triangle bintree: right triangles in a `SlotMap`, linked to parent, children and their
//! three neighbours.
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
//! the border), until it is merged. With strips on, the leaves also form a doubly linked list in
//! Sierpinski (curve) order, `prev`/`next`, and the bintree counts the *joined junctions* of that
//! list (see `strips.rs`); split and merge keep both in O(1). The structure does no priority
//! work; `split.rs` and `merge.rs` change it, `validate.rs` checks it. Memory: one slot (about
//! 120 bytes) per triangle, leaves and interior nodes alike.

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
    /// For a leaf, with strips on: the previous leaf in curve order (`None` for the first).
    /// `None` on interior triangles and with strips off.
    pub prev: Option<TriangleKey>,
    /// For a leaf, with strips on: the next leaf in curve order (`None` for the last).
    pub next: Option<TriangleKey>,
    /// The §7.1 frustum flag of the triangle's wedgie (kept only with culling flags on).
    pub flag: CullFlag,
}

/// ROAM §7.1's frustum flag of a triangle's wedgie.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CullFlag {
    /// Entirely inside all six planes: descendants are inside too.
    Inside,
    /// Entirely outside one plane: descendants are outside too.
    Outside,
    /// Neither is known.
    DontKnow,
}

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
/// every split triangle; `n_leaves` counts the leaves; with `strips` on, the leaves' `prev`/`next`
/// links list every leaf once in curve order, from the first leaf of `roots[0]` to the last of
/// `roots[1]`, and `joined_junctions` counts the consecutive pairs of that list that continue a
/// strip (the rule of `strips.rs`).
pub struct Bintree {
    pub(super) lattice: Lattice,
    pub(super) triangles: SlotMap<TriangleKey, BinTriangle>,
    pub(super) roots: [TriangleKey; 2],
    pub(super) mesh: VertexSet,
    pub(super) n_leaves: u64,
    /// Whether the curve-order list and `joined_junctions` are kept (ROAM §7.2 strips).
    pub(super) strips: bool,
    pub(super) joined_junctions: u64,
}

impl Bintree {
    /// The base mesh: two triangles sharing the diagonal from (0, 0) to (2^n, 2^n). With
    /// `strips`, split and merge also keep the leaves' curve-order list (see `strips.rs`).
    pub fn new(lattice: &Lattice, strips: bool) -> Bintree {
        let mut bintree = Bintree {
            lattice: *lattice,
            triangles: SlotMap::with_key(),
            roots: [TriangleKey::default(); 2],
            mesh: VertexSet::base_mesh(lattice),
            n_leaves: 2,
            strips,
            joined_junctions: 0,
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
            prev: None,
            next: None,
            flag: CullFlag::DontKnow,
        };
        let a = self.triangles.insert(root(first));
        let b = self.triangles.insert(root(second));
        self.triangles[a].base = Some(b);
        self.triangles[b].base = Some(a);
        self.roots = [a, b];
        self.n_leaves = 2;
        self.joined_junctions = 0;
        if self.strips {
            super::strips::link_roots(self);
        }
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

    /// Whether the curve-order list and the joined-junction count are kept.
    pub fn tracks_strips(&self) -> bool {
        self.strips
    }

    /// Consecutive curve-order leaves that continue a strip (0 with strips off).
    pub fn joined_junctions(&self) -> u64 {
        self.joined_junctions
    }

    /// Every triangle, leaves and interior, in slot order.
    pub fn iter(&self) -> impl Iterator<Item = (TriangleKey, &BinTriangle)> {
        self.triangles.iter()
    }

    pub(super) fn set_flag(&mut self, key: TriangleKey, flag: CullFlag) {
        self.triangles[key].flag = flag;
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

    /// Leaves in Sierpinski order (consecutive leaves share a vertex), walked from the roots in
    /// O(triangles): the from-scratch reference for the incremental list of `strips.rs`. Reuses
    /// `stack` and `out`.
    pub fn leaves_in_curve_order(
        &self,
        stack: &mut Vec<(TriangleKey, bool)>,
        out: &mut Vec<TriangleKey>,
    ) {
        out.clear();
        stack.clear();
        stack.push((self.roots[1], true));
        stack.push((self.roots[0], true));
        while let Some((key, from_left)) = stack.pop() {
            match self.triangles[key].children {
                None => out.push(key),
                Some([c0, c1]) => {
                    // Entering at `left`: child 0 (leg apex–left) first, then child 1.
                    let (first, second) = if from_left { (c0, c1) } else { (c1, c0) };
                    stack.push((second, !from_left));
                    stack.push((first, !from_left));
                }
            }
        }
    }
}
