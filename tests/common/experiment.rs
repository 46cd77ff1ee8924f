//! Writing experiment files for tests: the quickstart as a JSON value, edited and saved, and
//! loaded back.

use serde_json::Value;
use std::path::{Path, PathBuf};

pub fn repository() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The shipped quickstart experiment, with its terrain path made absolute so that the edited
/// copy can live anywhere.
pub fn quickstart() -> Value {
    let path = repository().join("experiments/quickstart.json");
    let mut value: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let data = repository().join("experiments/data/N48E009.hgt");
    value["terrain"]["file"]["path"] = Value::String(data.display().to_string());
    value
}

/// The quickstart shortened to `frames` frames.
pub fn short_quickstart(frames: u64) -> Value {
    let mut value = quickstart();
    value["flight"]["frames"] = frames.into();
    value
}

/// Saves an experiment as `<dir>/<name>.json`.
pub fn save(dir: &Path, name: &str, experiment: &Value) -> PathBuf {
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_string_pretty(experiment).unwrap()).unwrap();
    path
}

/// Loads the quickstart with its algorithms replaced by `algorithms`: the validated configs, or
/// the problems as `field: problem` lines.
pub fn load_with_algorithms(
    algorithms: Value,
) -> Result<Vec<roamsim::sim::algorithm::AlgorithmConfig>, Vec<String>> {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = quickstart();
    experiment["algorithms"] = algorithms;
    let path = save(dir.path(), "algorithms", &experiment);
    match roamsim::edge::experiment::load(&path) {
        Ok(loaded) => Ok(loaded
            .algorithms
            .into_iter()
            .map(|spec| spec.config)
            .collect()),
        Err(error) => Err(error
            .problems
            .iter()
            .map(|p| format!("{}: {}", p.field, p.problem))
            .collect()),
    }
}
