//! Flights that break the experiment's speed bounds (SPEC §8): teleports, too-fast segments
//! (horizontal or vertical) and non-finite poses, from the experiment file to the outputs.
//! Violations are reported with their frame numbers before anything runs and in
//! `summary.json`; the algorithms that defer on the strength of the bounds revalidate at exactly
//! those frames; a NaN pose is refused before the run with an error naming its frame or line.
//!
//! What a revalidation does inside Wu and ROAM is tested in `tests/wu.rs` and `tests/roam.rs`.

mod common;

use roamsim::edge::experiment::{BoundOrigin, load};
use roamsim::edge::session::{NoProgress, RunOptions, run_experiment};
use roamsim::sim::flight::largest_turn;
use serde_json::{Value, json};
use std::path::Path;

/// A small synthetic experiment whose flight is `flight`; `wu` and `roam` with deferral.
fn experiment(flight: Value) -> Value {
    json!({
        "format_version": 1,
        "name": "speed",
        "terrain": { "synthetic": { "level": 6, "seed": 3, "amplitude_m": 60, "roughness": 0.7,
                                    "spacing_m": { "dx": 20, "dy": 20 } } },
        "view": { "width_px": 600, "height_px": 600, "fovy_deg": 60, "near_m": 1, "far_m": 100000 },
        "speed_bounds": { "horizontal_m_per_frame": 40, "vertical_m_per_frame": 20 },
        "flight": flight,
        "algorithms": [
            { "name": "wu", "label": "wu", "tau_px": 2 },
            { "name": "roam", "label": "roam deferral", "tau_px": 2, "deferral": true }
        ],
        "effects": {},
        "outputs": { "plots": false }
    })
}

/// A recorded log: one line per frame (x, y, z), looking east and down, never turning.
fn log(positions: &[(f64, f64, f64)]) -> String {
    let mut text = String::from("frame,x_m,y_m,z_m,yaw_deg,pitch_deg\n");
    for (frame, (x, y, z)) in positions.iter().enumerate() {
        text.push_str(&format!("{frame},{x},{y},{z},0,-20\n"));
    }
    text
}

/// Ten frames 1 m apart, a 1 km teleport at frame 5, a 100 m climb at frame 8.
fn teleport_and_climb() -> Vec<(f64, f64, f64)> {
    (0..10)
        .map(|f| {
            let x = 300.0 + f as f64 + if f >= 5 { 1000.0 } else { 0.0 };
            let z = 200.0 + if f >= 8 { 100.0 } else { 0.0 };
            (x, 600.0, z)
        })
        .collect()
}

fn save_with_log(dir: &Path, positions: &[(f64, f64, f64)]) -> std::path::PathBuf {
    std::fs::write(dir.join("log.csv"), log(positions)).unwrap();
    let flight = json!({ "path": { "recorded": { "path": "log.csv" } } });
    common::experiment::save(dir, "speed", &experiment(flight))
}

#[test]
fn a_teleport_and_a_too_fast_climb_are_reported_with_their_frames_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let loaded = load(&save_with_log(dir.path(), &teleport_and_climb())).unwrap();
    let reported: Vec<(u64, f64, f64)> = loaded
        .violations
        .iter()
        .map(|v| (v.frame, v.horizontal, v.vertical))
        .collect();
    assert_eq!(reported, vec![(5, 1001.0, 0.0), (8, 1.0, 100.0)]);
}

#[test]
fn a_too_fast_line_is_reported_at_every_frame() {
    // 10 km in 100 frames: 101 m a frame against a bound of 40.
    let dir = tempfile::tempdir().unwrap();
    let flight = json!({
        "frames": 100,
        "look": { "fixed": { "yaw_deg": 0, "pitch_deg": -20 } },
        "path": { "line": { "from_m": [0, 600, 300], "to_m": [10000, 600, 300] } }
    });
    let path = common::experiment::save(dir.path(), "line", &experiment(flight));
    let frames: Vec<u64> = load(&path)
        .unwrap()
        .violations
        .iter()
        .map(|v| v.frame)
        .collect();
    assert_eq!(frames, (1..100).collect::<Vec<u64>>());
}

#[test]
fn a_run_lists_the_violations_and_roam_revalidates_exactly_there() {
    let dir = tempfile::tempdir().unwrap();
    let path = save_with_log(dir.path(), &teleport_and_climb());
    let out = dir.path().join("out");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        check_meshes: true,
        threads: Some(1),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    let outcome = run_experiment(&path, &options, &NoProgress).unwrap();
    assert_eq!(outcome.speed_violation_frames, vec![5, 8]);

    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let run = &summary["flight"];
    assert_eq!(run["speed_violation_count"], 2);
    let listed: Vec<u64> = run["speed_violations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["frame"].as_u64().unwrap())
        .collect();
    assert_eq!(listed, vec![5, 8]);

    // ROAM's deferral recomputes every priority at the first frame and at each violation, and
    // nowhere else (the camera never turns).
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let (label, frame, revalidations) = (
        column("algorithm"),
        column("frame"),
        column("revalidations"),
    );
    let revalidated: Vec<u64> = lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|row| row[label] == "roam deferral" && row[revalidations] == "1")
        .map(|row| row[frame].parse().unwrap())
        .collect();
    assert_eq!(revalidated, vec![0, 5, 8]);
}

#[test]
fn a_nan_pose_is_refused_before_the_run_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = log(&teleport_and_climb());
    text = text.replace("3,303,600,200,0,-20", "3,303,NaN,200,0,-20");
    std::fs::write(dir.path().join("log.csv"), text).unwrap();
    let flight = json!({ "path": { "recorded": { "path": "log.csv" } } });
    let path = common::experiment::save(dir.path(), "nan", &experiment(flight));
    let error = load(&path)
        .err()
        .expect("a NaN pose is refused")
        .to_string();
    assert!(
        error.contains("log.csv, line 5")
            && error.contains("y_m \"NaN\": expected a finite number"),
        "{error}"
    );
    let out = dir.path().join("out");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        check_meshes: false,
        threads: Some(1),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    assert!(run_experiment(&path, &options, &NoProgress).is_err());
    assert!(
        !out.exists(),
        "nothing may be written for a refused experiment"
    );
}

#[test]
fn a_parametric_flight_that_overflows_to_infinity_is_refused_with_its_frame() {
    // A circle whose centre and radius are finite but whose positions overflow (1.5e308 +
    // 1e308 = ∞): the flight refuses the first non-finite pose before anything runs.
    let dir = tempfile::tempdir().unwrap();
    let flight = json!({
        "frames": 3,
        "look": { "fixed": { "yaw_deg": 0, "pitch_deg": -20 } },
        "path": { "circle": { "centre_m": [1.5e308, 0], "radius_m": 1e308, "altitude_m": 100,
                              "frames_per_lap": 4 } }
    });
    let path = common::experiment::save(dir.path(), "overflow", &experiment(flight));
    let error = load(&path)
        .err()
        .expect("an infinite pose is refused")
        .to_string();
    assert!(
        error.contains("flight: the pose of frame 0 is not finite"),
        "{error}"
    );
}

#[test]
fn a_turn_faster_than_the_rotation_bound_is_reported_as_a_rotation_violation() {
    // Ten frames 1 m apart looking east, then north from frame 6 on: a quarter turn in one frame
    // against a bound of 0.1 rad. Wu refines in view and revalidates there.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("frame,x_m,y_m,z_m,yaw_deg,pitch_deg\n");
    for frame in 0..10 {
        let yaw = if frame >= 6 { 90 } else { 0 };
        text.push_str(&format!("{frame},{},600,200,{yaw},-20\n", 300 + frame));
    }
    std::fs::write(dir.path().join("log.csv"), text).unwrap();
    let mut file = experiment(json!({ "path": { "recorded": { "path": "log.csv" } } }));
    file["speed_bounds"]["rotation_rad_per_frame"] = json!(0.1);
    file["algorithms"][0] = json!({ "name": "wu", "label": "wu", "tau_px": 2,
                                    "refine": "in_view" });
    let path = common::experiment::save(dir.path(), "turn", &file);
    let loaded = load(&path).unwrap();
    assert_eq!(loaded.violations.len(), 1);
    let violation = loaded.violations[0];
    assert_eq!(violation.frame, 6);
    // Both looks pitched 20° down: cos(angle) = sin²(20°).
    let expected = 20f64.to_radians().sin().powi(2).acos();
    assert!(
        (violation.rotation - expected).abs() < 1e-12,
        "{violation:?}"
    );
    assert!(violation.broken.rotation && !violation.broken.speed());

    let out = dir.path().join("out");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        check_meshes: true,
        threads: Some(1),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    run_experiment(&path, &options, &NoProgress).unwrap();
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let flight = &summary["flight"];
    assert_eq!(flight["speed_bounds"]["rotation_rad_per_frame"], 0.1);
    assert_eq!(
        flight["speed_violation_count_by_bound"],
        json!({ "horizontal": 0, "vertical": 0, "rotation": 1 })
    );
    assert_eq!(flight["speed_violations"][0]["broken"], json!(["rotation"]));
}

/// A recorded flight of 40 frames 2 m apart, looking 20° down and turning left unevenly (by up
/// to 1.5° a frame, some frames not at all): Wu refining in view with cone culling, and ROAM's
/// deferral, both use the rotation bound. The experiment declares `rotation` when given.
fn save_turning(dir: &Path, name: &str, rotation: Option<f64>) -> std::path::PathBuf {
    let turns = [0.2, 1.5, 0.7, 0.0, 1.1];
    let mut text = String::from("frame,x_m,y_m,z_m,yaw_deg,pitch_deg\n");
    let mut yaw = 0.0;
    for frame in 0..40 {
        if frame > 0 {
            yaw += turns[frame % turns.len()];
        }
        text.push_str(&format!("{frame},{},600,200,{yaw},-20\n", 300 + 2 * frame));
    }
    std::fs::write(dir.join("turning.csv"), text).unwrap();
    let mut file = experiment(json!({ "path": { "recorded": { "path": "turning.csv" } } }));
    if let Some(rotation) = rotation {
        file["speed_bounds"]["rotation_rad_per_frame"] = json!(rotation);
    }
    file["algorithms"][0] = json!({ "name": "wu", "label": "wu", "tau_px": 2,
                                    "refine": "in_view" });
    file["effects"] = json!({ "culling": true });
    file["outputs"]["meshes"] = json!({ "frames": [10, 25, 39] });
    common::experiment::save(dir, name, &file)
}

/// Runs the experiment at `path` into `out` (one thread, meshes checked every frame).
fn run_into(path: &Path, out: &Path) {
    let options = RunOptions {
        out_dir: Some(out.to_path_buf()),
        check_meshes: true,
        threads: Some(1),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    run_experiment(path, &options, &NoProgress).unwrap();
}

/// The bytes of every exported mesh under `out`, by path below it.
fn meshes(out: &Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    common::cli::files(&out.join("meshes"))
        .into_iter()
        .map(|file| {
            let bytes = std::fs::read(out.join("meshes").join(&file)).unwrap();
            (file, bytes)
        })
        .collect()
}

#[test]
fn an_undeclared_rotation_bound_is_the_flights_largest_turn_and_runs_as_if_declared() {
    let dir = tempfile::tempdir().unwrap();
    let undeclared = save_turning(dir.path(), "undeclared", None);
    let loaded = load(&undeclared).unwrap();
    assert_eq!(loaded.rotation_bound, BoundOrigin::Derived);
    let turn = largest_turn(&loaded.flight);
    assert_eq!(loaded.speed.rotation, turn);
    // The largest yaw step is 1.5°; pitched 20° down, the look direction turns by
    // 2·asin(cos 20° · sin 0.75°).
    let expected = 2.0 * (20f64.to_radians().cos() * 0.75f64.to_radians().sin()).asin();
    assert!((turn - expected).abs() < 1e-12, "{turn} against {expected}");
    assert!(loaded.violations.is_empty(), "{:?}", loaded.violations);

    let declared = save_turning(dir.path(), "declared", Some(turn));
    let declared_loaded = load(&declared).unwrap();
    assert_eq!(declared_loaded.rotation_bound, BoundOrigin::Declared);
    assert_eq!(declared_loaded.speed, loaded.speed);

    let (out_undeclared, out_declared) = (dir.path().join("a"), dir.path().join("b"));
    run_into(&undeclared, &out_undeclared);
    run_into(&declared, &out_declared);
    assert_eq!(
        common::cli::frames_without_timing(&out_undeclared.join("frames.csv")),
        common::cli::frames_without_timing(&out_declared.join("frames.csv"))
    );
    let undeclared_meshes = meshes(&out_undeclared);
    assert_eq!(undeclared_meshes.len(), 6, "two entries at three frames");
    assert_eq!(undeclared_meshes, meshes(&out_declared));

    let bounds = |out: &Path| {
        let summary = common::cli::summary_without_timing(&out.join("summary.json"));
        summary["flight"]["speed_bounds"].clone()
    };
    assert_eq!(
        bounds(&out_undeclared),
        json!({ "horizontal_m_per_frame": 40.0, "vertical_m_per_frame": 20.0,
                "rotation_rad_per_frame": turn, "rotation_rad_per_frame_derived": true })
    );
    assert_eq!(
        bounds(&out_declared),
        json!({ "horizontal_m_per_frame": 40.0, "vertical_m_per_frame": 20.0,
                "rotation_rad_per_frame": turn, "rotation_rad_per_frame_derived": false })
    );
    let report = |out: &Path| std::fs::read_to_string(out.join("report.md")).unwrap();
    let sentence = format!(
        "The rotation bound was not declared: the flight's largest turn, {turn} rad a frame, was \
         used."
    );
    assert!(report(&out_undeclared).contains(&sentence));
    assert!(!report(&out_declared).contains("was not declared"));
}

#[test]
fn validate_names_a_derived_rotation_bound_and_its_value() {
    let dir = tempfile::tempdir().unwrap();
    let undeclared = save_turning(dir.path(), "undeclared", None);
    let turn = load(&undeclared).unwrap().speed.rotation;
    let declared = save_turning(dir.path(), "declared", Some(turn));
    let stdout = |path: &Path| {
        let output = common::cli::roamsim(&["validate", path.to_str().unwrap()], dir.path());
        assert!(output.status.success(), "{output:?}");
        String::from_utf8(output.stdout).unwrap()
    };
    let line = format!(
        "note: no rotation bound declared: the flight's largest turn, {turn} rad a frame, is used"
    );
    assert!(
        stdout(&undeclared).contains(&line),
        "{}",
        stdout(&undeclared)
    );
    assert!(!stdout(&declared).contains("no rotation bound declared"));
}

#[test]
fn a_flight_that_never_turns_gets_a_rotation_bound_of_zero() {
    // Wu's view keys and ROAM's deferral then assume no turn, which the flight honours.
    let dir = tempfile::tempdir().unwrap();
    let path = save_with_log(dir.path(), &teleport_and_climb());
    let loaded = load(&path).unwrap();
    assert_eq!(loaded.rotation_bound, BoundOrigin::Derived);
    assert_eq!(loaded.speed.rotation, 0.0);
    assert!(loaded.violations.iter().all(|v| !v.broken.rotation));
}
