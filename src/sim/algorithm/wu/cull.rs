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
    let field = hierarchy.field();
    let mut rendered = 0;
    for_each_triangle(hierarchy.lattice(), mesh, |t| {
        let corners = [t.apex, t.left, t.right].map(|p| field.position(p.i as usize, p.j as usize));
        let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
        let radius = corners
            .iter()
            .map(|c| c.distance(centre))
            .fold(0.0, f64::max);
        let to_centre = centre - camera.eye;
        let distance = to_centre.length();
        let inside = distance <= radius || {
            let angle = (to_centre.dot(camera.forward) / distance)
                .clamp(-1.0, 1.0)
                .acos();
            angle <= half_angle + (radius / distance).asin()
        };
        rendered += u64::from(inside);
    });
    rendered
}
