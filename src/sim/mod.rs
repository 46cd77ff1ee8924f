//! The simulation core: terrain, the 4-8 hierarchy, meshes, views and metrics, flights,
//! algorithms, the audit and statistics (SPEC §2–§9 and §12, the papers' algorithms).
//!
//! Nothing in here does IO or knows about clap, serde, plotters or wgpu: it takes values and
//! returns values, so it cannot fail for reasons outside the simulation. The only thing of the
//! outside world it touches is the clock, to time updates (and the parts of an update some
//! algorithms report apart, such as detail synthesis and strip construction). The edges
//! (`crate::edge`) read files, check experiments, and write tables and plots.

pub mod algorithm;
pub mod audit;
pub mod draw;
pub mod flight;
pub mod hierarchy;
pub mod mesh;
pub mod metrics;
pub mod run;
pub mod stats;
pub mod terrain;
pub mod tuning;
pub mod view;
pub mod zone;
