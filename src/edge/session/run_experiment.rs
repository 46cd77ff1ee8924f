//! Running an experiment file, `roamsim run` (SPEC §8): the experiment planned, the options
//! checked, the output folder staged, then the loop over the experiment's points, or a shard's
//! run handed over to `shards.rs`. Not the running of a point (`point.rs`), nor the writing of
//! its outputs (`assemble.rs`).
//!
//! **Nothing runs before the output folder is known to be writable.** The experiment is planned
//! (every point parsed and checked), the options checked and the staging folder made before
//! anything is simulated: a run must not find out at the end that it cannot write, nor replace a
//! folder it did not write.

use super::assemble::RunAssembly;
use super::point::run_point;
use super::progress_sink::ProgressSink;
use super::run::{PointSettings, RunFailure, RunOptions, RunOutcome, normalised_out_dir};
use super::shards::{ShardRun, run_shard};
use super::timing::Timing;
use crate::edge::experiment;
use crate::edge::output::atomic_dir::StagedDir;
use crate::edge::output::summary_json::RunRecord;
use std::path::Path;

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
    check_options(options)?;
    let (pool, threads) = worker_pool(options.threads)?;
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
        assembly.add_point((k, &plan), &experiment, point, staging.path())?;
    }
    assembly.finish(&plan, path, staging)
}

/// The options' own rules: at least one thread, at least one timing pass, and `--repeat` above 1
/// not with `--time-with-effects`.
fn check_options(options: &RunOptions) -> Result<(), RunFailure> {
    if options.threads == Some(0) {
        return Err(RunFailure::ZeroThreads);
    }
    match options.timing {
        Timing { repeat: 0, .. } => Err(RunFailure::ZeroRepeat),
        Timing {
            repeat,
            with_effects: true,
        } if repeat > 1 => Err(RunFailure::RepeatWithEffects(repeat)),
        _ => Ok(()),
    }
}

/// The pool the entries run on, and its number of threads: the one asked for, else one per
/// core.
fn worker_pool(threads: Option<usize>) -> Result<(rayon::ThreadPool, usize), RunFailure> {
    let threads =
        threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| RunFailure::Threads {
            threads,
            message: e.to_string(),
        })?;
    Ok((pool, threads))
}
