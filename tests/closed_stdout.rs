//! A reader that stops early (`roamsim info … | head`): a command whose stdout is a closed pipe
//! stops quietly, with exit status 141 (128 + SIGPIPE, src/main.rs) and nothing on stderr, never
//! a panic; a run has committed its outputs by then.

mod common;

use common::cli::{files, roamsim_into_closed_pipe};
use common::experiment::repository;
use std::process::Output;

/// 128 + SIGPIPE: what a shell shows for a program a closed pipe ended.
const CLOSED_STDOUT_STATUS: i32 = 141;

fn assert_quiet_stop(args: &[&str], output: &Output) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(
        output.status.code(),
        Some(CLOSED_STDOUT_STATUS),
        "roamsim {args:?}: {stderr}"
    );
    assert!(
        !stderr.contains("panicked") && !stderr.contains("error:"),
        "roamsim {args:?} said: {stderr}"
    );
}

#[test]
fn info_on_a_terrain_file_into_a_closed_pipe_stops_quietly() {
    let args = ["info", "experiments/data/N48E009.hgt"];
    let output = roamsim_into_closed_pipe(&args, &repository());
    assert_quiet_stop(&args, &output);
    assert!(output.stderr.is_empty(), "{:?}", output.stderr);
}

#[test]
fn info_on_an_experiment_into_a_closed_pipe_stops_quietly() {
    let args = ["info", "experiments/quickstart.json"];
    let output = roamsim_into_closed_pipe(&args, &repository());
    assert_quiet_stop(&args, &output);
    assert!(output.stderr.is_empty(), "{:?}", output.stderr);
}

#[test]
fn validate_into_a_closed_pipe_stops_quietly() {
    let args = ["validate", "experiments/quickstart.json"];
    let output = roamsim_into_closed_pipe(&args, &repository());
    assert_quiet_stop(&args, &output);
    assert!(output.stderr.is_empty(), "{:?}", output.stderr);
}

#[test]
fn a_run_into_a_closed_pipe_has_committed_its_outputs_when_it_stops() {
    let out = tempfile::tempdir().unwrap();
    let out_dir = out.path().join("qs");
    let out_arg = out_dir.to_str().unwrap();
    let args = [
        "run",
        "experiments/quickstart.json",
        "--frames",
        "3",
        "--threads",
        "2",
        "--out",
        out_arg,
    ];
    let output = roamsim_into_closed_pipe(&args, &repository());
    // Progress lines and warnings go to stderr; only the closed stdout ends the run.
    assert_quiet_stop(&args, &output);
    let written = files(&out_dir);
    for expected in ["frames.csv", "summary.json", "report.md"] {
        assert!(
            written.iter().any(|f| f.as_os_str() == expected),
            "{expected} missing from {written:?}"
        );
    }
    assert!(out_dir.join(".roamsim-output").exists(), "no manifest");
}
