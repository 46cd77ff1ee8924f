//! roamsim: a simulator of view-dependent terrain level-of-detail algorithms (SPEC §1).
//!
//! It replays camera flights over height fields, runs Wu et al.'s life-axis split/merge queues
//! beside baselines on exactly the same views, and reports what each algorithm did, what it
//! cost and how accurate its mesh really was. [`sim`] is the pure simulation core, which does no
//! IO; [`edge`] reads and writes files and depends on the core, never the reverse; the command
//! line is the binary's (`src/main.rs`). See `ARCHITECTURE.md` for the map.

pub mod edge;
pub mod sim;
