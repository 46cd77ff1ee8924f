//! Output writers: `frames.csv`, `summary.json`, plots, and the all-or-nothing output folder.

pub mod plots;
