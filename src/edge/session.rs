//! One `roamsim run`: load the experiment, preprocess, run every algorithm over the flight,
//! write the outputs all-or-nothing.
//!
//! Every algorithm entry (sweep points included) runs from its own fresh state on the shared
//! preprocessed terrain, in parallel on a rayon pool of `threads` threads; results are collected
//! in the experiment's order, so the outputs do not depend on the thread count (timings do:
//! entries running side by side share the cores; use one thread for timing comparisons).
//! Progress goes to a [`ProgressSink`] (the CLI's progress bar, or nothing). A tuned entry
//! (`"tune"`) first runs its search over short probe runs (`tune_entry`, one progress line per
//! probe), then its run with the value found.
//!
//! An experiment with a top-level sweep runs its points one after another, each into its own
//! sub-folder, then writes the sweep's own `summary.json`, `report.md` and plots at the top; the
//! whole folder is staged and moved into place only when every point has succeeded.

use crate::edge::experiment::{
    self, AlgorithmSpec, Experiment, ExperimentError, Plan, SweepChoice,
};
use crate::edge::experiment::{Tune, TuneTarget, tuned_spec};
use crate::edge::output::atomic_dir::{CommitError, OutputLocationError, StagedDir};
use crate::edge::output::columns::{RunColumns, TIMING_COLUMNS};
use crate::edge::output::end_of_run::PointFigures;
use crate::edge::output::frames_csv::frames_csv;
use crate::edge::output::goal_check::{GoalCheck, check_goal};
use crate::edge::output::mesh_ply::{PlyHeader, mesh_ply};
use crate::edge::output::plots::PlotError;
use crate::edge::output::report_md::{ReportInputs, report_markdown, row};
use crate::edge::output::run_plots::{RunPlotInputs, write_run_plots};
use crate::edge::output::summary_json::{Preprocessing, RunRecord, summary_json};
use crate::edge::output::sweep_outputs::{
    EntryFigures, SweepPoint, SweepRun, sweep_report_markdown, sweep_summary_json,
    write_sweep_plots,
};
use crate::edge::output::tuning::{TuningRecord, mean_of_target, probe_line};
use crate::edge::output::warm_up::summarised_runs;
use crate::edge::shard::frame_codec::encode_frame;
use crate::edge::shard::{
    MergeError, SHARD_FILE, ShardEntry, ShardExperiment, ShardFile, ShardPoint, ShardSpec,
    ShardTuning, read_complete_set,
};
use crate::sim::audit::AuditSettings;
use crate::sim::flight::{Flight, speed_violations};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::run::{
    CheckError, Effects, RunError, RunInputs, run_algorithm, run_algorithm_with,
};
use crate::sim::stats::{FrameStats, nearest_rank, summarise};
use crate::sim::tuning::{Probe, probe_speed, probe_stride, search};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Receives progress from every running algorithm at once (so it must be `Sync`).
pub trait ProgressSink: Sync {
    /// The total number of frames all entries will run.
    fn start(&self, total_frames: u64);
    /// `frames` more frames are done.
    fn advance(&self, frames: u64);
    fn finish(&self);
    /// The number of algorithm entries about to run (before `start`).
    fn entries(&self, count: usize) {
        let _ = count;
    }
    /// One more entry has run all its frames.
    fn entry_finished(&self) {}
    /// Point `index` of `count` of the experiment's top-level sweep is about to load and run.
    fn point(&self, index: usize, count: usize, choice: &str) {
        let _ = (index, count, choice);
    }
    /// A tuned entry's probe is done: one line (see `edge::output::tuning::probe_line`).
    fn tuning(&self, line: &str) {
        eprintln!("{line}");
    }
    /// Something the user should know while the run goes on (see [`large_work_notice`]).
    fn notice(&self, message: &str) {
        eprintln!("note: {message}");
    }
}

/// A first frame with this many triangles is worth a word before the rest of the run.
pub const LARGE_MESH_TRIANGLES: u64 = 1_000_000;
/// A flight projected to take this long (seconds, from its first frame) is worth a word.
pub const LONG_RUN_SECONDS: f64 = 300.0;

/// What to tell the user after an entry's first frame when its work looks large: a mesh of
/// [`LARGE_MESH_TRIANGLES`] or more, or a flight projected at the first frame's pace to take
/// [`LONG_RUN_SECONDS`] or more. `None` when neither.
pub fn large_work_notice(
    label: &str,
    triangles: u64,
    first_frame_seconds: f64,
    n_frames: u64,
    max_triangles: u64,
) -> Option<String> {
    let projected = first_frame_seconds * n_frames as f64;
    if triangles < LARGE_MESH_TRIANGLES && projected < LONG_RUN_SECONDS {
        return None;
    }
    let duration = if projected >= 3600.0 {
        format!("{:.1} h", projected / 3600.0)
    } else if projected >= 60.0 {
        format!("{:.0} min", projected / 60.0)
    } else {
        format!("{projected:.0} s")
    };
    Some(format!(
        "entry '{label}': frame 0 has {triangles} triangles and took {first_frame_seconds:.2} s; \
         at that pace its {n_frames} frames take about {duration} (incremental algorithms are \
         usually faster after their first frame). A frame over {max_triangles} triangles stops \
         the run (limits.max_triangles); --frames N makes a shorter probe"
    ))
}

/// Progress that goes nowhere.
pub struct NoProgress;

impl ProgressSink for NoProgress {
    fn start(&self, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
    fn notice(&self, _: &str) {}
    fn tuning(&self, _: &str) {}
}

/// How to run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder; by default `out/<experiment name>` under the working directory.
    pub out_dir: Option<PathBuf>,
    /// Validate every mesh every frame.
    pub check_meshes: bool,
    /// Threads running algorithm entries side by side; `None`: one per core.
    pub threads: Option<usize>,
    /// The command line that asked for the run, recorded in `summary.json`.
    pub command_line: Option<Vec<String>>,
    /// Run only the first this many frames of every flight (`--frames N`); `None`: all.
    pub max_frames: Option<u64>,
    /// Run only this part of the experiment and write its raw results (`--shard K/N`); see
    /// [`crate::edge::shard`].
    pub shard: Option<ShardSpec>,
    /// How update times are measured.
    pub timing: Timing,
}

/// How update times are measured (`--repeat N`, `--time-with-effects`).
///
/// The effects between two updates (the audit above all, also culling, mesh checks and
/// exports) evict the algorithm's data from the caches and inflate its next update by up to
/// 1.5–2×. So by default, when any effect is on, each entry's flight is flown again from a
/// fresh algorithm with every effect off — a **timing pass** — and its update times replace
/// the measured pass's (the counts and meshes come from the measured pass; the timing pass
/// must draw the same triangle counts, else the run stops). `repeat` = N runs N timing
/// passes (even with no effect on): frames.csv's `update_ns` is each frame's median over the
/// passes, and summary.json's facts give the passes' medians (their median, least and
/// greatest): the spread of the figure a paper would quote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timing {
    /// Timing passes (at least 1).
    pub repeat: u32,
    /// Keep the measured pass's times (no timing pass; `repeat` must be 1).
    pub with_effects: bool,
}

impl Default for Timing {
    fn default() -> Timing {
        Timing {
            repeat: 1,
            with_effects: false,
        }
    }
}

impl Timing {
    /// The timing passes an entry needs: none when its measured pass is already clean (no
    /// effect on) and one pass is asked for, or when the effects' times are kept.
    fn passes(&self, effects_on: bool) -> u32 {
        if self.with_effects || (!effects_on && self.repeat == 1) {
            0
        } else {
            self.repeat
        }
    }
}

/// What a finished run produced.
pub struct RunOutcome {
    pub out_dir: PathBuf,
    pub experiment_name: String,
    pub frames: u64,
    /// (entry, frame) meshes made, over every point.
    pub meshes: u64,
    /// Entries that did not hold their budget or target, as `label: why` (a sweep point's
    /// entries prefixed with the point).
    pub goal_flags: Vec<String>,
    pub speed_violation_frames: Vec<u64>,
    pub preprocessing_seconds: f64,
    pub threads: usize,
    /// Whether every mesh was validated (`--check`, or shards run with it).
    pub check_meshes: bool,
    /// Every point's entries and their report figures, in order (one point without a sweep).
    pub points: Vec<PointFigures>,
}

impl RunOutcome {
    /// The outcome of a run of `plan` before any point has run.
    fn nothing_yet(plan: &Plan, out_dir: PathBuf, threads: usize, check_meshes: bool) -> Self {
        RunOutcome {
            out_dir,
            experiment_name: plan.name().to_string(),
            frames: 0,
            meshes: 0,
            goal_flags: Vec::new(),
            speed_violation_frames: Vec::new(),
            preprocessing_seconds: 0.0,
            threads,
            check_meshes,
            points: Vec::new(),
        }
    }
}

/// Why a run produced nothing.
#[derive(Debug, thiserror::Error)]
pub enum RunFailure {
    #[error("{0}")]
    Experiment(#[from] ExperimentError),
    #[error("{0}")]
    Mesh(#[from] RunError),
    #[error("{path}: cannot write the output: {source}")]
    Output {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{0}")]
    OutputLocation(#[from] OutputLocationError),
    #[error("{0}")]
    Commit(#[from] CommitError),
    #[error("{0}")]
    Plot(#[from] PlotError),
    #[error("--threads must be at least 1 (leave it out for one thread per core)")]
    ZeroThreads,
    #[error("--repeat must be at least 1")]
    ZeroRepeat,
    #[error("--repeat {0} asks for timing passes, --time-with-effects for none: give one of them")]
    RepeatWithEffects(u32),
    #[error("cannot start {threads} worker threads: {message}")]
    Threads { threads: usize, message: String },
    #[error("{0}")]
    Merge(Box<MergeError>),
}

impl From<MergeError> for RunFailure {
    fn from(error: MergeError) -> RunFailure {
        RunFailure::Merge(Box::new(error))
    }
}

/// Runs an experiment file: every point of its top-level sweep one after another (each with its
/// own terrain, so only one is in memory at a time), every algorithm entry of a point in
/// parallel. Nothing is written unless every point succeeds. With a shard
/// ([`RunOptions::shard`]), only that part of the points' entries runs, and the output folder
/// holds its raw results (`shard.json`) for `roamsim merge`.
pub fn run_experiment(
    path: &Path,
    options: &RunOptions,
    progress: &dyn ProgressSink,
) -> Result<RunOutcome, RunFailure> {
    let plan = experiment::plan(path)?;
    let default_folder = match options.shard {
        Some(shard) => format!("{}-shard-{}-of-{}", plan.name(), shard.index, shard.count),
        None => plan.name().to_string(),
    };
    let out_dir = normalised_out_dir(options.out_dir.as_deref(), &default_folder);
    if options.threads == Some(0) {
        return Err(RunFailure::ZeroThreads);
    }
    match options.timing {
        Timing { repeat: 0, .. } => return Err(RunFailure::ZeroRepeat),
        Timing {
            repeat,
            with_effects: true,
        } if repeat > 1 => return Err(RunFailure::RepeatWithEffects(repeat)),
        _ => {}
    }
    let threads = options
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| RunFailure::Threads {
            threads,
            message: e.to_string(),
        })?;
    // Before simulating: a run must not find out at the end that it cannot write, nor replace a
    // folder it did not write. The staging folder is made now and filled as points finish.
    let staging = StagedDir::new(&out_dir)?;
    let settings = PointSettings {
        check_meshes: options.check_meshes,
        max_frames: options.max_frames,
        timing: options.timing,
    };
    if let Some(shard) = options.shard {
        let run = ShardRun {
            shard,
            settings,
            options,
            pool: &pool,
            threads,
        };
        return run_shard(path, &plan, &run, progress, (out_dir, staging));
    }
    let record = RunRecord {
        threads,
        check_meshes: options.check_meshes,
        command_line: options.command_line.clone(),
    };
    let mut assembly = RunAssembly::new(&plan, out_dir, threads, record);
    for k in 0..plan.n_points() {
        let experiment = settings.load_point(&plan, k)?;
        if let Some(choice) = plan.choice(k) {
            progress.point(k, plan.n_points(), &experiment::choice_label(choice));
        }
        let entries: Vec<usize> = (0..experiment.algorithms.len()).collect();
        let point = run_point(&experiment, &entries, settings.timing, &pool, progress)?;
        assembly.add_point((k, plan.choice(k)), &experiment, point, staging.path())?;
    }
    assembly.finish(&plan, path, staging)
}

/// What every point is loaded with: `--check` and `--frames`.
#[derive(Clone, Copy)]
struct PointSettings {
    check_meshes: bool,
    max_frames: Option<u64>,
    timing: Timing,
}

impl PointSettings {
    /// Loads point `k` (its terrain and flight) as the run sees it.
    fn load_point(&self, plan: &Plan, k: usize) -> Result<Experiment, RunFailure> {
        let mut experiment = plan.load_point(k)?;
        experiment.effects.check_meshes = self.check_meshes;
        if let Some(n_frames) = self.max_frames {
            experiment.keep_first_frames(n_frames);
            experiment.check_warm_up()?;
        }
        Ok(experiment)
    }
}

/// The output folder: the one given, or `out/<default_folder>`; normalised, so that `out/.`
/// names `out`, whose rename is what commits the run.
fn normalised_out_dir(given: Option<&Path>, default_folder: &str) -> PathBuf {
    given
        .map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("out").join(default_folder))
        .components()
        .collect()
}

/// The outputs of a run (or of merged shards) being assembled point by point: each point's
/// files are written as it is added, the sweep's own files and the commit at the end.
struct RunAssembly {
    outcome: RunOutcome,
    sweep_points: Vec<SweepPoint>,
    record: RunRecord,
}

impl RunAssembly {
    fn new(plan: &Plan, out_dir: PathBuf, threads: usize, record: RunRecord) -> RunAssembly {
        RunAssembly {
            outcome: RunOutcome::nothing_yet(plan, out_dir, threads, record.check_meshes),
            sweep_points: Vec::new(),
            record,
        }
    }

    /// Writes point `k`'s outputs into its folder under `top` and keeps its figures.
    fn add_point(
        &mut self,
        (k, plan_choice): (usize, Option<&SweepChoice>),
        experiment: &Experiment,
        point: PointRun,
        top: &Path,
    ) -> Result<(), RunFailure> {
        let choice_label = plan_choice.map(|c| experiment::choice_label(c));
        let context = OutputContext {
            experiment,
            preprocessing: &point.preprocessing,
            hierarchy_bytes: point.hierarchy_bytes,
            record: &self.record,
        };
        let folder = plan_choice.map(|c| point_folder(c)).unwrap_or_default();
        let point_dir = top.join(&folder);
        let figures = write_outputs(&context, &point.results, &point_dir)?;
        let outcome = &mut self.outcome;
        outcome.frames += experiment.flight.n_frames();
        outcome.meshes += experiment.flight.n_frames() * experiment.algorithms.len() as u64;
        for (spec, result) in experiment.algorithms.iter().zip(&point.results) {
            // Over the summarised frames, as report.md and summary.json judge it.
            let all = RunColumns {
                label: &spec.label,
                extra_columns: &result.extra_columns,
                frames: &result.frames,
            };
            let run = summarised_runs(&[all], experiment.warm_up_frames).remove(0);
            if let Some(goal) = spec.config.count_goal()
                && let Some(GoalCheck {
                    flag: Some(reason), ..
                }) = check_goal(&run, goal)
            {
                let point = choice_label
                    .as_deref()
                    .map_or(String::new(), |c| format!("({c}) "));
                outcome
                    .goal_flags
                    .push(format!("{point}{}: {reason}", spec.label));
            }
            if let Some(tuning) = &result.tuning
                && !tuning.reached
            {
                let point = choice_label
                    .as_deref()
                    .map_or(String::new(), |c| format!("({c}) "));
                outcome.goal_flags.push(format!(
                    "{point}{}: tune did not reach {} {} within {}: the closest probe gave {} at {} = {}",
                    spec.label,
                    tuning.target.value(),
                    tuning.target.unit(),
                    tuning.tolerance,
                    tuning.probe_mean,
                    tuning.parameter,
                    tuning.value,
                ));
            }
        }
        outcome.preprocessing_seconds += point.preprocessing.seconds;
        if k == 0 {
            outcome.speed_violation_frames = point.violation_frames;
        }
        outcome.points.push(PointFigures {
            choice: choice_label.clone(),
            folder: folder.clone(),
            entries: figures.clone(),
            below_ground_frames: experiment.below_ground_frames.clone(),
        });
        if let Some(choice) = plan_choice {
            self.sweep_points.push(SweepPoint {
                choice: choice.clone(),
                folder,
                side: experiment.field.side(),
                n_samples: experiment.field.n_samples(),
                frames: experiment.flight.n_frames(),
                preprocessing_seconds: point.preprocessing.seconds,
                hierarchy_bytes_per_sample: point.preprocessing.bytes_per_sample,
                entries: figures,
            });
        }
        Ok(())
    }

    /// Writes the sweep's own files (for a sweep) and moves the folder into place.
    fn finish(
        self,
        plan: &Plan,
        path: &Path,
        staging: StagedDir,
    ) -> Result<RunOutcome, RunFailure> {
        if plan.is_sweep() {
            let top = staging.path();
            let sweep = SweepRun {
                name: plan.name(),
                description: plan.description(),
                file: path,
                content_sha256: plan.content_sha256(),
                record: &self.record,
                points: &self.sweep_points,
            };
            let summary_path = top.join("summary.json");
            let text =
                serde_json::to_string_pretty(&sweep_summary_json(&sweep)).unwrap_or_default();
            std::fs::write(&summary_path, text + "\n").map_err(io_error(&summary_path))?;
            let report_path = top.join("report.md");
            std::fs::write(&report_path, sweep_report_markdown(&sweep))
                .map_err(io_error(&report_path))?;
            let plots = top.join("plots");
            std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
            write_sweep_plots(&plots, &sweep)?;
        }
        staging.commit()?;
        Ok(self.outcome)
    }
}

/// What a shard runs with.
struct ShardRun<'a> {
    shard: ShardSpec,
    settings: PointSettings,
    options: &'a RunOptions,
    pool: &'a rayon::ThreadPool,
    threads: usize,
}

/// Runs shard `shard` of the plan: the entries of its units, point by point, and writes their
/// raw results to `shard.json` in the staged folder.
fn run_shard(
    path: &Path,
    plan: &Plan,
    run: &ShardRun,
    progress: &dyn ProgressSink,
    (out_dir, staging): (PathBuf, StagedDir),
) -> Result<RunOutcome, RunFailure> {
    let ShardRun {
        shard,
        settings,
        options,
        pool,
        threads,
    } = *run;
    let file = std::fs::canonicalize(path).map_err(|source| RunFailure::Output {
        path: path.to_path_buf(),
        source,
    })?;
    // Units in order: (point, entry). Counting entries needs only the checked plan.
    let mut units = Vec::new();
    for k in 0..plan.n_points() {
        units.extend((0..plan.n_entries(k)).map(|e| (k, e)));
    }
    let mine = &units[shard.units(units.len())];
    let mut file_out = ShardFile::new(
        ShardExperiment {
            name: plan.name().to_string(),
            file,
            file_as_given: path.to_path_buf(),
            content_sha256: plan.content_sha256().to_string(),
        },
        shard,
        (options.max_frames, options.check_meshes),
        (options.timing.repeat, options.timing.with_effects),
        threads,
        options.command_line.clone(),
    );
    let mut outcome = RunOutcome::nothing_yet(plan, out_dir, threads, options.check_meshes);
    for k in 0..plan.n_points() {
        let entries: Vec<usize> = mine
            .iter()
            .filter(|(point, _)| *point == k)
            .map(|(_, entry)| *entry)
            .collect();
        if entries.is_empty() {
            continue;
        }
        let experiment = settings.load_point(plan, k)?;
        if let Some(choice) = plan.choice(k) {
            progress.point(k, plan.n_points(), &experiment::choice_label(choice));
        }
        let point = run_point(&experiment, &entries, settings.timing, pool, progress)?;
        outcome.frames += experiment.flight.n_frames();
        outcome.meshes += experiment.flight.n_frames() * entries.len() as u64;
        outcome.preprocessing_seconds += point.preprocessing.seconds;
        file_out.points.push(ShardPoint {
            point: k,
            preprocessing_seconds_bits: point.preprocessing.seconds.to_bits(),
            bytes_per_sample_bits: point.preprocessing.bytes_per_sample.to_bits(),
            hierarchy_bytes_bits: point.hierarchy_bytes.to_bits(),
            violation_frames: point.violation_frames,
            entries: entries
                .iter()
                .zip(point.results)
                .map(|(&entry, result)| ShardEntry {
                    entry,
                    label: experiment.algorithms[entry].label.clone(),
                    memory_bytes: result.memory_bytes,
                    preprocessing_seconds_bits: result.preprocessing.seconds.to_bits(),
                    bytes_per_sample_bits: result.preprocessing.bytes_per_sample.to_bits(),
                    extra_columns: result.extra_columns.iter().map(|c| c.to_string()).collect(),
                    facts: result
                        .facts
                        .iter()
                        .map(|(name, value)| (name.to_string(), value.to_bits()))
                        .collect(),
                    meshes: result.meshes,
                    frames: result.frames.iter().map(encode_frame).collect(),
                    tuning: result.tuning.map(|t| ShardTuning {
                        value_bits: t.value.to_bits(),
                        probe_mean_bits: t.probe_mean.to_bits(),
                        reached: t.reached,
                        probe_frames: t.probe_frames,
                        probe_stride: t.probe_stride,
                        probes: t
                            .probes
                            .iter()
                            .map(|p| (p.value.to_bits(), p.mean.to_bits()))
                            .collect(),
                        full_run_mean_bits: t.full_run_mean.to_bits(),
                    }),
                })
                .collect(),
        });
    }
    let shard_path = staging.path().join(SHARD_FILE);
    let text = serde_json::to_string(&file_out).unwrap_or_default() + "\n";
    std::fs::write(&shard_path, text).map_err(io_error(&shard_path))?;
    staging.commit()?;
    Ok(outcome)
}

/// How to merge.
#[derive(Clone, Debug, Default)]
pub struct MergeOptions {
    /// Output folder; by default `out/<experiment name>`.
    pub out_dir: Option<PathBuf>,
    /// The command line that asked for the merge, recorded in `summary.json`.
    pub command_line: Option<Vec<String>>,
}

/// Merges shard folders into the outputs one run of the whole experiment writes (see
/// [`crate::edge::shard`]): every check first, then each point's terrain and flight loaded
/// again for the writers, nothing simulated.
pub fn merge_shards(
    folders: &[PathBuf],
    options: &MergeOptions,
    progress: &dyn ProgressSink,
) -> Result<RunOutcome, RunFailure> {
    let shards = read_complete_set(folders)?;
    let (first_folder, first) = &shards[0];
    let path = first.experiment.file_to_read();
    let plan = experiment::plan(&path)?;
    if plan.content_sha256() != first.experiment.content_sha256 {
        return Err(MergeError::ExperimentChanged {
            path,
            now: plan.content_sha256().to_string(),
            then: first.experiment.content_sha256.clone(),
        }
        .into());
    }
    // Every unit exactly once, before anything is loaded or written.
    let mut units: Vec<Vec<Option<(&ShardPoint, &ShardEntry)>>> = (0..plan.n_points())
        .map(|k| vec![None; plan.n_entries(k)])
        .collect();
    for (folder, shard) in &shards {
        let inconsistent = |problem: String| MergeError::Inconsistent {
            path: folder.join(SHARD_FILE),
            problem,
        };
        for point in &shard.points {
            let slots = units.get_mut(point.point).ok_or_else(|| {
                inconsistent(format!(
                    "point {} is not in the experiment ({} points)",
                    point.point,
                    plan.n_points()
                ))
            })?;
            for entry in &point.entries {
                let n_slots = slots.len();
                let slot = slots.get_mut(entry.entry).ok_or_else(|| {
                    inconsistent(format!(
                        "entry {} of point {} is not in the experiment ({n_slots} entries)",
                        entry.entry, point.point
                    ))
                })?;
                if slot.is_some() {
                    return Err(inconsistent(format!(
                        "entry {} of point {} is in two shards",
                        entry.entry, point.point
                    ))
                    .into());
                }
                *slot = Some((point, entry));
            }
        }
    }
    let out_dir = normalised_out_dir(options.out_dir.as_deref(), plan.name());
    let staging = StagedDir::new(&out_dir)?;
    let settings = PointSettings {
        check_meshes: first.check_meshes,
        max_frames: first.max_frames,
        timing: Timing {
            repeat: first.repeat,
            with_effects: first.time_with_effects,
        },
    };
    let record = RunRecord {
        threads: first.threads,
        check_meshes: first.check_meshes,
        command_line: options.command_line.clone(),
    };
    let mut assembly = RunAssembly::new(&plan, out_dir, first.threads, record);
    for (k, slots) in units.iter().enumerate() {
        let experiment = settings.load_point(&plan, k)?;
        if let Some(choice) = plan.choice(k) {
            progress.point(k, plan.n_points(), &experiment::choice_label(choice));
        }
        let mut results = Vec::new();
        let mut point_facts = None;
        for (e, slot) in slots.iter().enumerate() {
            let Some((point, entry)) = slot else {
                return Err(MergeError::Inconsistent {
                    path: first_folder.join(SHARD_FILE),
                    problem: format!(
                        "no shard ran entry {e} of point {k} ({:?}): were the shards made by \
                         another roamsim?",
                        experiment.algorithms[e].label
                    ),
                }
                .into());
            };
            let label = &experiment.algorithms[e].label;
            if &entry.label != label {
                return Err(MergeError::Inconsistent {
                    path: first_folder.join(SHARD_FILE),
                    problem: format!(
                        "entry {e} of point {k} is {:?} in a shard, {label:?} in the experiment",
                        entry.label
                    ),
                }
                .into());
            }
            point_facts.get_or_insert(*point);
            let frames = entry
                .decode_frames()
                .map_err(|problem| MergeError::Inconsistent {
                    path: first_folder.join(SHARD_FILE),
                    problem,
                })?;
            results.push(AlgorithmResult {
                memory_bytes: entry.memory_bytes,
                preprocessing: Preprocessing {
                    seconds: f64::from_bits(entry.preprocessing_seconds_bits),
                    bytes_per_sample: f64::from_bits(entry.bytes_per_sample_bits),
                },
                frames,
                extra_columns: entry.extra_columns.iter().map(String::as_str).collect(),
                facts: entry
                    .facts
                    .iter()
                    .map(|(name, bits)| (name.as_str(), f64::from_bits(*bits)))
                    .collect(),
                meshes: entry.meshes.clone(),
                tuning: experiment.algorithms[e]
                    .tune
                    .as_ref()
                    .zip(entry.tuning.as_ref())
                    .map(|(tune, t)| TuningRecord {
                        target: tune.target,
                        parameter: tune.parameter,
                        value: f64::from_bits(t.value_bits),
                        probe_mean: f64::from_bits(t.probe_mean_bits),
                        reached: t.reached,
                        tolerance: tune.tolerance,
                        probe_frames: t.probe_frames,
                        probe_stride: t.probe_stride,
                        probes: t
                            .probes
                            .iter()
                            .map(|&(value, mean)| Probe {
                                value: f64::from_bits(value),
                                mean: f64::from_bits(mean),
                            })
                            .collect(),
                        full_run_mean: f64::from_bits(t.full_run_mean_bits),
                    }),
            });
        }
        // The point's own figures from the first shard that ran any of its entries.
        let Some(point) = point_facts else {
            continue;
        };
        let run = PointRun {
            preprocessing: Preprocessing {
                seconds: f64::from_bits(point.preprocessing_seconds_bits),
                bytes_per_sample: f64::from_bits(point.bytes_per_sample_bits),
            },
            hierarchy_bytes: f64::from_bits(point.hierarchy_bytes_bits),
            violation_frames: point.violation_frames.clone(),
            results,
        };
        assembly.add_point((k, plan.choice(k)), &experiment, run, staging.path())?;
    }
    assembly.finish(&plan, &path, staging)
}

/// A folder name for a sweep point: `parameter=value` pairs joined by `_`, anything but letters,
/// digits and `._=-+` replaced by `-` (field names keep their `_`: `view.fovy_deg=60`).
fn point_folder(choice: &[(String, serde_json::Value)]) -> String {
    choice
        .iter()
        .map(|(parameter, value)| {
            let value = match value {
                serde_json::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            file_name_part(&format!("{parameter}={value}"))
        })
        .collect::<Vec<_>>()
        .join("_")
}

/// `text` with anything but ASCII letters, digits and `._=-+` replaced by `-`.
fn file_name_part(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._=-+".contains(c) {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// The folder of entry `k`'s exported meshes, under `meshes/`: its position and its label.
fn mesh_folder(k: usize, label: &str) -> String {
    format!("{k}-{}", file_name_part(label))
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> RunFailure + use<> {
    let path = path.to_path_buf();
    move |source| RunFailure::Output { path, source }
}

/// One point's run: preprocessing and every entry's result.
struct PointRun<'a> {
    preprocessing: Preprocessing,
    hierarchy_bytes: f64,
    violation_frames: Vec<u64>,
    results: Vec<AlgorithmResult<'a>>,
}

/// Runs the entries `entries` (indices into the experiment's algorithms, in order) of one
/// point; their results in the same order.
fn run_point<'a>(
    experiment: &'a Experiment,
    entries: &[usize],
    timing: Timing,
    pool: &rayon::ThreadPool,
    progress: &dyn ProgressSink,
) -> Result<PointRun<'a>, RunFailure> {
    let start = Instant::now();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let preprocessing = Preprocessing {
        seconds: start.elapsed().as_secs_f64(),
        bytes_per_sample: hierarchy.bytes_per_sample(),
    };
    let violation_frames: Vec<u64> = experiment.violations.iter().map(|v| v.frame).collect();
    let inputs = RunInputs {
        hierarchy: &hierarchy,
        view: &experiment.view,
        flight: &experiment.flight,
        violations: &experiment.violations,
        effects: experiment.effects,
        max_triangles: Some(experiment.max_triangles),
        detail_truth: None,
    };
    let n_frames = experiment.flight.n_frames();
    let exported = |k: usize| {
        experiment
            .mesh_exports
            .as_ref()
            .is_some_and(|exports| exports.entries.contains(&k) && !exports.frames.is_empty())
    };
    let effects = experiment.effects;
    let effects_on = |k: usize| {
        effects.audit.is_some() || effects.culling || effects.check_meshes || exported(k)
    };
    let timing_passes = |k: usize| timing.passes(effects_on(k));
    let passes_in_all: u64 = entries.iter().map(|&k| u64::from(timing_passes(k))).sum();
    progress.entries(entries.len());
    progress.start(n_frames * (entries.len() as u64 + passes_in_all));
    let n_samples = experiment.field.n_samples() as f64;
    let run_one = |k: usize| -> Result<AlgorithmResult<'a>, RunError> {
        let written: &AlgorithmSpec = &experiment.algorithms[k];
        // A tuned entry runs with the value its search found (the search's probes first).
        let tuned = match &written.tune {
            Some(tune) => Some(tune_entry(experiment, &hierarchy, written, tune, progress)?),
            None => None,
        };
        let spec: &AlgorithmSpec = tuned.as_ref().map_or(written, |(spec, _)| spec);
        let start = Instant::now();
        let mut algorithm = spec
            .config
            .build(&hierarchy, &experiment.view, experiment.speed);
        let preprocessing = Preprocessing {
            seconds: start.elapsed().as_secs_f64(),
            bytes_per_sample: algorithm.memory_bytes() as f64 / n_samples,
        };
        let export_frames: &[u64] = match &experiment.mesh_exports {
            Some(exports) if exports.entries.contains(&k) => &exports.frames,
            _ => &[],
        };
        let mut meshes = Vec::new();
        let mut reported = 0;
        // An entry that synthesises detail is audited against the detail-extended surface too.
        let detail_truth = experiment
            .effects
            .audit
            .and_then(|_| spec.config.detail_truth(&hierarchy));
        let inputs = RunInputs {
            detail_truth: detail_truth.as_ref(),
            ..inputs
        };
        let frames_started = Instant::now();
        let frames = run_algorithm_with(
            &inputs,
            &spec.label,
            algorithm.as_mut(),
            &mut |outcome, algorithm| {
                let frame = outcome.stats.frame;
                if export_frames.binary_search(&frame).is_ok() {
                    let header = PlyHeader {
                        experiment: &experiment.name,
                        entry: &spec.label,
                        frame,
                    };
                    meshes.push((frame, mesh_ply(&hierarchy, algorithm.mesh(), &header)));
                }
                if frame == 0
                    && let Some(message) = large_work_notice(
                        &spec.label,
                        outcome.stats.triangles,
                        frames_started.elapsed().as_secs_f64(),
                        n_frames,
                        experiment.max_triangles,
                    )
                {
                    progress.notice(&message);
                }
                let done = frame + 1;
                if done.is_multiple_of(16) || done == n_frames {
                    progress.advance(done - reported);
                    reported = done;
                }
            },
        )?;
        let mut frames = frames;
        let mut facts = algorithm.run_facts();
        let memory_bytes = algorithm.memory_bytes();
        let extra_columns = algorithm.extra_columns().to_vec();
        // Gone before a timing pass builds its own, so that the run's peak memory is one
        // algorithm's.
        drop(algorithm);
        let passes = timing_passes(k);
        facts.push(("timing_passes", f64::from(passes)));
        if passes > 0 {
            let clean = RunInputs {
                effects: Effects {
                    audit: None,
                    culling: false,
                    check_meshes: false,
                },
                ..inputs
            };
            let mut pass_times = Vec::new();
            let mut pass_frames = Vec::new();
            for _ in 0..passes {
                let mut fresh = spec
                    .config
                    .build(&hierarchy, &experiment.view, experiment.speed);
                let mut reported = 0;
                let timed =
                    run_algorithm_with(&clean, &spec.label, fresh.as_mut(), &mut |outcome, _| {
                        let done = outcome.stats.frame + 1;
                        if done.is_multiple_of(16) || done == n_frames {
                            progress.advance(done - reported);
                            reported = done;
                        }
                    })?;
                pass_times.push(same_counts_timed(&spec.label, &frames, &timed)?);
                pass_frames.push(timed);
            }
            facts.extend(take_pass_times(
                &mut frames,
                &pass_times,
                experiment.warm_up_frames,
            ));
            take_pass_sub_timings(&mut frames, &pass_frames, &extra_columns);
        }
        progress.entry_finished();
        let tuning = tuned.map(|(_, mut record)| {
            record.full_run_mean = mean_of_target(&frames, record.target);
            record
        });
        Ok(AlgorithmResult {
            memory_bytes,
            preprocessing,
            frames,
            extra_columns,
            facts,
            meshes,
            tuning,
        })
    };
    let results: Vec<Result<AlgorithmResult, RunError>> =
        pool.install(|| entries.par_iter().map(|&k| run_one(k)).collect());
    progress.finish();
    let results = results.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok(PointRun {
        preprocessing,
        hierarchy_bytes: hierarchy.bytes_per_sample() * hierarchy.field().n_samples() as f64,
        violation_frames,
        results,
    })
}

/// A timing pass's update times, when it drew the measured pass's triangle counts frame by
/// frame (else the run stops: an algorithm must decide alike on every pass).
fn same_counts_timed(
    label: &str,
    measured: &[FrameStats],
    timed: &[FrameStats],
) -> Result<Vec<u64>, RunError> {
    for (m, t) in measured.iter().zip(timed) {
        if m.triangles != t.triangles {
            return Err(RunError {
                algorithm: label.to_string(),
                frame: m.frame,
                error: CheckError::TimingPassDiverged {
                    measured: m.triangles,
                    timed: t.triangles,
                },
            });
        }
    }
    Ok(timed.iter().map(|f| f.update_ns).collect())
}

/// Puts each frame's median (nearest rank) over the timing passes into `frames`, and returns
/// the facts of the spread: the median update time of each pass over the summarised frames
/// (after `warm_up_frames`), and those medians' median, least and greatest, in µs.
fn take_pass_times(
    frames: &mut [FrameStats],
    pass_times: &[Vec<u64>],
    warm_up_frames: u64,
) -> Vec<(&'static str, f64)> {
    let mut at_frame = Vec::with_capacity(pass_times.len());
    for (k, frame) in frames.iter_mut().enumerate() {
        at_frame.clear();
        at_frame.extend(pass_times.iter().map(|pass| pass[k]));
        at_frame.sort_unstable();
        frame.update_ns = at_frame[at_frame.len().div_ceil(2) - 1];
    }
    let skip = usize::try_from(warm_up_frames).unwrap_or(usize::MAX);
    let medians: Vec<f64> = pass_times
        .iter()
        .filter_map(|pass| {
            let summarised: Vec<f64> = pass.iter().skip(skip).map(|&ns| ns as f64).collect();
            summarise(&summarised).map(|s| s.p50 / 1e3)
        })
        .collect();
    match summarise(&medians) {
        Some(spread) => vec![
            ("update_p50_us_median_of_passes", spread.p50),
            ("update_p50_us_least_of_passes", least(&medians)),
            ("update_p50_us_greatest_of_passes", spread.max),
        ],
        None => Vec::new(),
    }
}

/// The algorithm's own timing columns (parts of its update, such as the stitching strips'
/// construction or chunked's synthesis: [`TIMING_COLUMNS`]) taken from the timing passes too,
/// each frame's median over them, so that a part is never measured with the effects on while
/// the whole is measured without.
fn take_pass_sub_timings(
    frames: &mut [FrameStats],
    pass_frames: &[Vec<FrameStats>],
    extra_columns: &[&str],
) {
    let timing: Vec<usize> = extra_columns
        .iter()
        .enumerate()
        .filter(|(_, name)| TIMING_COLUMNS.contains(name))
        .map(|(k, _)| k)
        .collect();
    let mut at_frame: Vec<f64> = Vec::with_capacity(pass_frames.len());
    for column in timing {
        for (k, frame) in frames.iter_mut().enumerate() {
            at_frame.clear();
            at_frame.extend(
                pass_frames
                    .iter()
                    .filter_map(|pass| pass[k].extra.get(column)),
            );
            at_frame.sort_unstable_by(|a, b| a.total_cmp(b));
            if let Some(slot) = frame.extra.get_mut(column)
                && !at_frame.is_empty()
            {
                *slot = nearest_rank(&at_frame, 0.5);
            }
        }
    }
}

/// The least value of a non-empty slice.
fn least(values: &[f64]) -> f64 {
    values.iter().copied().fold(f64::INFINITY, f64::min)
}

/// One algorithm's run (names borrowed from the algorithm, or from a shard file when merging).
struct AlgorithmResult<'a> {
    memory_bytes: usize,
    /// Building the algorithm (its own tables and trees) before the first frame.
    preprocessing: Preprocessing,
    frames: Vec<FrameStats>,
    extra_columns: Vec<&'a str>,
    facts: Vec<(&'a str, f64)>,
    /// Exported meshes: frame and PLY text.
    meshes: Vec<(u64, String)>,
    /// A tuned entry's search (`None` for an entry without `tune`).
    tuning: Option<TuningRecord>,
}

/// Runs a tuned entry's search (`sim::tuning`) over probe runs of the point's flight: each probe
/// flies `tune.probe_frames` frames spread over the flight, frames 0, s, 2s, … (s from
/// [`probe_stride`]), with the speed bounds multiplied by s, the experiment's culling, the audit
/// (without popping) only for an error target, no mesh checks, exports nor timing passes.
/// Returns the entry with the value found and the record of the search (its `full_run_mean` is
/// filled after the real run).
fn tune_entry(
    experiment: &Experiment,
    hierarchy: &Hierarchy,
    spec: &AlgorithmSpec,
    tune: &Tune,
    progress: &dyn ProgressSink,
) -> Result<(AlgorithmSpec, TuningRecord), RunError> {
    let failed = |problem: String| RunError {
        algorithm: spec.label.clone(),
        frame: 0,
        error: CheckError::Tuning(problem),
    };
    let flight = &experiment.flight;
    let (stride, count) = probe_stride(flight.n_frames(), tune.probe_frames);
    let poses = (0..count).map(|i| *flight.pose(i * stride)).collect();
    let probe_flight = Flight::from_poses(poses).map_err(|e| failed(e.to_string()))?;
    let speed = probe_speed(experiment.speed, stride);
    let violations = speed_violations(&probe_flight, speed);
    let audit = match tune.target {
        TuneTarget::AuditP95Px(_) => experiment.effects.audit.map(|a| AuditSettings {
            popping: false,
            ..a
        }),
        TuneTarget::RenderedTriangles(_) => None,
    };
    let inputs = RunInputs {
        hierarchy,
        view: &experiment.view,
        flight: &probe_flight,
        violations: &violations,
        effects: Effects {
            audit,
            culling: experiment.effects.culling,
            check_meshes: false,
        },
        max_triangles: Some(experiment.max_triangles),
        detail_truth: None,
    };
    let found = search(&tune.search_settings(), |k, value| {
        let probe = tuned_spec(spec, tune, value).map_err(failed)?;
        let mut algorithm = probe.config.build(hierarchy, &experiment.view, speed);
        let label = format!(
            "{} (tuning probe {k}: {}={value})",
            spec.label, tune.parameter
        );
        let frames = run_algorithm(&inputs, &label, algorithm.as_mut(), &mut |_| {}).map_err(
            // The probe's frame k is the flight's frame k·s.
            |error| RunError {
                frame: error.frame * stride,
                ..error
            },
        )?;
        let mean = mean_of_target(&frames, tune.target);
        progress.tuning(&probe_line(&spec.label, tune, k, value, mean));
        Ok(mean)
    })?;
    let tuned = tuned_spec(spec, tune, found.value).map_err(failed)?;
    Ok((
        tuned,
        TuningRecord {
            target: tune.target,
            parameter: tune.parameter,
            value: found.value,
            probe_mean: found.mean,
            reached: found.reached,
            tolerance: tune.tolerance,
            probe_frames: count,
            probe_stride: stride,
            probes: found.probes,
            full_run_mean: f64::NAN,
        },
    ))
}

/// What the writers need besides the results.
struct OutputContext<'a> {
    experiment: &'a Experiment,
    preprocessing: &'a Preprocessing,
    /// Bytes of the shared preprocessed terrain (heights and Wu's node table).
    hierarchy_bytes: f64,
    record: &'a RunRecord,
}

/// Writes one point's `frames.csv`, `summary.json`, `report.md` and plots into `dir` (inside the
/// staged output folder); returns each entry's report figures.
fn write_outputs(
    context: &OutputContext,
    results: &[AlgorithmResult],
    dir: &Path,
) -> Result<Vec<EntryFigures>, RunFailure> {
    let experiment = context.experiment;
    let preprocessing = context.preprocessing;
    let runs: Vec<RunColumns> = experiment
        .algorithms
        .iter()
        .zip(results)
        .map(|(spec, result)| RunColumns {
            label: &spec.label,
            extra_columns: &result.extra_columns,
            frames: &result.frames,
        })
        .collect();
    let audited = experiment.effects.audit.is_some();
    std::fs::create_dir_all(dir).map_err(io_error(dir))?;
    let csv_path = dir.join("frames.csv");
    std::fs::write(&csv_path, frames_csv(&runs, audited)).map_err(io_error(&csv_path))?;
    // A tuned entry's parameters are listed with the value its search found.
    let parameters: Vec<_> = experiment
        .algorithms
        .iter()
        .zip(results)
        .map(|(spec, result)| {
            spec.tune
                .as_ref()
                .zip(result.tuning.as_ref())
                .and_then(|(tune, record)| tuned_spec(spec, tune, record.value).ok())
                .map_or_else(|| spec.parameters.clone(), |tuned| tuned.parameters)
        })
        .collect();
    let tunings: Vec<Option<&TuningRecord>> = results.iter().map(|r| r.tuning.as_ref()).collect();
    let names: Vec<&str> = experiment
        .algorithms
        .iter()
        .map(|s| s.config.name())
        .collect();
    let facts: Vec<_> = results.iter().map(|r| r.facts.clone()).collect();
    let entry_preprocessing: Vec<Preprocessing> = results.iter().map(|r| r.preprocessing).collect();
    let summary = summary_json(
        context.record,
        experiment,
        preprocessing,
        &runs,
        &parameters,
        &names,
        &facts,
        &entry_preprocessing,
        &tunings,
    );
    let summary_path = dir.join("summary.json");
    let text = serde_json::to_string_pretty(&summary).unwrap_or_default() + "\n";
    std::fs::write(&summary_path, text).map_err(io_error(&summary_path))?;
    let n_samples = experiment.field.n_samples() as f64;
    let bytes_per_sample: Vec<f64> = results
        .iter()
        .map(|r| (context.hierarchy_bytes + r.memory_bytes as f64) / n_samples)
        .collect();
    let report = report_markdown(&ReportInputs {
        experiment,
        runs: &runs,
        names: &names,
        bytes_per_sample: &bytes_per_sample,
        threads: context.record.threads,
        terrain_preprocessing: preprocessing,
        entry_preprocessing: &entry_preprocessing,
        tunings: &tunings,
    });
    let report_path = dir.join("report.md");
    std::fs::write(&report_path, report).map_err(io_error(&report_path))?;
    for (k, (spec, result)) in experiment.algorithms.iter().zip(results).enumerate() {
        if result.meshes.is_empty() {
            continue;
        }
        let folder = dir.join("meshes").join(mesh_folder(k, &spec.label));
        std::fs::create_dir_all(&folder).map_err(io_error(&folder))?;
        for (frame, text) in &result.meshes {
            let path = folder.join(format!("frame-{frame:06}.ply"));
            std::fs::write(&path, text).map_err(io_error(&path))?;
        }
    }
    if experiment.plots {
        let plots = dir.join("plots");
        std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
        let violation_frames: Vec<u64> = experiment.violations.iter().map(|v| v.frame).collect();
        write_run_plots(
            &plots,
            &RunPlotInputs {
                runs: &runs,
                names: &names,
                audited,
                speed_violation_frames: &violation_frames,
                horizontal_m_per_frame: experiment.speed.horizontal,
                warm_up_frames: experiment.warm_up_frames,
            },
        )?;
    }
    Ok(summarised_runs(&runs, experiment.warm_up_frames)
        .iter()
        .zip(&names)
        .zip(&bytes_per_sample)
        .map(|((run, name), bytes)| EntryFigures {
            label: run.label.to_string(),
            name: name.to_string(),
            row: row(run),
            bytes_per_sample: *bytes,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames_with(triangles: &[u64], update_ns: &[u64]) -> Vec<FrameStats> {
        triangles
            .iter()
            .zip(update_ns)
            .enumerate()
            .map(|(frame, (&triangles, &update_ns))| FrameStats {
                frame: frame as u64,
                triangles,
                update_ns,
                ..FrameStats::default()
            })
            .collect()
    }

    #[test]
    fn each_frame_gets_its_median_over_the_passes_and_the_facts_their_spread() {
        let mut frames = frames_with(&[10, 20, 30], &[999, 999, 999]);
        // Three passes; frame 0's times 5, 9, 7 → 7; the passes' medians over frames 1.. (one
        // warm-up frame): pass 0 {2000, 4000} → 2 µs, pass 1 {1000, 1000} → 1, pass 2
        // {3000, 5000} → 3.
        let passes = [
            vec![5, 2000, 4000],
            vec![9, 1000, 1000],
            vec![7, 3000, 5000],
        ];
        let facts = take_pass_times(&mut frames, &passes, 1);
        let times: Vec<u64> = frames.iter().map(|f| f.update_ns).collect();
        assert_eq!(times, [7, 2000, 4000]);
        assert_eq!(
            facts,
            [
                ("update_p50_us_median_of_passes", 2.0),
                ("update_p50_us_least_of_passes", 1.0),
                ("update_p50_us_greatest_of_passes", 3.0),
            ]
        );
    }

    #[test]
    fn an_algorithms_own_timing_columns_come_from_the_passes_too() {
        let with_extra = |update_ns: u64, extra: [f64; 2]| FrameStats {
            update_ns,
            extra: extra.to_vec(),
            ..FrameStats::default()
        };
        // Column 0 is a count, column 1 a part of the update (strip_construction_ns).
        let mut frames = vec![with_extra(100, [7.0, 90.0])];
        let passes = [
            vec![with_extra(40, [7.0, 30.0])],
            vec![with_extra(50, [7.0, 10.0])],
            vec![with_extra(60, [7.0, 20.0])],
        ];
        take_pass_sub_timings(&mut frames, &passes, &["m_blocks", "strip_construction_ns"]);
        assert_eq!(frames[0].extra, [7.0, 20.0]);
    }

    #[test]
    fn a_timing_pass_that_draws_other_counts_stops_the_run() {
        let measured = frames_with(&[10, 20, 30], &[1, 1, 1]);
        let same = frames_with(&[10, 20, 30], &[4, 5, 6]);
        assert_eq!(same_counts_timed("a", &measured, &same), Ok(vec![4, 5, 6]));
        let other = frames_with(&[10, 21, 30], &[4, 5, 6]);
        let error = same_counts_timed("a", &measured, &other).expect_err("diverged");
        assert_eq!(error.frame, 1);
        assert!(
            error
                .to_string()
                .contains("drew 21 triangles where the measured pass drew 20"),
            "{error}"
        );
    }

    #[test]
    fn timing_passes_run_when_an_effect_is_on_or_more_than_one_is_asked_for() {
        let default = Timing::default();
        assert_eq!(default.passes(true), 1);
        assert_eq!(default.passes(false), 0);
        let three = Timing {
            repeat: 3,
            with_effects: false,
        };
        assert_eq!((three.passes(true), three.passes(false)), (3, 3));
        let kept = Timing {
            repeat: 1,
            with_effects: true,
        };
        assert_eq!(kept.passes(true), 0);
    }

    #[test]
    fn a_large_first_frame_or_a_long_projected_run_is_announced_with_its_figures() {
        assert_eq!(
            large_work_notice("small", 20_000, 0.01, 1000, 2_000_000),
            None
        );
        let big = large_work_notice("roam τ=0.1px", 2_700_000, 1.0, 1000, 4_000_000)
            .expect("2.7 M triangles");
        assert!(
            big.contains("frame 0 has 2700000 triangles and took 1.00 s"),
            "{big}"
        );
        assert!(big.contains("its 1000 frames take about 17 min"), "{big}");
        assert!(big.contains("limits.max_triangles"), "{big}");
        let slow = large_work_notice("slow", 50_000, 0.5, 10_000, 2_000_000).expect("83 min");
        assert!(slow.contains("about 1.4 h"), "{slow}");
    }
}
