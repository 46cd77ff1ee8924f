//! What can be wrong with an experiment file: one problem with its field path
//! ([`FieldProblem`]), a file's whole list ([`ExperimentError`]), the collector every check adds
//! to, and the decoding of a JSON value into a format type with the field path of a type error.
//! The bottom of the configuration's stages: it imports none of them, and knows nothing of what
//! the fields mean.
//!
//! **Every problem at once, each with its field path.** Checking collects every semantic problem
//! (`view.fovy_deg`, `algorithms[1].tau_px`, `(terrain.synthetic.level=12) flight.frames` for a
//! sweep point) with what was expected, rather than stopping at the first; reading the terrain
//! or a flight log stops at the first.

use serde_json::Value;
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

/// The problems found so far, in the order found: every check adds to one collector, so that a
/// file's problems are all reported at once.
#[derive(Default)]
pub(super) struct Problems {
    pub(super) list: Vec<FieldProblem>,
}

impl Problems {
    pub(super) fn add(&mut self, field: impl Into<String>, problem: impl Into<String>) {
        self.list.push(FieldProblem {
            field: field.into(),
            problem: problem.into(),
        });
    }

    pub(super) fn positive(&mut self, field: &str, value: f64) {
        if !(value > 0.0 && value.is_finite()) {
            self.add(field, format!("{value}: expected a finite number above 0"));
        }
    }

    pub(super) fn non_negative(&mut self, field: &str, value: f64) {
        if !(value >= 0.0 && value.is_finite()) {
            self.add(
                field,
                format!("{value}: expected a finite number of at least 0"),
            );
        }
    }

    pub(super) fn finite(&mut self, field: &str, values: &[f64]) {
        if values.iter().any(|v| !v.is_finite()) {
            self.add(field, format!("{values:?}: expected finite numbers"));
        }
    }

    pub(super) fn positive_int(&mut self, field: &str, value: u32) {
        if value == 0 {
            self.add(field, "0: expected at least 1");
        }
    }
}

/// `parameters` (at `origin`) as `T`, or `None` with serde's problem added at its field path.
pub(super) fn decode<T: serde::de::DeserializeOwned>(
    origin: &str,
    parameters: &Value,
    problems: &mut Problems,
) -> Option<T> {
    serde_path_to_error::deserialize(parameters)
        .map_err(|error| {
            let inner = error.path().to_string();
            let field = if inner == "." {
                origin.to_string()
            } else {
                format!("{origin}.{inner}")
            };
            problems.add(field, error.into_inner().to_string());
        })
        .ok()
}
