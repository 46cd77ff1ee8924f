//! The experiment entries of the block-based algorithms, `geomipmap`, `chunked`, `vanek` and
//! `stitching-strips`: their
//! parameters as the file writes them (format version 1, documented in
//! `docs/experiment-format.md`) and their check into an [`AlgorithmConfig`]. Kept apart from
//! `check.rs`, which only dispatches to it by name.

use super::FieldProblem;
use crate::sim::algorithm::chunked::detail::MAX_DETAIL_LEVELS;
use crate::sim::algorithm::chunked::{DetailConfig, LoadingConfig};
use crate::sim::algorithm::{
    AlgorithmConfig, BlockDistance, BlockGoal, ChunkedConfig, GeomipmapConfig, LevelDifference,
    LodCurve, LodRounding, PBlockShape, PatchDistance, Projection, SkirtDepth, StitchingConfig,
    StitchingMethod, VanekConfig, ViewDirection,
};
use serde::Deserialize;
use serde_json::Value;

/// The paper's chunks: 65² vertices (Lauritsen–Nielsen §6.1.2).
pub const CHUNKED_DEFAULT_CHUNK_LEVEL: u32 = 6;

/// `geomipmap`: exactly one of `tau_px` and `target_triangles`, and the patch level k
/// (patches of (2^k + 1)² samples).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct GeomipmapParameters {
    #[serde(default)]
    tau_px: Option<f64>,
    #[serde(default)]
    target_triangles: Option<u64>,
    patch_level: u32,
    /// Default `one` (the survey's figure 2.14).
    #[serde(default)]
    level_difference: Option<LevelDifferenceEntry>,
    #[serde(default)]
    morph: bool,
    /// Default `horizontal_view` (the papers').
    #[serde(default)]
    projection: Option<ProjectionEntry>,
}

/// `chunked`: exactly one of `tau_px` and `target_triangles`; the chunk level c (chunks of
/// (2^c + 1)² vertices, default 6); skirts, projection and the effects.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ChunkedParameters {
    #[serde(default)]
    tau_px: Option<f64>,
    #[serde(default)]
    target_triangles: Option<u64>,
    #[serde(default)]
    chunk_level: Option<u32>,
    /// Default `chunk_error` (the paper's §3.2.6).
    #[serde(default)]
    skirt_depth: Option<SkirtDepthEntry>,
    #[serde(default)]
    projection: Option<ProjectionEntry>,
    #[serde(default)]
    morph: bool,
    #[serde(default)]
    box_culling: bool,
    #[serde(default)]
    front_to_back: bool,
    /// Runtime detail below the finest source level (§3.3–3.4); absent: off.
    #[serde(default)]
    detail: Option<DetailEntry>,
    /// Out-of-core loading with latency (§3.2.14); absent: off.
    #[serde(default)]
    loading: Option<LoadingEntry>,
}

/// `chunked.loading`: the latency, the bandwidth and the memory cap.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LoadingEntry {
    latency_frames: u32,
    bandwidth_chunks_per_frame: u32,
    resident_chunks: u32,
}

/// `chunked.detail`: the synthesised levels, the displacement function, the creation limit
/// and the cache's size.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DetailEntry {
    levels: u32,
    seed: u64,
    amplitude_m: f64,
    /// Default 0.5 (each octave half the previous one's amplitude).
    #[serde(default)]
    roughness: Option<f64>,
    max_created_per_frame: u32,
    cache_chunks: u32,
}

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

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum LevelDifferenceEntry {
    One,
    Any,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum ProjectionEntry {
    HorizontalView,
    Exact,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum SkirtDepthEntry {
    ChunkError,
    Covering,
}

/// The `geomipmap` entry at `origin` (e.g. `algorithms[3]`), or every problem found in it.
pub(super) fn geomipmap_config(
    origin: &str,
    parameters: &Value,
) -> Result<AlgorithmConfig, Vec<FieldProblem>> {
    let p: GeomipmapParameters = decode(origin, parameters)?;
    let mut problems = Vec::new();
    let goal = goal(origin, p.tau_px, p.target_triangles, &mut problems);
    level_in_range(origin, "patch_level", p.patch_level, &mut problems);
    match goal {
        Some(goal) if problems.is_empty() => Ok(AlgorithmConfig::Geomipmap(GeomipmapConfig {
            patch_level: p.patch_level,
            goal,
            level_difference: match p.level_difference {
                None | Some(LevelDifferenceEntry::One) => LevelDifference::AtMostOne,
                Some(LevelDifferenceEntry::Any) => LevelDifference::Any,
            },
            morph: p.morph,
            projection: projection(p.projection),
        })),
        _ => Err(problems),
    }
}

/// The `chunked` entry at `origin`, or every problem found in it.
pub(super) fn chunked_config(
    origin: &str,
    parameters: &Value,
) -> Result<AlgorithmConfig, Vec<FieldProblem>> {
    let p: ChunkedParameters = decode(origin, parameters)?;
    let mut problems = Vec::new();
    let goal = goal(origin, p.tau_px, p.target_triangles, &mut problems);
    let chunk_level = p.chunk_level.unwrap_or(CHUNKED_DEFAULT_CHUNK_LEVEL);
    level_in_range(origin, "chunk_level", chunk_level, &mut problems);
    let detail = p
        .detail
        .map(|entry| detail_config(origin, &entry, &mut problems));
    let loading = p.loading.map(|entry| {
        let mut add = |field: &str, problem: String| {
            problems.push(FieldProblem {
                field: format!("{origin}.loading.{field}"),
                problem,
            })
        };
        if entry.latency_frames < 1 {
            add(
                "latency_frames",
                "0: expected at least 1 frame (a request is made after the frame's selection)"
                    .to_string(),
            );
        }
        for (field, value) in [
            (
                "bandwidth_chunks_per_frame",
                entry.bandwidth_chunks_per_frame,
            ),
            ("resident_chunks", entry.resident_chunks),
        ] {
            if value < 4 {
                add(
                    field,
                    format!("{value}: expected at least 4 chunks (siblings travel together)"),
                );
            }
        }
        LoadingConfig {
            latency_frames: entry.latency_frames,
            bandwidth_chunks_per_frame: entry.bandwidth_chunks_per_frame,
            resident_chunks: entry.resident_chunks,
        }
    });
    match goal {
        Some(goal) if problems.is_empty() => Ok(AlgorithmConfig::Chunked(ChunkedConfig {
            detail,
            loading,
            chunk_level,
            goal,
            projection: projection(p.projection),
            skirts: match p.skirt_depth {
                None | Some(SkirtDepthEntry::ChunkError) => SkirtDepth::ChunkError,
                Some(SkirtDepthEntry::Covering) => SkirtDepth::Covering,
            },
            morph: p.morph,
            culling: p.box_culling,
            front_to_back: p.front_to_back,
        })),
        _ => Err(problems),
    }
}

/// The detail effect of the `chunked` entry at `origin`; problems added to `problems`.
fn detail_config(
    origin: &str,
    entry: &DetailEntry,
    problems: &mut Vec<FieldProblem>,
) -> DetailConfig {
    let mut add = |field: &str, problem: String| {
        problems.push(FieldProblem {
            field: format!("{origin}.detail.{field}"),
            problem,
        })
    };
    if !(1..=MAX_DETAIL_LEVELS).contains(&entry.levels) {
        add(
            "levels",
            format!(
                "{}: expected 1 to {MAX_DETAIL_LEVELS} synthesised levels",
                entry.levels
            ),
        );
    }
    if !(entry.amplitude_m >= 0.0 && entry.amplitude_m.is_finite()) {
        add(
            "amplitude_m",
            format!(
                "{}: expected a finite amplitude of at least 0 m",
                entry.amplitude_m
            ),
        );
    }
    let roughness = entry.roughness.unwrap_or(0.5);
    if !(0.0..=1.0).contains(&roughness) {
        add(
            "roughness",
            format!("{roughness}: expected a ratio from 0 to 1"),
        );
    }
    for (field, value) in [
        ("max_created_per_frame", entry.max_created_per_frame),
        ("cache_chunks", entry.cache_chunks),
    ] {
        if value < 4 {
            add(
                field,
                format!("{value}: expected at least 4 chunks (children are made four at a time)"),
            );
        }
    }
    DetailConfig {
        levels: entry.levels,
        seed: entry.seed,
        amplitude_m: entry.amplitude_m,
        roughness,
        max_created_per_frame: entry.max_created_per_frame,
        cache_chunks: entry.cache_chunks,
    }
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

fn decode<T: serde::de::DeserializeOwned>(
    origin: &str,
    parameters: &Value,
) -> Result<T, Vec<FieldProblem>> {
    serde_path_to_error::deserialize(parameters).map_err(|error| {
        let inner = error.path().to_string();
        let field = if inner == "." {
            origin.to_string()
        } else {
            format!("{origin}.{inner}")
        };
        vec![FieldProblem {
            field,
            problem: error.into_inner().to_string(),
        }]
    })
}

/// The goal: exactly one of a tolerance (finite, ≥ 0) and a triangle target (≥ 1).
fn goal(
    origin: &str,
    tau_px: Option<f64>,
    target_triangles: Option<u64>,
    problems: &mut Vec<FieldProblem>,
) -> Option<BlockGoal> {
    let mut add = |field: String, problem: String| problems.push(FieldProblem { field, problem });
    match (tau_px, target_triangles) {
        (Some(tau), None) if tau >= 0.0 && tau.is_finite() => Some(BlockGoal::TolerancePx(tau)),
        (Some(tau), None) => {
            add(
                format!("{origin}.tau_px"),
                format!("{tau}: expected a finite tolerance of at least 0 pixels"),
            );
            None
        }
        (None, Some(0)) => {
            add(
                format!("{origin}.target_triangles"),
                "0: expected at least 1 triangle".to_string(),
            );
            None
        }
        (None, Some(target)) => Some(BlockGoal::TargetTriangles(target)),
        _ => {
            add(
                origin.to_string(),
                "expected exactly one of \"tau_px\" and \"target_triangles\"".to_string(),
            );
            None
        }
    }
}

/// Patch and chunk levels: blocks of (2^k + 1)² samples, the largest grid has level 15.
fn level_in_range(origin: &str, name: &str, level: u32, problems: &mut Vec<FieldProblem>) {
    if !(1..=15).contains(&level) {
        problems.push(FieldProblem {
            field: format!("{origin}.{name}"),
            problem: format!("{level}: expected a level from 1 to 15 (blocks of (2^k+1)² samples)"),
        });
    }
}

fn projection(entry: Option<ProjectionEntry>) -> Projection {
    match entry {
        None | Some(ProjectionEntry::HorizontalView) => Projection::HorizontalView,
        Some(ProjectionEntry::Exact) => Projection::Exact,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn defaults_are_the_papers_and_options_are_read() {
        let chunked = chunked_config("a", &json!({"tau_px": 4})).unwrap();
        assert_eq!(
            chunked,
            AlgorithmConfig::Chunked(ChunkedConfig {
                chunk_level: 6,
                goal: BlockGoal::TolerancePx(4.0),
                projection: Projection::HorizontalView,
                skirts: SkirtDepth::ChunkError,
                morph: false,
                culling: false,
                front_to_back: false,
                detail: None,
                loading: None,
            })
        );
        let geomipmap = geomipmap_config(
            "a",
            &json!({"target_triangles": 9000, "patch_level": 4, "level_difference": "any",
                    "morph": true, "projection": "exact"}),
        )
        .unwrap();
        assert_eq!(
            geomipmap,
            AlgorithmConfig::Geomipmap(GeomipmapConfig {
                patch_level: 4,
                goal: BlockGoal::TargetTriangles(9000),
                level_difference: LevelDifference::Any,
                morph: true,
                projection: Projection::Exact,
            })
        );
    }

    #[test]
    fn bad_entries_name_the_field_and_what_was_expected() {
        let fields = |result: Result<AlgorithmConfig, Vec<FieldProblem>>| -> Vec<String> {
            result
                .unwrap_err()
                .into_iter()
                .map(|p| format!("{}: {}", p.field, p.problem))
                .collect()
        };
        assert_eq!(
            fields(chunked_config(
                "algorithms[2]",
                &json!({"tau_px": -1, "chunk_level": 0})
            )),
            [
                "algorithms[2].tau_px: -1: expected a finite tolerance of at least 0 pixels",
                "algorithms[2].chunk_level: 0: expected a level from 1 to 15 (blocks of (2^k+1)² samples)"
            ]
        );
        assert_eq!(
            fields(geomipmap_config("g", &json!({"patch_level": 4}))),
            ["g: expected exactly one of \"tau_px\" and \"target_triangles\""]
        );
        let unknown = fields(chunked_config("c", &json!({"tau_px": 1, "skirts": true})));
        assert!(
            unknown[0].starts_with("c.skirts: unknown field `skirts`"),
            "{unknown:?}"
        );
        let missing = fields(geomipmap_config("g", &json!({"tau_px": 1})));
        assert!(
            missing[0].contains("missing field `patch_level`"),
            "{missing:?}"
        );
    }

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
