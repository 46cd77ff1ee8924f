//! `tuned-experiment.json`: what a run with tuned entries found, frozen into an experiment that
//! runs again without searching (`docs/output-formats.md`, "tuned-experiment.json";
//! `docs/experiment-format.md`, "Tuning to a target"). It builds the document; reading the
//! experiment file and writing the output are the session's (`edge::session::assemble`).
//!
//! **The experiment as it ran.** The point's document as written (a top-level sweep expanded
//! away: each sweep point writes its own, in its folder), with:
//!
//! - `algorithms` replaced by the entries as they ran: entry sweeps expanded, each entry with
//!   its label, its tuned parameter set to the value found (vanek's `distance_scale` already
//!   multiplied into `min_dist_m` and `max_dist_m`) and its `tune` removed. A value is written
//!   as JSON writes an `f64`, the shortest text that reads back to the same number, so the
//!   entry runs with the very value the run used;
//! - `flight.first_frames` set when the run flew fewer frames than the flight has (`--frames`):
//!   the flight stays the file's, so its derived rotation bound and every pose are the run's;
//! - `name` suffixed with `-tuned`, so that running it with the default `--out` does not replace
//!   the output it was written into;
//! - every file path rewritten so that it resolves from the folder the file is written in.
//!
//! **File paths: relative when they can be.** Every string field named `path` under `terrain`
//! and `flight` (a terrain file, a recorded flight log; a reader that adds a file names it
//! `path` too) is rewritten relative to the folder `tuned-experiment.json` is written in, so that
//! an output folder moved together with the experiment's data (a repository with its `out/` and
//! `experiments/data/`) still runs; where no relative path exists (another drive) it is
//! absolute. Either way it names the same file the run read. A run of it therefore reproduces
//! the run's counts exactly (`tests/tuning.rs`); its timings are a new measurement.

use serde_json::{Map, Value};
use std::path::{Component, Path, PathBuf};

/// The file's name in the output folder (or a sweep point's folder).
pub const TUNED_EXPERIMENT_FILE: &str = "tuned-experiment.json";

/// What the document is made from.
pub struct FrozenRun<'a> {
    /// The point's experiment document as written (without a top-level sweep).
    pub document: &'a Value,
    /// The entries as they ran: `name`, `label` and their parameters, tuned values written in.
    pub algorithms: Vec<Value>,
    /// The frames the run flew, when fewer than the flight has (`--frames`).
    pub first_frames: Option<u64>,
}

/// The tuned experiment: `run.document` with the entries as they ran, the frames limit, the
/// `-tuned` name and every file path passed through `rewrite_path`.
pub fn tuned_experiment(run: &FrozenRun, rewrite_path: &dyn Fn(&str) -> String) -> Value {
    let mut document = run.document.clone();
    let Some(top) = document.as_object_mut() else {
        return document;
    };
    if let Some(Value::String(name)) = top.get_mut("name") {
        name.push_str("-tuned");
    }
    top.insert("algorithms".into(), Value::Array(run.algorithms.clone()));
    for section in ["terrain", "flight"] {
        if let Some(value) = top.get_mut(section) {
            rewrite_paths(value, rewrite_path);
        }
    }
    if let Some(n_frames) = run.first_frames
        && let Some(Value::Object(flight)) = top.get_mut("flight")
    {
        flight.insert("first_frames".into(), n_frames.into());
    }
    document
}

/// One entry as it ran: `name`, `label` and `parameters` (an object) in one object.
pub fn entry_as_run(name: &str, label: &str, parameters: &Value) -> Value {
    let mut entry = parameters.as_object().cloned().unwrap_or_else(Map::new);
    entry.insert("name".into(), name.into());
    entry.insert("label".into(), label.into());
    Value::Object(entry)
}

/// Every string field named `path` in `value`, through `rewrite`.
fn rewrite_paths(value: &mut Value, rewrite: &dyn Fn(&str) -> String) {
    match value {
        Value::Object(map) => {
            for (key, field) in map.iter_mut() {
                match field {
                    Value::String(path) if key == "path" => *path = rewrite(path),
                    other => rewrite_paths(other, rewrite),
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(|v| rewrite_paths(v, rewrite)),
        _ => {}
    }
}

/// `target` relative to the folder `from`, both absolute and normalised (no `.` or `..`); `None`
/// when they share no root (another drive).
pub fn relative_path(from: &Path, target: &Path) -> Option<PathBuf> {
    let from: Vec<Component> = from.components().collect();
    let target: Vec<Component> = target.components().collect();
    if from.first() != target.first() {
        return None;
    }
    let common = from.iter().zip(&target).take_while(|(a, b)| a == b).count();
    let mut relative = PathBuf::new();
    for _ in common..from.len() {
        relative.push("..");
    }
    for part in &target[common..] {
        relative.push(part.as_os_str());
    }
    Some(relative)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn the_document_gets_the_entries_as_run_the_frames_limit_and_rewritten_paths() {
        let document = json!({
            "name": "alps",
            "terrain": {"file": {"path": "data/alps.png", "format": "png"}},
            "flight": {"frames": 400, "path": {"recorded": {"path": "logs/eye.csv"}}},
            "algorithms": [{"name": "wu", "tune": {"audit_p95_px": 1}, "sweep": {"zone": ["paper"]}}],
            "outputs": {"plots": false}
        });
        let algorithms = vec![entry_as_run(
            "wu",
            "wu zone=paper",
            &json!({"zone": "paper", "tau_px": 2.5}),
        )];
        let run = FrozenRun {
            document: &document,
            algorithms,
            first_frames: Some(40),
        };
        let tuned = tuned_experiment(&run, &|p| format!("../../{p}"));
        assert_eq!(
            tuned,
            json!({
                "name": "alps-tuned",
                "terrain": {"file": {"path": "../../data/alps.png", "format": "png"}},
                "flight": {"frames": 400, "first_frames": 40,
                           "path": {"recorded": {"path": "../../logs/eye.csv"}}},
                "algorithms": [{"name": "wu", "label": "wu zone=paper", "zone": "paper", "tau_px": 2.5}],
                "outputs": {"plots": false}
            })
        );
    }

    #[test]
    fn a_path_is_made_relative_to_the_output_folder() {
        let relative = |from: &str, to: &str| {
            relative_path(Path::new(from), Path::new(to)).map(|p| p.display().to_string())
        };
        assert_eq!(
            relative("/repo/out/run", "/repo/experiments/data/a.hgt").as_deref(),
            Some("../../experiments/data/a.hgt")
        );
        assert_eq!(
            relative("/repo/out/run/point=1", "/repo/out/run/point=1/a.png").as_deref(),
            Some("a.png")
        );
        assert_eq!(relative("/", "/a.png").as_deref(), Some("a.png"));
    }
}
