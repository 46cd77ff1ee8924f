//! The `vanek` validator: one frame's levels, culling and triangles checked against rules
//! recomputed from scratch. Tests call it after every frame; the mesh itself is checked by the
//! triangle-list validator under crack policy `collapsed` (the surface tiles the domain, every
//! inner surface edge is shared by two surface triangles) like every algorithm's, in tests and
//! under `roamsim run --check`.
//!
//! Checked, first failure reported (patches row by row):
//! 1. every drawn patch's level is the brute-force one ([`lods_from_scratch`]: the patch's
//!    height range and distance recomputed from its samples, k found by trying every level);
//! 2. a patch is culled exactly when culling is on and its box is outside the view (the
//!    quadtree culls a node only where the test culls each of its patches, `block_lod/quadtree.rs`);
//! 3. the list has, per drawn patch, its strip's triangles ((2m + 2)(m − 1) − 2, m = 2^k + 1),
//!    and its degenerate triangles are the strip joins (4(m − 1) − 2 per patch) plus the
//!    collapsed ones the algorithm counted;
//! 4. collapsed borders line up: along every side two drawn patches share, the distinct corners
//!    of both patches' surface triangles on it (positions and heights) are the same, and are
//!    exactly the samples of the coarser patch's level (2^k′ + 1 of them). A side beside a
//!    culled patch meets nothing and is not collapsed.

use super::select::{LodCurve, LodRounding, patch_distance};
use super::{EAST, NORTH, SOUTH, Vanek, VanekConfig, WEST};
use crate::sim::algorithm::block_lod::cull::box_outside_view;
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::{SUBGRID_UNITS_PER_CELL, TriangleRole};
use crate::sim::view::Camera;
use glam::DVec3;

/// The first thing found wrong with a frame.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum VanekError {
    #[error("patch {patch}: level {lod}, the brute-force selection gives {expected}")]
    LodWrong {
        patch: usize,
        lod: u32,
        expected: u32,
    },
    #[error("patch {patch}: culled is {culled}, its box outside the view is {outside}")]
    CullingWrong {
        patch: usize,
        culled: bool,
        outside: bool,
    },
    #[error("the triangle list has {actual} {what}; the levels imply {expected}")]
    MeshCountWrong {
        what: &'static str,
        expected: u64,
        actual: u64,
    },
    #[error(
        "patches {patch} and {neighbour}: their shared side has the vertices {ours:?} and \
         {theirs:?} (grid units, heights); the coarser level has {expected}"
    )]
    BorderMismatch {
        patch: usize,
        neighbour: usize,
        ours: Vec<((f64, f64), f32)>,
        theirs: Vec<((f64, f64), f32)>,
        expected: u32,
    },
}

/// Every patch's level, row by row, recomputed by brute force for an eye at `eye` (terrain-local
/// metres) and distances multiplied by `multiplier`: the box from the patch's samples, the
/// distance by clamping, and k as the level the rounding picks among all n + 1.
pub fn lods_from_scratch(
    hierarchy: &Hierarchy,
    config: &VanekConfig,
    multiplier: f64,
    eye: DVec3,
) -> Vec<u32> {
    let level = hierarchy.lattice().level();
    let n = config.patch_level.clamp(1, level);
    let per_side = 1u32 << (level - n);
    let cells = 1u32 << n;
    let spacing = hierarchy.field().spacing();
    let mut lods = Vec::new();
    for py in 0..per_side {
        for px in 0..per_side {
            let (x0, y0) = (px * cells, py * cells);
            let heights: Vec<f32> = (y0..=y0 + cells)
                .flat_map(|j| (x0..=x0 + cells).map(move |i| (i, j)))
                .map(|(i, j)| hierarchy.height(GridPoint::new(i, j)))
                .collect();
            let low = heights.iter().copied().fold(f32::INFINITY, f32::min);
            let high = heights.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            let corner = |i: u32, j: u32, z: f32| {
                DVec3::new(
                    f64::from(i) * spacing.dx,
                    f64::from(j) * spacing.dy,
                    f64::from(z),
                )
            };
            let dist = patch_distance(
                eye,
                corner(x0, y0, low),
                corner(x0 + cells, y0 + cells, high),
                config.distance,
            );
            lods.push(brute_force_lod(&config.curve, n, dist * multiplier));
        }
    }
    lods
}

/// The level among 0..=n that `curve`'s rounding picks for the continuous k at `dist`.
fn brute_force_lod(curve: &LodCurve, n: u32, dist: f64) -> u32 {
    let k = if dist <= curve.min_dist_m {
        f64::from(n)
    } else if dist >= curve.max_dist_m {
        0.0
    } else {
        let t = (dist - curve.min_dist_m) / (curve.max_dist_m - curve.min_dist_m);
        f64::from(n) * (1.0 - t.powf(curve.exponent))
    };
    let levels = 0..=n;
    match curve.rounding {
        LodRounding::Down => levels.filter(|&j| f64::from(j) <= k).max().unwrap_or(0),
        LodRounding::Up => levels.filter(|&j| f64::from(j) >= k).min().unwrap_or(n),
        // Halves go up: the larger of two equally near levels.
        LodRounding::Nearest => levels
            .rev()
            .min_by(|&a, &b| {
                (f64::from(a) - k)
                    .abs()
                    .total_cmp(&(f64::from(b) - k).abs())
            })
            .unwrap_or(0),
    }
}

pub(super) fn validate(vanek: &Vanek, camera: &Camera) -> Result<(), VanekError> {
    let expected = lods_from_scratch(vanek.hierarchy, &vanek.config, vanek.multiplier, camera.eye);
    for (patch, &want) in expected.iter().enumerate() {
        let culled = !vanek.is_drawn(patch);
        let lod = vanek.lods[patch];
        if !culled && lod != want {
            return Err(VanekError::LodWrong {
                patch,
                lod,
                expected: want,
            });
        }
        let outside = box_outside_view(camera, &vanek.patch_box(patch));
        if culled != (vanek.config.box_culling && outside) {
            return Err(VanekError::CullingWrong {
                patch,
                culled,
                outside,
            });
        }
    }
    validate_mesh(vanek)
}

/// Checks 3 and 4: the list against the frame's levels and culling.
pub(super) fn validate_mesh(vanek: &Vanek) -> Result<(), VanekError> {
    let (mut triangles, mut joins) = (0, 0);
    for patch in (0..vanek.lods.len()).filter(|&p| vanek.is_drawn(p)) {
        let m = (1u64 << vanek.lods[patch]) + 1;
        triangles += (2 * m + 2) * (m - 1) - 2;
        joins += 4 * (m - 1) - 2;
    }
    let list = &vanek.list;
    for (what, expected, actual) in [
        ("triangles", triangles, list.n_triangles()),
        (
            "degenerate triangles",
            joins + vanek.collapsed,
            list.role_count(TriangleRole::Degenerate),
        ),
    ] {
        if expected != actual {
            return Err(VanekError::MeshCountWrong {
                what,
                expected,
                actual,
            });
        }
    }
    borders_line_up(vanek)
}

/// A border vertex: fixed-point position and height bits.
type BorderVertex = ((i64, i64), u32);

/// Check 4: per drawn patch and side, the distinct surface corners on the side, compared with
/// the neighbour's and with the coarser level's samples.
fn borders_line_up(vanek: &Vanek) -> Result<(), VanekError> {
    let unit = SUBGRID_UNITS_PER_CELL;
    let cells = i64::from(vanek.cells());
    let mut on_side: Vec<[Vec<BorderVertex>; 4]> = vec![Default::default(); vanek.lods.len()];
    let vertices = vanek.list.vertices();
    for (corners, info) in vanek.list.triangles().iter().zip(vanek.list.info()) {
        if !info.role.is_surface() {
            continue;
        }
        let patch = info.group as usize;
        let (x0, y0) = vanek.origin(patch);
        let (x0, y0) = (i64::from(x0) * unit, i64::from(y0) * unit);
        let (x1, y1) = (x0 + cells * unit, y0 + cells * unit);
        for &c in corners {
            let point = vertices[c as usize];
            let (x, y) = point.position.raw();
            let key = ((x, y), point.z.to_bits());
            for (side, on) in [
                (WEST, x == x0),
                (EAST, x == x1),
                (SOUTH, y == y0),
                (NORTH, y == y1),
            ] {
                if on {
                    on_side[patch][side].push(key);
                }
            }
        }
    }
    for sides in &mut on_side {
        for list in sides.iter_mut() {
            list.sort_unstable();
            list.dedup();
        }
    }
    for patch in 0..vanek.lods.len() {
        for (side, opposite) in [(EAST, WEST), (NORTH, SOUTH)] {
            let Some(neighbour) = vanek.neighbour(patch, side) else {
                continue;
            };
            if !vanek.is_drawn(patch) || !vanek.is_drawn(neighbour) {
                continue;
            }
            let coarser = vanek.lods[patch].min(vanek.lods[neighbour]);
            let expected = (1u32 << coarser) + 1;
            let (ours, theirs) = (&on_side[patch][side], &on_side[neighbour][opposite]);
            if ours != theirs || ours.len() != expected as usize {
                let readable = |list: &[BorderVertex]| {
                    list.iter()
                        .map(|&((x, y), z)| {
                            (
                                (x as f64 / unit as f64, y as f64 / unit as f64),
                                f32::from_bits(z),
                            )
                        })
                        .collect()
                };
                return Err(VanekError::BorderMismatch {
                    patch,
                    neighbour,
                    ours: readable(ours),
                    theirs: readable(theirs),
                    expected,
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::select::PatchDistance;
    use super::*;

    #[test]
    fn the_brute_force_level_agrees_with_the_formula_everywhere_on_a_fine_sweep() {
        for rounding in [LodRounding::Down, LodRounding::Nearest, LodRounding::Up] {
            for exponent in [0.5, 1.0, 2.0] {
                let curve = LodCurve {
                    min_dist_m: 50.0,
                    max_dist_m: 650.0,
                    exponent,
                    rounding,
                };
                for step in 0..=7000 {
                    let d = f64::from(step) * 0.1;
                    assert_eq!(
                        brute_force_lod(&curve, 9, d),
                        curve.lod(9, d),
                        "{curve:?} at {d} m"
                    );
                }
            }
        }
    }

    #[test]
    fn a_patch_is_never_drawn_coarser_for_its_distance_by_centre_than_by_box() {
        let (low, high) = (DVec3::ZERO, DVec3::new(100.0, 100.0, 10.0));
        let curve = LodCurve {
            min_dist_m: 10.0,
            max_dist_m: 400.0,
            exponent: 1.0,
            rounding: LodRounding::Down,
        };
        for x in [-300.0, -20.0, 0.0, 50.0, 130.0] {
            let eye = DVec3::new(x, 40.0, 30.0);
            let by_box = curve.lod(6, patch_distance(eye, low, high, PatchDistance::Box));
            let by_centre = curve.lod(6, patch_distance(eye, low, high, PatchDistance::Centre));
            assert!(by_box >= by_centre, "eye x = {x}");
        }
    }
}
