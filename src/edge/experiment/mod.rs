//! Experiment files: parse (what the file says), check (is it meaningful? `check.rs`), load
//! (terrain read and preprocessed inputs, flight built and checked against the speed bounds:
//! `load.rs`), and the plan of a swept experiment's points (`plan.rs`).
//!
//! Every error names the file, the field path (`flight.path.circle.radius_m`,
//! `algorithms[1].tau_px`) and what was expected. Checking reports every semantic problem at
//! once; reading the terrain or a flight log stops at the first. Nothing runs before all of this
//! has passed. The format is documented in `docs/experiment-format.md`.

mod block_lod;
mod check;
mod format;
mod load;
mod plan;
mod sweep;
mod tune;

pub use check::KNOWN_ALGORITHMS;
pub use format::FORMAT_VERSION;
pub use load::{AlgorithmSpec, Experiment, MeshExports, TerrainReport};
pub use plan::{Plan, check_bytes, load, plan};
pub use sweep::{SweepChoice, choice_label};
pub use tune::{Tune, TuneTarget, tuned_spec};

use std::fmt;
use std::path::PathBuf;

/// One thing wrong with an experiment file.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldProblem {
    /// Path of the field, e.g. `view.fovy_deg` or `algorithms[0].label`; empty for the file.
    pub field: String,
    pub problem: String,
}

/// An experiment file that cannot run, with everything found wrong in it.
#[derive(Clone, Debug, PartialEq)]
pub struct ExperimentError {
    pub file: PathBuf,
    pub problems: Vec<FieldProblem>,
}

impl ExperimentError {
    pub(crate) fn single(
        file: &std::path::Path,
        field: impl Into<String>,
        problem: impl Into<String>,
    ) -> ExperimentError {
        ExperimentError {
            file: file.to_path_buf(),
            problems: vec![FieldProblem {
                field: field.into(),
                problem: problem.into(),
            }],
        }
    }
}

impl fmt::Display for ExperimentError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, p) in self.problems.iter().enumerate() {
            if k > 0 {
                writeln!(f)?;
            }
            if p.field.is_empty() {
                write!(f, "{}: {}", self.file.display(), p.problem)?;
            } else {
                write!(f, "{}: {}: {}", self.file.display(), p.field, p.problem)?;
            }
        }
        Ok(())
    }
}

impl std::error::Error for ExperimentError {}
