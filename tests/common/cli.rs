//! Running the `roamsim` binary from tests, as a user or a batch system does, and reading its
//! outputs back.

use std::path::Path;
use std::process::{Command, Output};

pub fn roamsim(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_roamsim"))
        .args(args)
        .current_dir(cwd)
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

/// frames.csv without its timing column.
pub fn frames_without_timing(path: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>());
    let header = lines.next().unwrap();
    let timing = header.iter().position(|c| c == "update_ns").unwrap();
    std::iter::once(header)
        .chain(lines)
        .map(|mut row| {
            row.remove(timing);
            row
        })
        .collect()
}
