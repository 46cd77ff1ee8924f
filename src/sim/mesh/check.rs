//! What `--check` (and every test) runs on a frame's [`MeshOutput`], whatever its form: the 4-8
//! validator on a vertex set (plus: every morphed vertex is active), the triangle-list
//! validator on a triangle list. Both compare the algorithm's own triangle count with the mesh
//! (SPEC §3: "an algorithm's own count must always equal this; test it"). It reads the mesh
//! only, never an algorithm's own structures (their validators live beside each algorithm); the
//! runner checks the extra columns.

use super::list_validate::{TriangleListError, TriangleListValidator};
use super::output::{LatticeMesh, MeshOutput};
use super::validate::{MeshError, validate_reported};
use crate::sim::hierarchy::{GridPoint, Hierarchy};

/// The first thing found wrong with a frame's mesh.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshCheckError {
    #[error("{0}")]
    Lattice(#[from] MeshError),
    #[error("vertex {vertex:?} is drawn at a morphed height but is not in the mesh")]
    MorphedInactiveVertex { vertex: GridPoint },
    #[error("{0}")]
    TriangleList(#[from] TriangleListError),
}

/// Checks meshes frame after frame, keeping the triangle-list validator's buffers.
#[derive(Debug, Default)]
pub struct MeshChecker {
    list_validator: TriangleListValidator,
}

impl MeshChecker {
    pub fn new() -> MeshChecker {
        MeshChecker::default()
    }

    /// Checks `mesh` and that `reported_triangles` (the algorithm's own count) matches it.
    pub fn check(
        &mut self,
        hierarchy: &Hierarchy,
        mesh: MeshOutput,
        reported_triangles: u64,
    ) -> Result<(), MeshCheckError> {
        match mesh {
            MeshOutput::Lattice(LatticeMesh { vertices, morphed }) => {
                let lattice = hierarchy.lattice();
                validate_reported(lattice, vertices, reported_triangles)?;
                if let Some(morphed) = morphed
                    && let Some(&id) = morphed
                        .sorted_ids()
                        .iter()
                        .find(|&&id| id as usize >= lattice.n_vertices() || !vertices.contains(id))
                {
                    return Err(MeshCheckError::MorphedInactiveVertex {
                        vertex: lattice.point(id),
                    });
                }
                Ok(())
            }
            MeshOutput::Triangles(list) => {
                Ok(self
                    .list_validator
                    .validate(hierarchy, list, reported_triangles)?)
            }
        }
    }
}
