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
        let mut args = vec![
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
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
    let counts = |line: &str| -> String { line.split(',').take(8).collect::<Vec<_>>().join(",") };
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
    assert!(
        stdout.contains("error max / mean / mean of p95 (px)"),
        "{stdout}"
    );
    for label in ["wu", "roam", "reference"] {
        assert!(
            stdout.lines().any(|l| l.trim_start().starts_with(label)),
            "{label} missing: {stdout}"
        );
    }
    assert!(stdout.contains("report.md"), "{stdout}");
    // stderr is a pipe here, not a terminal: plain progress lines, the last one at 100 %. The
    // audit is on, so each entry's 5 frames are flown twice (the timing pass): 30 frames.
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(
        stderr.contains("progress: 30/30 frames (100%), 3/3 entries done"),
        "{stderr}"
    );
}

fn run_quietly(path: &Path, out: &Path) -> Result<(), String> {
    let options = roamsim::edge::session::RunOptions {
        out_dir: Some(out.to_path_buf()),
        check_meshes: false,
        threads: Some(1),
        max_frames: None,
        command_line: None,
        shard: None,
        timing: Default::default(),
    };
    roamsim::edge::session::run_experiment(path, &options, &roamsim::edge::session::NoProgress)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

#[test]
fn warm_up_frames_are_left_out_of_the_summaries_and_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = waypoint_scene();
    scene["outputs"] = json!({"warm_up_frames": 10, "plots": false});
    let path = save(dir.path(), "warm", &scene);
    let out = dir.path().join("out");
    run_quietly(&path, &out).unwrap();
    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["flight"]["warm_up_frames"], 10);
    let roam = &summary["algorithms"][1];
    assert_eq!(roam["frames"], 30);
    assert_eq!(roam["frames_summarised"], 20);
    // The mean of triangles is over frames 10 to 29 of frames.csv.
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let triangles: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|c| c[0] == "roam" && c[1].parse::<u64>().unwrap() >= 10)
        .map(|c| c[2].parse().unwrap())
        .collect();
    assert_eq!(triangles.len(), 20);
    let mean = triangles.iter().sum::<f64>() / 20.0;
    let summarised = roam["columns"]["triangles"]["mean"].as_f64().unwrap();
    assert!(
        (summarised - mean).abs() < 1e-9,
        "{summarised} against {mean}"
    );
    assert_eq!(
        csv.lines().count(),
        1 + 3 * 30,
        "frames.csv keeps every frame"
    );
    assert_eq!(roam["settling"]["column"], "triangles");
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("The first 10 frames (0 to 9) are left out"),
        "{report}"
    );
}

#[test]
fn a_warm_up_as_long_as_the_flight_is_refused_with_the_field_named() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = waypoint_scene();
    scene["outputs"] = json!({"warm_up_frames": 30});
    let path = save(dir.path(), "long-warm", &scene);
    let error = run_quietly(&path, &dir.path().join("out")).unwrap_err();
    assert!(
        error.contains("outputs.warm_up_frames: 30 leaves no frame"),
        "{error}"
    );
    // --frames shortening below the warm-up says so.
    scene["outputs"] = json!({"warm_up_frames": 10});
    let path = save(dir.path(), "short-warm", &scene);
    let output = roamsim(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        dir.path().join("out2").to_str().unwrap(),
        "--frames",
        "5",
    ]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("shortened by --frames from 30"), "{stderr}");
}

#[test]
fn the_report_says_when_a_target_entry_had_not_settled() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = waypoint_scene();
    // A target far beyond what this terrain can give: never within 10 %.
    scene["algorithms"] = json!([{"name": "roam", "target_triangles": 1000000}]);
    scene["outputs"] = json!({"plots": false});
    let path = save(dir.path(), "unsettled", &scene);
    let out = dir.path().join("out");
    run_quietly(&path, &out).unwrap();
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains(
            "**Not settled:** roam never came within 10 % of its target (1000000 triangles)"
        ),
        "{report}"
    );
}

#[test]
fn sweep_folders_keep_the_field_names_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = waypoint_scene();
    scene["sweep"] = json!({"terrain.synthetic.amplitude_m": [30]});
    scene["outputs"] = json!({"plots": false});
    let path = save(dir.path(), "swept", &scene);
    let out = dir.path().join("out");
    run_quietly(&path, &out).unwrap();
    assert!(
        out.join("terrain.synthetic.amplitude_m=30/report.md")
            .exists(),
        "{:?}",
        std::fs::read_dir(&out).unwrap().collect::<Vec<_>>()
    );
}

/// A low straight flight across the scene's terrain: heights 0 to about 40 m.
fn low_line(altitude: Option<&str>, z: f64) -> Value {
    let mut scene = waypoint_scene();
    scene["flight"] = json!({"frames": 40, "look": {"fixed": {"yaw_deg": 0, "pitch_deg": -10}},
                             "path": {"line": {"from_m": [20, 320, z], "to_m": [620, 300, z]}}});
    if let Some(altitude) = altitude {
        scene["flight"]["altitude"] = json!(altitude);
    }
    scene["outputs"] = json!({"plots": false});
    scene
}

#[test]
fn frames_with_the_eye_below_the_ground_are_reported() {
    let dir = tempfile::tempdir().unwrap();
    let field = roamsim::edge::experiment::load(&save(dir.path(), "probe", &low_line(None, 0.0)))
        .unwrap()
        .field;
    let (lo, hi) = field.height_range();
    // At the mean height the line must cross the relief somewhere.
    let path = save(dir.path(), "low", &low_line(None, f64::from(lo + hi) / 2.0));
    let experiment = roamsim::edge::experiment::load(&path).unwrap();
    let below = experiment.below_ground_frames.clone();
    assert!(!below.is_empty() && below.len() < 40, "{below:?}");
    for frame in 0..40 {
        let eye = experiment.flight.pose(frame).position;
        let ground = experiment.field.ground_height(eye.truncate());
        assert_eq!(below.contains(&frame), eye.z < ground, "frame {frame}");
    }
    let out = dir.path().join("out");
    run_quietly(&path, &out).unwrap();
    let summary = read_json(&out.join("summary.json"));
    assert_eq!(summary["flight"]["eye_below_ground_count"], below.len());
    assert_eq!(summary["flight"]["eye_below_ground_frames"][0], below[0]);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains(&format!(
        "**Eye below the ground** in {} frame(s)",
        below.len()
    )));
    let validate = roamsim(&["validate", path.to_str().unwrap()]);
    assert!(
        String::from_utf8_lossy(&validate.stdout).contains("the eye is below the ground in"),
        "{validate:?}"
    );
}

#[test]
fn an_above_ground_flight_holds_its_clearance_over_the_relief() {
    let dir = tempfile::tempdir().unwrap();
    let path = save(dir.path(), "clear", &low_line(Some("above_ground"), 15.0));
    let experiment = roamsim::edge::experiment::load(&path).unwrap();
    assert!(experiment.below_ground_frames.is_empty());
    let mut heights = Vec::new();
    for frame in 0..40 {
        let eye = experiment.flight.pose(frame).position;
        let clearance = eye.z - experiment.field.ground_height(eye.truncate());
        assert!(
            (clearance - 15.0).abs() < 1e-9,
            "frame {frame}: {clearance}"
        );
        heights.push(eye.z);
    }
    // It follows the ground: its world height is not constant.
    assert!(
        heights.iter().any(|&z| (z - heights[0]).abs() > 1.0),
        "{heights:?}"
    );
    // Absolute (the default) is today's behaviour: z as written.
    let absolute = save(dir.path(), "abs", &low_line(Some("absolute"), 15.0));
    let experiment = roamsim::edge::experiment::load(&absolute).unwrap();
    assert_eq!(experiment.flight.pose(7).position.z, 15.0);
}

#[test]
fn a_recorded_flight_cannot_be_flown_above_the_ground() {
    let mut scene = waypoint_scene();
    scene["flight"] =
        json!({"path": {"recorded": {"path": "log.csv"}}, "altitude": "above_ground"});
    let error = roamsim::edge::experiment::check_bytes(
        Path::new("recorded.json"),
        scene.to_string().as_bytes(),
    )
    .unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains(
            "recorded.json: flight.altitude: a recorded flight brings its own world heights"
        ),
        "{text}"
    );
}

#[test]
fn the_report_says_what_its_p95_is_and_marks_from_scratch_operation_counts() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = waypoint_scene();
    scene["outputs"] = json!({"plots": false});
    let path = save(dir.path(), "words", &scene);
    let out = dir.path().join("out");
    run_quietly(&path, &out).unwrap();
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("| error max / mean / mean of p95 (px) |"),
        "{report}"
    );
    let row = |label: &str| {
        report
            .lines()
            .find(|l| l.starts_with(&format!("| {label} | ")))
            .unwrap()
            .to_string()
    };
    assert!(row("reference").contains(" †"), "{}", row("reference"));
    assert!(!row("wu").contains('†'), "{}", row("wu"));
    assert!(!row("roam").contains('†'), "{}", row("roam"));
    assert!(report.contains("not comparable with an incremental algorithm's"));
    // Wu's b in frames of travel, and beside it in metres (× the 10 m horizontal bound).
    let summary = read_json(&out.join("summary.json"));
    let columns = &summary["algorithms"][0]["columns"];
    for stat in ["mean", "p50", "p95", "max"] {
        let frames = columns["base_b"][stat].as_f64().unwrap();
        let metres = columns["base_b_m"][stat].as_f64().unwrap();
        assert_eq!(metres, frames * 10.0, "{stat}");
    }
}

#[cfg(not(feature = "preview"))]
#[test]
fn render_and_preview_without_the_feature_say_how_to_get_them() {
    for command in ["render", "preview"] {
        let output = roamsim(&[command, "x.json", "--frames", "0", "--out", "o"]);
        assert!(!output.status.success());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains("--features preview"), "{stderr}");
        assert!(!stderr.contains("unrecognized subcommand"), "{stderr}");
    }
}
