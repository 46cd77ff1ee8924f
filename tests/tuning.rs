//! Tuned entries (`"tune"` in an algorithm entry, `docs/experiment-format.md`, "Tuning to a
//! target"): the search over probe runs sets τ, ρ, c or C, or vanek's distances so that the mean
//! rendered triangles, or the mean audited p95 error, over the probe frames comes within the
//! tolerance of the target; the real run uses the value found, and summary.json, report.md and
//! shard.json record the search. Through the binary, on a small synthetic terrain; the search
//! itself is unit-tested in `src/sim/tuning.rs`.

mod common;

use common::cli::{
    fails_with, files, frames_without_timing, roamsim, succeeds, summary_without_timing,
};
use common::experiment::save;
use serde_json::{Value, json};
use std::path::Path;

/// A 60-frame circle over a gentle 257² synthetic terrain, audited, culling on.
fn experiment(algorithms: Value) -> Value {
    json!({
        "format_version": 1,
        "name": "tuned",
        "terrain": {"synthetic": {"level": 8, "seed": 3, "amplitude_m": 80, "roughness": 0.5,
                                  "spacing_m": {"dx": 30, "dy": 30}}},
        "view": {"width_px": 400, "height_px": 300, "fovy_deg": 60, "near_m": 1, "far_m": 50000},
        "speed_bounds": {"horizontal_m_per_frame": 50, "vertical_m_per_frame": 10,
                         "rotation_rad_per_frame": 0.05},
        "flight": {"frames": 60, "look": {"along_path": {"pitch_deg": -20}},
                   "path": {"circle": {"centre_m": [3840, 3840], "radius_m": 2000,
                                       "altitude_m": 600, "frames_per_lap": 300}}},
        "algorithms": algorithms,
        "effects": {"audit": {"stride": 2}, "culling": true},
        "outputs": {"plots": false}
    })
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn entry<'a>(summary: &'a Value, label: &str) -> &'a Value {
    summary["algorithms"]
        .as_array()
        .unwrap()
        .iter()
        .find(|a| a["label"] == label)
        .unwrap_or_else(|| panic!("no entry {label:?}"))
}

/// The record's promises: the value run is the probe closest to the target (the earlier on a
/// tie), `reached` says whether it is within the tolerance, and the probe mean is that probe's.
fn assert_consistent(label: &str, tuning: &Value) {
    let target = tuning["target"]
        .as_object()
        .unwrap()
        .values()
        .next()
        .unwrap();
    let target = target.as_f64().unwrap();
    let probes: Vec<(f64, f64)> = tuning["probes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["value"].as_f64().unwrap(), p["mean"].as_f64().unwrap()))
        .collect();
    let closest = probes.iter().fold(probes[0], |best, &p| {
        if (p.1 - target).abs() < (best.1 - target).abs() {
            p
        } else {
            best
        }
    });
    assert_eq!(tuning["value"].as_f64().unwrap(), closest.0, "{label}");
    assert_eq!(tuning["probe_mean"].as_f64().unwrap(), closest.1, "{label}");
    let within = (closest.1 - target).abs() <= 0.02 * target;
    assert_eq!(tuning["reached"], within, "{label}: {tuning}");
}

#[test]
fn tuned_entries_land_within_the_tolerance_and_the_run_uses_the_value_found() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let tune = |target: Value| {
        let mut tune = target;
        tune["probe_frames"] = 20.into();
        tune
    };
    let algorithms = json!([
        {"name": "wu", "label": "wu @2500", "zone": "paper",
         "tune": tune(json!({"rendered_triangles": 2500}))},
        {"name": "wu", "label": "wu @1px", "zone": "paper",
         "tune": tune(json!({"audit_p95_px": 1}))},
        {"name": "rottger", "label": "rottger C @2000", "desired_resolution": 30,
         "tune": tune(json!({"rendered_triangles": 2000, "parameter": "minimum_resolution"}))},
        {"name": "vanek", "label": "vanek @2000", "patch_level": 4, "min_dist_m": 500,
         "max_dist_m": 6000, "tune": tune(json!({"rendered_triangles": 2000}))},
        {"name": "stitching-strips", "label": "strips @400", "rho_threshold_px": 1,
         "block_level": 4, "tune": tune(json!({"rendered_triangles": 400}))},
    ]);
    save(cwd, "tuned", &experiment(algorithms));
    let output = roamsim(
        &["run", "tuned.json", "--out", "out", "--threads", "2"],
        cwd,
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains("tune 'wu @2500': probe 1: tau_px=2 -> ")
            && stderr.contains(" rendered triangles (target 2500)"),
        "{stderr}"
    );
    assert!(
        stderr.contains("tune 'wu @1px': probe 1: tau_px=2 -> ")
            && stderr.contains(" px audited p95 (target 1.000)"),
        "{stderr}"
    );
    let out = cwd.join("out");
    let summary = summary(&out);
    for (label, column, parameter) in [
        ("wu @2500", "triangles_rendered", "tau_px"),
        ("wu @1px", "audit_projected_p95_px", "tau_px"),
        (
            "rottger C @2000",
            "triangles_rendered",
            "minimum_resolution",
        ),
        ("vanek @2000", "triangles_rendered", "distance_scale"),
        ("strips @400", "triangles_rendered", "rho_threshold_px"),
    ] {
        let entry = entry(&summary, label);
        let tuning = &entry["tuning"];
        assert_consistent(label, tuning);
        assert_eq!(tuning["parameter"], parameter, "{label}");
        assert_eq!(
            (&tuning["probe_frames"], &tuning["probe_stride"]),
            (&json!(20), &json!(3)),
            "{label}: 20 of 60 frames"
        );
        // The full run's mean over its frames is recorded (no warm-up: every frame summarised).
        let full = tuning["full_run_mean"].as_f64().unwrap();
        let column_mean = entry["columns"][column]["mean"].as_f64().unwrap();
        assert!(
            (full - column_mean).abs() <= 1e-9 * column_mean,
            "{label}: {full} against {column_mean}"
        );
        // The tuned value is listed with the parameters.
        let value = tuning["value"].as_f64().unwrap();
        if parameter == "distance_scale" {
            assert_eq!(entry["parameters"]["min_dist_m"], json!(500.0 * value));
            assert_eq!(entry["parameters"]["max_dist_m"], json!(6000.0 * value));
        } else {
            assert_eq!(entry["parameters"][parameter], json!(value), "{label}");
        }
    }
    // The monotone ones land within 2 % of their targets over the probe frames.
    for label in ["wu @2500", "wu @1px", "rottger C @2000", "vanek @2000"] {
        assert_eq!(entry(&summary, label)["tuning"]["reached"], true, "{label}");
    }
    // The search moved: wu's τ is not the start, and the run drew about the target.
    let wu = &entry(&summary, "wu @2500")["tuning"];
    assert_ne!(wu["value"].as_f64().unwrap(), 2.0);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("\n## Tuned entries\n"), "{report}");
    assert!(report.contains("| wu @2500 | tau_px = "), "{report}");
    assert!(
        report.contains("| vanek @2000 | distance_scale = "),
        "{report}"
    );

    // The same entry written with the value found draws the same frames.
    let tau = wu["value"].as_f64().unwrap();
    let fixed = json!([{"name": "wu", "label": "wu @2500", "zone": "paper", "tau_px": tau}]);
    save(cwd, "fixed", &experiment(fixed));
    succeeds(&["run", "fixed.json", "--out", "fixed"], cwd);
    let columns = |dir: &Path| {
        let summary = summary_without_timing(&dir.join("summary.json"));
        entry(&summary, "wu @2500")["columns"].clone()
    };
    assert_eq!(columns(&cwd.join("fixed")), columns(&out));
}

/// The problems of loading an experiment with these entries (and `effects`), as
/// `field: problem` lines.
fn problems(algorithms: Value, effects: Value) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let mut value = experiment(algorithms);
    value["effects"] = effects;
    let path = save(dir.path(), "bad", &value);
    match roamsim::edge::experiment::load(&path) {
        Ok(_) => Vec::new(),
        Err(error) => error
            .problems
            .iter()
            .map(|p| format!("{}: {}", p.field, p.problem))
            .collect(),
    }
}

fn has(problems: &[String], field: &str, words: &str) {
    assert!(
        problems
            .iter()
            .any(|p| p.starts_with(&format!("{field}: ")) && p.contains(words)),
        "{problems:?} lacks {field}: …{words}…"
    );
}

#[test]
fn clashing_counts_a_missing_audit_unknown_parameters_and_bad_settings_are_refused() {
    let audited = json!({"audit": {"stride": 4}});
    let clash = problems(
        json!([
            {"name": "wu", "budget_triangles": 5000, "tune": {"rendered_triangles": 5000}},
            {"name": "rottger", "minimum_resolution": 8, "target_fan_vertices": 900,
             "tune": {"rendered_triangles": 5000}},
        ]),
        audited.clone(),
    );
    has(&clash, "algorithms[0].tune", "tune and budget_triangles");
    has(&clash, "algorithms[1].tune", "tune and target_fan_vertices");
    let no_audit = problems(
        json!([{"name": "wu", "tune": {"audit_p95_px": 2}}]),
        json!({"culling": true}),
    );
    has(
        &no_audit,
        "algorithms[0].tune.audit_p95_px",
        "needs the audit",
    );
    let unknown = problems(
        json!([
            {"name": "wu", "tune": {"rendered_triangles": 5000, "parameter": "rho_threshold_px"}},
            {"name": "vanek", "patch_level": 4, "min_dist_m": 1, "max_dist_m": 9,
             "tune": {"rendered_triangles": 5000, "parameter": "min_dist_m"}},
        ]),
        audited.clone(),
    );
    has(&unknown, "algorithms[0].tune.parameter", "expected tau_px");
    has(
        &unknown,
        "algorithms[1].tune.parameter",
        "expected distance_scale",
    );
    let settings = problems(
        json!([
            {"name": "wu", "tune": {"rendered_triangles": 5000, "audit_p95_px": 1}},
            {"name": "wu", "label": "b", "tune": {"parameter": "tau_px"}},
            {"name": "wu", "label": "c", "tune": {"rendered_triangles": -1, "probe_frames": 1,
                                                   "tolerance": 0, "max_probes": 1}},
            {"name": "wu", "label": "d", "tune": {"rendered_triangles": 5, "frames": 9}},
        ]),
        audited.clone(),
    );
    has(&settings, "algorithms[0].tune", "exactly one target");
    has(&settings, "algorithms[1].tune", "exactly one target");
    has(
        &settings,
        "algorithms[2].tune.rendered_triangles",
        "above 0",
    );
    has(&settings, "algorithms[2].tune.probe_frames", "at least 2");
    has(&settings, "algorithms[2].tune.tolerance", "above 0");
    has(&settings, "algorithms[2].tune.max_probes", "at least 2");
    has(
        &settings,
        "algorithms[3].tune.frames",
        "unknown field `frames`",
    );
    // A tune with its own problem adds no second one for the τ it would have set.
    assert_eq!(
        settings.iter().filter(|p| p.contains("tau_px")).count(),
        0,
        "{settings:#?}"
    );
    let swept = problems(
        json!([
            {"name": "wu", "tune": {"rendered_triangles": 5000}, "sweep": {"tau_px": [1, 2]}},
            {"name": "wu", "label": "b", "sweep": {"tune": [{"rendered_triangles": 5000}]}},
            {"name": "rottger", "minimum_resolution": 8, "label": "c",
             "tune": {"rendered_triangles": 9, "parameter": "minimum_resolution"},
             "sweep": {"minimum_resolution": [4, 8]}},
            {"name": "rottger", "minimum_resolution": 8, "label": "d",
             "tune": {"rendered_triangles": 9}, "sweep": {"minimum_resolution": [4, 8]}},
        ]),
        audited.clone(),
    );
    has(
        &swept,
        "algorithms[0].sweep.tau_px",
        "the entry's tune sets tau_px",
    );
    has(&swept, "algorithms[1].sweep.tune", "tune cannot be swept");
    has(
        &swept,
        "algorithms[2].sweep.minimum_resolution",
        "the entry's tune sets minimum_resolution",
    );
    // Röttger's tune sets c by default: a sweep of C beside it is fine.
    assert!(
        !swept.iter().any(|p| p.starts_with("algorithms[3]")),
        "{swept:#?}"
    );
    // Without the tuned parameter written, the entry is checked with the start (Wu needs a τ
    // or a budget; roam exactly one of τ and a target): no problem.
    let fine = problems(
        json!([
            {"name": "wu", "tune": {"rendered_triangles": 5000}},
            {"name": "roam", "tune": {"audit_p95_px": 2}},
            {"name": "rottger", "minimum_resolution": 8, "tune": {"rendered_triangles": 9}},
        ]),
        audited,
    );
    assert_eq!(fine, Vec::<String>::new());
}

#[test]
fn validate_checks_the_tune_fields_and_runs_no_probe() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let good = json!([{"name": "wu", "label": "wu @2500", "tune": {"rendered_triangles": 2500}}]);
    save(cwd, "good", &experiment(good));
    let output = roamsim(&["validate", "good.json"], cwd);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.contains("tune '"), "{stderr}");
    let bad = json!([{"name": "wu", "tune": {"rendered_triangles": 2500, "parameter": "c"}}]);
    save(cwd, "bad", &experiment(bad));
    fails_with(
        &["validate", "bad.json"],
        cwd,
        &["algorithms[0].tune.parameter", "\"c\""],
    );
}

/// Every file of two output folders equal, timings and run metadata left out.
fn assert_same_outputs(a: &Path, b: &Path) {
    let listed = files(a);
    assert_eq!(files(b), listed);
    for file in &listed {
        let name = file.to_string_lossy();
        if name.ends_with("frames.csv") {
            assert_eq!(
                frames_without_timing(&a.join(file)),
                frames_without_timing(&b.join(file)),
                "{name}"
            );
        } else if name.ends_with("summary.json") {
            assert_eq!(
                summary_without_timing(&a.join(file)),
                summary_without_timing(&b.join(file)),
                "{name}"
            );
        }
    }
}

#[test]
fn threads_shards_sweep_points_and_frames_give_the_same_tuned_runs() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let algorithms = json!([
        {"name": "wu", "label": "wu @2500", "zone": "paper",
         "tune": {"rendered_triangles": 2500, "probe_frames": 20}},
        {"name": "geomipmap", "label": "geomipmap", "tau_px": 2, "patch_level": 4},
        {"name": "vanek", "label": "vanek @2000", "patch_level": 4, "min_dist_m": 500,
         "max_dist_m": 6000, "tune": {"rendered_triangles": 2000, "probe_frames": 20}},
    ]);
    let mut value = experiment(algorithms);
    value["sweep"] = json!({"view.fovy_deg": [50, 70]});
    save(cwd, "tuned", &value);
    let run = |extra: &[&str], out: &str| {
        let mut args = vec!["run", "tuned.json", "--out", out, "--frames", "45"];
        args.extend_from_slice(extra);
        succeeds(&args, cwd);
    };
    run(&["--threads", "1"], "one");
    run(&["--threads", "2"], "two");
    for k in 1..=3 {
        run(&["--shard", &format!("{k}/3")], &format!("shards/{k}"));
    }
    succeeds(
        &[
            "merge", "shards/2", "shards/3", "shards/1", "--out", "merged",
        ],
        cwd,
    );
    assert_same_outputs(&cwd.join("one"), &cwd.join("two"));
    assert_same_outputs(&cwd.join("one"), &cwd.join("merged"));
    // Each point tuned on its own view; the probes spread over the 45 frames --frames kept.
    let mut values = Vec::new();
    for point in ["view.fovy_deg=50", "view.fovy_deg=70"] {
        let summary = summary(&cwd.join("one").join(point));
        let tuning = &entry(&summary, "wu @2500")["tuning"];
        assert_eq!(
            tuning["probe_stride"], 3,
            "{point}: 45 frames, at most 20 probes"
        );
        assert_eq!(tuning["reached"], true, "{point}: {tuning}");
        values.push(tuning["value"].as_f64().unwrap());
        assert!(entry(&summary, "geomipmap").get("tuning").is_none());
        let merged = self::summary(&cwd.join("merged").join(point));
        assert_eq!(entry(&merged, "wu @2500")["tuning"], *tuning, "{point}");
    }
    assert_ne!(values[0], values[1], "a wider view needs another τ");
}

/// frames.csv's count columns: every column but the timing ones (`TIMING_COLUMNS`), row by row.
fn frame_counts(path: &Path) -> Vec<Vec<String>> {
    use roamsim::edge::output::columns::TIMING_COLUMNS;
    let text = std::fs::read_to_string(path).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    let kept: Vec<usize> = (0..rows[0].len())
        .filter(|&k| !TIMING_COLUMNS.contains(&rows[0][k]))
        .collect();
    rows.iter()
        .map(|row| kept.iter().map(|&k| row[k].to_string()).collect())
        .collect()
}

/// A 65² ESRI ASCII grid of rolling hills, 20 m posts.
fn write_ascii_grid(path: &Path) {
    let mut text = String::from(
        "ncols 65\nnrows 65\nxllcorner 0\nyllcorner 0\ncellsize 20\nNODATA_value -9999\n",
    );
    for row in 0..65 {
        let heights: Vec<String> = (0..65)
            .map(|col| {
                let (x, y) = (col as f64 / 9.0, row as f64 / 7.0);
                format!(
                    "{:.2}",
                    40.0 * x.sin() * y.cos() + 3.0 * ((col * row) % 5) as f64
                )
            })
            .collect();
        text.push_str(&heights.join(" "));
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn the_tuned_experiment_written_beside_the_outputs_reproduces_the_runs_counts() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    std::fs::create_dir_all(cwd.join("data")).unwrap();
    std::fs::create_dir_all(cwd.join("experiments")).unwrap();
    write_ascii_grid(&cwd.join("data/hills.asc"));
    let tune = |target: Value| {
        let mut tune = target;
        tune["probe_frames"] = 10.into();
        tune
    };
    let mut value = experiment(json!([
        {"name": "wu", "label": "wu @600", "zone": "paper",
         "tune": tune(json!({"rendered_triangles": 600}))},
        {"name": "vanek", "label": "vanek @500", "patch_level": 3, "min_dist_m": 100,
         "max_dist_m": 900, "tune": tune(json!({"rendered_triangles": 500}))},
        {"name": "roam", "label": "roam", "sweep": {"tau_px": [2, 4]}},
    ]));
    value["name"] = "hills".into();
    value["terrain"] = json!({"file": {"path": "../data/hills.asc", "fit": "crop"}});
    value["flight"]["path"]["circle"] =
        json!({"centre_m": [640, 640], "radius_m": 300, "altitude_m": 250, "frames_per_lap": 90});
    value["speed_bounds"]["horizontal_m_per_frame"] = 30.into();
    value["speed_bounds"]
        .as_object_mut()
        .unwrap()
        .remove("rotation_rad_per_frame");
    save(&cwd.join("experiments"), "hills", &value);
    let output = roamsim(
        &[
            "run",
            "experiments/hills.json",
            "--out",
            "out/hills",
            "--frames",
            "25",
        ],
        cwd,
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(stdout.contains("tuned-experiment.json"), "{stdout}");
    let frozen_path = cwd.join("out/hills/tuned-experiment.json");
    let frozen: Value =
        serde_json::from_str(&std::fs::read_to_string(&frozen_path).unwrap()).unwrap();
    assert_eq!(frozen["name"], "hills-tuned");
    assert_eq!(frozen["flight"]["first_frames"], 25, "--frames written in");
    assert_eq!(
        frozen["terrain"]["file"]["path"], "../../data/hills.asc",
        "relative to the output folder"
    );
    let summary = summary(&cwd.join("out/hills"));
    for (k, label) in ["wu @600", "vanek @500"].iter().enumerate() {
        let written = &frozen["algorithms"][k];
        assert_eq!(written["label"], *label);
        assert!(written.get("tune").is_none(), "{written}");
        assert_eq!(
            written,
            &{
                let mut e = entry(&summary, label)["parameters"].clone();
                e["name"] = entry(&summary, label)["name"].clone();
                e["label"] = json!(label);
                e
            },
            "the parameters summary.json lists, tuned value included"
        );
    }
    assert_eq!(frozen["algorithms"][3]["label"], "roam tau_px=4");

    // Run from elsewhere: the file's own paths resolve from where it is written.
    succeeds(
        &[
            "run",
            frozen_path.to_str().unwrap(),
            "--out",
            "rerun",
            "--threads",
            "1",
        ],
        cwd,
    );
    assert!(
        !cwd.join("rerun/tuned-experiment.json").exists(),
        "nothing left to tune"
    );
    let (first, again) = (
        frame_counts(&cwd.join("out/hills/frames.csv")),
        frame_counts(&cwd.join("rerun/frames.csv")),
    );
    assert_eq!(first.len(), 1 + 4 * 25);
    assert_eq!(first, again);
}

#[test]
fn a_search_whose_parameter_stopped_mattering_stops_on_a_plateau_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    // The stitching strips cannot draw 0.3 px at any ρ on this flight: their blocks reach the
    // highest tessellation factor first.
    let mut value = experiment(json!([
        {"name": "stitching-strips", "label": "strips @0.3px", "rho_threshold_px": 1,
         "block_level": 4, "tune": {"audit_p95_px": 0.3, "probe_frames": 10}},
    ]));
    value["terrain"]["synthetic"]["level"] = 7.into();
    value["flight"]["path"]["circle"]["centre_m"] = json!([1900, 1900]);
    value["flight"]["path"]["circle"]["radius_m"] = 1000.into();
    value["flight"]["frames"] = 20.into();
    save(cwd, "plateau", &value);
    let output = roamsim(&["run", "plateau.json", "--out", "out"], cwd);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let summary = summary(&cwd.join("out"));
    let tuning = &entry(&summary, "strips @0.3px")["tuning"];
    let plateau = &tuning["plateau"];
    assert_eq!(tuning["reached"], false);
    assert_eq!(plateau["probes"], 4, "{tuning}");
    let probes = tuning["probes"].as_array().unwrap();
    assert!(probes.len() < 24, "stopped before max_probes: {tuning}");
    let [low, high] = [0, 1].map(|k| plateau["values"][k].as_f64().unwrap());
    assert_eq!(high / low, 8.0, "three doublings");
    let reason = plateau["reason"].as_str().unwrap();
    assert!(
        reason.contains("every M-block is in the highest tessellation factor's bin"),
        "{reason}"
    );
    let warning = stderr
        .lines()
        .find(|l| l.starts_with("warning: strips @0.3px: tune did not reach"))
        .unwrap_or_else(|| panic!("{stderr}"));
    assert!(
        warning.contains("it stopped on a plateau: rho_threshold_px from "),
        "{warning}"
    );
    assert!(
        warning.ends_with("(report.md, \"Tuned entries\")"),
        "{warning}"
    );
    let report = std::fs::read_to_string(cwd.join("out/report.md")).unwrap();
    assert!(
        report.contains("**strips @0.3px: the search stopped on a plateau**"),
        "{report}"
    );
    assert!(report.contains(reason), "{report}");
}
