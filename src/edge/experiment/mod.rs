//! Experiment files (SPEC §8): from the file's bytes to a runnable [`Experiment`], in stages that
//! never call back. Not the running of an experiment (`edge::session`) nor its outputs
//! (`edge::output`). The format is documented in `docs/experiment-format.md`.
//!
//! **Parsed data, then checked configuration, then the loaded experiment** (ripgrep's
//! low-level and high-level arguments). Each stage imports only the ones before it:
//!
//! 1. *Parse*: `format.rs` is the file as written (serde types, format version 1); `sweep.rs`
//!    expands a top-level sweep into one JSON document per point, knowing nothing of the fields.
//! 2. *Check* (no IO), bottom up: `problems.rs` (what can be wrong, with its field path);
//!    `block_lod.rs`, `block_strips.rs` and `parameters.rs` (one entry's parameters into its
//!    `AlgorithmConfig`); `tune.rs` (an entry's `"tune"`); `entries.rs` (the entries: sweeps
//!    expanded, labels, [`AlgorithmSpec`], [`tuned_spec`]); `check.rs` (the whole file).
//! 3. *Load* (the IO): `terrain_size.rs` first refuses a terrain the run cannot hold, from its
//!    declared layout or its header; `load.rs` reads or generates the terrain, reads a recorded
//!    flight, builds the flight: the [`Experiment`].
//!
//! `terrain_alone.rs` runs stages 1 to 3 on a terrain entry alone (`roamsim info`'s options).
//! `plan.rs` drives them: stages 1 and 2 for every point of the file at once ([`plan`], so every
//! problem of every point is reported before any terrain is read), stage 3 for one point at a
//! time ([`Plan::load_point`]). Nothing runs before all three have passed for a point. This file
//! only declares the stages and re-exports what the rest of the crate uses.

mod block_lod;
mod block_strips;
mod check;
mod entries;
mod format;
mod load;
mod parameters;
mod plan;
mod problems;
mod sweep;
mod terrain_alone;
mod terrain_pyramid;
mod terrain_size;
mod tune;

pub use check::MeshExports;
pub use entries::{AlgorithmSpec, tuned_spec};
pub use format::FORMAT_VERSION;
pub use load::{BoundOrigin, Experiment, TerrainReport};
pub use parameters::KNOWN_ALGORITHMS;
pub use plan::{Plan, check_bytes, load, plan};
pub use problems::{ExperimentError, FieldProblem};
pub use sweep::{SweepChoice, choice_label, point_document};
pub use terrain_alone::{ASSUMED_SPACING_M, load_terrain_file};
pub use tune::{Tune, TuneTarget};
