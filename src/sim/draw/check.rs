//! The buffers are the mesh: the triangles a GPU would draw from an algorithm's buffers equal
//! the triangles of its [`MeshOutput`] (corners, drawn heights and winding), the check `--check`
//! runs every frame and the tests run for every algorithm.
//!
//! Compared as multisets: the order of draws and of triangles within them is the algorithm's,
//! and a triangle may start at any of its corners (rotations keep the winding; a flipped
//! triangle is a difference). Triangles with two equal corners (position and height) are left
//! out on both sides: they draw nothing, and strips join with them where a list would not.
//! Degenerate triangles with three distinct collinear corners are compared like any other.
//! What it is not: a check of the mesh itself (the validators do that).

use super::GpuBuffers;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::{MeshOutput, SurfacePoint};

/// A triangle as compared: corners rotated to start at the smallest, heights by their bits.
type Key = [(i64, i64, u32); 3];

/// How the buffers and the mesh differ.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "the buffers a GPU would draw are not the mesh: {in_buffers} triangle(s) drawn from the \
     buffers, {in_mesh} in the mesh (degenerate ones left out); first difference: {first}"
)]
pub struct DrawMismatch {
    pub in_buffers: u64,
    pub in_mesh: u64,
    pub first: String,
}

/// Checks that `buffers` draw exactly the triangles of `mesh`.
pub fn check_buffers_draw_mesh(
    buffers: &GpuBuffers,
    mesh: MeshOutput,
    hierarchy: &Hierarchy,
) -> Result<(), DrawMismatch> {
    let mut drawn = Vec::new();
    buffers.for_each_triangle(|corners| drawn.extend(key(corners)));
    let mut meshed = Vec::new();
    mesh.for_each_triangle(hierarchy, |t| meshed.extend(key(t.corners)));
    drawn.sort_unstable();
    meshed.sort_unstable();
    if drawn == meshed {
        return Ok(());
    }
    let first = first_difference(&drawn, &meshed);
    Err(DrawMismatch {
        in_buffers: drawn.len() as u64,
        in_mesh: meshed.len() as u64,
        first,
    })
}

fn key(corners: [SurfacePoint; 3]) -> Option<Key> {
    let point = |c: SurfacePoint| {
        let (x, y) = c.position.raw();
        (x, y, c.z.to_bits())
    };
    let points = corners.map(point);
    if points[0] == points[1] || points[1] == points[2] || points[0] == points[2] {
        return None;
    }
    let start = (0..3).min_by_key(|&k| points[k]).unwrap_or(0);
    Some([0, 1, 2].map(|k| points[(start + k) % 3]))
}

/// Describes the first triangle one side has and the other lacks (both sorted).
fn first_difference(drawn: &[Key], meshed: &[Key]) -> String {
    let (mut a, mut b) = (0, 0);
    let describe = |k: &Key| {
        let corner = |(x, y, z): (i64, i64, u32)| {
            let scale = crate::sim::mesh::SUBGRID_UNITS_PER_CELL as f64;
            format!(
                "({}, {}, {} m)",
                x as f64 / scale,
                y as f64 / scale,
                f32::from_bits(z)
            )
        };
        format!("{} {} {}", corner(k[0]), corner(k[1]), corner(k[2]))
    };
    loop {
        match (drawn.get(a), meshed.get(b)) {
            (Some(x), Some(y)) if x == y => {
                a += 1;
                b += 1;
            }
            (Some(x), Some(y)) if x < y => {
                return format!("drawn but not in the mesh: {}", describe(x));
            }
            (_, Some(y)) => return format!("in the mesh but not drawn: {}", describe(y)),
            (Some(x), None) => return format!("drawn but not in the mesh: {}", describe(x)),
            (None, None) => return "none".to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::draw::{DrawCall, DrawVertex, Topology, VERTEX_BYTES};
    use crate::sim::hierarchy::GridPoint;
    use crate::sim::mesh::{SubgridPoint, VertexSet};
    use crate::sim::terrain::{Heightfield, Spacing};

    fn ramp() -> Hierarchy {
        let side = 3;
        let heights = (0..side * side).map(|k| (k % side) as f32).collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 1.0, dy: 1.0 }).unwrap())
    }

    fn draw_list(gpu: &mut GpuBuffers, corners: &[[(u32, u32); 3]], hierarchy: &Hierarchy) {
        let mut vertices = Vec::new();
        for t in corners {
            for &(i, j) in t {
                let z = hierarchy.height(GridPoint::new(i, j));
                vertices.push(DrawVertex::fixed(SubgridPoint::grid(i, j), z));
            }
        }
        let n = vertices.len() as u32;
        let vb = gpu.create_vertices(vertices, VERTEX_BYTES);
        let ib = gpu.create_indices((0..n).collect());
        gpu.draw(DrawCall {
            vertices: vb,
            indices: ib,
            first_index: 0,
            index_count: n,
            topology: Topology::TriangleList,
            blend: 0.0,
        });
    }

    #[test]
    fn the_base_mesh_drawn_from_a_list_is_the_mesh_and_a_flipped_one_is_not() {
        let hierarchy = ramp();
        let vertices = VertexSet::base_mesh(hierarchy.lattice());
        let mesh = MeshOutput::lattice(&vertices);
        let mut triangles = Vec::new();
        mesh.for_each_triangle(&hierarchy, |t| {
            triangles.push(t.corners.map(|c| {
                let p = c.position.grid_point().unwrap();
                (p.i, p.j)
            }))
        });

        let mut gpu = GpuBuffers::new();
        draw_list(&mut gpu, &triangles, &hierarchy);
        assert_eq!(check_buffers_draw_mesh(&gpu, mesh, &hierarchy), Ok(()));

        let mut flipped = triangles.clone();
        flipped[0].swap(1, 2);
        let mut gpu = GpuBuffers::new();
        draw_list(&mut gpu, &flipped, &hierarchy);
        let error = check_buffers_draw_mesh(&gpu, mesh, &hierarchy).unwrap_err();
        assert!(error.first.contains("not"), "{error}");

        let mut gpu = GpuBuffers::new();
        draw_list(&mut gpu, &triangles[1..], &hierarchy);
        let error = check_buffers_draw_mesh(&gpu, mesh, &hierarchy).unwrap_err();
        assert_eq!((error.in_buffers, error.in_mesh), (1, 2));
        assert!(
            error.first.starts_with("in the mesh but not drawn"),
            "{error}"
        );
    }
}
