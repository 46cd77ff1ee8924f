//! Wu's cone culling: the view frustum approximated by the cone around it.
//!
//! A triangle counts as rendered when its bounding sphere meets the cone whose apex is the eye,
//! whose axis is the view direction and whose half-angle is the angle from the axis to a frustum
//! corner. Conservative: a triangle inside the frustum is always counted.
//!
//! This file defines the cone and the per-triangle test, and the O(triangles) count by
//! enumerating the mesh, which is the definition the hierarchical count of `cone_count.rs` must
//! equal (tests compare them frame by frame).

use crate::sim::hierarchy::GridPoint;
#[cfg(test)]
use crate::sim::hierarchy::Hierarchy;
#[cfg(test)]
use crate::sim::mesh::{VertexSet, triangles::for_each_triangle};
use crate::sim::terrain::Heightfield;
use crate::sim::view::Camera;
use glam::DVec3;

/// The view cone of one frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cone {
    eye: DVec3,
    forward: DVec3,
    sin_half: f64,
    cos_half: f64,
}

impl Cone {
    /// The cone around the camera's frustum (half-angle below π/2 for any finite field of view).
    pub fn new(camera: &Camera) -> Cone {
        let settings = camera.settings;
        let tan_y = (0.5 * settings.fovy).tan();
        let tan_x = tan_y * settings.aspect();
        let half_angle = (tan_x * tan_x + tan_y * tan_y).sqrt().atan();
        let (sin_half, cos_half) = half_angle.sin_cos();
        Cone {
            eye: camera.eye,
            forward: camera.forward,
            sin_half,
            cos_half,
        }
    }

    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    /// Signed distance from `point` to the cone: negative inside (minus the distance to the
    /// surface), the distance outside. 1-Lipschitz in `point`, which is what lets a block's
    /// bounding sphere decide for every triangle in it.
    pub fn signed_distance(&self, point: DVec3) -> f64 {
        let v = point - self.eye;
        let along = v.dot(self.forward);
        let across = v.cross(self.forward).length();
        // Distance to the cone's surface (negative inside), valid while the nearest point of the
        // cone is not its apex; behind the apex the apex is nearest.
        if along * self.cos_half + across * self.sin_half >= 0.0 {
            across * self.cos_half - along * self.sin_half
        } else {
            v.length()
        }
    }

    /// Whether the bounding sphere of the triangle (`left`–`right` its hypotenuse) meets the cone.
    /// Symmetric in `left` and `right`.
    pub fn meets_triangle(
        &self,
        field: &Heightfield,
        apex: GridPoint,
        left: GridPoint,
        right: GridPoint,
    ) -> bool {
        let corners = [apex, left, right].map(|p| field.position(p.i as usize, p.j as usize));
        // The hypotenuse midpoint is the centre of the triangle's circumscribed sphere.
        let centre = (corners[1] + corners[2]) * 0.5;
        let radius = corners
            .iter()
            .map(|c| c.distance(centre))
            .fold(0.0, f64::max);
        let v = centre - self.eye;
        let along = v.dot(self.forward);
        let across = v.cross(self.forward).length();
        let to_surface = across * self.cos_half - along * self.sin_half;
        if along * self.cos_half + across * self.sin_half >= 0.0 {
            to_surface <= radius
        } else {
            v.length() <= radius
        }
    }
}

/// Triangles of `mesh` whose bounding sphere meets the view cone, by enumerating them:
/// O(triangles). The definition the hierarchical count is tested against.
#[cfg(test)]
pub(super) fn cone_rendered_triangles(
    hierarchy: &Hierarchy,
    mesh: &VertexSet,
    camera: &Camera,
) -> u64 {
    let cone = Cone::new(camera);
    let field = hierarchy.field();
    let mut rendered = 0;
    for_each_triangle(hierarchy.lattice(), mesh, |t| {
        rendered += u64::from(cone.meets_triangle(field, t.apex, t.left, t.right));
    });
    rendered
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};
    use crate::sim::view::{Pose, ViewSettings};
    use glam::DVec3;

    #[test]
    fn looking_away_from_the_terrain_renders_nothing_and_looking_at_it_renders_all() {
        let field = Heightfield::new(9, vec![0.0; 81], Spacing { dx: 10.0, dy: 10.0 }).unwrap();
        let hierarchy = Hierarchy::new(field);
        let mut mesh = VertexSet::new(hierarchy.lattice());
        for id in 0..81 {
            mesh.insert(id);
        }
        let settings = ViewSettings {
            width_px: 100,
            height_px: 100,
            fovy: 60f64.to_radians(),
            near: 1.0,
            far: 1e6,
        };
        let camera = |pitch: f64| {
            Camera::new(
                &Pose {
                    position: DVec3::new(40.0, 40.0, 1000.0),
                    yaw: 0.0,
                    pitch,
                },
                settings,
            )
        };
        let down =
            cone_rendered_triangles(&hierarchy, &mesh, &camera(-std::f64::consts::FRAC_PI_2));
        let up = cone_rendered_triangles(&hierarchy, &mesh, &camera(std::f64::consts::FRAC_PI_2));
        assert_eq!(down, 128);
        assert_eq!(up, 0);
    }
}
