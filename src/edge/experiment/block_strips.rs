//! The experiment entries of the two block-based algorithms whose blocks are joined by strips
//! (SPEC §6), `vanek` (Vaněk–Ježek's distance-driven patches with degenerate strips) and
//! `stitching-strips` (continuously tessellated blocks with stitching strips, 2019): their
//! parameters as the file writes them (format version 1, documented in
//! `docs/experiment-format.md`) and their check into an [`AlgorithmConfig`]. Not the other
//! entries (`parameters.rs`, which dispatches here by name; `block_lod.rs`, whose shared rules
//! this uses).
//!
//! **Defaults on their fields.** Each optional parameter's default is named on its field here
//! and documented in `docs/experiment-format.md`; the stitching strips' options (method, view
//! direction, P-block shape, distance) are where the paper is open.

use super::block_lod::{decode, level_in_range};
use super::problems::FieldProblem;
use crate::sim::algorithm::{
    AlgorithmConfig, BlockDistance, LodCurve, LodRounding, PBlockShape, PatchDistance,
    StitchingConfig, StitchingMethod, VanekConfig, ViewDirection,
};
use serde::Deserialize;
use serde_json::Value;

/// `vanek`: the patch level n, the paper's mindist, maxdist and exp, how k is rounded and dist
/// measured, an optional triangle target and box culling.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct VanekParameters {
    patch_level: u32,
    min_dist_m: f64,
    max_dist_m: f64,
    /// Default 1 (linear).
    #[serde(default)]
    exponent: Option<f64>,
    /// Default `down`.
    #[serde(default)]
    rounding: Option<RoundingEntry>,
    /// Default `box`.
    #[serde(default)]
    distance: Option<DistanceEntry>,
    #[serde(default)]
    target_triangles: Option<u64>,
    #[serde(default)]
    box_culling: bool,
}

/// `stitching-strips`: ρ_thr, the smallest block's level, the strip width, the method and the
/// options where the paper is open.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct StitchingParameters {
    rho_threshold_px: f64,
    block_level: u32,
    /// Default 1 cell.
    #[serde(default)]
    strip_width_cells: Option<f64>,
    /// Default `strips`.
    #[serde(default)]
    method: Option<MethodEntry>,
    /// Default `centre`.
    #[serde(default)]
    distance: Option<DistanceEntry>,
    /// Default `to_block`.
    #[serde(default)]
    view_direction: Option<ViewDirectionEntry>,
    /// Default `two_triangles`.
    #[serde(default)]
    p_block: Option<PBlockEntry>,
    #[serde(default)]
    culling: bool,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum MethodEntry {
    Strips,
    PowerOfTwo,
    Uniform,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum ViewDirectionEntry {
    ToBlock,
    Look,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum PBlockEntry {
    TwoTriangles,
    Fan,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum RoundingEntry {
    Down,
    Nearest,
    Up,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum DistanceEntry {
    Box,
    Centre,
}

/// The `vanek` entry at `origin`, or every problem found in it.
pub(super) fn vanek_config(
    origin: &str,
    parameters: &Value,
) -> Result<AlgorithmConfig, Vec<FieldProblem>> {
    let p: VanekParameters = decode(origin, parameters)?;
    let mut problems = Vec::new();
    let mut add = |field: &str, problem: String| {
        problems.push(FieldProblem {
            field: format!("{origin}.{field}"),
            problem,
        })
    };
    if !(p.min_dist_m >= 0.0 && p.min_dist_m.is_finite()) {
        add(
            "min_dist_m",
            format!(
                "{}: expected a finite distance of at least 0 m",
                p.min_dist_m
            ),
        );
    } else if !(p.max_dist_m > p.min_dist_m && p.max_dist_m.is_finite()) {
        add(
            "max_dist_m",
            format!(
                "{}: expected a finite distance above min_dist_m ({} m)",
                p.max_dist_m, p.min_dist_m
            ),
        );
    }
    let exponent = p.exponent.unwrap_or(1.0);
    if !(exponent > 0.0 && exponent.is_finite()) {
        add(
            "exponent",
            format!("{exponent}: expected a finite exponent above 0"),
        );
    }
    if p.target_triangles == Some(0) {
        add(
            "target_triangles",
            "0: expected at least 1 triangle".to_string(),
        );
    }
    level_in_range(origin, "patch_level", p.patch_level, &mut problems);
    if !problems.is_empty() {
        return Err(problems);
    }
    Ok(AlgorithmConfig::Vanek(VanekConfig {
        patch_level: p.patch_level,
        curve: LodCurve {
            min_dist_m: p.min_dist_m,
            max_dist_m: p.max_dist_m,
            exponent,
            rounding: match p.rounding {
                None | Some(RoundingEntry::Down) => LodRounding::Down,
                Some(RoundingEntry::Nearest) => LodRounding::Nearest,
                Some(RoundingEntry::Up) => LodRounding::Up,
            },
        },
        distance: match p.distance {
            None | Some(DistanceEntry::Box) => PatchDistance::Box,
            Some(DistanceEntry::Centre) => PatchDistance::Centre,
        },
        target_triangles: p.target_triangles,
        box_culling: p.box_culling,
    }))
}

/// The `stitching-strips` entry at `origin`, or every problem found in it.
pub(super) fn stitching_config(
    origin: &str,
    parameters: &Value,
) -> Result<AlgorithmConfig, Vec<FieldProblem>> {
    let p: StitchingParameters = decode(origin, parameters)?;
    let mut problems = Vec::new();
    if !(p.rho_threshold_px >= 0.0 && p.rho_threshold_px.is_finite()) {
        problems.push(FieldProblem {
            field: format!("{origin}.rho_threshold_px"),
            problem: format!(
                "{}: expected a finite threshold of at least 0 pixels",
                p.rho_threshold_px
            ),
        });
    }
    let strip_width_cells = p.strip_width_cells.unwrap_or(1.0);
    if !(strip_width_cells > 0.0 && strip_width_cells.is_finite()) {
        problems.push(FieldProblem {
            field: format!("{origin}.strip_width_cells"),
            problem: format!(
                "{strip_width_cells}: expected a finite width above 0 cells (it is clamped to \
                 half the smallest block)"
            ),
        });
    }
    level_in_range(origin, "block_level", p.block_level, &mut problems);
    if !problems.is_empty() {
        return Err(problems);
    }
    Ok(AlgorithmConfig::Stitching(StitchingConfig {
        threshold_px: p.rho_threshold_px,
        block_level: p.block_level,
        strip_width_cells,
        method: match p.method {
            None | Some(MethodEntry::Strips) => StitchingMethod::Strips,
            Some(MethodEntry::PowerOfTwo) => StitchingMethod::PowerOfTwo,
            Some(MethodEntry::Uniform) => StitchingMethod::Uniform,
        },
        distance: match p.distance {
            None | Some(DistanceEntry::Centre) => BlockDistance::Centre,
            Some(DistanceEntry::Box) => BlockDistance::Box,
        },
        view_direction: match p.view_direction {
            None | Some(ViewDirectionEntry::ToBlock) => ViewDirection::ToBlock,
            Some(ViewDirectionEntry::Look) => ViewDirection::Look,
        },
        p_block: match p.p_block {
            None | Some(PBlockEntry::TwoTriangles) => PBlockShape::TwoTriangles,
            Some(PBlockEntry::Fan) => PBlockShape::Fan,
        },
        culling: p.culling,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn stitching_entries_defaults_options_and_bad_values() {
        let plain = stitching_config(
            "algorithms[0]",
            &json!({"rho_threshold_px": 1.0, "block_level": 3}),
        )
        .expect("a plain entry");
        assert_eq!(
            plain,
            AlgorithmConfig::Stitching(StitchingConfig {
                threshold_px: 1.0,
                block_level: 3,
                strip_width_cells: 1.0,
                method: StitchingMethod::Strips,
                distance: BlockDistance::Centre,
                view_direction: ViewDirection::ToBlock,
                p_block: PBlockShape::TwoTriangles,
                culling: false,
            })
        );
        let AlgorithmConfig::Stitching(options) = stitching_config(
            "algorithms[0]",
            &json!({"rho_threshold_px": 2.0, "block_level": 4,
                    "strip_width_cells": 0.5, "method": "power_of_two", "distance": "box",
                    "view_direction": "look", "p_block": "fan", "culling": true}),
        )
        .expect("every option") else {
            panic!("not stitching-strips")
        };
        assert_eq!(options.method, StitchingMethod::PowerOfTwo);
        assert_eq!(options.distance, BlockDistance::Box);
        assert_eq!(options.view_direction, ViewDirection::Look);
        assert_eq!(options.p_block, PBlockShape::Fan);
        assert!(options.culling && options.strip_width_cells == 0.5);
        let problems: Vec<String> = stitching_config(
            "algorithms[2]",
            &json!({"rho_threshold_px": -1.0, "block_level": 0,
                    "strip_width_cells": 0.0}),
        )
        .expect_err("bad values")
        .into_iter()
        .map(|p| p.field)
        .collect();
        assert_eq!(
            problems,
            [
                "algorithms[2].rho_threshold_px",
                "algorithms[2].strip_width_cells",
                "algorithms[2].block_level"
            ]
        );
        let unknown = stitching_config(
            "algorithms[0]",
            &json!({"rho_threshold_px": 1.0, "block_level": 3,
                    "method": "quadtree"}),
        )
        .expect_err("an unknown method");
        assert_eq!(unknown[0].field, "algorithms[0].method");
    }

    #[test]
    fn vanek_entries_defaults_options_and_bad_values() {
        let plain = vanek_config(
            "v",
            &json!({"patch_level": 4, "min_dist_m": 10, "max_dist_m": 500}),
        )
        .unwrap();
        assert_eq!(
            plain,
            AlgorithmConfig::Vanek(VanekConfig {
                patch_level: 4,
                curve: LodCurve {
                    min_dist_m: 10.0,
                    max_dist_m: 500.0,
                    exponent: 1.0,
                    rounding: LodRounding::Down,
                },
                distance: PatchDistance::Box,
                target_triangles: None,
                box_culling: false,
            })
        );
        let options = vanek_config(
            "v",
            &json!({"patch_level": 3, "min_dist_m": 0, "max_dist_m": 5, "exponent": 0.5,
                    "rounding": "nearest", "distance": "centre", "target_triangles": 900,
                    "box_culling": true}),
        )
        .unwrap();
        let AlgorithmConfig::Vanek(c) = options else {
            panic!("{options:?}")
        };
        assert_eq!(
            (
                c.curve.rounding,
                c.distance,
                c.target_triangles,
                c.box_culling
            ),
            (LodRounding::Nearest, PatchDistance::Centre, Some(900), true)
        );
        assert_eq!(c.curve.exponent, 0.5);
        let problems: Vec<String> = vanek_config(
            "algorithms[1]",
            &json!({"patch_level": 16, "min_dist_m": 50, "max_dist_m": 50, "exponent": 0,
                    "target_triangles": 0}),
        )
        .unwrap_err()
        .into_iter()
        .map(|p| format!("{}: {}", p.field, p.problem))
        .collect();
        assert_eq!(
            problems,
            [
                "algorithms[1].max_dist_m: 50: expected a finite distance above min_dist_m (50 m)",
                "algorithms[1].exponent: 0: expected a finite exponent above 0",
                "algorithms[1].target_triangles: 0: expected at least 1 triangle",
                "algorithms[1].patch_level: 16: expected a level from 1 to 15 (blocks of (2^k+1)² samples)",
            ]
        );
        let negative = vanek_config(
            "v",
            &json!({"patch_level": 2, "min_dist_m": -1, "max_dist_m": 5}),
        )
        .unwrap_err();
        assert_eq!(negative[0].field, "v.min_dist_m");
    }
}
