//! `summary.json`: per algorithm, mean/p50/p95/max of every numeric column and its own
//! preprocessing, plus the run's metadata. Format version 1 is documented in
//! `docs/output-formats.md`, "summary.json". It lays out the document and writes no file; the
//! summaries are `sim::stats`'s, the goal's verdict `goal_check.rs`'s, the warm-up `warm_up.rs`'s.

use super::columns::{RunColumns, numeric_columns, value};
use super::goal_check::check_goal;
use super::tuning::TuningRecord;
use super::warm_up::{SETTLED_WITHIN, settling, summarised_runs};
use crate::edge::experiment::{BoundOrigin, Experiment};
use crate::sim::algorithm::columns::wu::BASE_B;
use crate::sim::flight::BrokenBounds;
use crate::sim::stats::summarise;
use serde_json::{Map, Value, json};

/// The column every time figure of the outputs is read from (report.md's table and Pareto
/// front, the plots, the terminal summary): the time from the new camera to drawable buffers.
pub const TIME_AXIS: &str = "frame_ns";

/// The summary of Wu's b in metres (b × the horizontal speed bound), beside `base_b`.
pub const BASE_B_METRES: &str = "base_b_m";

/// The format version of `summary.json`.
pub const SUMMARY_FORMAT_VERSION: u32 = 1;

/// Most speed violations listed one by one (the count is always exact).
pub const MAX_LISTED_VIOLATIONS: usize = 10_000;

/// Facts measured while preparing the run: the shared terrain's preprocessing, or one
/// algorithm entry's (building its own tables and trees before the first frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Preprocessing {
    pub seconds: f64,
    pub bytes_per_sample: f64,
}

/// How the run was made: what `summary.json` records of the command, not of the experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct RunRecord {
    /// The worker threads running entries side by side.
    pub threads: usize,
    /// Whether every mesh was validated after every frame (`--check`). A run whose check fails
    /// writes nothing, so a written `true` means every mesh passed.
    pub check_meshes: bool,
    /// The command line as given (`roamsim run …`), when the run came from one.
    pub command_line: Option<Vec<String>>,
}

impl RunRecord {
    /// The `run` object of `summary.json`; `meshes` is the number of (entry, frame) meshes made.
    pub fn to_json(&self, meshes: u64) -> Value {
        json!({
            "threads": self.threads,
            "check_meshes": self.check_meshes,
            "meshes_checked": if self.check_meshes { meshes } else { 0 },
            "command_line": self.command_line,
            "peak_resident_bytes": peak_resident_bytes(),
        })
    }
}

/// The process's peak resident set so far, bytes (`VmHWM` of `/proc/self/status`); `None`
/// where the system does not say (not Linux). Measured when the summary is written, so it
/// covers every point run before it.
pub fn peak_resident_bytes() -> Option<u64> {
    proc_status_bytes("VmHWM:")
}

/// The process's resident set now, bytes (`VmRSS` of `/proc/self/status`); `None` where the
/// system does not say (not Linux).
pub fn resident_bytes() -> Option<u64> {
    proc_status_bytes("VmRSS:")
}

/// A `kB` figure of `/proc/self/status`, in bytes.
fn proc_status_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|line| line.starts_with(key))?;
    let kib: u64 = line
        .trim_start_matches(key)
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

/// The whole document.
#[allow(clippy::too_many_arguments)]
pub fn summary_json(
    record: &RunRecord,
    experiment: &Experiment,
    preprocessing: &Preprocessing,
    runs: &[RunColumns],
    parameters: &[Value],
    names: &[&str],
    facts: &[Vec<(&str, f64)>],
    entry_preprocessing: &[Preprocessing],
    tunings: &[Option<&TuningRecord>],
    frames_resident: Option<u64>,
) -> Value {
    let audited = experiment.effects.audit.is_some();
    let columns = numeric_columns(runs, audited);
    // Column summaries leave out the warm-up frames; `frames` still counts them all.
    let summarised = summarised_runs(runs, experiment.warm_up_frames);
    let algorithms: Vec<Value> = runs
        .iter()
        .zip(&summarised)
        .zip(parameters)
        .zip(names)
        .zip(facts)
        .zip(entry_preprocessing)
        .zip(&experiment.algorithms)
        .enumerate()
        .map(|(index, ((((((run, summarised), parameters), name), facts), preprocessing), spec))| {
            let goal = spec.config.count_goal().and_then(|goal| {
                let check = check_goal(summarised, goal)?;
                Some(json!({
                    "column": goal.column,
                    "target": goal.target,
                    "mean": check.mean,
                    "mean_deviation": check.mean_deviation,
                    "approach_frames": check.approach_frames,
                    "frames_straying": check.frames_straying,
                    "longest_stretch": check.longest_stretch,
                    "longest_stretch_start": check.longest_stretch_start,
                    "held": check.flag.is_none(),
                    "flag": check.flag,
                }))
            });
            let mut summaries = Map::new();
            for column in &columns {
                let values: Vec<f64> = summarised
                    .frames
                    .iter()
                    .filter_map(|f| value(summarised, f, column))
                    .collect();
                if let Some(s) = summarise(&values) {
                    summaries.insert(
                        column.to_string(),
                        json!({"mean": s.mean, "p50": s.p50, "p95": s.p95, "max": s.max}),
                    );
                }
            }
            // Wu's b is in frames of travel at the horizontal speed bound; beside it in metres.
            if let Some(b) = summaries.get(BASE_B).cloned() {
                let metres = |stat: &str| b[stat].as_f64().map(|v| v * experiment.speed.horizontal);
                summaries.insert(
                    BASE_B_METRES.to_string(),
                    json!({"mean": metres("mean"), "p50": metres("p50"), "p95": metres("p95"), "max": metres("max")}),
                );
            }
            let mut entry = json!({
                "label": run.label,
                "name": name,
                "parameters": parameters,
                "facts": facts.iter().map(|(k, v)| (k.to_string(), json!(v))).collect::<Map<String, Value>>(),
                "preprocessing": {
                    "seconds": preprocessing.seconds,
                    "bytes_per_sample": preprocessing.bytes_per_sample,
                },
                "frames": run.frames.len(),
                "frames_summarised": summarised.frames.len(),
                "settling": settling(spec.config.count_goal(), run).map(|s| json!({
                    "target": s.target,
                    "column": s.column,
                    "within": SETTLED_WITHIN,
                    "first_frame": s.first_frame,
                })),
                "goal": goal,
                "columns": summaries,
            });
            if let Some(Some(record)) = tunings.get(index) {
                entry["tuning"] = record.to_json();
            }
            entry
        })
        .collect();
    let terrain = &experiment.terrain;
    let violations: Vec<Value> = experiment
        .violations
        .iter()
        .take(MAX_LISTED_VIOLATIONS)
        .map(|v| {
            json!({
                "frame": v.frame,
                "horizontal_m": v.horizontal,
                "vertical_m": v.vertical,
                "rotation_rad": v.rotation,
                "broken": broken_bound_names(v.broken),
            })
        })
        .collect();
    let count_broken = |broke: fn(&BrokenBounds) -> bool| {
        experiment
            .violations
            .iter()
            .filter(|v| broke(&v.broken))
            .count()
    };
    let meshes: u64 = runs.iter().map(|r| r.frames.len() as u64).sum();
    // A point's own measure of what its frames held, beside the process's peak.
    let mut run = record.to_json(meshes);
    run["frames_resident_bytes"] = json!(frames_resident);
    run["frames_resident_bytes_per_sample"] =
        json!(frames_resident.map(|bytes| bytes as f64 / experiment.field.n_samples() as f64));
    json!({
        "format_version": SUMMARY_FORMAT_VERSION,
        "roamsim_version": env!("CARGO_PKG_VERSION"),
        "time_axis": TIME_AXIS,
        "run": run,
        "experiment": {
            "name": experiment.name,
            "description": experiment.description,
            "file": experiment.file.display().to_string(),
            "content_sha256": experiment.content_sha256,
            "sweep_point": experiment.sweep_point.as_ref().map(|choice| {
                choice.iter().cloned().collect::<Map<String, Value>>()
            }),
        },
        "terrain": {
            "source": terrain.source,
            "format": terrain.format,
            "source_columns": terrain.source_columns,
            "source_rows": terrain.source_rows,
            "side": terrain.side,
            "padded_columns": terrain.padded_columns,
            "padded_rows": terrain.padded_rows,
            "crop_origin": terrain.crop_origin.map(|(i, j)| [i, j]),
            "voids_filled": terrain.voids_filled,
            "spacing_m": {"dx": terrain.spacing.dx, "dy": terrain.spacing.dy},
            "spacing_from": terrain.spacing_from,
            "origin_m": experiment.field.origin().to_array(),
            "height_range_m": [terrain.height_min_m, terrain.height_max_m],
            "preprocessing_seconds": preprocessing.seconds,
            "bytes_per_sample": preprocessing.bytes_per_sample,
            "read_on_demand_bytes": experiment
                .field
                .paged_samples()
                .map(|paged| paged.memory_bytes()),
        },
        "view": {
            "width_px": experiment.view.width_px,
            "height_px": experiment.view.height_px,
            "fovy_deg": experiment.fovy_deg,
            "near_m": experiment.view.near,
            "far_m": experiment.view.far,
        },
        "flight": {
            "kind": experiment.flight_kind,
            "frames": experiment.flight.n_frames(),
            "frames_in_file": experiment.frames_in_file,
            "warm_up_frames": experiment.warm_up_frames,
            "eye_below_ground_count": experiment.below_ground_frames.len(),
            "eye_below_ground_frames": experiment
                .below_ground_frames
                .iter()
                .take(MAX_LISTED_VIOLATIONS)
                .collect::<Vec<_>>(),
            "speed_bounds": {
                "horizontal_m_per_frame": experiment.speed.horizontal,
                "vertical_m_per_frame": experiment.speed.vertical,
                "rotation_rad_per_frame": experiment.speed.rotation,
                "rotation_rad_per_frame_derived":
                    experiment.rotation_bound == BoundOrigin::Derived,
            },
            "speed_violation_count": experiment.violations.len(),
            "speed_violation_count_by_bound": {
                "horizontal": count_broken(|b| b.horizontal),
                "vertical": count_broken(|b| b.vertical),
                "rotation": count_broken(|b| b.rotation),
            },
            "speed_violations": violations,
        },
        "effects": {
            "audit": experiment
                .effects
                .audit
                .map(|a| json!({"stride": a.stride, "popping": a.popping, "detail_stride": a.detail_stride})),
            "culling": experiment.effects.culling,
        },
        "algorithms": algorithms,
    })
}

/// The names of the bounds a frame broke, as `summary.json` lists them.
fn broken_bound_names(broken: BrokenBounds) -> Vec<&'static str> {
    [
        ("horizontal", broken.horizontal),
        ("vertical", broken.vertical),
        ("rotation", broken.rotation),
    ]
    .into_iter()
    .filter_map(|(name, broke)| broke.then_some(name))
    .collect()
}
