//! One `roamsim run` and one `roamsim merge` (SPEC §8): load the experiment, preprocess, run
//! every algorithm entry over the flight, write the outputs all-or-nothing. Not the experiment
//! file (`edge::experiment`), the output formats (`edge::output`), the shard file
//! (`edge::shard`) nor the frame loop (`sim::run`): this module puts them together.
//!
//! One job per file: `run_experiment.rs` plans a run and loops over its points; `shards.rs` runs
//! a shard and merges shards; `assemble.rs` writes the outputs; `point.rs` runs one point's
//! entries; `tune.rs` a tuned entry's probe runs; `run.rs` holds a run's terms (options,
//! outcome, failures); `timing.rs` the timing passes; `progress_sink.rs` what a run reports while
//! it goes. Each file imports only files listed after it: nothing calls back.
//!
//! **Entries side by side, results in order.** Every algorithm entry (sweep points included)
//! runs from its own fresh state on the shared preprocessed terrain, in parallel on a rayon pool
//! of `threads` threads; results are collected in the experiment's order, so the outputs do not
//! depend on the thread count (timings do: entries running side by side share the cores; use one
//! thread for timing comparisons).
//!
//! **Points one after another, committed together.** An experiment with a top-level sweep runs
//! its points one after another (one terrain in memory at a time), each into its own sub-folder,
//! then writes the sweep's own `summary.json`, `report.md` and plots at the top; the whole folder
//! is staged and moved into place only when every point has succeeded.

mod assemble;
mod point;
mod progress_sink;
mod run;
mod run_experiment;
mod shards;
mod timing;
mod tune;

pub use progress_sink::{
    LARGE_MESH_TRIANGLES, LONG_RUN_SECONDS, NoProgress, ProgressSink, large_work_notice,
};
pub use run::{RunFailure, RunOptions, RunOutcome};
pub use run_experiment::run_experiment;
pub use shards::{MergeOptions, merge_shards};
pub use timing::Timing;
