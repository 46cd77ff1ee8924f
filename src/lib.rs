//! roamsim: a simulator of view-dependent terrain level-of-detail algorithms.
//!
//! It replays camera flights over height fields, runs Wu et al.'s life-axis split/merge queues
//! beside baselines on exactly the same views, and reports what each algorithm did, what it
//! cost and how accurate its mesh really was. See `ARCHITECTURE.md` for the map.

pub mod edge;
pub mod sim;
