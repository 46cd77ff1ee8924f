//! The triangles of a 4-8 mesh, found by descending the bintree of right triangles (SPEC §3:
//! triangles follow from the active vertex set alone). Nothing here stores triangles; a
//! triangle list is visited as its algorithm built it ([`super::MeshOutput::for_each_triangle`]).
//!
//! Start from the two base triangles (hypotenuse from (0,0) to (2^n,2^n)); a triangle is split
//! when the midpoint of its hypotenuse is an active vertex. This visits O(T) triangles and
//! allocates only a small stack (depth ≤ 2n). It assumes nothing of the set: on a set that is not
//! closed it still terminates, and the validator compares its count with the formula.

use super::VertexSet;
use crate::sim::hierarchy::{GridPoint, Lattice};

/// A right isosceles triangle: `apex` is the right-angle corner, `left`–`right` the hypotenuse.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Triangle {
    pub apex: GridPoint,
    pub left: GridPoint,
    pub right: GridPoint,
}

impl Triangle {
    /// The midpoint of the hypotenuse, if it is a grid vertex.
    pub fn split_vertex(&self) -> Option<GridPoint> {
        let (si, sj) = (self.left.i + self.right.i, self.left.j + self.right.j);
        (si % 2 == 0 && sj % 2 == 0).then(|| GridPoint::new(si / 2, sj / 2))
    }

    /// The triangle's depth in the bintree: the base triangles (hypotenuse² = 2·4^n in grid
    /// units) are level 0 and each split halves the squared hypotenuse.
    pub fn level(&self, lattice: &Lattice) -> u32 {
        let di = u64::from(self.left.i.abs_diff(self.right.i));
        let dj = u64::from(self.left.j.abs_diff(self.right.j));
        let hypotenuse_squared = di * di + dj * dj;
        2 * lattice.level() + 1 - hypotenuse_squared.ilog2()
    }

    /// The two halves when split at `mid` (the hypotenuse midpoint).
    pub fn children(&self, mid: GridPoint) -> [Triangle; 2] {
        [
            Triangle {
                apex: mid,
                left: self.apex,
                right: self.left,
            },
            Triangle {
                apex: mid,
                left: self.right,
                right: self.apex,
            },
        ]
    }
}

/// The two triangles of the base mesh.
pub fn base_triangles(lattice: &Lattice) -> [Triangle; 2] {
    let [sw, se, nw, ne] = lattice.corners();
    [
        Triangle {
            apex: se,
            left: ne,
            right: sw,
        },
        Triangle {
            apex: nw,
            left: sw,
            right: ne,
        },
    ]
}

/// Calls `visit` on every triangle of the mesh, in a deterministic order.
pub fn for_each_triangle(lattice: &Lattice, set: &VertexSet, visit: impl FnMut(&Triangle)) {
    for_each_triangle_within(lattice, set, |_| true, visit);
}

/// [`for_each_triangle`] without the subtrees of the bintree whose triangle `within` rejects:
/// the triangles of the mesh inside accepted ancestors, in the same order. A triangle holds
/// its descendants, so a test of a region (a box) that rejects a triangle rejects them all.
pub fn for_each_triangle_within(
    lattice: &Lattice,
    set: &VertexSet,
    mut within: impl FnMut(&Triangle) -> bool,
    mut visit: impl FnMut(&Triangle),
) {
    let mut stack: Vec<Triangle> = base_triangles(lattice).into_iter().rev().collect();
    while let Some(triangle) = stack.pop() {
        if !within(&triangle) {
            continue;
        }
        match triangle.split_vertex() {
            Some(mid) if set.contains_point(lattice, mid) => {
                let [first, second] = triangle.children(mid);
                stack.push(second);
                stack.push(first);
            }
            _ => visit(&triangle),
        }
    }
}

/// The number of triangles, by enumeration.
pub fn count_triangles(lattice: &Lattice, set: &VertexSet) -> u64 {
    let mut count = 0;
    for_each_triangle(lattice, set, |_| count += 1);
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_base_triangles_are_level_zero_and_each_split_goes_one_level_down() {
        let lattice = Lattice::new(4);
        let [first, _] = base_triangles(&lattice);
        assert_eq!(first.level(&lattice), 0);
        let mut triangle = first;
        for level in 1..=2 * lattice.level() {
            let mid = triangle.split_vertex().unwrap();
            triangle = triangle.children(mid)[level as usize % 2];
            assert_eq!(triangle.level(&lattice), level);
        }
        assert_eq!(
            triangle.split_vertex(),
            None,
            "the finest level has no split vertex"
        );
    }
}
