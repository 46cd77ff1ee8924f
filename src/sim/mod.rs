//! The simulation core: terrain, the 4-8 hierarchy, meshes, views and metrics, flights,
//! algorithms, the audit and statistics.
//!
//! Nothing in here does IO or knows about clap, serde, plotters or wgpu: it takes values and
//! returns values, so it cannot fail for reasons outside the simulation. The edges
//! (`crate::edge`) read files, validate experiments, and write tables and plots.

pub mod algorithm;
pub mod audit;
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
