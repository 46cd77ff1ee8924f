//! Wu's cone count, hierarchically: how many mesh triangles meet the view cone, without visiting
//! them all.
//!
//! **Per-block counts.** When a quadtree block's centre is active, the mesh triangles inside the
//! block tile it exactly (closure makes the block's two halves bintree triangles), and their
//! number is 2 + 2·(active vertices strictly inside the block, its centre included) + (active
//! vertices on its boundary, corners excluded): each active vertex splits the two triangles of its
//! diamond, one of them inside the block when the vertex is on the block's edge. The bracket is
//! kept per block of half-size ≥ 2 ([`BlockTriangleCounts`], 4 bytes per such block: a quarter of
//! the nodes, a third of a byte per sample), updated in O(levels) on every vertex insertion and
//! deletion; for the finest blocks it is read off the mesh (4 boundary bits).
//!
//! **Top-down count** ([`cone_rendered_triangles_hierarchical`]): from the root block, a block
//! whose bounding sphere (its footprint × height range) lies inside the cone adds its count, one
//! whose every triangle's sphere must miss the cone adds nothing, and a block the cone's surface
//! crosses tests the triangles it holds directly (its quarters, or the halves of its inactive
//! sub-blocks) with the exact per-triangle test of `cull.rs`, and recurses into its active
//! sub-blocks. A relative margin keeps rounding from deciding a block: the result equals the
//! enumeration's count exactly. Cost: O(blocks the cone's surface crosses + their triangles)
//! instead of O(T). That is not o(T) on every mesh: Wu refines around the eye, which is the
//! cone's apex, so blocks near the eye straddle at every level. On the Table 1 flight at a
//! 6000-triangle budget it tests about 6 600 of 19 600 triangles one by one and visits about
//! 2 700 blocks per frame: 1.06 M instructions a frame against the enumeration's 5.6 M.
//!
//! It relies on the mesh being closed, which Wu's split and merge keep at all times.

use super::cull::Cone;
use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice};
use crate::sim::mesh::VertexSet;
use crate::sim::mesh::triangles::base_triangles;
use crate::sim::view::Camera;
use glam::DVec3;

/// Relative margin (of the distance to the eye plus the block's radius) below which a block's
/// bounding sphere is not trusted to decide all its triangles; far above `f64` rounding.
const BLOCK_DECISION_MARGIN: f64 = 1e-9;

/// Per block of half-size ≥ 2: 2·(active vertices strictly inside) + (active non-corner vertices
/// on the boundary). Blocks are numbered as in `SquareIndex` (coarsest level first); the finest
/// level, last in that order, is not stored.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct BlockTriangleCounts {
    cells: u32,
    weights: Vec<u32>,
}

impl BlockTriangleCounts {
    /// The counts of `mesh`: O(active vertices · levels).
    pub fn new(lattice: &Lattice, mesh: &VertexSet) -> BlockTriangleCounts {
        let cells = lattice.cells();
        let n_stored = ((cells as usize / 2).pow(2) - 1) / 3;
        let mut counts = BlockTriangleCounts {
            cells,
            weights: vec![0; n_stored],
        };
        for id in mesh.iter() {
            counts.vertex_inserted(lattice.point(id));
        }
        counts
    }

    pub fn memory_bytes(&self) -> usize {
        self.weights.capacity() * std::mem::size_of::<u32>()
    }

    pub fn vertex_inserted(&mut self, p: GridPoint) {
        self.for_each_block_holding(p, |weight, by| *weight += by);
    }

    pub fn vertex_removed(&mut self, p: GridPoint) {
        self.for_each_block_holding(p, |weight, by| *weight -= by);
    }

    /// Calls `change(weight, 2)` for each stored block `p` is strictly inside and
    /// `change(weight, 1)` for each it is on the boundary of (not a corner). O(levels).
    fn for_each_block_holding(&mut self, p: GridPoint, mut change: impl FnMut(&mut u32, u32)) {
        let lowest_bit = (p.i | p.j) & (p.i | p.j).wrapping_neg();
        if lowest_bit == 0 {
            return; // The origin, a corner of every block.
        }
        let mut level = 0;
        // Block side 2^n >> level; stored blocks have side ≥ 4, and p is a corner of every block
        // whose side divides both its coordinates (side ≤ lowest_bit).
        while let Some(side) = self.cells.checked_shr(level)
            && side >= 4
            && side > lowest_bit
        {
            let per_side = 1u32 << level;
            let level_offset = ((1usize << (2 * level)) - 1) / 3;
            let mut at = |a: u32, b: u32, by: u32| {
                if a < per_side && b < per_side {
                    let k = level_offset + (b * per_side + a) as usize;
                    change(&mut self.weights[k], by);
                }
            };
            let (a, b) = (p.i / side, p.j / side);
            match (p.i.is_multiple_of(side), p.j.is_multiple_of(side)) {
                (false, false) => at(a, b, 2),
                // On a vertical block edge: the blocks to its west and east.
                (true, false) => {
                    at(a.wrapping_sub(1), b, 1);
                    at(a, b, 1);
                }
                (false, true) => {
                    at(a, b.wrapping_sub(1), 1);
                    at(a, b, 1);
                }
                (true, true) => unreachable!("side > lowest bit: p is no corner here"),
            }
            level += 1;
        }
    }

    /// Mesh triangles inside the block centred at `centre` (whose centre must be active).
    fn triangles_in_active_block(
        &self,
        lattice: &Lattice,
        mesh: &VertexSet,
        centre: GridPoint,
        half: u32,
    ) -> u64 {
        if half == 1 {
            let on_boundary = lattice
                .boundary_vertices(centre, 1)
                .iter()
                .filter(|m| mesh.contains_point(lattice, **m))
                .count();
            return 4 + on_boundary as u64;
        }
        let level = (self.cells / (2 * half)).trailing_zeros();
        let per_side = 1u32 << level;
        let level_offset = ((1usize << (2 * level)) - 1) / 3;
        let k =
            level_offset + ((centre.j / (2 * half)) * per_side + centre.i / (2 * half)) as usize;
        2 + u64::from(self.weights[k])
    }
}

/// Triangles of `mesh` whose bounding sphere meets the view cone, equal to
/// `cull::cone_rendered_triangles`, top-down over the blocks (see the module docs).
pub(super) fn cone_rendered_triangles_hierarchical(
    hierarchy: &Hierarchy,
    mesh: &VertexSet,
    counts: &BlockTriangleCounts,
    camera: &Camera,
) -> u64 {
    let counter = Counter {
        cone: Cone::new(camera),
        hierarchy,
        lattice: hierarchy.lattice(),
        mesh,
        counts,
    };
    let lattice = hierarchy.lattice();
    let root = lattice.root();
    if mesh.contains_point(lattice, root) {
        counter.block(root, lattice.cells() / 2)
    } else {
        base_triangles(lattice)
            .iter()
            .map(|t| counter.triangle(t.apex, t.left, t.right))
            .sum()
    }
}

struct Counter<'a> {
    cone: Cone,
    hierarchy: &'a Hierarchy,
    lattice: &'a Lattice,
    mesh: &'a VertexSet,
    counts: &'a BlockTriangleCounts,
}

impl Counter<'_> {
    fn active(&self, p: GridPoint) -> bool {
        self.mesh.contains_point(self.lattice, p)
    }

    fn triangle(&self, apex: GridPoint, left: GridPoint, right: GridPoint) -> u64 {
        u64::from(
            self.cone
                .meets_triangle(self.hierarchy.field(), apex, left, right),
        )
    }

    /// Rendered triangles inside the active block at `c`.
    fn block(&self, c: GridPoint, h: u32) -> u64 {
        let spacing = self.hierarchy.field().spacing();
        let (z_min, z_max) = self.hierarchy.node_height_range(c, h);
        let (z_min, z_max) = (f64::from(z_min), f64::from(z_max));
        let centre = DVec3::new(
            f64::from(c.i) * spacing.dx,
            f64::from(c.j) * spacing.dy,
            0.5 * (z_min + z_max),
        );
        let horizontal = f64::from(h) * spacing.dx.hypot(spacing.dy);
        let radius = horizontal.hypot(0.5 * (z_max - z_min));
        let distance = self.cone.signed_distance(centre);
        let margin = BLOCK_DECISION_MARGIN * (centre.distance(self.cone_eye()) + radius);
        // Every triangle of the block has its corners in the block's sphere, hence its sphere's
        // centre too. Its corners lie within `horizontal` of that centre across (the block's
        // halves are its largest triangles) and within the height range up or down, which bounds
        // its sphere's radius.
        if distance <= -radius - margin {
            return self
                .counts
                .triangles_in_active_block(self.lattice, self.mesh, c, h);
        }
        let largest_triangle_radius = horizontal.hypot(z_max - z_min);
        if distance > radius + largest_triangle_radius + margin {
            return 0;
        }
        let (sw, se) = (
            GridPoint::new(c.i - h, c.j - h),
            GridPoint::new(c.i + h, c.j - h),
        );
        let (nw, ne) = (
            GridPoint::new(c.i - h, c.j + h),
            GridPoint::new(c.i + h, c.j + h),
        );
        let [west, east, south, north] = self.lattice.boundary_vertices(c, h);
        let mut rendered = 0;
        for (midpoint, ends) in [
            (west, [sw, nw]),
            (east, [se, ne]),
            (south, [sw, se]),
            (north, [nw, ne]),
        ] {
            if !self.active(midpoint) {
                // The quarter on this edge is a mesh triangle.
                rendered += self.triangle(c, ends[0], ends[1]);
                continue;
            }
            // Split: each half is a half of the sub-block at that corner, a mesh triangle unless
            // the sub-block is active (then it is counted with that block below).
            for corner in ends {
                let sub = GridPoint::new((c.i + corner.i) / 2, (c.j + corner.j) / 2);
                if h == 1 || !self.active(sub) {
                    rendered += self.triangle(midpoint, c, corner);
                }
            }
        }
        if let Some(subs) = self.lattice.sub_blocks(c, h) {
            for sub in subs {
                if self.active(sub) {
                    rendered += self.block(sub, h / 2);
                }
            }
        }
        rendered
    }

    fn cone_eye(&self) -> DVec3 {
        self.cone.eye()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::algorithm::wu::cull::cone_rendered_triangles;
    use crate::sim::algorithm::wu::{BudgetConfig, Wu, WuConfig};
    use crate::sim::algorithm::{FrameInput, LodAlgorithm};
    use crate::sim::mesh::triangles::for_each_triangle;
    use crate::sim::stats::FrameStats;
    use crate::sim::terrain::Spacing;
    use crate::sim::terrain::synthetic::{SyntheticTerrain, generate};
    use crate::sim::view::{Pose, ViewSettings};
    use crate::sim::zone::{SpeedBound, ZoneVariant};

    fn terrain(level: u32, seed: u64) -> Hierarchy {
        let field = generate(&SyntheticTerrain {
            level,
            seed,
            amplitude: 300.0,
            roughness: 0.6,
            spacing: Spacing { dx: 30.0, dy: 45.0 },
        })
        .unwrap();
        Hierarchy::new(field)
    }

    fn view() -> ViewSettings {
        ViewSettings {
            width_px: 600,
            height_px: 400,
            fovy: 50f64.to_radians(),
            near: 1.0,
            far: 1e6,
        }
    }

    /// A low circle over the terrain's middle, looking along the path and slightly down.
    fn pose_on_circle(hierarchy: &Hierarchy, frame: u64) -> Pose {
        let lattice = hierarchy.lattice();
        let spacing = hierarchy.field().spacing();
        let extent_x = f64::from(lattice.cells()) * spacing.dx;
        let extent_y = f64::from(lattice.cells()) * spacing.dy;
        let angle = frame as f64 * 0.01;
        Pose {
            position: DVec3::new(
                0.5 * extent_x + 0.3 * extent_x * angle.cos(),
                0.5 * extent_y + 0.3 * extent_y * angle.sin(),
                400.0 + 100.0 * (frame as f64 * 0.03).sin(),
            ),
            yaw: angle + std::f64::consts::FRAC_PI_2,
            pitch: -0.2 - 0.3 * (frame as f64 * 0.02).sin().abs(),
        }
    }

    fn wu_with_cone(hierarchy: &Hierarchy, budget: Option<u64>) -> Wu<'_> {
        let config = WuConfig {
            nesting: crate::sim::hierarchy::NestingRule::Max,
            tau_px: budget.is_none().then_some(1.5),
            budget: budget.map(|triangles| BudgetConfig {
                triangles,
                dead_band: 0,
                base_limit: 100,
                initial_tau_k: 1.5,
            }),
            zone: ZoneVariant::Conservative,
            block_priority: true,
            depth_limit: None,
            cone_culling: true,
            wheel_links: 32,
        };
        let speed = SpeedBound {
            horizontal: 200.0,
            vertical: 100.0,
        };
        Wu::new(hierarchy, config, &view(), speed)
    }

    /// Flies `wu` along the circle; after every frame the count it used equals the enumeration's
    /// and the per-block counts equal a recount.
    fn check_cone_count_along_the_circle(hierarchy: &Hierarchy, mut wu: Wu, frames: u64) {
        let mut stats = FrameStats::default();
        let mut any_partly_visible = false;
        for frame in 0..frames {
            let camera = Camera::new(&pose_on_circle(hierarchy, frame), view());
            wu.update(
                &FrameInput {
                    frame,
                    camera: &camera,
                    speed_bound_broken: false,
                },
                &mut stats,
            );
            let hierarchical = *stats.extra.last().unwrap() as u64;
            let enumerated = cone_rendered_triangles(hierarchy, wu.vertex_set(), &camera);
            assert_eq!(hierarchical, enumerated, "frame {frame}");
            any_partly_visible |= enumerated > 0 && enumerated < wu.triangle_count();
            wu.validate_queues(false).unwrap();
        }
        assert!(any_partly_visible, "the flight never saw part of the mesh");
    }

    #[test]
    fn the_hierarchical_cone_count_equals_the_enumeration_along_a_flight_at_fixed_tau() {
        let hierarchy = terrain(7, 11);
        check_cone_count_along_the_circle(&hierarchy, wu_with_cone(&hierarchy, None), 300);
    }

    #[test]
    fn the_hierarchical_cone_count_equals_the_enumeration_along_a_flight_at_a_budget() {
        let hierarchy = terrain(8, 5);
        check_cone_count_along_the_circle(&hierarchy, wu_with_cone(&hierarchy, Some(3000)), 300);
    }

    #[test]
    fn a_full_mesh_seen_from_every_direction_counts_as_the_enumeration() {
        let hierarchy = terrain(4, 3);
        let lattice = hierarchy.lattice();
        let mut mesh = VertexSet::new(lattice);
        for id in 0..lattice.n_vertices() as u32 {
            mesh.insert(id);
        }
        let counts = BlockTriangleCounts::new(lattice, &mesh);
        for step in 0..64 {
            let yaw = f64::from(step) * std::f64::consts::TAU / 64.0;
            for pitch in [-1.4, -0.6, -0.1, 0.4] {
                for position in [
                    DVec3::new(240.0, 360.0, 500.0),
                    DVec3::new(-100.0, 50.0, 200.0),
                    DVec3::new(100.0, 700.0, 5000.0),
                ] {
                    let camera = Camera::new(
                        &Pose {
                            position,
                            yaw,
                            pitch,
                        },
                        view(),
                    );
                    assert_eq!(
                        cone_rendered_triangles_hierarchical(&hierarchy, &mesh, &counts, &camera),
                        cone_rendered_triangles(&hierarchy, &mesh, &camera),
                        "yaw {yaw}, pitch {pitch}, eye {position}"
                    );
                }
            }
        }
    }

    #[test]
    fn an_active_block_holds_as_many_triangles_as_the_enumeration_finds_inside_it() {
        let hierarchy = terrain(5, 9);
        let lattice = hierarchy.lattice();
        // A closed mesh, fine in the south and west, coarse in the north-east.
        fn insert_closed(lattice: &Lattice, mesh: &mut VertexSet, p: GridPoint) {
            if !mesh.contains_point(lattice, p) {
                for parent in lattice.parents(p).as_slice() {
                    insert_closed(lattice, mesh, *parent);
                }
                mesh.insert(lattice.id(p));
            }
        }
        let mut mesh = VertexSet::base_mesh(lattice);
        for id in 0..lattice.n_vertices() as u32 {
            let p = lattice.point(id);
            if p.i <= 9 || p.j <= 5 || (p.i | p.j).is_multiple_of(8) {
                insert_closed(lattice, &mut mesh, p);
            }
        }
        assert!(crate::sim::mesh::validate::validate(lattice, &mesh).is_ok());
        assert!(mesh.len() < lattice.n_vertices());
        let counts = BlockTriangleCounts::new(lattice, &mesh);
        let mut half = 1;
        while half < lattice.cells() {
            for c in crate::sim::hierarchy::square_points(lattice, half) {
                if !mesh.contains_point(lattice, c) {
                    continue;
                }
                let mut inside = 0;
                for_each_triangle(lattice, &mesh, |t| {
                    let within =
                        |p: GridPoint| p.i.abs_diff(c.i) <= half && p.j.abs_diff(c.j) <= half;
                    inside += u64::from(within(t.apex) && within(t.left) && within(t.right));
                });
                assert_eq!(
                    counts.triangles_in_active_block(lattice, &mesh, c, half),
                    inside,
                    "block at {c:?}, half {half}"
                );
            }
            half *= 2;
        }
    }
}
