//! Wu's cone culling: the view frustum approximated by the cone around it.
//!
//! A triangle counts as rendered when its bounding sphere meets the cone whose apex is the eye,
//! whose axis is the view direction and whose half-angle is the angle from the axis to a frustum
//! corner. Conservative: a triangle inside the frustum is always counted. O(triangles).

use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::VertexSet;
use crate::sim::mesh::triangles::for_each_triangle;
use crate::sim::view::Camera;

/// Triangles of `mesh` whose bounding sphere meets the view cone.
pub(super) fn cone_rendered_triangles(
    hierarchy: &Hierarchy,
    mesh: &VertexSet,
    camera: &Camera,
) -> u64 {
    let settings = camera.settings;
    let tan_y = (0.5 * settings.fovy).tan();
    let tan_x = tan_y * settings.aspect();
    let half_angle = (tan_x * tan_x + tan_y * tan_y).sqrt().atan();
    let (sin_half, cos_half) = half_angle.sin_cos();
    let field = hierarchy.field();
    let mut rendered = 0;
    for_each_triangle(hierarchy.lattice(), mesh, |t| {
        let corners = [t.apex, t.left, t.right].map(|p| field.position(p.i as usize, p.j as usize));
        // The hypotenuse midpoint is the centre of the triangle's circumscribed sphere.
        let centre = (corners[1] + corners[2]) * 0.5;
        let radius = corners
            .iter()
            .map(|c| c.distance(centre))
            .fold(0.0, f64::max);
        let v = centre - camera.eye;
        let along = v.dot(camera.forward);
        let across = v.cross(camera.forward).length();
        // Distance from the centre to the cone's surface (negative inside), valid while the
        // nearest point of the cone is not its apex; behind the apex the apex is nearest.
        let to_surface = across * cos_half - along * sin_half;
        let inside = if along * cos_half + across * sin_half >= 0.0 {
            to_surface <= radius
        } else {
            v.length() <= radius
        };
        rendered += u64::from(inside);
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
