//! Running one point of an experiment (SPEC §8): its terrain preprocessed once, then the entries
//! asked for, side by side on the run's thread pool, each through its search when tuned, its
//! measured pass and its timing passes. Not the writing of the results (`assemble.rs`), nor the
//! loop over the points (`run_experiment.rs`, `shards.rs`).
//!
//! **Fresh state, shared terrain, results in order.** Every entry runs from its own fresh
//! algorithm on the point's one preprocessed terrain (the `Hierarchy`); the results come back in
//! the order of the entries asked for, whatever the thread count.
//!
//! **Two preprocessing times.** The terrain's preprocessing (the hierarchy) is timed once per
//! point; each entry's own (building its algorithm: its tables and trees) is timed apart, before
//! its first frame.
//!
//! **Meshes exported as the frames pass.** The meshes asked for (`outputs.meshes`) are written
//! as PLY text right after their frame, from the measured pass, and kept with the entry's result.
//!
//! **Detail is audited against its own surface.** An entry that synthesises detail beyond the
//! source is audited against the detail-extended surface too.

use super::progress_sink::{FrameProgress, ProgressSink, large_work_notice};
use super::run::RunFailure;
use super::timing::{Timing, TimingPasses};
use super::tune::tune_entry;
use crate::edge::experiment::{AlgorithmSpec, Experiment, ExperimentError};
use crate::edge::output::mesh_ply::{PlyHeader, mesh_ply};
use crate::edge::output::summary_json::{Preprocessing, resident_bytes};
use crate::edge::output::tuning::{TuningRecord, mean_of_target};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::run::{RunError, RunInputs, run_algorithm_with};
use crate::sim::stats::FrameStats;
use rayon::prelude::*;
use std::sync::Arc;
use std::time::Instant;

/// One point's run: preprocessing and every entry's result.
pub(super) struct PointRun<'a> {
    pub(super) preprocessing: Preprocessing,
    pub(super) hierarchy_bytes: f64,
    /// The process's largest resident set measured at the end of an entry's measured frames,
    /// its algorithm still alive (`None` where the system does not say).
    pub(super) frames_resident_bytes: Option<u64>,
    pub(super) violation_frames: Vec<u64>,
    pub(super) results: Vec<AlgorithmResult<'a>>,
}

/// One algorithm's run (names borrowed from the algorithm, or from a shard file when merging).
pub(super) struct AlgorithmResult<'a> {
    pub(super) memory_bytes: usize,
    /// Building the algorithm (its own tables and trees) before the first frame.
    pub(super) preprocessing: Preprocessing,
    pub(super) frames: Vec<FrameStats>,
    pub(super) extra_columns: Vec<&'a str>,
    pub(super) facts: Vec<(&'a str, f64)>,
    /// Exported meshes: frame and PLY text.
    pub(super) meshes: Vec<(u64, String)>,
    /// A tuned entry's search (`None` for an entry without `tune`).
    pub(super) tuning: Option<TuningRecord>,
}

/// Runs the entries `entries` (indices into the experiment's algorithms, in order) of one
/// point; their results in the same order.
pub(super) fn run_point<'a>(
    experiment: &'a Experiment,
    entries: &[usize],
    timing: Timing,
    pool: &rayon::ThreadPool,
    progress: &dyn ProgressSink,
) -> Result<PointRun<'a>, RunFailure> {
    let start = Instant::now();
    // The run shares the experiment's heights; Wu's node table is built only for entries that
    // read it, here so that its time is the terrain's preprocessing.
    let hierarchy = Hierarchy::new(Arc::clone(&experiment.field));
    if entries
        .iter()
        .any(|&k| experiment.algorithms[k].config.reads_node_table())
    {
        hierarchy.build_node_table();
    }
    let preprocessing = Preprocessing {
        seconds: start.elapsed().as_secs_f64(),
        bytes_per_sample: hierarchy.bytes_per_sample(),
    };
    let violation_frames: Vec<u64> = experiment.violations.iter().map(|v| v.frame).collect();
    let point = PointEntries {
        experiment,
        hierarchy: &hierarchy,
        timing,
        progress,
    };
    let passes_in_all: u64 = entries
        .iter()
        .map(|&k| u64::from(point.timing_passes(k)))
        .sum();
    progress.entries(entries.len());
    progress.start(experiment.flight.n_frames() * (entries.len() as u64 + passes_in_all));
    let results: Vec<Result<(AlgorithmResult, Option<u64>), RunError>> =
        pool.install(|| entries.par_iter().map(|&k| point.run_entry(k)).collect());
    progress.finish();
    // A terrain read on demand whose file failed a read during the frames: the figures are
    // not the terrain's.
    if let Some(failure) = experiment
        .field
        .paged_samples()
        .and_then(|paged| paged.failure())
    {
        return Err(RunFailure::Experiment(ExperimentError::single(
            &experiment.file,
            "terrain.pyramid.file",
            format!("a read failed during the run: {failure}"),
        )));
    }
    let (results, resident): (Vec<_>, Vec<_>) = results
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    Ok(PointRun {
        preprocessing,
        hierarchy_bytes: hierarchy.bytes_per_sample() * hierarchy.field().n_samples() as f64,
        frames_resident_bytes: resident.into_iter().flatten().max(),
        violation_frames,
        results,
    })
}

/// What every entry of one point runs with.
struct PointEntries<'p> {
    experiment: &'p Experiment,
    hierarchy: &'p Hierarchy,
    timing: Timing,
    progress: &'p dyn ProgressSink,
}

/// An entry's measured pass: everything of its result but the timing passes' and the search's.
struct MeasuredPass {
    preprocessing: Preprocessing,
    frames: Vec<FrameStats>,
    facts: Vec<(&'static str, f64)>,
    memory_bytes: usize,
    extra_columns: Vec<&'static str>,
    meshes: Vec<(u64, String)>,
    /// The process's resident set right after the frames, the algorithm still alive.
    resident_bytes: Option<u64>,
}

impl<'p> PointEntries<'p> {
    /// The timing passes entry `k` needs: whether any effect is on in its measured pass (the
    /// audit, culling, mesh checks, or an export of its meshes) decides with `--repeat`.
    fn timing_passes(&self, k: usize) -> u32 {
        let exported = self
            .experiment
            .mesh_exports
            .as_ref()
            .is_some_and(|exports| exports.entries.contains(&k) && !exports.frames.is_empty());
        let effects = self.experiment.effects;
        let effects_on =
            effects.audit.is_some() || effects.culling || effects.check_meshes || exported;
        self.timing.passes(effects_on)
    }

    /// Runs entry `k`: its search when it is tuned, its measured pass, its timing passes; with
    /// the resident set at the end of its measured frames.
    fn run_entry(&self, k: usize) -> Result<(AlgorithmResult<'static>, Option<u64>), RunError> {
        let experiment = self.experiment;
        let written: &AlgorithmSpec = &experiment.algorithms[k];
        // A tuned entry runs with the value its search found (the search's probes first).
        let tuned = match &written.tune {
            Some(tune) => Some(tune_entry(
                experiment,
                self.hierarchy,
                written,
                tune,
                self.progress,
            )?),
            None => None,
        };
        let spec: &AlgorithmSpec = tuned.as_ref().map_or(written, |(spec, _)| spec);
        // An entry that synthesises detail is audited against the detail-extended surface too.
        let detail_truth = experiment
            .effects
            .audit
            .and_then(|_| spec.config.detail_truth(self.hierarchy));
        let inputs = RunInputs {
            hierarchy: self.hierarchy,
            view: &experiment.view,
            flight: &experiment.flight,
            violations: &experiment.violations,
            effects: experiment.effects,
            max_triangles: Some(experiment.max_triangles),
            detail_truth: detail_truth.as_ref(),
        };
        let measured = self.measured_pass(k, spec, &inputs)?;
        let mut frames = measured.frames;
        let mut facts = measured.facts;
        let passes = self.timing_passes(k);
        facts.push(("timing_passes", f64::from(passes)));
        if passes > 0 {
            let timing_passes = TimingPasses {
                experiment,
                spec,
                inputs,
                progress: self.progress,
            };
            facts.extend(timing_passes.retime(passes, &mut frames, &measured.extra_columns)?);
        }
        self.progress.entry_finished();
        let tuning = tuned.map(|(_, mut record)| {
            record.full_run_mean = mean_of_target(&frames, record.target);
            record
        });
        let result = AlgorithmResult {
            memory_bytes: measured.memory_bytes,
            preprocessing: measured.preprocessing,
            frames,
            extra_columns: measured.extra_columns,
            facts,
            meshes: measured.meshes,
            tuning,
        };
        Ok((result, measured.resident_bytes))
    }

    /// Builds entry `k`'s algorithm (its preprocessing, timed) and flies it over the flight with
    /// the experiment's effects, exporting the meshes asked for as the frames pass. The algorithm
    /// is gone when this returns, before a timing pass builds its own, so that the run's peak
    /// memory is one algorithm's.
    fn measured_pass(
        &self,
        k: usize,
        spec: &AlgorithmSpec,
        inputs: &RunInputs,
    ) -> Result<MeasuredPass, RunError> {
        let experiment = self.experiment;
        let n_frames = experiment.flight.n_frames();
        let n_samples = experiment.field.n_samples() as f64;
        let start = Instant::now();
        let mut algorithm = spec
            .config
            .build(self.hierarchy, &experiment.view, experiment.speed);
        let preprocessing = Preprocessing {
            seconds: start.elapsed().as_secs_f64(),
            bytes_per_sample: algorithm.memory_bytes() as f64 / n_samples,
        };
        let export_frames: &[u64] = match &experiment.mesh_exports {
            Some(exports) if exports.entries.contains(&k) => &exports.frames,
            _ => &[],
        };
        let mut meshes = Vec::new();
        let mut progress = FrameProgress::new(self.progress, n_frames);
        let frames_started = Instant::now();
        let frames = run_algorithm_with(
            inputs,
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
                    meshes.push((frame, mesh_ply(self.hierarchy, algorithm.mesh(), &header)));
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
                    self.progress.notice(&message);
                }
                progress.frame_done(frame);
            },
        )?;
        let resident_bytes = resident_bytes();
        Ok(MeasuredPass {
            preprocessing,
            frames,
            facts: algorithm.run_facts(),
            memory_bytes: algorithm.memory_bytes(),
            extra_columns: algorithm.extra_columns().to_vec(),
            meshes,
            resident_bytes,
        })
    }
}
