//! Sharded runs (SPEC §8): `roamsim run --shard K/N` runs its part of the experiment's
//! (point, entry) units and writes their raw results (`shard.json`); `roamsim merge` reads the N
//! parts back and writes the whole run's outputs. Not the shard file's format, which units a
//! part runs, nor the merge's checks of the files: those are `edge::shard`.
//!
//! **A part runs as a whole run does.** Each unit runs through the same `run_point` as in a whole
//! run (its own fresh algorithm over the point's terrain and flight), and a part loads only the
//! points it has units of.
//!
//! **The merge feeds the same writers** as a whole run (`RunAssembly`, see `assemble.rs`), point
//! by point; each point's terrain and flight are loaded again for them (summary.json's terrain
//! and flight sections); nothing is simulated.
//!
//! **A merge refuses to guess.** The shards must be of the same experiment bytes (the file is
//! read again and its hash compared) and settings, every unit must be in exactly one shard
//! (checked before anything is loaded or written), and each under the label the experiment
//! gives it.

use super::assemble::RunAssembly;
use super::point::{AlgorithmResult, PointRun, run_point};
use super::progress_sink::ProgressSink;
use super::run::{PointSettings, RunFailure, RunOptions, RunOutcome, io_error, normalised_out_dir};
use super::timing::Timing;
use crate::edge::experiment::{self, AlgorithmSpec, Experiment, Plan};
use crate::edge::output::atomic_dir::StagedDir;
use crate::edge::output::summary_json::{Preprocessing, RunRecord};
use crate::edge::output::tuning::{PlateauRecord, TuningRecord};
use crate::edge::shard::frame_codec::encode_frame;
use crate::edge::shard::{
    MergeError, SHARD_FILE, ShardEntry, ShardExperiment, ShardFile, ShardPlateau, ShardPoint,
    ShardSpec, ShardTuning, read_complete_set,
};
use crate::sim::stats::FrameStats;
use crate::sim::tuning::Probe;
use std::path::{Path, PathBuf};

/// What a shard runs with.
pub(super) struct ShardRun<'a> {
    pub(super) shard: ShardSpec,
    pub(super) settings: PointSettings,
    pub(super) options: &'a RunOptions,
    pub(super) pool: &'a rayon::ThreadPool,
    pub(super) threads: usize,
}

/// Runs shard `shard` of the plan: the entries of its units, point by point, and writes their
/// raw results to `shard.json` in the staged folder.
pub(super) fn run_shard(
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
    let mine = shard_units(plan, shard);
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
        file_out
            .points
            .push(shard_point(k, &experiment, &entries, point));
    }
    let shard_path = staging.path().join(SHARD_FILE);
    let text = serde_json::to_string(&file_out).unwrap_or_default() + "\n";
    std::fs::write(&shard_path, text).map_err(io_error(&shard_path))?;
    staging.commit()?;
    Ok(outcome)
}

/// The (point, entry) units shard `shard` runs, in order. Counting entries needs only the
/// checked plan.
fn shard_units(plan: &Plan, shard: ShardSpec) -> Vec<(usize, usize)> {
    let mut units = Vec::new();
    for k in 0..plan.n_points() {
        units.extend((0..plan.n_entries(k)).map(|e| (k, e)));
    }
    units[shard.units(units.len())].to_vec()
}

/// Point `k`'s run as the shard file keeps it: its own figures and its entries' results, every
/// `f64` as its bits.
fn shard_point(
    k: usize,
    experiment: &Experiment,
    entries: &[usize],
    point: PointRun,
) -> ShardPoint {
    ShardPoint {
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
                    plateau: t.plateau.map(|p| ShardPlateau {
                        values_bits: (p.values.0.to_bits(), p.values.1.to_bits()),
                        means_bits: (p.means.0.to_bits(), p.means.1.to_bits()),
                        probes: p.probes,
                        reason: p.reason,
                    }),
                }),
            })
            .collect(),
    }
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
    let units = place_units(&plan, &shards)?;
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
        let merged = MergedPoint {
            experiment: &experiment,
            k,
            shard_file: first_folder.join(SHARD_FILE),
        };
        let Some(run) = merged.point_run(slots)? else {
            continue;
        };
        assembly.add_point((k, &plan), &experiment, run, staging.path())?;
    }
    assembly.finish(&plan, &path, staging)
}

/// Where each unit's results are: for every point, for every entry, the shard's point and entry
/// that ran it.
type Slots<'s> = Vec<Vec<Option<(&'s ShardPoint, &'s ShardEntry)>>>;

/// Every unit of the plan placed from the shard that ran it, each exactly once, before anything
/// is loaded or written. A unit no shard ran is left empty here (and found when its point is
/// merged).
fn place_units<'s>(
    plan: &Plan,
    shards: &'s [(PathBuf, ShardFile)],
) -> Result<Slots<'s>, RunFailure> {
    let mut units: Slots<'s> = (0..plan.n_points())
        .map(|k| vec![None; plan.n_entries(k)])
        .collect();
    for (folder, shard) in shards {
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
    Ok(units)
}

/// One point being merged: its experiment as loaded again, and the shard file that errors name.
struct MergedPoint<'e> {
    experiment: &'e Experiment,
    k: usize,
    /// The first shard's file.
    shard_file: PathBuf,
}

impl MergedPoint<'_> {
    /// The point's run from its units' slots: every entry's result, and the point's own figures
    /// from the first shard that ran any of its entries (`None` for a point without entries).
    fn point_run<'s>(
        &self,
        slots: &[Option<(&'s ShardPoint, &'s ShardEntry)>],
    ) -> Result<Option<PointRun<'s>>, RunFailure> {
        let (experiment, k) = (self.experiment, self.k);
        let mut results = Vec::new();
        let mut point_facts = None;
        for (e, slot) in slots.iter().enumerate() {
            let Some((point, entry)) = slot else {
                return Err(self
                    .inconsistent(format!(
                        "no shard ran entry {e} of point {k} ({:?}): were the shards made by \
                         another roamsim?",
                        experiment.algorithms[e].label
                    ))
                    .into());
            };
            let label = &experiment.algorithms[e].label;
            if &entry.label != label {
                return Err(self
                    .inconsistent(format!(
                        "entry {e} of point {k} is {:?} in a shard, {label:?} in the experiment",
                        entry.label
                    ))
                    .into());
            }
            point_facts.get_or_insert(*point);
            let frames = entry
                .decode_frames()
                .map_err(|problem| self.inconsistent(problem))?;
            results.push(merged_result(&experiment.algorithms[e], entry, frames));
        }
        let Some(point) = point_facts else {
            return Ok(None);
        };
        Ok(Some(PointRun {
            preprocessing: Preprocessing {
                seconds: f64::from_bits(point.preprocessing_seconds_bits),
                bytes_per_sample: f64::from_bits(point.bytes_per_sample_bits),
            },
            hierarchy_bytes: f64::from_bits(point.hierarchy_bytes_bits),
            // The parts' processes measured their own resident sets; the merge ran no frame.
            frames_resident_bytes: None,
            violation_frames: point.violation_frames.clone(),
            results,
        }))
    }

    fn inconsistent(&self, problem: String) -> MergeError {
        MergeError::Inconsistent {
            path: self.shard_file.clone(),
            problem,
        }
    }
}

/// Entry `spec`'s result as a shard recorded it (names borrowed from the shard file), with its
/// decoded `frames`.
fn merged_result<'s>(
    spec: &AlgorithmSpec,
    entry: &'s ShardEntry,
    frames: Vec<FrameStats>,
) -> AlgorithmResult<'s> {
    AlgorithmResult {
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
        tuning: spec
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
                plateau: t.plateau.as_ref().map(|p| PlateauRecord {
                    values: (
                        f64::from_bits(p.values_bits.0),
                        f64::from_bits(p.values_bits.1),
                    ),
                    means: (
                        f64::from_bits(p.means_bits.0),
                        f64::from_bits(p.means_bits.1),
                    ),
                    probes: p.probes,
                    reason: p.reason.clone(),
                }),
            }),
    }
}
