//! One `roamsim run`: load the experiment, preprocess, run every algorithm over the flight,
//! write the outputs all-or-nothing.
//!
//! Algorithms run one after another in the experiment's order, each from its own fresh state on
//! the shared preprocessed terrain, so the counts and meshes do not depend on anything but the
//! experiment. Progress goes to a [`ProgressSink`] (the CLI's progress bar, or nothing).

use crate::edge::experiment::{self, Experiment, ExperimentError};
use crate::edge::output::atomic_dir::StagedDir;
use crate::edge::output::columns::RunColumns;
use crate::edge::output::frames_csv::frames_csv;
use crate::edge::output::plots::PlotError;
use crate::edge::output::run_plots::write_run_plots;
use crate::edge::output::summary_json::{Preprocessing, summary_json};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::run::{RunError, RunInputs, run_algorithm};
use crate::sim::stats::FrameStats;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Receives progress: one phase per algorithm.
pub trait ProgressSink {
    fn start(&mut self, label: &str, total_frames: u64);
    fn advance(&mut self, frames_done: u64);
    fn finish(&mut self);
}

/// Progress that goes nowhere.
pub struct NoProgress;

impl ProgressSink for NoProgress {
    fn start(&mut self, _: &str, _: u64) {}
    fn advance(&mut self, _: u64) {}
    fn finish(&mut self) {}
}

/// How to run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder; by default `out/<experiment name>` under the working directory.
    pub out_dir: Option<PathBuf>,
    /// Validate every mesh every frame.
    pub check_meshes: bool,
}

/// What a finished run produced.
pub struct RunOutcome {
    pub out_dir: PathBuf,
    pub experiment_name: String,
    pub frames: u64,
    pub speed_violation_frames: Vec<u64>,
    pub preprocessing_seconds: f64,
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
}

/// Runs an experiment file.
pub fn run_experiment(
    path: &Path,
    options: &RunOptions,
    progress: &mut dyn ProgressSink,
) -> Result<RunOutcome, RunFailure> {
    let mut experiment = experiment::load(path)?;
    experiment.effects.check_meshes = options.check_meshes;
    let out_dir = options
        .out_dir
        .clone()
        .unwrap_or_else(|| Path::new("out").join(&experiment.name));

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
        violation_frames: &violation_frames,
        effects: experiment.effects,
    };
    let mut results: Vec<AlgorithmResult> = Vec::new();
    for spec in &experiment.algorithms {
        let mut algorithm = spec
            .config
            .build(&hierarchy, &experiment.view, experiment.speed);
        progress.start(&spec.label, experiment.flight.n_frames());
        let frames = run_algorithm(&inputs, &spec.label, algorithm.as_mut(), &mut |done| {
            progress.advance(done)
        });
        progress.finish();
        results.push(AlgorithmResult {
            frames: frames?,
            extra_columns: algorithm.extra_columns(),
            facts: algorithm.run_facts(),
        });
    }

    write_outputs(&experiment, &preprocessing, &results, &out_dir)?;
    Ok(RunOutcome {
        out_dir,
        experiment_name: experiment.name.clone(),
        frames: experiment.flight.n_frames(),
        speed_violation_frames: violation_frames,
        preprocessing_seconds: preprocessing.seconds,
    })
}

/// One algorithm's run.
struct AlgorithmResult {
    frames: Vec<FrameStats>,
    extra_columns: &'static [&'static str],
    facts: Vec<(&'static str, f64)>,
}

fn write_outputs(
    experiment: &Experiment,
    preprocessing: &Preprocessing,
    results: &[AlgorithmResult],
    out_dir: &Path,
) -> Result<(), RunFailure> {
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
    let io_error = |path: &Path| {
        let path = path.to_path_buf();
        move |source| RunFailure::Output { path, source }
    };
    let staged = StagedDir::new(out_dir).map_err(io_error(out_dir))?;
    let csv_path = staged.path().join("frames.csv");
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
    let summary = summary_json(
        experiment,
        preprocessing,
        &runs,
        &parameters,
        &names,
        &facts,
    );
    let summary_path = staged.path().join("summary.json");
    let text = serde_json::to_string_pretty(&summary).unwrap_or_default() + "\n";
    std::fs::write(&summary_path, text).map_err(io_error(&summary_path))?;
    if experiment.plots {
        let plots = staged.path().join("plots");
        std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
        write_run_plots(&plots, &runs, audited)?;
    }
    staged.commit().map_err(io_error(out_dir))?;
    Ok(())
}
