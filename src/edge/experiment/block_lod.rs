//! The experiment entries of two block-based algorithms (SPEC §6), `geomipmap` (de Boer) and
//! `chunked` (Ulrich, Lauritsen–Nielsen): their parameters as the file writes them (format
//! version 1, documented in `docs/experiment-format.md`) and their check into an
//! [`AlgorithmConfig`]; and the rules every block algorithm's entry shares (decoding, the goal,
//! the block level), which `block_strips.rs` uses too. Not the other algorithms' entries
//! (`parameters.rs`, which dispatches here by name, and `block_strips.rs`).
//!
//! **Each entry returns its own problems.** A block entry's check returns its configuration or
//! every problem found in it, rather than adding to the shared collector, and
//! `parameters.rs` adds them to the file's list.

use super::problems::FieldProblem;
use crate::sim::algorithm::chunked::detail::MAX_DETAIL_LEVELS;
use crate::sim::algorithm::chunked::{DetailConfig, LoadingConfig};
use crate::sim::algorithm::{
    AlgorithmConfig, BlockGoal, ChunkedConfig, GeomipmapConfig, LevelDifference, Projection,
    SkirtDepth,
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
    /// Default false: every patch drawn.
    #[serde(default)]
    box_culling: bool,
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
    max_queued_chunks: u32,
    /// §3.4.4's velocity-based limit; absent: off.
    #[serde(default)]
    max_speed_per_spacing: Option<f64>,
    /// The old name of a different limit, refused with a pointer to the new one.
    #[serde(default)]
    max_created_per_frame: Option<u32>,
    cache_chunks: u32,
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
            box_culling: p.box_culling,
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
    if let Some(old) = entry.max_created_per_frame {
        add(
            "max_created_per_frame",
            format!(
                "{old}: no longer a key; the creation limit is `max_queued_chunks`, the chunks \
                 requested and not yet finished (Lauritsen–Nielsen §3.4.4: 4–8), not chunks made \
                 per frame"
            ),
        );
    }
    if let Some(k) = entry.max_speed_per_spacing
        && !(k > 0.0 && k.is_finite())
    {
        add(
            "max_speed_per_spacing",
            format!("{k}: expected a finite number of sample spacings per frame above 0"),
        );
    }
    for (field, value) in [
        ("max_queued_chunks", entry.max_queued_chunks),
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
        max_queued_chunks: entry.max_queued_chunks,
        max_speed_per_spacing: entry.max_speed_per_spacing,
        cache_chunks: entry.cache_chunks,
    }
}

/// `parameters` (at `origin`) as `T`, or serde's problem at its field path.
pub(super) fn decode<T: serde::de::DeserializeOwned>(
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
pub(super) fn level_in_range(
    origin: &str,
    name: &str,
    level: u32,
    problems: &mut Vec<FieldProblem>,
) {
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
                box_culling: false,
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
}
