//! The mesh validator: what makes a vertex set a crack-free mesh of the 4-8 family (SPEC §3).
//! It checks the set only; triangle lists have their own validator (`list_validate`).
//!
//! A valid mesh holds the four corners, is closed under parents (every active vertex's parents
//! are active), its enumerated triangles number T = 2 + Σ parents, and each of them is wound
//! counter-clockwise seen from above in the corner order the mesh visitor hands out (apex,
//! left, right: [`super::winding`]). Tests call it after every frame; `roamsim run --check` calls
//! it every frame too. O(active vertices + triangles): the winding is checked in the same
//! enumeration that counts the triangles.

use super::VertexSet;
use super::triangles::for_each_triangle;
use super::winding::Winding;
use crate::sim::hierarchy::{GridPoint, Lattice};

/// The first thing found wrong with a mesh.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MeshError {
    #[error("corner {corner:?} is not active")]
    MissingCorner { corner: GridPoint },
    #[error("vertex {vertex:?} is active but its parent {parent:?} is not (a crack)")]
    NotClosed {
        vertex: GridPoint,
        parent: GridPoint,
    },
    #[error(
        "triangle {triangle} (apex {apex:?}, left {left:?}, right {right:?}) is wound clockwise \
         seen from above"
    )]
    Clockwise {
        triangle: u64,
        apex: GridPoint,
        left: GridPoint,
        right: GridPoint,
    },
    #[error("{enumerated} triangles enumerated, but 2 + Σ parents = {formula}")]
    CountMismatch { enumerated: u64, formula: u64 },
    #[error("the algorithm reports {reported} triangles; the mesh has {actual}")]
    ReportedCountWrong { reported: u64, actual: u64 },
}

/// Checks that `set` is a mesh; returns its triangle count.
pub fn validate(lattice: &Lattice, set: &VertexSet) -> Result<u64, MeshError> {
    for corner in lattice.corners() {
        if !set.contains_point(lattice, corner) {
            return Err(MeshError::MissingCorner { corner });
        }
    }
    for id in set.iter() {
        let vertex = lattice.point(id);
        for parent in &lattice.parents(vertex) {
            if !set.contains_point(lattice, *parent) {
                return Err(MeshError::NotClosed {
                    vertex,
                    parent: *parent,
                });
            }
        }
    }
    let formula = set.triangle_count(lattice);
    let mut enumerated = 0;
    let mut first_clockwise = None;
    for_each_triangle(lattice, set, |t| {
        let corners = [t.apex, t.left, t.right].map(Into::into);
        if first_clockwise.is_none() && Winding::of_points(corners) != Winding::CounterClockwise {
            first_clockwise = Some(MeshError::Clockwise {
                triangle: enumerated,
                apex: t.apex,
                left: t.left,
                right: t.right,
            });
        }
        enumerated += 1;
    });
    if let Some(error) = first_clockwise {
        return Err(error);
    }
    if enumerated != formula {
        return Err(MeshError::CountMismatch {
            enumerated,
            formula,
        });
    }
    Ok(formula)
}

/// Checks the mesh and that an algorithm's own triangle count matches it.
pub fn validate_reported(
    lattice: &Lattice,
    set: &VertexSet,
    reported_triangles: u64,
) -> Result<(), MeshError> {
    let actual = validate(lattice, set)?;
    if actual != reported_triangles {
        return Err(MeshError::ReportedCountWrong {
            reported: reported_triangles,
            actual,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_base_mesh_has_two_triangles() {
        let lattice = Lattice::new(3);
        assert_eq!(validate(&lattice, &VertexSet::base_mesh(&lattice)), Ok(2));
    }

    #[test]
    fn the_full_grid_has_two_triangles_per_cell_pair() {
        // Full resolution of a 2^n+1 grid: 2 · (2^n)² triangles... in 4-8 terms, each of the
        // (2^n)² unit cells holds two triangles.
        let lattice = Lattice::new(3);
        let mut set = VertexSet::new(&lattice);
        for id in 0..lattice.n_vertices() as u32 {
            set.insert(id);
        }
        assert_eq!(validate(&lattice, &set), Ok(2 * 64));
    }

    #[test]
    fn every_triangle_of_the_full_grid_is_counter_clockwise_and_a_flipped_one_would_be_refused() {
        // The bintree's halving keeps each child in its parent's winding, so a full grid passes;
        // the check itself is the one `validate` runs on every triangle it enumerates.
        let lattice = Lattice::new(3);
        let mut set = VertexSet::new(&lattice);
        for id in 0..lattice.n_vertices() as u32 {
            set.insert(id);
        }
        let mut n = 0;
        for_each_triangle(&lattice, &set, |t| {
            let corners = [t.apex, t.left, t.right].map(Into::into);
            assert_eq!(Winding::of_points(corners), Winding::CounterClockwise);
            let flipped = [t.apex, t.right, t.left].map(Into::into);
            assert_eq!(Winding::of_points(flipped), Winding::Clockwise);
            n += 1;
        });
        assert_eq!(validate(&lattice, &set), Ok(n));
    }

    #[test]
    fn a_vertex_without_its_parents_is_a_crack() {
        let lattice = Lattice::new(3);
        let mut set = VertexSet::base_mesh(&lattice);
        set.insert(lattice.id(GridPoint::new(2, 2)));
        assert!(matches!(
            validate(&lattice, &set),
            Err(MeshError::NotClosed { .. })
        ));
    }

    #[test]
    fn a_missing_corner_is_reported() {
        let lattice = Lattice::new(2);
        let mut set = VertexSet::base_mesh(&lattice);
        set.remove(0);
        assert_eq!(
            validate(&lattice, &set),
            Err(MeshError::MissingCorner {
                corner: GridPoint::new(0, 0)
            })
        );
    }

    #[test]
    fn a_wrong_reported_count_is_caught() {
        let lattice = Lattice::new(2);
        let set = VertexSet::base_mesh(&lattice);
        assert_eq!(
            validate_reported(&lattice, &set, 3),
            Err(MeshError::ReportedCountWrong {
                reported: 3,
                actual: 2
            })
        );
    }
}
