//! What the view cone says about a node, and how soon the camera can change it: the view side of
//! Wu's `in_view` refinement (Wu et al. 2001 §3.2, "the spatial relations between such nodes and
//! view-frustum when deciding whether to split or merge them"; SPEC §5, Culling). It decides no
//! split or merge itself; the frame loop (`mod.rs`) combines its view keys with the life keys.
//!
//! **Node spheres.** A node's bounding sphere is centred on its block's centre at the middle of
//! the block's height range, with radius h·√(dx² + dy²) + (z_max − z_min)/2 (the half-diagonal of
//! the footprint *plus* half the height range, not their Euclidean sum). The sum makes the spheres
//! nest: a sub-block's centre is h/2·√(dx² + dy²) across and at most (Δz − Δz')/2 up or down from
//! its parent's, so its sphere lies inside its parent's (triangle inequality). Hence a visible
//! sub-block always has a visible parent, and so has every node that sub-block depends on through
//! its parent.
//!
//! **Sight.** A node is *in view* when its sphere meets the view cone: s(c) ≤ ρ, with s the
//! cone's signed distance (`cull.rs`) and c, ρ the sphere's centre and radius. Wu refines a node
//! only in view and merges it (in `in_view` mode) once it is out of view at a frame it is looked
//! at: the exact test both ways, so the mesh shown does not depend on the declared bounds. Its
//! *margin* is one frame of cone motion at its distance, m = v + ω·(|c − e| + ρ) with v the
//! longest eye step and ω the rotation bound: how far out of view a node whose merge a budget
//! deferred by a frame may still be (the reference's loosest test, `ViewThreshold::WithinMargin`).
//! The margin nests like the spheres (a parent's |c − e| + ρ is at least its sub-block's).
//!
//! **How soon it can change.** The cone's signed distance is 1-Lipschitz in the point; moving the
//! eye by at most v and turning the axis by at most ω about the eye changes s at a point at
//! distance d from the eye by at most v + ω·d in a frame (the rotation moves the point relative
//! to the cone by at most 2d·sin(ω/2) ≤ ω·d). With d growing by at most v a frame, k frames
//! change s by at most S(k) = Σ_{i=1..k} (v + ω·(d + i·v)) = (ωv/2)·k² + (v + ω·(d + v/2))·k.
//! The frames before a gap g can close are the root of S(k) = g, taken a little early (by a
//! relative 10⁻⁹ of the distance) so that rounding never decides; a node whose state cannot
//! change sooner than that is looked at again then, and not before. These are the view keys the
//! queues use beside the life keys; they are valid only while both bounds hold, so a frame that
//! breaks either revalidates them. An experiment that declares no rotation bound gets its
//! flight's largest turn (derived at load), which no frame breaks; a flight that never turns gets
//! ω = 0, and the keys are those of the eye's motion alone. π (`SpeedBound::NO_ROTATION_BOUND`)
//! bounds nothing: every view key is then one frame, so every node near or in the view is
//! cone-tested every frame (costly, and honest), and out-of-view nodes still merge (issue #30,
//! item 3; `tests/hard_cases.rs::a_rotation_bound_of_pi_keeps_wus_whole_mesh_that_of_the_true_bound`).
//!
//! **Owned triangles.** Each mesh triangle lies in exactly one smallest active block (or, while
//! the root is inactive, in none: the two base triangles). [`owned_triangles`] counts a block's
//! own, which is what Wu's in-view count adds for each visible active node.

use super::cull::Cone;
use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice};
use crate::sim::mesh::VertexSet;
use crate::sim::zone::SpeedBound;
use glam::DVec3;

/// Relative slack (of the node's distance plus radius) taken off every gap before it is turned
/// into frames, so that a state which rounding alone could flip is looked at every frame.
const GAP_ROUNDING_SLACK: f64 = 1e-9;

/// How far the view cone can move in a frame: the motion bounds, as the view keys use them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::sim::algorithm) struct ConeMotion {
    /// The longest eye step, √(v_h² + v_v²), metres per frame.
    eye_step: f64,
    /// The rotation bound, radians per frame.
    rotation: f64,
}

impl ConeMotion {
    pub fn new(speed: SpeedBound) -> ConeMotion {
        ConeMotion {
            eye_step: speed.eye_step(),
            rotation: speed.rotation,
        }
    }

    /// A node's margin: one frame of cone motion at its farthest point, v + ω·(d + ρ).
    pub fn margin(&self, sight: &Sight) -> f64 {
        self.eye_step + self.rotation * (sight.distance + sight.radius)
    }

    /// The real k ≥ 0 at which (ωv/2)·k² + (v + ω·(d + v/2))·k reaches `gap` (after the
    /// rounding slack): no fewer frames can close the gap. +∞ when nothing moves.
    fn frames_to_close(&self, gap: f64, sight: &Sight) -> f64 {
        let gap = gap - GAP_ROUNDING_SLACK * (sight.distance + sight.radius + 1.0);
        if gap <= 0.0 {
            return 0.0;
        }
        let (v, w) = (self.eye_step, self.rotation);
        let quadratic = 0.5 * w * v;
        let linear = v + w * (sight.distance + 0.5 * v);
        if linear <= 0.0 {
            return f64::INFINITY;
        }
        // The stable form of the positive root.
        2.0 * gap / (linear + (linear * linear + 4.0 * quadratic * gap).sqrt())
    }
}

/// A node's bounding sphere (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::sim::algorithm) struct NodeSphere {
    pub centre: DVec3,
    pub radius: f64,
}

impl NodeSphere {
    /// The sphere of a node, looking its height range up.
    pub fn of_node(hierarchy: &Hierarchy, centre: GridPoint, half: u32) -> NodeSphere {
        SphereShape::new(hierarchy).node_sphere(hierarchy, centre, half)
    }
}

/// What the node spheres of one terrain share: the grid spacing and the half-diagonal of a cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::sim::algorithm) struct SphereShape {
    dx: f64,
    dy: f64,
    /// √(dx² + dy²): a block of half-size h has a footprint half-diagonal of h times this.
    cell_diagonal: f64,
}

impl SphereShape {
    pub fn new(hierarchy: &Hierarchy) -> SphereShape {
        let spacing = hierarchy.field().spacing();
        SphereShape {
            dx: spacing.dx,
            dy: spacing.dy,
            cell_diagonal: spacing.dx.hypot(spacing.dy),
        }
    }

    /// The sphere of the block centred at `centre` with half-size `half` and sample height range
    /// [`z_min`, `z_max`].
    pub fn sphere(&self, centre: GridPoint, half: u32, z_min: f32, z_max: f32) -> NodeSphere {
        let (z_min, z_max) = (f64::from(z_min), f64::from(z_max));
        NodeSphere {
            centre: DVec3::new(
                f64::from(centre.i) * self.dx,
                f64::from(centre.j) * self.dy,
                0.5 * (z_min + z_max),
            ),
            radius: f64::from(half) * self.cell_diagonal + 0.5 * (z_max - z_min),
        }
    }

    /// The sphere of a node, looking its height range up.
    pub fn node_sphere(&self, hierarchy: &Hierarchy, centre: GridPoint, half: u32) -> NodeSphere {
        let (z_min, z_max) = hierarchy.node_height_range(centre, half);
        self.sphere(centre, half, z_min, z_max)
    }
}

/// Where a node's sphere is relative to one frame's view cone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(in crate::sim::algorithm) struct Sight {
    /// s(c) − ρ: ≤ 0 when the sphere meets the cone (in view), else how far outside it is.
    pub gap: f64,
    /// |c − e|, the centre's distance from the eye.
    pub distance: f64,
    pub radius: f64,
}

impl Sight {
    pub fn new(cone: &Cone, sphere: &NodeSphere) -> Sight {
        Sight {
            gap: cone.signed_distance(sphere.centre) - sphere.radius,
            distance: sphere.centre.distance(cone.eye()),
            radius: sphere.radius,
        }
    }

    /// Whether the sphere meets the cone.
    pub fn in_view(&self) -> bool {
        self.gap <= 0.0
    }

    /// Whether the sphere is more than its margin outside the cone.
    pub fn beyond_margin(&self, motion: &ConeMotion) -> bool {
        self.gap > motion.margin(self)
    }

    /// Frames before the node may be in view: 0 when it is, else at least 1.
    pub fn frames_until_in_view(&self, motion: &ConeMotion) -> f64 {
        if self.in_view() {
            0.0
        } else {
            motion.frames_to_close(self.gap, self).max(1.0)
        }
    }

    /// Frames before [`Sight::in_view`] may change (at least 1).
    pub fn frames_until_view_changes(&self, motion: &ConeMotion) -> f64 {
        // Leaving needs s − ρ to grow past 0 (strictly); entering needs it to fall to 0.
        motion.frames_to_close(self.gap.abs(), self).max(1.0)
    }
}

/// Triangles of the mesh inside the active block at `centre` (half-size `half`) and inside none
/// of its active sub-blocks: per block edge, the quarter on it when its midpoint is inactive, else
/// each of its two halves whose sub-block is inactive. 0 to 8.
pub(in crate::sim::algorithm) fn owned_triangles(
    lattice: &Lattice,
    mesh: &VertexSet,
    centre: GridPoint,
    half: u32,
) -> u64 {
    let (c, h) = (centre, half);
    let [west, east, south, north] = lattice.boundary_vertices(c, h);
    let corners = |i: i64, j: i64| {
        GridPoint::new(
            (i64::from(c.i) + i * i64::from(h)) as u32,
            (i64::from(c.j) + j * i64::from(h)) as u32,
        )
    };
    let mut owned = 0;
    for (midpoint, ends) in [
        (west, [corners(-1, -1), corners(-1, 1)]),
        (east, [corners(1, -1), corners(1, 1)]),
        (south, [corners(-1, -1), corners(1, -1)]),
        (north, [corners(-1, 1), corners(1, 1)]),
    ] {
        if !mesh.contains_point(lattice, midpoint) {
            owned += 1;
            continue;
        }
        for corner in ends {
            let sub = GridPoint::new((c.i + corner.i) / 2, (c.j + corner.j) / 2);
            owned += u64::from(h == 1 || !mesh.contains_point(lattice, sub));
        }
    }
    owned
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::synthetic::{SyntheticTerrain, generate};
    use crate::sim::terrain::{Heightfield, Spacing};
    use crate::sim::view::{Camera, Pose, ViewSettings};

    fn rough_terrain() -> Hierarchy {
        Hierarchy::new(
            generate(&SyntheticTerrain {
                level: 5,
                seed: 4,
                amplitude: 400.0,
                roughness: 0.5,
                spacing: Spacing { dx: 30.0, dy: 45.0 },
            })
            .unwrap(),
        )
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

    #[test]
    fn a_sub_block_sphere_lies_inside_its_parent_sphere() {
        let hierarchy = rough_terrain();
        let lattice = hierarchy.lattice();
        let mut half = 2;
        while half < lattice.cells() {
            for c in crate::sim::hierarchy::square_points(lattice, half) {
                let parent = NodeSphere::of_node(&hierarchy, c, half);
                for sub in lattice.sub_blocks(c, half).unwrap() {
                    let child = NodeSphere::of_node(&hierarchy, sub, half / 2);
                    let reach = child.centre.distance(parent.centre) + child.radius;
                    assert!(reach <= parent.radius * (1.0 + 1e-12), "{c:?} half {half}");
                }
            }
            half *= 2;
        }
    }

    #[test]
    fn a_node_cannot_change_its_view_sooner_than_its_key_says() {
        // Walk and turn at exactly the bounds, towards and away from the node: its in-view
        // state never changes before the frames it promised.
        let hierarchy = rough_terrain();
        let speed = SpeedBound {
            horizontal: 30.0,
            vertical: 10.0,
            rotation: 0.02,
        };
        let motion = ConeMotion::new(speed);
        let lattice = hierarchy.lattice();
        let mut checked_changes = 0;
        for (start_yaw, turn) in [(0.0f64, 1.0), (2.0, -1.0), (3.5, 1.0)] {
            let pose = |frame: u64| {
                let k = frame as f64;
                let heading = start_yaw + 0.5 * turn;
                Pose {
                    position: DVec3::new(
                        -300.0 + k * 30.0 * heading.cos(),
                        200.0 + k * 30.0 * heading.sin(),
                        900.0 - 10.0 * k,
                    ),
                    yaw: start_yaw + turn * 0.02 * k,
                    pitch: -0.4,
                }
            };
            let cone = |frame| Cone::new(&Camera::new(&pose(frame), view()));
            for half in [1, 4, 16] {
                for c in crate::sim::hierarchy::square_points(lattice, half) {
                    let sphere = NodeSphere::of_node(&hierarchy, c, half);
                    let first = Sight::new(&cone(0), &sphere);
                    let until_change = first.frames_until_view_changes(&motion);
                    for frame in 1..60u64 {
                        let now = Sight::new(&cone(frame), &sphere);
                        if (frame as f64) < until_change {
                            assert_eq!(now.in_view(), first.in_view(), "{c:?} frame {frame}");
                        } else if now.in_view() != first.in_view() {
                            checked_changes += 1;
                        }
                    }
                }
            }
        }
        assert!(checked_changes > 100, "{checked_changes} changes seen");
    }

    #[test]
    fn the_owned_triangles_of_the_active_blocks_add_up_to_the_mesh() {
        let field = Heightfield::new(17, vec![0.0; 17 * 17], Spacing { dx: 1.0, dy: 1.0 }).unwrap();
        let hierarchy = Hierarchy::new(field);
        let lattice = hierarchy.lattice();
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
            if p.i <= 5 || p.j == 3 || (p.i | p.j).is_multiple_of(4) {
                insert_closed(lattice, &mut mesh, p);
            }
        }
        let mut total = 0;
        let mut half = 1;
        while half < lattice.cells() {
            for c in crate::sim::hierarchy::square_points(lattice, half) {
                if mesh.contains_point(lattice, c) {
                    total += owned_triangles(lattice, &mesh, c, half);
                }
            }
            half *= 2;
        }
        let mut enumerated = 0;
        crate::sim::mesh::triangles::for_each_triangle(lattice, &mesh, |_| enumerated += 1);
        assert_eq!(total, enumerated);
    }
}
