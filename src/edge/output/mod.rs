//! Output writers: `frames.csv`, `summary.json`, `report.md`, plots, exported meshes (PLY), and
//! the all-or-nothing output folder.

pub mod atomic_dir;
pub mod columns;
pub mod end_of_run;
pub mod frames_csv;
pub mod goal_check;
pub mod label_placement;
pub mod mesh_ply;
pub mod plots;
pub mod report_md;
pub mod run_plots;
pub mod summary_json;
pub mod sweep_outputs;
pub mod tuning;
pub mod warm_up;
