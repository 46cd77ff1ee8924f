//! The edges: everything that touches files or formats. Experiment files, terrain readers,
//! flight logs, output writers and plots. The edges depend on the core (`crate::sim`), never
//! the reverse.

pub mod experiment;
pub mod flight_log;
pub mod output;
pub mod session;
pub mod terrain_readers;
