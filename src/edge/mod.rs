//! The edges: everything that touches files, formats or the terminal. Experiment files
//! (`docs/experiment-format.md`), terrain readers, flight logs, one `roamsim run` and its shards
//! (`session`, `shard`; `docs/sharding.md`), the output writers and plots
//! (`docs/output-formats.md`), progress lines, the report `roamsim info` prints, and (with the
//! `preview` feature) the preview window and offscreen renderer.
//!
//! The edges depend on the core (`crate::sim`), never the reverse. No algorithm, metric or audit
//! lives here: the edges decide what goes into a run and how its results are written, not what
//! a frame computes.

pub mod experiment;
pub mod flight_log;
pub mod flight_motion;
pub mod info_command;
pub mod output;
#[cfg(feature = "preview")]
pub mod preview;
pub mod progress;
pub mod pyramid;
pub mod session;
pub mod shard;
pub mod terrain_info;
pub mod terrain_readers;
