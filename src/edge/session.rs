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
use crate::edge::output::atomic_dir::{StagedDir, check_destination};
use crate::edge::output::columns::RunColumns;
use crate::edge::output::end_of_run::PointFigures;
use crate::edge::output::frames_csv::frames_csv;
use crate::edge::output::mesh_ply::{PlyHeader, mesh_ply};
use crate::edge::output::plots::PlotError;
use crate::edge::output::report_md::{ReportInputs, report_markdown, row};
use crate::edge::output::run_plots::{RunPlotInputs, write_run_plots};
use crate::edge::output::summary_json::{Preprocessing, summary_json};
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
}

/// Progress that goes nowhere.
pub struct NoProgress;

impl ProgressSink for NoProgress {
    fn start(&self, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
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
    /// Run only the first this many frames of every flight (`--frames N`); `None`: all.
    pub max_frames: Option<u64>,
}

/// What a finished run produced.
pub struct RunOutcome {
    pub out_dir: PathBuf,
    pub experiment_name: String,
    pub frames: u64,
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
    #[error("mesh check failed: {0}")]
    Mesh(#[from] RunError),
    #[error("{path}: cannot write the output: {source}")]
    Output {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{0}")]
    Plot(#[from] PlotError),
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
    let out_dir = options
        .out_dir
        .clone()
        .unwrap_or_else(|| Path::new("out").join(plan.name()));
    // Before simulating: a run must not find out at the end that it cannot write.
    check_destination(&out_dir).map_err(|source| RunFailure::Output {
        path: out_dir.clone(),
        source,
    })?;
    let threads = options
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| RunFailure::Threads {
            threads,
            message: e.to_string(),
        })?;
    // Staged when the first point has run, so that a staging folder means outputs are being written.
    let mut staged: Option<StagedDir> = None;
    let mut outcome = RunOutcome {
        out_dir: out_dir.clone(),
        experiment_name: plan.name().to_string(),
        frames: 0,
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
            threads,
        };
        let folder = match plan.choice(k) {
            Some(choice) => point_folder(choice),
            None => String::new(),
        };
        let staging = match staged.take() {
            Some(staging) => staging,
            None => StagedDir::new(&out_dir).map_err(io_error(&out_dir))?,
        };
        let point_dir = staging.path().join(&folder);
        staged = Some(staging);
        let figures = write_outputs(&context, &point.results, &point_dir)?;
        outcome.frames += experiment.flight.n_frames();
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
    if let (true, Some(staging)) = (plan.is_sweep(), &staged) {
        let top = staging.path();
        let sweep = SweepRun {
            name: plan.name(),
            description: plan.description(),
            file: path,
            content_sha256: plan.content_sha256(),
            threads,
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
    if let Some(staged) = staged {
        staged.commit().map_err(io_error(&out_dir))?;
    }
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
    threads: usize,
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
        threads: context.threads,
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
