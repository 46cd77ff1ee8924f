//! The algorithm entries of an experiment checked (stage 2, no IO): each entry's `"sweep"`
//! expanded into entries, labels checked unique, `tune` and parameters checked, giving the
//! [`AlgorithmSpec`]s a run builds its algorithms from; and [`tuned_spec`], an entry with its
//! tuned parameter set to a value. Not the parameters' own rules (`parameters.rs`), not the
//! experiment's other fields (`check.rs`).
//!
//! **An entry's sweep is an entry per point.** `"sweep": {"tau_px": [1, 2]}` expands, by the
//! expansion rule of `sweep.rs`, into one entry per point, labelled with the entry's label and
//! its choice (`roam tau_px=1`), each checked like a written entry and run from its own fresh
//! state. `tune` cannot be swept, nor can the parameter it sets: the label would name a value
//! the run does not use.
//!
//! **A tuned value is checked again.** [`tuned_spec`] puts the value into the entry's parameters
//! as written and checks them again (`parameters.rs`'s `entry_config`), for every probe and for
//! the real run; the outputs list the parameters with the value found.

use super::format::AlgorithmEntry;
use super::parameters::entry_config;
use super::problems::{FieldProblem, Problems};
use super::sweep::{MAX_SWEEP_POINTS, cartesian, choice_label};
use super::tune::{Tune, check_tune, tuned_parameter};
use crate::sim::algorithm::AlgorithmConfig;
use serde_json::Value;
use std::collections::HashSet;

/// One algorithm entry: its label, configuration and the parameters as written.
#[derive(Clone)]
pub struct AlgorithmSpec {
    pub label: String,
    pub config: AlgorithmConfig,
    pub parameters: Value,
    /// The entry's `tune`: its parameter is set by a search over probe runs before it runs.
    pub tune: Option<Tune>,
}

/// An algorithm entry after sweep expansion: where it came from, for error paths.
struct ExpandedEntry {
    /// `algorithms[k]`, or `algorithms[k] (tau_px=0.5)` for a sweep point.
    origin: String,
    name: String,
    label: String,
    parameters: serde_json::Map<String, Value>,
}

/// Expands every entry's `"sweep": {"parameter": [values…], …}` into the cartesian product of
/// its lists (parameters in alphabetical order, the first one outermost); each point is an
/// entry whose label is the entry's label followed by ` parameter=value, …`.
fn expand_sweeps(entries: &[AlgorithmEntry], problems: &mut Problems) -> Vec<ExpandedEntry> {
    let mut expanded = Vec::new();
    for (k, entry) in entries.iter().enumerate() {
        let label = entry.label.clone().unwrap_or_else(|| entry.name.clone());
        let mut parameters = entry.parameters.clone();
        let Some(sweep) = parameters.remove("sweep") else {
            expanded.push(ExpandedEntry {
                origin: format!("algorithms[{k}]"),
                name: entry.name.clone(),
                label,
                parameters,
            });
            continue;
        };
        let Some(sweep) = sweep.as_object().filter(|s| !s.is_empty()) else {
            problems.add(
                format!("algorithms[{k}].sweep"),
                "expected a non-empty object of parameter lists, e.g. {\"tau_px\": [1, 2, 4]}",
            );
            continue;
        };
        let tuned = parameters
            .get("tune")
            .and_then(|tune| tuned_parameter(&entry.name, tune));
        let mut axes: Vec<(String, Vec<Value>)> = Vec::new();
        for (parameter, values) in sweep {
            if parameter == "tune" || Some(parameter.as_str()) == tuned {
                problems.add(
                    format!("algorithms[{k}].sweep.{parameter}"),
                    if parameter == "tune" {
                        "tune cannot be swept: expected one entry per target".to_string()
                    } else {
                        format!(
                            "the entry's tune sets {parameter}, so a sweep of it would run the \
                             value found, not the value in the label: expected it swept without \
                             tune, or tune without the sweep"
                        )
                    },
                );
                continue;
            }
            match values.as_array().filter(|v| !v.is_empty()) {
                Some(values) if !["name", "label", "sweep"].contains(&parameter.as_str()) => {
                    axes.push((parameter.clone(), values.clone()))
                }
                _ => problems.add(
                    format!("algorithms[{k}].sweep.{parameter}"),
                    "expected a non-empty list of values of an algorithm parameter",
                ),
            }
        }
        let points: usize = axes.iter().map(|(_, v)| v.len()).product();
        if points > MAX_SWEEP_POINTS {
            problems.add(
                format!("algorithms[{k}].sweep"),
                format!("{points} points: expected at most {MAX_SWEEP_POINTS}"),
            );
            continue;
        }
        for choice in cartesian(&axes) {
            let mut parameters = parameters.clone();
            for (parameter, value) in &choice {
                parameters.insert(parameter.clone(), value.clone());
            }
            let suffix = choice_label(&choice);
            expanded.push(ExpandedEntry {
                origin: format!("algorithms[{k}] ({suffix})"),
                name: entry.name.clone(),
                label: format!("{label} {suffix}"),
                parameters,
            });
        }
    }
    expanded
}

pub(super) fn check_algorithms(
    entries: &[AlgorithmEntry],
    audited: bool,
    problems: &mut Problems,
) -> Vec<AlgorithmSpec> {
    if entries.is_empty() {
        problems.add("algorithms", "empty: expected at least one algorithm");
    }
    let mut labels = HashSet::new();
    let mut specs = Vec::new();
    for entry in expand_sweeps(entries, problems) {
        let k = &entry.origin;
        let label = entry.label.clone();
        if label.is_empty() || label.contains(['\n', '\r']) {
            problems.add(
                format!("{k}.label"),
                format!("{label:?}: expected a non-empty, single-line label"),
            );
        } else if !labels.insert(label.clone()) {
            problems.add(
                format!("{k}.label"),
                format!(
                    "{label:?} is already used by an earlier entry: expected unique labels \
                     (give this entry a \"label\")"
                ),
            );
        }
        let mut written = entry.parameters.clone();
        let tune = written
            .remove("tune")
            .and_then(|tune| check_tune(k, &entry.name, &tune, &mut written, audited, problems));
        let parameters = Value::Object(written);
        let config = entry_config(k, &entry.name, &parameters, problems);
        if let Some(config) = config {
            specs.push(AlgorithmSpec {
                label,
                config,
                parameters,
                tune,
            });
        }
    }
    specs
}

/// The entry `spec` (tuned by `tune`) with its tuned parameter set to `value`: its configuration
/// and its parameters as listed in the outputs (vanek's `distance_scale` multiplies
/// `min_dist_m` and `max_dist_m`). An error, which a value inside the parameter's range does
/// not give, names the entry's field and what was wrong.
pub fn tuned_spec(spec: &AlgorithmSpec, tune: &Tune, value: f64) -> Result<AlgorithmSpec, String> {
    let mut parameters = spec.parameters.clone();
    let Some(map) = parameters.as_object_mut() else {
        return Err(format!("{}: expected an object of parameters", tune.origin));
    };
    if tune.parameter == "distance_scale" {
        for field in ["min_dist_m", "max_dist_m"] {
            let written = map.get(field).and_then(Value::as_f64).unwrap_or(0.0);
            map.insert(field.to_string(), Value::from(written * value));
        }
    } else {
        map.insert(tune.parameter.to_string(), Value::from(value));
    }
    let mut problems = Problems::default();
    let config = entry_config(&tune.origin, &tune.name, &parameters, &mut problems);
    match config {
        Some(config) if problems.list.is_empty() => Ok(AlgorithmSpec {
            label: spec.label.clone(),
            config,
            parameters,
            tune: spec.tune.clone(),
        }),
        _ => Err(problems
            .list
            .iter()
            .map(|FieldProblem { field, problem }| format!("{field}: {problem}"))
            .collect::<Vec<_>>()
            .join("; ")),
    }
}
