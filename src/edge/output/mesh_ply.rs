//! Mesh export: one frame's drawn mesh as a PLY file (ASCII, format 1.0), for opening what an
//! algorithm drew in one's own tools (MeshLab, Blender, ParaView, CloudCompare); the format is
//! `docs/output-formats.md`, "Meshes". It returns the file's text: which frames and entries are
//! exported, and where the file goes, are the caller's.
//!
//! Read through the mesh visitor ([`MeshOutput::for_each_triangle`]), so both mesh forms come
//! out the same way: every drawn triangle (skirts and degenerate triangles included) as a face
//! with three extra properties, `role` (0 surface, 1 skirt, 2 degenerate, 3 stitch), `level`
//! and `group`; vertices in terrain-local metres (`double`), each distinct corner (position and
//! height) once, numbered in the order the visitor first meets it. The header's comments say
//! which run, entry and frame it is and the terrain's world origin (world = local + origin).
//! Numbers are written in Rust's shortest round-trip form, so the file holds the exact values.
//! `docs/output-formats.md` documents the format.

use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::{MeshOutput, SubgridPoint};
use std::collections::HashMap;
use std::fmt::Write;

/// What the header says about the mesh.
pub struct PlyHeader<'a> {
    pub experiment: &'a str,
    pub entry: &'a str,
    pub frame: u64,
}

/// The whole file as text. O(T) time, O(distinct corners) memory.
pub fn mesh_ply(hierarchy: &Hierarchy, mesh: MeshOutput, header: &PlyHeader) -> String {
    let spacing = hierarchy.field().spacing();
    let mut index: HashMap<(SubgridPoint, u32), u32> = HashMap::new();
    let mut vertices = String::new();
    let mut faces = String::new();
    let (mut n_vertices, mut n_faces) = (0u32, 0u64);
    mesh.for_each_triangle(hierarchy, |triangle| {
        let corners = triangle.corners.map(|corner| {
            *index
                .entry((corner.position, corner.z.to_bits()))
                .or_insert_with(|| {
                    let local = corner.local(spacing);
                    let _ = writeln!(vertices, "{} {} {}", local.x, local.y, local.z);
                    n_vertices += 1;
                    n_vertices - 1
                })
        });
        let info = triangle.info;
        let _ = writeln!(
            faces,
            "3 {} {} {} {} {} {}",
            corners[0],
            corners[1],
            corners[2],
            info.role.index(),
            info.level,
            info.group
        );
        n_faces += 1;
    });
    let origin = hierarchy.field().origin();
    let mut text = String::new();
    let _ = write!(
        text,
        "ply\n\
         format ascii 1.0\n\
         comment roamsim {}: experiment {}, entry {}, frame {}\n\
         comment vertices in terrain-local metres, z up; world = local + origin {} {} {}\n\
         comment face role: 0 surface, 1 skirt, 2 degenerate, 3 stitch; level and group as the \
         algorithm numbers them\n\
         element vertex {n_vertices}\n\
         property double x\n\
         property double y\n\
         property double z\n\
         element face {n_faces}\n\
         property list uchar uint vertex_indices\n\
         property uchar role\n\
         property uint level\n\
         property uint group\n\
         end_header\n",
        env!("CARGO_PKG_VERSION"),
        single_line(header.experiment),
        single_line(header.entry),
        header.frame,
        origin.x,
        origin.y,
        origin.z,
    );
    text.push_str(&vertices);
    text.push_str(&faces);
    text
}

/// A label as a PLY comment can hold it (one line).
fn single_line(text: &str) -> String {
    text.replace(['\n', '\r'], " ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mesh::VertexSet;
    use crate::sim::terrain::{Heightfield, Spacing};

    #[test]
    fn the_base_mesh_is_four_vertices_and_two_surface_faces() {
        let heights = (0..9).map(|k| k as f32).collect();
        let field = Heightfield::new(3, heights, Spacing { dx: 2.0, dy: 3.0 }).unwrap();
        let hierarchy = Hierarchy::new(field);
        let base = VertexSet::base_mesh(hierarchy.lattice());
        let header = PlyHeader {
            experiment: "tiny",
            entry: "base",
            frame: 7,
        };
        let text = mesh_ply(&hierarchy, MeshOutput::lattice(&base), &header);
        let body: Vec<&str> = text.split("end_header\n").nth(1).unwrap().lines().collect();
        assert!(text.contains("element vertex 4\n") && text.contains("element face 2\n"));
        assert!(text.contains("comment roamsim 0.1.0: experiment tiny, entry base, frame 7\n"));
        // The first triangle visited is (apex (2,0), (2,2), (0,0)): heights 2, 8, 0.
        assert_eq!(body[..4], ["4 0 2", "4 6 8", "0 0 0", "0 6 6"]);
        assert_eq!(body[4..], ["3 0 1 2 0 0 0", "3 3 2 1 0 0 0"]);
    }
}
