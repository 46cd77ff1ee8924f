//! Running the `roamsim` binary from tests, as a user or a batch system does, and reading its
//! outputs back.

use roamsim::edge::output::columns::TIMING_COLUMNS;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn roamsim(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_roamsim"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the roamsim binary runs")
}

/// Runs the binary with its stdout a pipe whose reader has already gone (`roamsim … | head`
/// after `head` has quit): its first write to stdout fails with a broken pipe.
pub fn roamsim_into_closed_pipe(args: &[&str], cwd: &Path) -> Output {
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    Command::new(env!("CARGO_BIN_EXE_roamsim"))
        .args(args)
        .current_dir(cwd)
        .stdout(writer)
        .output()
        .expect("the roamsim binary runs")
}

pub fn succeeds(args: &[&str], cwd: &Path) {
    let output = roamsim(args, cwd);
    assert!(
        output.status.success(),
        "roamsim {args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

pub fn fails_with(args: &[&str], cwd: &Path, expected: &[&str]) {
    let output = roamsim(args, cwd);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "roamsim {args:?} succeeded");
    for part in expected {
        assert!(
            stderr.contains(part),
            "roamsim {args:?}: {stderr:?} lacks {part:?}"
        );
    }
}

/// frames.csv without its timing columns (`TIMING_COLUMNS`).
pub fn frames_without_timing(path: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>());
    let header = lines.next().unwrap();
    let kept: Vec<usize> = (0..header.len())
        .filter(|&k| !TIMING_COLUMNS.contains(&header[k].as_str()))
        .collect();
    std::iter::once(header)
        .chain(lines)
        .map(|row| kept.iter().map(|&k| row[k].clone()).collect())
        .collect()
}

/// Every file under `dir` (relative paths, sorted), the manifest left out.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    fn walk(root: &Path, at: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(at).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(root, &path, out);
            } else if entry.file_name() != ".roamsim-output" {
                out.push(path.strip_prefix(root).unwrap().to_path_buf());
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, &mut out);
    out.sort();
    out
}

/// summary.json with the fields that are timings or run metadata removed.
pub fn summary_without_timing(path: &Path) -> Value {
    fn strip(value: &mut Value) {
        match value {
            Value::Object(map) => {
                map.retain(|key, _| {
                    !(key == "run"
                        || key.contains("_ns")
                        || key.contains("seconds")
                        || key.contains("_us"))
                });
                map.values_mut().for_each(strip);
            }
            Value::Array(items) => items.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut value: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    strip(&mut value);
    value
}
