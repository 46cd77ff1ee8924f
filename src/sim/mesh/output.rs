//! The mesh an algorithm hands the runner, in one of two forms, and the one way every consumer
//! visits its triangles: SPEC §3's two kinds of mesh under SPEC §7's one yardstick. It borrows
//! the algorithm's mesh for the frame and stores nothing; it is not a renderer's buffer.
//!
//! - [`MeshOutput::Lattice`], the 4-8 fast path: a [`VertexSet`] closed under parents, plus
//!   optionally [`MorphedHeights`] (vertices drawn at a geomorphed height). Wu, ROAM, Lindstrom,
//!   the references (and Röttger's restricted quadtree) hand this form.
//! - [`MeshOutput::Triangles`], the general form: a [`TriangleList`] with positions and heights
//!   of its own, roles (surface, skirt, degenerate, stitch), groups and levels, and a declared
//!   crack policy. Block-based families (geomipmapping, chunked LOD, Vaněk–Ježek, stitching
//!   strips) hand this form.
//!
//! [`MeshOutput::for_each_triangle`] is the visitor: every triangle with its three corners
//! (position and drawn height) and its [`TriangleInfo`]. Culling, the audit, the validators,
//! the preview and mesh export all read meshes through it, whatever the form (the
//! lowest common denominator of the two forms). A lattice mesh's triangles are visited in
//! bintree order ([`super::triangles::for_each_triangle`]), all of role surface, group 0, level
//! = depth in the bintree, corners (apex, left, right); a triangle list's in the order the
//! algorithm added them, corners in the order it gave. Either way the corners are in drawing
//! order, counter-clockwise seen from above ([`super::winding`]), as the validators check.
//!
//! What consumers may still do by form: the audit keeps its exact integer rasteriser for the
//! lattice form (bit-identical figures since the first release) and uses the general one with
//! its tie rule for triangle lists; the 4-8 validator checks the vertex set, the triangle-list
//! validator the list. Both are fed by the visitor.

use super::VertexSet;
use super::morph::MorphedHeights;
use super::position::{SubgridPoint, SurfacePoint};
use super::triangle_list::{TriangleInfo, TriangleList, TriangleRole};
use super::triangles;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::stats::MeshCounts;

/// One drawn triangle: its corners as drawn and what it is drawn for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawnTriangle {
    pub corners: [SurfacePoint; 3],
    pub info: TriangleInfo,
}

/// A 4-8 mesh: the active vertices, and the heights of those drawn morphed.
#[derive(Clone, Copy, Debug)]
pub struct LatticeMesh<'a> {
    pub vertices: &'a VertexSet,
    /// Vertices drawn at a height other than their sample's; `None`: none are.
    pub morphed: Option<&'a MorphedHeights>,
}

/// The mesh of one frame, borrowed from the algorithm that drew it.
#[derive(Clone, Copy, Debug)]
pub enum MeshOutput<'a> {
    Lattice(LatticeMesh<'a>),
    Triangles(&'a TriangleList),
}

impl<'a> MeshOutput<'a> {
    /// A 4-8 mesh drawn at its samples' heights.
    pub fn lattice(vertices: &'a VertexSet) -> MeshOutput<'a> {
        MeshOutput::Lattice(LatticeMesh {
            vertices,
            morphed: None,
        })
    }

    /// A 4-8 mesh whose vertices in `morphed` are drawn at their morphed heights.
    pub fn morphed_lattice(vertices: &'a VertexSet, morphed: &'a MorphedHeights) -> MeshOutput<'a> {
        MeshOutput::Lattice(LatticeMesh {
            vertices,
            morphed: Some(morphed),
        })
    }

    /// A general triangle list.
    pub fn triangles(list: &'a TriangleList) -> MeshOutput<'a> {
        MeshOutput::Triangles(list)
    }

    /// The active vertices of a 4-8 mesh; `None` for a triangle list.
    pub fn lattice_vertices(self) -> Option<&'a VertexSet> {
        match self {
            MeshOutput::Lattice(mesh) => Some(mesh.vertices),
            MeshOutput::Triangles(_) => None,
        }
    }

    /// Calls `visit` on every drawn triangle, skirts and degenerate triangles included, in a
    /// deterministic order. O(T); allocates only the lattice descent's small stack.
    pub fn for_each_triangle(self, hierarchy: &Hierarchy, visit: impl FnMut(&DrawnTriangle)) {
        self.for_each_triangle_within(hierarchy, |_| true, visit);
    }

    /// [`MeshOutput::for_each_triangle`], skipping (for a 4-8 mesh) the bintree's subtrees
    /// whose triangle's plane corners (heights not looked up: 0) `within` rejects; `within`
    /// must then reject every triangle inside such a triangle (a test of overlap with a
    /// region does). A triangle list's triangles are all visited.
    pub fn for_each_triangle_within(
        self,
        hierarchy: &Hierarchy,
        mut within: impl FnMut(&[SurfacePoint; 3]) -> bool,
        mut visit: impl FnMut(&DrawnTriangle),
    ) {
        match self {
            MeshOutput::Lattice(mesh) => {
                let lattice = hierarchy.lattice();
                let corner = |p| SurfacePoint {
                    position: SubgridPoint::from(p),
                    z: match mesh.morphed {
                        None => hierarchy.height(p),
                        Some(morphed) => morphed
                            .get(lattice.id(p))
                            .unwrap_or_else(|| hierarchy.height(p)),
                    },
                };
                let plane = |p| SurfacePoint {
                    position: SubgridPoint::from(p),
                    z: 0.0,
                };
                let within = |t: &triangles::Triangle| {
                    within(&[plane(t.apex), plane(t.left), plane(t.right)])
                };
                triangles::for_each_triangle_within(lattice, mesh.vertices, within, |t| {
                    visit(&DrawnTriangle {
                        corners: [corner(t.apex), corner(t.left), corner(t.right)],
                        info: TriangleInfo {
                            role: TriangleRole::Surface,
                            group: 0,
                            level: t.level(lattice),
                        },
                    });
                });
            }
            MeshOutput::Triangles(list) => {
                let vertices = list.vertices();
                for (corners, info) in list.triangles().iter().zip(list.info()) {
                    visit(&DrawnTriangle {
                        corners: corners.map(|k| vertices[k as usize]),
                        info: *info,
                    });
                }
            }
        }
    }

    /// What the families beyond plain 4-8 meshes are counted by: triangles by role, draw
    /// batches, morphing vertices. `None` for a 4-8 mesh without morphed heights (nothing to
    /// count there but its triangles); `triangles` is the mesh's triangle count (a 4-8 mesh's
    /// is not stored with it).
    pub fn counts(self, triangles: u64) -> Option<MeshCounts> {
        match self {
            MeshOutput::Lattice(LatticeMesh { morphed: None, .. }) => None,
            MeshOutput::Lattice(LatticeMesh {
                morphed: Some(morphed),
                ..
            }) => Some(MeshCounts {
                triangles_by_role: [triangles, 0, 0, 0],
                morphing_vertices: morphed.len() as u64,
            }),
            MeshOutput::Triangles(list) => Some(MeshCounts {
                triangles_by_role: TriangleRole::ALL.map(|role| list.role_count(role)),
                morphing_vertices: list.morphing_vertices(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::hierarchy::GridPoint;
    use crate::sim::terrain::{Heightfield, Spacing};

    fn ramp() -> Hierarchy {
        let side = 5;
        let heights = (0..side * side).map(|k| (k % side) as f32).collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 1.0, dy: 1.0 }).unwrap())
    }

    #[test]
    fn a_lattice_mesh_is_visited_as_surface_triangles_with_sample_or_morphed_heights() {
        let hierarchy = ramp();
        let lattice = hierarchy.lattice();
        let mut vertices = VertexSet::base_mesh(lattice);
        let centre = GridPoint::new(2, 2);
        vertices.insert(lattice.id(centre));
        let mut seen = Vec::new();
        MeshOutput::lattice(&vertices).for_each_triangle(&hierarchy, |t| seen.push(*t));
        assert_eq!(seen.len(), 4);
        assert!(seen.iter().all(|t| t.info.role == TriangleRole::Surface));
        assert!(seen.iter().all(|t| t.info.level == 1));
        let centre_z = |seen: &[DrawnTriangle]| {
            seen[0]
                .corners
                .iter()
                .find(|c| c.position == SubgridPoint::grid(2, 2))
                .map(|c| c.z)
        };
        assert_eq!(centre_z(&seen), Some(2.0));

        let mut morphed = MorphedHeights::new();
        morphed.set(lattice.id(centre), 7.5);
        let mesh = MeshOutput::morphed_lattice(&vertices, &morphed);
        seen.clear();
        mesh.for_each_triangle(&hierarchy, |t| seen.push(*t));
        assert_eq!(centre_z(&seen), Some(7.5));
        let counts = mesh.counts(4).unwrap();
        assert_eq!(
            (counts.triangles_by_role, counts.morphing_vertices),
            ([4, 0, 0, 0], 1)
        );
        assert_eq!(MeshOutput::lattice(&vertices).counts(4), None);
    }
}
