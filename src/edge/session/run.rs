//! The terms of one run (SPEC §8): the options it takes ([`RunOptions`]), the outcome it reports
//! ([`RunOutcome`]), the failures that stop it ([`RunFailure`]), and what every point is loaded
//! with. Not the running itself (`run_experiment.rs` and the files below it), which all build on
//! these types.
//!
//! **Failures are values, grouped by what stopped the run.** The experiment (every problem of
//! the file), an algorithm's run (the algorithm, the frame and what broke), the output (the path
//! that could not be written), the options, the thread pool, a merge: each its own variant.

use super::timing::Timing;
use crate::edge::experiment::{Experiment, ExperimentError, Plan};
use crate::edge::output::atomic_dir::{CommitError, OutputLocationError};
use crate::edge::output::end_of_run::PointFigures;
use crate::edge::output::plots::PlotError;
use crate::edge::shard::{MergeError, ShardSpec};
use crate::sim::run::RunError;
use crate::sim::terrain::MAX_SIDE;
use std::path::{Path, PathBuf};

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

/// What a finished run produced.
pub struct RunOutcome {
    pub out_dir: PathBuf,
    pub experiment_name: String,
    pub frames: u64,
    /// (entry, frame) meshes made, over every point.
    pub meshes: u64,
    /// The run's warnings: entries that did not hold their budget or target, or whose search did
    /// not reach its target, as `label: why (report.md, "section")` (a sweep point's entries
    /// prefixed with the point, its report in the point's folder); and a `tuned-experiment.json`
    /// that could not be written.
    pub goal_flags: Vec<String>,
    /// What the output folder holds at its top, as the end of the run lists it: files, and
    /// folders with a `/` (a sweep's point folders and the manifest left out); empty for a shard.
    pub written: Vec<String>,
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
    pub(super) fn nothing_yet(
        plan: &Plan,
        out_dir: PathBuf,
        threads: usize,
        check_meshes: bool,
    ) -> Self {
        RunOutcome {
            out_dir,
            experiment_name: plan.name().to_string(),
            frames: 0,
            meshes: 0,
            goal_flags: Vec::new(),
            written: Vec::new(),
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

/// What every point is loaded with: `--check` and `--frames`.
#[derive(Clone, Copy)]
pub(super) struct PointSettings {
    pub(super) check_meshes: bool,
    pub(super) max_frames: Option<u64>,
    pub(super) timing: Timing,
}

impl PointSettings {
    /// Loads point `k` (its terrain and flight) as the run sees it.
    pub(super) fn load_point(&self, plan: &Plan, k: usize) -> Result<Experiment, RunFailure> {
        let mut experiment = plan.load_point(k)?;
        let side = experiment.field.side();
        if self.check_meshes && side > MAX_SIDE {
            // Only a pyramid is this large (`terrain::MAX_PAGED_LEVEL`).
            return Err(RunFailure::Experiment(ExperimentError::single(
                &experiment.file,
                "terrain.pyramid.file",
                format!(
                    "`--check` validates a mesh against an owner count for every sample of the \
                     terrain (4 bytes a sample: {:.1} GB for this {side}² pyramid), at most \
                     {MAX_SIDE}²: run without `--check`, or prepare a crop of the terrain",
                    (side * side * 4) as f64 / 1e9
                ),
            )));
        }
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
pub(super) fn normalised_out_dir(given: Option<&Path>, default_folder: &str) -> PathBuf {
    given
        .map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("out").join(default_folder))
        .components()
        .collect()
}

/// Turns an IO error on `path` into the run's failure to write it.
pub(super) fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> RunFailure + use<> {
    let path = path.to_path_buf();
    move |source| RunFailure::Output { path, source }
}
