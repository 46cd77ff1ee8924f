//! The triangle-list validator: what makes a [`TriangleList`] a mesh of its terrain under the
//! crack policy it declares (SPEC §3: the meshes beyond the 4-8 family, with T-junctions, skirts,
//! collapsed borders and stitches). `roamsim run --check` runs it after every frame; tests call
//! it after every frame too. It does not measure how well the mesh fits the terrain (the audit
//! does); the 4-8 validator (`validate`) is separate.
//!
//! Checked, first failure reported (triangles and edges in the list's order, samples in
//! row-major order):
//!
//! 1. every triangle's role is allowed by the policy ([`CrackPolicy::allows`]);
//! 2. shapes: surface and stitch triangles have area in the plane; degenerate and skirt
//!    triangles have none (a skirt is vertical; a degenerate triangle is collapsed or a strip
//!    join); every triangle with area is wound counter-clockwise seen from above (as a GPU
//!    culls back faces, exact in fixed point: [`super::winding`]);
//! 3. the surface tiles the domain, less the regions the algorithm declares culled
//!    ([`TriangleList::culled_regions`]): the plane areas of the surface triangles and of the
//!    culled regions add up to the domain's, exactly (fixed-point integers), and every grid
//!    sample is owned by exactly one surface triangle under the rasteriser's tie rule
//!    ([`SampleRaster`]: a sample owned twice is an overlap, one owned by none a hole), except
//!    that a sample in a culled region is owned by none (strictly inside it) or at most one (on
//!    its boundary);
//! 4. borders: a surface edge inside the domain (ends and heights) must be shared by exactly two
//!    surface triangles under `closed`, `stitched` and `collapsed` (stitch triangles are surface;
//!    degenerate triangles are left out, so a collapsed border is closed by the triangles that
//!    keep their area), one on the domain's border or a culled region's; under `skirted`, an
//!    edge that is not shared is a crack and must be the top edge of a skirt triangle (same ends
//!    and heights) that hangs below it, at a depth of zero or more. The validator checks that a
//!    skirt is there, not how deep it reaches: the audit measures the crack gaps a skirt has to
//!    hide (`audit_crack_gap_max_m`) and the part of them the skirts leave open
//!    (`audit_crack_uncovered_max_m`);
//! 5. the algorithm's own triangle count equals the list's.
//!
//! Every check reads the list through the mesh visitor ([`MeshOutput::for_each_triangle`]), the
//! way every other consumer does; triangles are numbered in the order it visits them.
//!
//! Cost: O(T) for the shapes, areas and edges (a hash map of edges, kept across frames), plus
//! one pass of the rasteriser over every grid sample, O(samples).

use super::output::MeshOutput;
use super::position::{SubgridPoint, SurfacePoint};
use super::raster::SampleRaster;
use super::triangle_list::{CrackPolicy, TriangleList, TriangleRole};
use super::winding::plane_area2;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::SUBGRID_UNITS_PER_CELL;
use std::collections::HashMap;
use std::collections::hash_map::DefaultHasher;
use std::hash::BuildHasherDefault;

/// The first thing found wrong with a triangle list. Positions are in grid units.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TriangleListError {
    #[error(
        "triangle {triangle} has role {role:?}, which the crack policy {policy:?} does not allow"
    )]
    RoleNotAllowed {
        triangle: usize,
        role: TriangleRole,
        policy: CrackPolicy,
    },
    #[error("triangle {triangle} ({role:?}) has no area in the plane")]
    SurfaceWithoutArea { triangle: usize, role: TriangleRole },
    #[error("triangle {triangle} ({role:?}) should have no area in the plane but has")]
    FlatRoleWithArea { triangle: usize, role: TriangleRole },
    #[error(
        "triangle {triangle} ({role:?}, group {group}) is wound clockwise seen from above: signed \
         area {signed_area_cells} cells²"
    )]
    Clockwise {
        triangle: usize,
        role: TriangleRole,
        group: u32,
        signed_area_cells: f64,
    },
    #[error(
        "the surface triangles cover {surface_cells} cells² in the plane; the domain has {domain_cells}"
    )]
    AreaMismatch {
        surface_cells: f64,
        domain_cells: f64,
    },
    #[error("grid sample {sample:?} is covered by no surface triangle (a hole)")]
    Hole { sample: (usize, usize) },
    #[error("grid sample {sample:?} is covered by {owners} surface triangles (an overlap)")]
    Overlap { sample: (usize, usize), owners: u32 },
    #[error(
        "the surface edge {from:?}–{to:?} is shared by {count} surface triangles (the crack policy \
         {policy:?} wants 2 inside the domain, 1 on its border)"
    )]
    EdgeNotClosed {
        from: (f64, f64),
        to: (f64, f64),
        count: u32,
        policy: CrackPolicy,
    },
    #[error("the crack along the surface edge {from:?}–{to:?} has no skirt below it")]
    CrackNotSkirted { from: (f64, f64), to: (f64, f64) },
    #[error("the algorithm reports {reported} triangles; the list has {actual}")]
    ReportedCountWrong { reported: u64, actual: u64 },
}

/// An edge by its two ends (position and height bits), smaller end first.
type EdgeKey = ((SubgridPoint, u32), (SubgridPoint, u32));

/// Buffers of the validator, reused across frames.
#[derive(Debug, Default)]
pub struct TriangleListValidator {
    surface_edges: HashMap<EdgeKey, u32, BuildHasherDefault<DefaultHasher>>,
    skirt_edges: HashMap<EdgeKey, bool, BuildHasherDefault<DefaultHasher>>,
    owners: Vec<u32>,
}

impl TriangleListValidator {
    pub fn new() -> TriangleListValidator {
        TriangleListValidator::default()
    }

    /// Checks `list` (a mesh of `hierarchy`'s terrain) and that the algorithm's own count,
    /// `reported_triangles`, matches it.
    pub fn validate(
        &mut self,
        hierarchy: &Hierarchy,
        list: &TriangleList,
        reported_triangles: u64,
    ) -> Result<(), TriangleListError> {
        let mesh = MeshOutput::triangles(list);
        let policy = list.crack_policy();
        let mut first_error = None;
        let mut surface_area2: i128 = 0;
        let mut triangle = 0;
        let cell2 = (SUBGRID_UNITS_PER_CELL as f64).powi(2);
        mesh.for_each_triangle(hierarchy, |t| {
            let role = t.info.role;
            let area2 = plane_area2(&t.corners);
            let error = if !policy.allows(role) {
                Some(TriangleListError::RoleNotAllowed {
                    triangle,
                    role,
                    policy,
                })
            } else if role.is_surface() && area2 == 0 {
                Some(TriangleListError::SurfaceWithoutArea { triangle, role })
            } else if !role.is_surface() && area2 != 0 {
                Some(TriangleListError::FlatRoleWithArea { triangle, role })
            } else if area2 < 0 {
                Some(TriangleListError::Clockwise {
                    triangle,
                    role,
                    group: t.info.group,
                    signed_area_cells: area2 as f64 / 2.0 / cell2,
                })
            } else {
                None
            };
            if first_error.is_none() {
                first_error = error;
            }
            if role.is_surface() {
                surface_area2 += area2.abs();
            }
            triangle += 1;
        });
        if let Some(error) = first_error {
            return Err(error);
        }
        let domain = i128::from(list.domain_max());
        let culled_area2: i128 = list
            .culled_regions()
            .iter()
            .map(|(low, high)| {
                let ((x0, y0), (x1, y1)) = (low.raw(), high.raw());
                2 * i128::from(x1 - x0) * i128::from(y1 - y0)
            })
            .sum();
        let surface_area2 = surface_area2 + culled_area2;
        if surface_area2 != 2 * domain * domain {
            return Err(TriangleListError::AreaMismatch {
                surface_cells: surface_area2 as f64 / 2.0 / cell2,
                domain_cells: (domain * domain) as f64 / cell2,
            });
        }
        self.check_samples(hierarchy, list)?;
        self.check_borders(hierarchy, list)?;
        if list.n_triangles() != reported_triangles {
            return Err(TriangleListError::ReportedCountWrong {
                reported: reported_triangles,
                actual: list.n_triangles(),
            });
        }
        Ok(())
    }

    /// Every grid sample owned by exactly one surface triangle.
    fn check_samples(
        &mut self,
        hierarchy: &Hierarchy,
        list: &TriangleList,
    ) -> Result<(), TriangleListError> {
        let cells = (list.domain_max() / SUBGRID_UNITS_PER_CELL) as usize;
        let side = cells + 1;
        let raster = SampleRaster::new(SUBGRID_UNITS_PER_CELL, side, list.domain_max());
        self.owners.clear();
        self.owners.resize(side * side, 0);
        let owners = &mut self.owners;
        MeshOutput::triangles(list).for_each_triangle(hierarchy, |t| {
            if t.info.role.is_surface() {
                raster.for_each_covered_sample(&t.corners, |sample| {
                    owners[sample.index] += u32::from(sample.owned);
                });
            }
        });
        // Culled regions: nothing may own a sample strictly inside one; a sample on a region's
        // boundary may be owned by the surface beside it, or by none.
        let step = SUBGRID_UNITS_PER_CELL;
        for &(low, high) in list.culled_regions() {
            let ((x0, y0), (x1, y1)) = (low.raw(), high.raw());
            let first = |v: i64| ((v + step - 1) / step) as usize;
            let last = |v: i64| (v / step) as usize;
            for j in first(y0)..=last(y1) {
                for i in first(x0)..=last(x1) {
                    let (x, y) = (i as i64 * step, j as i64 * step);
                    let inside = x0 < x && x < x1 && y0 < y && y < y1;
                    let owners = &mut self.owners[j * side + i];
                    if inside && *owners != 0 {
                        return Err(TriangleListError::Overlap {
                            sample: (i, j),
                            owners: *owners + 1,
                        });
                    }
                    *owners = (*owners).max(1);
                }
            }
        }
        match self.owners.iter().position(|&n| n != 1) {
            None => Ok(()),
            Some(index) => {
                let sample = (index % side, index / side);
                match self.owners[index] {
                    0 => Err(TriangleListError::Hole { sample }),
                    owners => Err(TriangleListError::Overlap { sample, owners }),
                }
            }
        }
    }

    /// Shared surface edges, or skirts below the cracks.
    fn check_borders(
        &mut self,
        hierarchy: &Hierarchy,
        list: &TriangleList,
    ) -> Result<(), TriangleListError> {
        let policy = list.crack_policy();
        let mesh = MeshOutput::triangles(list);
        self.surface_edges.clear();
        self.skirt_edges.clear();
        let (surface_edges, skirt_edges) = (&mut self.surface_edges, &mut self.skirt_edges);
        mesh.for_each_triangle(hierarchy, |t| {
            let corners = t.corners;
            for k in 0..3 {
                let (a, b) = (corners[k], corners[(k + 1) % 3]);
                if a.position == b.position {
                    continue;
                }
                let key = edge_key(a, b);
                if t.info.role.is_surface() {
                    *surface_edges.entry(key).or_insert(0) += 1;
                } else if t.info.role == TriangleRole::Skirt {
                    // The third corner must hang below the edge: on the plane position of one
                    // of its ends, lower.
                    let c = corners[(k + 2) % 3];
                    let hangs = (c.position == a.position && c.z <= a.z)
                        || (c.position == b.position && c.z <= b.z);
                    *skirt_edges.entry(key).or_insert(false) |= hangs;
                }
            }
        });
        let domain_max = list.domain_max();
        let mut first_error = None;
        mesh.for_each_triangle(hierarchy, |t| {
            if first_error.is_some() || !t.info.role.is_surface() {
                return;
            }
            for k in 0..3 {
                let (a, b) = (t.corners[k], t.corners[(k + 1) % 3]);
                let key = edge_key(a, b);
                let count = self.surface_edges[&key];
                let on_border = on_domain_border(a.position, b.position, domain_max)
                    || on_culled_boundary(a.position, b.position, list.culled_regions());
                if count == if on_border { 1 } else { 2 } {
                    continue;
                }
                let skirted = policy == CrackPolicy::Skirted
                    && count == 1
                    && self.skirt_edges.get(&key) == Some(&true);
                if skirted {
                    continue;
                }
                let (from, to) = (a.position.grid_units(), b.position.grid_units());
                first_error = Some(if policy == CrackPolicy::Skirted && count == 1 {
                    TriangleListError::CrackNotSkirted { from, to }
                } else {
                    TriangleListError::EdgeNotClosed {
                        from,
                        to,
                        count,
                        policy,
                    }
                });
                return;
            }
        });
        first_error.map_or(Ok(()), Err)
    }
}

fn edge_key(a: SurfacePoint, b: SurfacePoint) -> EdgeKey {
    let (a, b) = ((a.position, a.z.to_bits()), (b.position, b.z.to_bits()));
    if a <= b { (a, b) } else { (b, a) }
}

/// Whether the segment lies on one of the domain's four sides.
fn on_domain_border(a: SubgridPoint, b: SubgridPoint, domain_max: i64) -> bool {
    let ((ax, ay), (bx, by)) = (a.raw(), b.raw());
    let both = |u: i64, v: i64, at: i64| u == at && v == at;
    both(ax, bx, 0) || both(ax, bx, domain_max) || both(ay, by, 0) || both(ay, by, domain_max)
}

/// Whether the segment lies on a side of one of the culled rectangles. O(regions); only asked
/// about edges that are not shared.
fn on_culled_boundary(
    a: SubgridPoint,
    b: SubgridPoint,
    culled: &[(SubgridPoint, SubgridPoint)],
) -> bool {
    let ((ax, ay), (bx, by)) = (a.raw(), b.raw());
    culled.iter().any(|(low, high)| {
        let ((x0, y0), (x1, y1)) = (low.raw(), high.raw());
        let within = |u: i64, lo: i64, hi: i64| lo <= u && u <= hi;
        let on_vertical = |x: i64| ax == x && bx == x && within(ay, y0, y1) && within(by, y0, y1);
        let on_horizontal = |y: i64| ay == y && by == y && within(ax, x0, x1) && within(bx, x0, x1);
        on_vertical(x0) || on_vertical(x1) || on_horizontal(y0) || on_horizontal(y1)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::hierarchy::Lattice;
    use crate::sim::mesh::TriangleInfo;
    use crate::sim::terrain::{Heightfield, Spacing};

    /// A flat 5×5 terrain: the domain of the lists below (the visitor reads no height of it).
    fn terrain() -> Hierarchy {
        let field = Heightfield::new(5, vec![0.0; 25], Spacing { dx: 1.0, dy: 1.0 }).unwrap();
        Hierarchy::new(field)
    }

    fn surface(group: u32) -> TriangleInfo {
        TriangleInfo {
            role: TriangleRole::Surface,
            group,
            level: 0,
        }
    }

    /// The 4×4-cell domain as two squares side by side ([0,2]×[0,4] and [2,4]×[0,4]), the
    /// right one split at (2, 2) and (4, 2) into two: a T-junction at (2, 2) when the left one
    /// is drawn whole.
    fn t_junction(policy: CrackPolicy, z_at_junction: f32) -> TriangleList {
        let mut list = TriangleList::new(&Lattice::new(2), policy);
        let mut v = |i: u32, j: u32, z: f32| list.add_vertex(SubgridPoint::grid(i, j), z);
        let (l0, l1, l2, l3) = (v(0, 0, 0.0), v(2, 0, 0.0), v(2, 4, 0.0), v(0, 4, 0.0));
        let (r0, r1, r2, r3) = (
            v(2, 0, 0.0),
            v(4, 0, 0.0),
            v(4, 2, 0.0),
            v(2, 2, z_at_junction),
        );
        let (r4, r5) = (v(4, 4, 0.0), v(2, 4, 0.0));
        for (corners, group) in [
            ([l0, l1, l2], 0),
            ([l0, l2, l3], 0),
            ([r0, r1, r2], 1),
            ([r0, r2, r3], 1),
            ([r3, r2, r4], 1),
            ([r3, r4, r5], 1),
        ] {
            list.add_triangle(corners, surface(group));
        }
        list
    }

    #[test]
    fn a_closed_mesh_passes_and_a_t_junction_is_an_open_edge() {
        let mut validator = TriangleListValidator::new();
        let mut closed = TriangleList::new(&Lattice::new(2), CrackPolicy::Closed);
        let c = [(0, 0), (4, 0), (4, 4), (0, 4)]
            .map(|(i, j)| closed.add_vertex(SubgridPoint::grid(i, j), 1.0));
        closed.add_triangle([c[0], c[1], c[2]], surface(0));
        closed.add_triangle([c[0], c[2], c[3]], surface(0));
        assert_eq!(validator.validate(&terrain(), &closed, 2), Ok(()));
        assert_eq!(
            validator.validate(&terrain(), &closed, 3),
            Err(TriangleListError::ReportedCountWrong {
                reported: 3,
                actual: 2
            })
        );
        let open = t_junction(CrackPolicy::Closed, 0.0);
        assert!(matches!(
            validator.validate(&terrain(), &open, 6),
            Err(TriangleListError::EdgeNotClosed { count: 1, .. })
        ));
    }

    #[test]
    fn under_the_skirted_policy_a_crack_needs_a_skirt_below_it() {
        let mut validator = TriangleListValidator::new();
        let bare = t_junction(CrackPolicy::Skirted, 3.0);
        assert!(matches!(
            validator.validate(&terrain(), &bare, 6),
            Err(TriangleListError::CrackNotSkirted { .. })
        ));
        // Skirts below the left square's right edge and the right squares' left edges.
        let mut skirted = t_junction(CrackPolicy::Skirted, 3.0);
        let skirt = TriangleInfo {
            role: TriangleRole::Skirt,
            group: 2,
            level: 0,
        };
        for (from, to) in [
            ((2, 0, 0.0), (2, 4, 0.0)),
            ((2, 0, 0.0), (2, 2, 3.0)),
            ((2, 2, 3.0), (2, 4, 0.0)),
        ] {
            let mut v =
                |(i, j, z): (u32, u32, f32)| skirted.add_vertex(SubgridPoint::grid(i, j), z);
            let (top_a, top_b) = (v(from), v(to));
            let bottom_b = v((to.0, to.1, to.2 - 10.0));
            skirted.add_triangle([top_a, top_b, bottom_b], skirt);
        }
        assert_eq!(validator.validate(&terrain(), &skirted, 9), Ok(()));
    }

    #[test]
    fn a_missing_triangle_is_an_area_mismatch_and_an_overlap_is_found() {
        let mut validator = TriangleListValidator::new();
        let mut list = TriangleList::new(&Lattice::new(2), CrackPolicy::Closed);
        let c = [(0, 0), (4, 0), (4, 4), (0, 4)]
            .map(|(i, j)| list.add_vertex(SubgridPoint::grid(i, j), 1.0));
        list.add_triangle([c[0], c[1], c[2]], surface(0));
        assert!(matches!(
            validator.validate(&terrain(), &list, 1),
            Err(TriangleListError::AreaMismatch { .. })
        ));
        // Same area, wrong place: the first triangle twice (its corners rotated).
        list.add_triangle([c[1], c[2], c[0]], surface(0));
        assert!(matches!(
            validator.validate(&terrain(), &list, 2),
            Err(TriangleListError::Overlap { owners: 2, .. })
        ));
    }

    #[test]
    fn a_culled_region_may_be_left_uncovered_but_not_overlapped_or_miscounted() {
        let mut validator = TriangleListValidator::new();
        // The west half drawn as two triangles, the east half declared culled.
        let half = |culled: Option<(SubgridPoint, SubgridPoint)>| {
            let mut list = TriangleList::new(&Lattice::new(2), CrackPolicy::Closed);
            let c = [(0, 0), (2, 0), (2, 4), (0, 4)]
                .map(|(i, j)| list.add_vertex(SubgridPoint::grid(i, j), 1.0));
            list.add_triangle([c[0], c[1], c[2]], surface(0));
            list.add_triangle([c[0], c[2], c[3]], surface(0));
            if let Some((low, high)) = culled {
                list.add_culled_region(low, high);
            }
            list
        };
        let east = (SubgridPoint::grid(2, 0), SubgridPoint::grid(4, 4));
        // Its border with the culled half is open, like the domain's border.
        assert_eq!(validator.validate(&terrain(), &half(Some(east)), 2), Ok(()));
        assert!(matches!(
            validator.validate(&terrain(), &half(None), 2),
            Err(TriangleListError::AreaMismatch { .. })
        ));
        // A culled region over drawn triangles: an overlap (here found by the areas).
        let west = (SubgridPoint::grid(0, 0), SubgridPoint::grid(2, 4));
        let mut both = half(Some(west));
        both.add_culled_region(east.0, east.1);
        assert!(validator.validate(&terrain(), &both, 2).is_err());
        // The areas add up, but the drawn triangle reaches into a culled region and leaves a
        // hole elsewhere: the sample (3, 1) is on its edge, owned by nothing.
        let mut list = TriangleList::new(&Lattice::new(2), CrackPolicy::Closed);
        let c =
            [(0, 0), (4, 0), (0, 4)].map(|(i, j)| list.add_vertex(SubgridPoint::grid(i, j), 1.0));
        list.add_triangle([c[0], c[1], c[2]], surface(0));
        list.add_culled_region(SubgridPoint::grid(2, 2), SubgridPoint::grid(4, 4));
        list.add_culled_region(SubgridPoint::grid(0, 2), SubgridPoint::grid(2, 4));
        assert_eq!(
            validator.validate(&terrain(), &list, 1),
            Err(TriangleListError::Hole { sample: (3, 1) })
        );
        // A drawn square inside a culled region: the sample strictly inside both is owned.
        let mut list = TriangleList::new(&Lattice::new(2), CrackPolicy::Closed);
        let c = [(0, 0), (4, 0), (4, 4), (0, 4)]
            .map(|(i, j)| list.add_vertex(SubgridPoint::grid(i, j), 1.0));
        list.add_triangle([c[0], c[1], c[2]], surface(0));
        list.add_triangle([c[0], c[2], c[3]], surface(0));
        let mut overlapping = list.clone();
        overlapping.add_culled_region(SubgridPoint::grid(1, 1), SubgridPoint::grid(3, 3));
        assert!(matches!(
            validator.validate(&terrain(), &overlapping, 2),
            Err(TriangleListError::AreaMismatch { .. })
        ));
    }

    #[test]
    fn a_clockwise_triangle_is_refused_with_its_index_role_group_and_signed_area() {
        let mut validator = TriangleListValidator::new();
        let square = |flip_second: bool| {
            let mut list = TriangleList::new(&Lattice::new(2), CrackPolicy::Closed);
            let c = [(0, 0), (4, 0), (4, 4), (0, 4)]
                .map(|(i, j)| list.add_vertex(SubgridPoint::grid(i, j), 1.0));
            list.add_triangle([c[0], c[1], c[2]], surface(0));
            let second = if flip_second {
                [c[0], c[3], c[2]]
            } else {
                [c[0], c[2], c[3]]
            };
            list.add_triangle(second, surface(7));
            list
        };
        assert_eq!(validator.validate(&terrain(), &square(false), 2), Ok(()));
        // The same two triangles, the same tiling, the second listed clockwise.
        assert_eq!(
            validator.validate(&terrain(), &square(true), 2),
            Err(TriangleListError::Clockwise {
                triangle: 1,
                role: TriangleRole::Surface,
                group: 7,
                signed_area_cells: -8.0,
            })
        );
    }

    #[test]
    fn flat_triangles_are_excepted_from_the_winding_rule() {
        let mut validator = TriangleListValidator::new();
        let mut list = TriangleList::new(&Lattice::new(2), CrackPolicy::Collapsed);
        let c = [(0, 0), (4, 0), (4, 4), (0, 4)]
            .map(|(i, j)| list.add_vertex(SubgridPoint::grid(i, j), 1.0));
        list.add_triangle([c[0], c[1], c[2]], surface(0));
        list.add_triangle([c[0], c[2], c[3]], surface(0));
        let degenerate = TriangleInfo {
            role: TriangleRole::Degenerate,
            group: 0,
            level: 0,
        };
        // A strip join (a repeated corner) and a triangle collapsed onto the diagonal, listed
        // in an order that would be clockwise if they had area.
        list.add_triangle([c[2], c[2], c[1]], degenerate);
        let middle = list.add_vertex(SubgridPoint::grid(2, 2), 1.0);
        list.add_triangle([c[0], c[2], middle], degenerate);
        assert_eq!(validator.validate(&terrain(), &list, 4), Ok(()));
    }

    #[test]
    fn flat_triangles_must_say_so_and_roles_must_fit_the_policy() {
        let mut validator = TriangleListValidator::new();
        let mut list = TriangleList::new(&Lattice::new(2), CrackPolicy::Closed);
        let a = list.add_vertex(SubgridPoint::grid(0, 0), 0.0);
        let b = list.add_vertex(SubgridPoint::grid(4, 0), 0.0);
        list.add_triangle([a, b, b], surface(0));
        assert_eq!(
            validator.validate(&terrain(), &list, 1),
            Err(TriangleListError::SurfaceWithoutArea {
                triangle: 0,
                role: TriangleRole::Surface
            })
        );
        let mut skirted = TriangleList::new(&Lattice::new(2), CrackPolicy::Closed);
        let a = skirted.add_vertex(SubgridPoint::grid(0, 0), 0.0);
        skirted.add_triangle(
            [a, a, a],
            TriangleInfo {
                role: TriangleRole::Skirt,
                group: 0,
                level: 0,
            },
        );
        assert!(matches!(
            validator.validate(&terrain(), &skirted, 1),
            Err(TriangleListError::RoleNotAllowed { .. })
        ));
    }
}
