//! One `roamsim run`: load the experiment, preprocess, run every algorithm over the flight,
//! write the outputs all-or-nothing.
//!
//! Every algorithm entry (sweep points included) runs from its own fresh state on the shared
//! preprocessed terrain, in parallel on a rayon pool of `threads` threads; results are collected
//! in the experiment's order, so the outputs do not depend on the thread count (timings do:
//! entries running side by side share the cores; use one thread for timing comparisons).
//! Progress goes to a [`ProgressSink`] (the CLI's progress bar, or nothing).
//!
//! An experiment with a top-level sweep runs its points one after another, each into its own
//! sub-folder, then writes the sweep's own `summary.json`, `report.md` and plots at the top; the
//! whole folder is staged and moved into place only when every point has succeeded.

use crate::edge::experiment::{self, AlgorithmSpec, Experiment, ExperimentError};
use crate::edge::output::atomic_dir::{CommitError, OutputLocationError, StagedDir};
use crate::edge::output::columns::RunColumns;
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
use crate::edge::output::warm_up::summarised_runs;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::run::{RunError, RunInputs, run_algorithm_with};
use crate::sim::stats::FrameStats;
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
    /// Every point's entries and their report figures, in order (one point without a sweep).
    pub points: Vec<PointFigures>,
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
    #[error("cannot start {threads} worker threads: {message}")]
    Threads { threads: usize, message: String },
}

/// Runs an experiment file: every point of its top-level sweep one after another (each with its
/// own terrain, so only one is in memory at a time), every algorithm entry of a point in
/// parallel. Nothing is written unless every point succeeds.
pub fn run_experiment(
    path: &Path,
    options: &RunOptions,
    progress: &dyn ProgressSink,
) -> Result<RunOutcome, RunFailure> {
    let plan = experiment::plan(path)?;
    // Normalised: `out/.` names `out`, whose rename is what commits the run.
    let out_dir: PathBuf = options
        .out_dir
        .clone()
        .unwrap_or_else(|| Path::new("out").join(plan.name()))
        .components()
        .collect();
    if options.threads == Some(0) {
        return Err(RunFailure::ZeroThreads);
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
    let record = RunRecord {
        threads,
        check_meshes: options.check_meshes,
        command_line: options.command_line.clone(),
    };
    let mut outcome = RunOutcome {
        out_dir: out_dir.clone(),
        experiment_name: plan.name().to_string(),
        frames: 0,
        meshes: 0,
        goal_flags: Vec::new(),
        speed_violation_frames: Vec::new(),
        preprocessing_seconds: 0.0,
        threads,
        points: Vec::new(),
    };
    let mut sweep_points = Vec::new();
    for k in 0..plan.n_points() {
        let mut experiment = plan.load_point(k)?;
        experiment.effects.check_meshes = options.check_meshes;
        if let Some(n_frames) = options.max_frames {
            experiment.keep_first_frames(n_frames);
            experiment.check_warm_up()?;
        }
        let choice_label = plan.choice(k).map(|c| experiment::choice_label(c));
        if let Some(label) = &choice_label {
            progress.point(k, plan.n_points(), label);
        }
        let point = run_point(&experiment, &pool, progress)?;
        let context = OutputContext {
            experiment: &experiment,
            preprocessing: &point.preprocessing,
            hierarchy_bytes: point.hierarchy_bytes,
            record: &record,
        };
        let folder = match plan.choice(k) {
            Some(choice) => point_folder(choice),
            None => String::new(),
        };
        let point_dir = staging.path().join(&folder);
        let figures = write_outputs(&context, &point.results, &point_dir)?;
        outcome.frames += experiment.flight.n_frames();
        outcome.meshes += experiment.flight.n_frames() * experiment.algorithms.len() as u64;
        for (spec, result) in experiment.algorithms.iter().zip(&point.results) {
            // Over the summarised frames, as report.md and summary.json judge it.
            let all = RunColumns {
                label: &spec.label,
                extra_columns: result.extra_columns,
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
        if let Some(choice) = plan.choice(k) {
            sweep_points.push(SweepPoint {
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
    }
    if plan.is_sweep() {
        let top = staging.path();
        let sweep = SweepRun {
            name: plan.name(),
            description: plan.description(),
            file: path,
            content_sha256: plan.content_sha256(),
            record: &record,
            points: &sweep_points,
        };
        let summary_path = top.join("summary.json");
        let text = serde_json::to_string_pretty(&sweep_summary_json(&sweep)).unwrap_or_default();
        std::fs::write(&summary_path, text + "\n").map_err(io_error(&summary_path))?;
        let report_path = top.join("report.md");
        std::fs::write(&report_path, sweep_report_markdown(&sweep))
            .map_err(io_error(&report_path))?;
        let plots = top.join("plots");
        std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
        write_sweep_plots(&plots, &sweep)?;
    }
    staging.commit()?;
    Ok(outcome)
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
struct PointRun {
    preprocessing: Preprocessing,
    hierarchy_bytes: f64,
    violation_frames: Vec<u64>,
    results: Vec<AlgorithmResult>,
}

fn run_point(
    experiment: &Experiment,
    pool: &rayon::ThreadPool,
    progress: &dyn ProgressSink,
) -> Result<PointRun, RunFailure> {
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
    progress.entries(experiment.algorithms.len());
    progress.start(n_frames * experiment.algorithms.len() as u64);
    let n_samples = experiment.field.n_samples() as f64;
    let run_one = |(k, spec): (usize, &AlgorithmSpec)| -> Result<AlgorithmResult, RunError> {
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
        progress.entry_finished();
        Ok(AlgorithmResult {
            memory_bytes: algorithm.memory_bytes(),
            preprocessing,
            frames,
            extra_columns: algorithm.extra_columns(),
            facts: algorithm.run_facts(),
            meshes,
        })
    };
    let results: Vec<Result<AlgorithmResult, RunError>> = pool.install(|| {
        experiment
            .algorithms
            .par_iter()
            .enumerate()
            .map(run_one)
            .collect()
    });
    progress.finish();
    let results = results.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok(PointRun {
        preprocessing,
        hierarchy_bytes: hierarchy.bytes_per_sample() * hierarchy.field().n_samples() as f64,
        violation_frames,
        results,
    })
}

/// One algorithm's run.
struct AlgorithmResult {
    memory_bytes: usize,
    /// Building the algorithm (its own tables and trees) before the first frame.
    preprocessing: Preprocessing,
    frames: Vec<FrameStats>,
    extra_columns: &'static [&'static str],
    facts: Vec<(&'static str, f64)>,
    /// Exported meshes: frame and PLY text.
    meshes: Vec<(u64, String)>,
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
            extra_columns: result.extra_columns,
            frames: &result.frames,
        })
        .collect();
    let audited = experiment.effects.audit.is_some();
    std::fs::create_dir_all(dir).map_err(io_error(dir))?;
    let csv_path = dir.join("frames.csv");
    std::fs::write(&csv_path, frames_csv(&runs, audited)).map_err(io_error(&csv_path))?;
    let parameters: Vec<_> = experiment
        .algorithms
        .iter()
        .map(|s| s.parameters.clone())
        .collect();
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
