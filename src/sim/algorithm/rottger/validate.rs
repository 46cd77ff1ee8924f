//! The validator of Röttger's quadtree matrix and of a frame's state: the d2 codes against eq. 2
//! and the propagation of §2.2, the blend bytes against the mesh (§2.3, §3's one byte per grid
//! point). Only tests call it, through `Rottger::validate_roughness` and
//! `Rottger::validate_frame`; no frame of a run does, and it is not the mesh validator.
//!
//! - [`validate_roughness`]: the d2 codes are what eq. 2 and the propagation define — every
//!   block's stored d2 is at least its local d2 and (with propagation) at least K times the
//!   stored d2 of every block one level finer that touches it along an edge or lies inside it
//!   (found here by geometry, not by the preprocessing's list), and is the smallest code that
//!   is; the top code is the terrain's largest local d2; entries that belong to no block are 0.
//! - [`validate_frame`]: a block centre is in the mesh iff its blend byte is not 0, and the list
//!   of subdivided blocks is exactly those; an edge midpoint is in the mesh iff the blocks beside
//!   it are all subdivided; the fans' triangles add up to the mesh's; with geomorphing, the
//!   morphed heights of the mesh output are exactly those of the vertices that morph, each at
//!   the height its blend gives (`geomorph.rs`).
//!
//! Both are O(samples). The mesh's own closure and triangle count are the mesh validator's.

use super::criterion::propagation_factor;
use super::fans::count_fans;
use super::geomorph::{morphed_height, morphs, vertex_blend_byte};
use super::matrix::QuadtreeMatrix;
use super::roughness::local_d2;
use crate::sim::hierarchy::{GridPoint, Hierarchy, VertexClass, square_points};
use crate::sim::mesh::{MorphedHeights, VertexSet};

/// The first thing found wrong, as a sentence.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("rottger: {0}")]
pub struct RottgerStateError(String);

fn fail<T>(message: String) -> Result<T, RottgerStateError> {
    Err(RottgerStateError(message))
}

/// Checks the matrix's d2 codes (see the module docs).
pub(super) fn validate_roughness(
    hierarchy: &Hierarchy,
    matrix: &QuadtreeMatrix,
    minimum_resolution: f64,
    propagate: bool,
) -> Result<(), RottgerStateError> {
    let lattice = hierarchy.lattice();
    let scale = matrix.scale();
    let k = propagation_factor(minimum_resolution);
    let mut largest_local: f64 = 0.0;
    let mut owned = vec![false; lattice.n_vertices()];
    let mut half = 1;
    while half < lattice.cells() {
        for centre in square_points(lattice, half) {
            owned[lattice.id(centre) as usize] = true;
            owned[lattice.id(GridPoint::new(centre.i, centre.j + half)) as usize] = true;
            let local = local_d2(hierarchy, centre, half);
            largest_local = largest_local.max(local);
            let mut required = local;
            if propagate && half >= 2 {
                let q = half / 2;
                // Every block of half-size q whose square meets this block's in a segment or more.
                let lo = |x: u32| x.saturating_sub(2 * half);
                for j in (lo(centre.j)..=centre.j + 2 * half).filter(|j| j % (2 * q) == q) {
                    for i in (lo(centre.i)..=centre.i + 2 * half).filter(|i| i % (2 * q) == q) {
                        if i + q > lattice.cells() || j + q > lattice.cells() {
                            continue;
                        }
                        let overlap = |a: u32, b: u32| {
                            let (a_lo, a_hi) = (
                                i64::from(a) - i64::from(half),
                                i64::from(a) + i64::from(half),
                            );
                            let (b_lo, b_hi) =
                                (i64::from(b) - i64::from(q), i64::from(b) + i64::from(q));
                            a_hi.min(b_hi) - a_lo.max(b_lo)
                        };
                        let (ox, oy) = (overlap(centre.i, i), overlap(centre.j, j));
                        if ox >= 0 && oy >= 0 && (ox > 0 || oy > 0) {
                            required = required.max(k * matrix.d2(GridPoint::new(i, j), q));
                        }
                    }
                }
            }
            let code = matrix.d2_code(centre, half);
            if scale.decode(code) < required {
                return fail(format!(
                    "block {centre:?} (half {half}) stores d2 {} below the {required} it needs",
                    scale.decode(code)
                ));
            }
            if code > 1 && scale.decode(code - 1) >= required {
                return fail(format!(
                    "block {centre:?} (half {half}) stores code {code}, one more than it needs"
                ));
            }
            if code == 1 && required == 0.0 {
                return fail(format!(
                    "block {centre:?} (half {half}) stores 1 for a d2 of 0"
                ));
            }
        }
        half *= 2;
    }
    if scale.largest() != largest_local {
        return fail(format!(
            "the top code stands for {}, the largest local d2 is {largest_local}",
            scale.largest()
        ));
    }
    for id in 0..lattice.n_vertices() as u32 {
        let p = lattice.point(id);
        let centre = matches!(lattice.classify(p), VertexClass::Square { .. });
        if !owned[id as usize] && !centre && matrix.blend_byte(id) != 0 {
            return fail(format!(
                "{p:?} belongs to no block but holds {}",
                matrix.blend_byte(id)
            ));
        }
    }
    Ok(())
}

/// Checks a frame's blend bytes, subdivided list, midpoints and fans against its mesh, and
/// the morphed heights (`morphed`, with geomorphing) against the blends.
pub(super) fn validate_frame(
    hierarchy: &Hierarchy,
    matrix: &QuadtreeMatrix,
    mesh: &VertexSet,
    subdivided: &[u32],
    morphed: Option<&MorphedHeights>,
) -> Result<(), RottgerStateError> {
    let lattice = hierarchy.lattice();
    let mut listed = vec![false; lattice.n_vertices()];
    for &id in subdivided {
        let p = lattice.point(id);
        if !matches!(lattice.classify(p), VertexClass::Square { .. }) {
            return fail(format!(
                "{p:?} is listed as subdivided but is no block centre"
            ));
        }
        if std::mem::replace(&mut listed[id as usize], true) {
            return fail(format!("{p:?} is listed twice"));
        }
    }
    for id in 0..lattice.n_vertices() as u32 {
        let p = lattice.point(id);
        let active = mesh.contains(id);
        match lattice.classify(p) {
            VertexClass::Corner => {}
            VertexClass::Square { .. } => {
                let byte = matrix.blend_byte(id);
                if active != (byte != 0) || active != listed[id as usize] {
                    return fail(format!(
                        "block {p:?}: in the mesh {active}, blend byte {byte}, listed {}",
                        listed[id as usize]
                    ));
                }
            }
            VertexClass::Rotated { .. } => {
                let beside = lattice
                    .parents(p)
                    .as_slice()
                    .iter()
                    .all(|q| mesh.contains_point(lattice, *q));
                if active != beside {
                    return fail(format!(
                        "midpoint {p:?}: in the mesh {active}, blocks beside it subdivided {beside}"
                    ));
                }
            }
        }
    }
    let fans = count_fans(hierarchy, mesh, subdivided, None);
    let triangles = mesh.triangle_count(lattice);
    if fans.triangles != triangles {
        return fail(format!(
            "the fans draw {} triangles, the mesh has {triangles}",
            fans.triangles
        ));
    }
    if let Some(morphed) = morphed {
        validate_morphed(hierarchy, matrix, mesh, morphed)?;
    }
    Ok(())
}

/// Every vertex of the mesh that morphs is in `morphed` at its morphed height, and nothing else
/// is.
fn validate_morphed(
    hierarchy: &Hierarchy,
    matrix: &QuadtreeMatrix,
    mesh: &VertexSet,
    morphed: &MorphedHeights,
) -> Result<(), RottgerStateError> {
    let lattice = hierarchy.lattice();
    let mut morphing = 0;
    for id in mesh.iter() {
        let p = lattice.point(id);
        let byte = vertex_blend_byte(lattice, matrix, p);
        let expected =
            morphs(hierarchy, p, byte).then(|| morphed_height(hierarchy, p, byte) as f32);
        if morphed.get(id) != expected {
            return fail(format!(
                "vertex {p:?} (blend byte {byte}) is drawn at {:?} in the mesh output, not {expected:?}",
                morphed.get(id)
            ));
        }
        morphing += usize::from(expected.is_some());
    }
    if morphed.len() != morphing {
        return fail(format!(
            "the mesh output morphs {} vertices, {morphing} of the mesh morph",
            morphed.len()
        ));
    }
    Ok(())
}
