//! The edges: everything that touches files or formats. Experiment files, terrain readers,
//! flight logs, output writers and plots, and (with the `preview` feature) the preview window
//! and offscreen renderer. The edges depend on the core (`crate::sim`), never
//! the reverse.

pub mod experiment;
pub mod flight_log;
pub mod output;
#[cfg(feature = "preview")]
pub mod preview;
pub mod progress;
pub mod session;
pub mod shard;
pub mod terrain_info;
pub mod terrain_readers;
