//! The geomipmap validator: the patch grid and one frame's levels, checked against the rules.
//! Tests call it after every frame; the mesh itself is checked by the triangle-list validator
//! (crack policy `stitched`) like every algorithm's.
//!
//! Checked, first failure reported (patches row by row):
//! 1. the grid: every patch's height range is its samples'; D_0 = 0 and each D_ℓ is the
//!    largest of the level errors up to ℓ (recomputed), so D never falls with the level;
//! 2. the criterion's level is the coarsest acceptable one: d ≥ D_ℓ·C there (or ℓ = 0), and
//!    d < D_ℓ+1·C above it;
//! 3. the drawn level never exceeds the criterion's, and with [`LevelDifference::AtMostOne`]
//!    neighbours differ by at most one and a patch is finer than its criterion only when a
//!    neighbour holds it there (ℓ = neighbour's + 1); with `Any` the levels are the criterion's;
//! 4. every morph factor is eq. 3.5's for the drawn level (1 at the coarsest, in [0, 1]);
//! 5. the triangle list has the triangles the levels imply, the stitch triangles among them.
//!
//! With box culling, steps 2–5 are over the drawn patches, and a culled neighbour is no
//! neighbour (nothing is drawn to stitch to); without it, every patch must be drawn.

use super::super::block_lod::threshold::DetailThreshold;
use super::levels::PatchLevels;
use super::patches::{PatchGrid, level_error};
use super::stitch::{patch_triangles, stitch_triangles};
use super::{GeomipmapConfig, LevelDifference, stitch_steps};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::{TriangleList, TriangleRole};
use crate::sim::view::Camera;

/// The first thing found wrong with the patches or a frame's levels.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GeomipmapError {
    #[error("patch {patch}: its box is not its samples' height range")]
    HeightRangeWrong { patch: usize },
    #[error("patch {patch}, level {level}: stored error {stored} m, recomputed {expected} m")]
    ErrorWrong {
        patch: usize,
        level: u32,
        stored: f32,
        expected: f32,
    },
    #[error("patch {patch}: level {level} is not the criterion's {expected}")]
    CriterionWrong {
        patch: usize,
        level: u32,
        expected: u32,
    },
    #[error("patch {patch}: drawn at level {level}: {problem}")]
    LevelWrong {
        patch: usize,
        level: u32,
        problem: &'static str,
    },
    #[error("patch {patch}: morph factor {stored}, eq. 3.5 gives {expected}")]
    MorphFactorWrong {
        patch: usize,
        stored: f64,
        expected: f64,
    },
    #[error("the triangle list has {actual} {what}; the levels imply {expected}")]
    MeshCountWrong {
        what: &'static str,
        expected: u64,
        actual: u64,
    },
}

/// What the check reads.
pub(super) struct FrameView<'a> {
    pub(super) hierarchy: &'a Hierarchy,
    pub(super) config: GeomipmapConfig,
    pub(super) grid: &'a PatchGrid,
    pub(super) levels: &'a PatchLevels,
    pub(super) threshold: &'a DetailThreshold,
    pub(super) list: &'a TriangleList,
    pub(super) camera: &'a Camera,
}

/// Checks the grid and the frame (see the module docs).
pub(super) fn validate(view: &FrameView) -> Result<(), GeomipmapError> {
    let (grid, levels, threshold) = (view.grid, view.levels, view.threshold);
    let k = grid.patch_level();
    let per_side = grid.per_side();
    let cells = grid.cells();
    for patch in 0..grid.n_patches() {
        let (px, py) = (patch as u32 % per_side, patch as u32 / per_side);
        let (x0, y0) = grid.origin(px, py);
        let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
        for j in y0..=y0 + cells {
            for i in x0..=x0 + cells {
                let z = view.hierarchy.height(GridPoint::new(i, j));
                (low, high) = (low.min(z), high.max(z));
            }
        }
        let block = grid.block_box(patch);
        if (block.low.z, block.high.z) != (f64::from(low), f64::from(high)) {
            return Err(GeomipmapError::HeightRangeWrong { patch });
        }
        let mut nested: f64 = 0.0;
        for level in 0..=k {
            if level > 0 {
                nested = nested.max(level_error(view.hierarchy, (x0, y0), cells, level));
            }
            let expected = super::super::block_lod::grid::round_up_f32(nested);
            let stored = grid.error(patch, level);
            if stored.to_bits() != expected.to_bits() {
                return Err(GeomipmapError::ErrorWrong {
                    patch,
                    level,
                    stored,
                    expected,
                });
            }
        }
        if !levels.is_drawn(patch) {
            if !view.config.box_culling {
                return Err(GeomipmapError::LevelWrong {
                    patch,
                    level: levels.level[patch],
                    problem: "not drawn although nothing is culled",
                });
            }
            continue;
        }
        let d = block.lod_distance(view.camera.eye, view.config.projection);
        let acceptable = |level: u32| level == 0 || !threshold.refines(grid.error(patch, level), d);
        let own = levels.own[patch];
        let coarsest = (0..=k).rev().find(|&l| acceptable(l)).unwrap_or(0);
        if own != coarsest || levels.distance[patch].to_bits() != d.to_bits() {
            return Err(GeomipmapError::CriterionWrong {
                patch,
                level: own,
                expected: coarsest,
            });
        }
        let level = levels.level[patch];
        let neighbours: Vec<usize> = levels
            .neighbours(grid, patch)
            .into_iter()
            .flatten()
            .collect();
        let problem = match view.config.level_difference {
            _ if level > own => Some("coarser than its criterion"),
            LevelDifference::Any if level != own => Some("not its criterion's level"),
            LevelDifference::AtMostOne
                if neighbours
                    .iter()
                    .any(|&q| levels.level[q].abs_diff(level) > 1) =>
            {
                Some("more than one level from a neighbour")
            }
            LevelDifference::AtMostOne
                if level < own && !neighbours.iter().any(|&q| levels.level[q] + 1 == level) =>
            {
                Some("finer than its criterion with no neighbour holding it there")
            }
            _ => None,
        };
        if let Some(problem) = problem {
            return Err(GeomipmapError::LevelWrong {
                patch,
                level,
                problem,
            });
        }
        let expected = if view.config.morph && level < k {
            threshold.morph_factor(grid.error(patch, level), grid.error(patch, level + 1), d)
        } else {
            1.0
        };
        let stored = levels.morph[patch];
        if stored.to_bits() != expected.to_bits() || !(0.0..=1.0).contains(&stored) {
            return Err(GeomipmapError::MorphFactorWrong {
                patch,
                stored,
                expected,
            });
        }
    }
    let mut triangles = 0;
    let mut stitches = 0;
    for &patch in &levels.drawn {
        let patch = patch as usize;
        let n = cells >> levels.level[patch];
        let stitched = stitch_steps(grid, levels, patch);
        triangles += patch_triangles(n, stitched);
        stitches += stitch_triangles(n, stitched);
    }
    for (what, expected, actual) in [
        ("triangles", triangles, view.list.n_triangles()),
        (
            "stitch triangles",
            stitches,
            view.list.role_count(TriangleRole::Stitch),
        ),
    ] {
        if expected != actual {
            return Err(GeomipmapError::MeshCountWrong {
                what,
                expected,
                actual,
            });
        }
    }
    Ok(())
}
