//! A researcher's quick probes and what a run tells them (issue #19): `--frames`, the lines a
//! run prints at its end and while it runs without a terminal, warm-up frames left out of the
//! summaries, flights that hold a clearance above the ground and eyes below it, and sweep
//! folders that keep field names as written.

mod common;

use common::experiment::save;
use serde_json::{Value, json};
use std::path::Path;
use std::process::Command;

/// A small synthetic scene flown through waypoints: 30 frames, three entries, audited.
fn waypoint_scene() -> Value {
    json!({
        "format_version": 1,
        "name": "probe",
        "terrain": {"synthetic": {"level": 6, "seed": 3, "amplitude_m": 40, "roughness": 0.5,
                                  "spacing_m": {"dx": 10, "dy": 10}}},
        "view": {"width_px": 200, "height_px": 200, "fovy_deg": 60, "near_m": 1, "far_m": 5000},
        "speed_bounds": {"horizontal_m_per_frame": 10, "vertical_m_per_frame": 5},
        "flight": {"look": {"fixed": {"yaw_deg": 45, "pitch_deg": -20}},
                   "path": {"waypoints": {"interpolation": "linear", "points": [
                       {"frame": 0, "position_m": [100, 100, 200]},
                       {"frame": 29, "position_m": [300, 300, 200]}]}}},
        "algorithms": [
            {"name": "wu", "budget_triangles": 300, "tau_px": 2},
            {"name": "roam", "target_triangles": 300},
            {"name": "reference", "tau_px": 2}
        ],
        "effects": {"audit": {"stride": 2}, "culling": true}
    })
}

fn roamsim(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_roamsim"))
        .args(args)
        .output()
        .unwrap()
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn frames_shortens_a_waypoint_flight_to_its_first_frames() {
    let dir = tempfile::tempdir().unwrap();
    let path = save(dir.path(), "probe", &waypoint_scene());
    let full = dir.path().join("full");
    let short = dir.path().join("short");
    let run = |out: &Path, extra: &[&str]| {
        let mut args = vec!["run", path.to_str().unwrap(), "--out", out.to_str().unwrap()];
        args.extend_from_slice(&["--threads", "1"]);
        args.extend_from_slice(extra);
        let output = roamsim(&args);
        assert!(output.status.success(), "{output:?}");
        output
    };
    run(&full, &[]);
    run(&short, &["--frames", "7"]);
    let csv = |out: &Path| std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let (full_csv, short_csv) = (csv(&full), csv(&short));
    assert_eq!(short_csv.lines().count(), 1 + 3 * 7);
    // The first frames are the full run's, count for count (timings aside).
    let counts = |line: &str| -> String {
        line.split(',').take(8).collect::<Vec<_>>().join(",")
    };
    let full_rows: Vec<String> = full_csv
        .lines()
        .filter(|l| {
            l.split(',')
                .nth(1)
                .and_then(|f| f.parse::<u64>().ok())
                .is_some_and(|f| f < 7)
        })
        .map(counts)
        .collect();
    let short_rows: Vec<String> = short_csv.lines().skip(1).map(counts).collect();
    assert_eq!(full_rows, short_rows);
    let summary = read_json(&short.join("summary.json"));
    assert_eq!(summary["flight"]["frames"], 7);
    assert_eq!(summary["flight"]["frames_in_file"], 30);
}

#[test]
fn frames_zero_is_refused_by_the_command_line() {
    let output = roamsim(&["run", "x.json", "--frames", "0"]);
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("--frames"));
}

#[test]
fn a_run_prints_each_entrys_figures_and_where_the_files_are_and_progress_without_a_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let path = save(dir.path(), "probe", &waypoint_scene());
    let out = dir.path().join("out");
    let output = roamsim(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--frames",
        "5",
    ]);
    assert!(output.status.success(), "{output:?}");
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(stdout.contains("error max / mean / p95 (px)"), "{stdout}");
    for label in ["wu", "roam", "reference"] {
        assert!(
            stdout.lines().any(|l| l.trim_start().starts_with(label)),
            "{label} missing: {stdout}"
        );
    }
    assert!(stdout.contains("report.md"), "{stdout}");
    // stderr is a pipe here, not a terminal: plain progress lines, the last one at 100 %.
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(
        stderr.contains("progress: 15/15 frames (100%), 3/3 entries done"),
        "{stderr}"
    );
}
