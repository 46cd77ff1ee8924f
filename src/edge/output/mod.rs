//! Output writers: `frames.csv`, `summary.json`, `report.md`, plots, exported meshes (PLY), the
//! top of a swept experiment's folder, the lines `roamsim run` prints at its end, and the
//! all-or-nothing output folder they go into. Every file's format is documented in
//! `docs/output-formats.md`.
//!
//! The writers see a run through its frame statistics, looked up by column name (`columns`), and
//! its measurements; their summaries and the Pareto front are the core's (`sim::stats`). What is
//! decided here is only what is reported: which frames a summary leaves out (`warm_up`) and
//! whether an entry held its count (`goal_check`). Nothing here changes what a run measured.

pub mod atomic_dir;
pub mod columns;
pub mod end_of_run;
pub mod flight_csv;
pub mod flight_map;
pub mod frames_csv;
pub mod goal_check;
pub mod label_placement;
pub mod mesh_ply;
pub mod plots;
pub mod report_md;
pub mod run_plots;
pub mod significant;
pub mod summary_json;
pub mod sweep_outputs;
pub mod tuned_experiment;
pub mod tuning;
pub mod warm_up;
