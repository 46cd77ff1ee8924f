//! Whole runs, as a user starts them: the same experiment gives the same counts whatever the
//! thread count (SPEC §8); every output file is written with the columns `docs/output-formats.md`
//! documents; sweeps expand into labelled entries and points compared at the top; the output
//! folder is all or nothing and never replaces what roamsim did not write; `validate` and `info`
//! answer as documented, and the CLI's exit statuses say whether it worked.

mod common;

use common::experiment::{repository, save, short_quickstart};
use roamsim::edge::output::columns::TIMING_COLUMNS;
use roamsim::edge::session::{NoProgress, RunOptions, run_experiment};
use std::path::Path;
use std::process::Command;

fn run_to(experiment: &Path, out: &Path, check_meshes: bool) {
    run_with_threads(experiment, out, check_meshes, 1);
}

fn run_with_threads(experiment: &Path, out: &Path, check_meshes: bool, threads: usize) {
    let options = RunOptions {
        out_dir: Some(out.to_path_buf()),
        check_meshes,
        threads: Some(threads),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    run_experiment(experiment, &options, &NoProgress).unwrap();
}

/// frames.csv with the timing columns blanked.
fn counts_only(csv: &str) -> String {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let timing: Vec<usize> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| TIMING_COLUMNS.contains(h))
        .map(|(k, _)| k)
        .collect();
    assert!(!timing.is_empty());
    lines
        .map(|line| {
            line.split(',')
                .enumerate()
                .map(|(k, v)| if timing.contains(&k) { "" } else { v })
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_same_experiment_twice_gives_identical_counts_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let short = short_quickstart(40);
    let n_algorithms = short["algorithms"].as_array().unwrap().len();
    let experiment = save(dir.path(), "short", &short);
    run_with_threads(&experiment, &dir.path().join("first"), false, 1);
    run_with_threads(&experiment, &dir.path().join("second"), true, 3);
    let read =
        |name: &str| std::fs::read_to_string(dir.path().join(name).join("frames.csv")).unwrap();
    let (first, second) = (read("first"), read("second"));
    assert_eq!(first.lines().count(), 1 + n_algorithms * 40);
    assert_eq!(counts_only(&first), counts_only(&second));
}

#[test]
fn a_run_writes_every_output_with_the_documented_columns() {
    let dir = tempfile::tempdir().unwrap();
    let experiment = save(dir.path(), "short", &short_quickstart(12));
    let out = dir.path().join("out");
    run_to(&experiment, &out, true);
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.starts_with(
        "algorithm,frame,triangles,triangles_rendered,splits,merges,vertices_inserted,\
         vertices_deleted,metric_evaluations,update_ns"
    ));
    for audit_column in [
        "audit_projected_max_px",
        "audit_projected_mean_px",
        "audit_projected_p95_px",
        "audit_view_angle_max_px",
        "audit_view_angle_mean_px",
        "audit_view_angle_p95_px",
    ] {
        assert!(header.contains(audit_column), "{header}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["format_version"], 1);
    assert_eq!(summary["terrain"]["side"], 1025);
    assert_eq!(summary["terrain"]["voids_filled"], 21);
    assert_eq!(
        summary["terrain"]["crop_origin"],
        serde_json::json!([88, 88])
    );
    assert_eq!(
        summary["experiment"]["content_sha256"]
            .as_str()
            .unwrap()
            .len(),
        64
    );
    let first = &summary["algorithms"][0];
    assert_eq!(first["label"], "reference τ=2px");
    let triangles = &first["columns"]["triangles"];
    assert!(triangles["max"].as_f64().unwrap() >= triangles["p95"].as_f64().unwrap());
    assert!(triangles["mean"].as_f64().unwrap() > 2.0);
    for plot in ["triangles", "frame_time", "error"] {
        for extension in ["png", "svg"] {
            let file = out.join("plots").join(format!("{plot}.{extension}"));
            assert!(
                std::fs::metadata(&file).unwrap().len() > 1000,
                "{}",
                file.display()
            );
        }
    }
}

#[test]
fn popping_mesh_exports_and_each_entrys_preprocessing_are_written_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(6);
    // The 4-8 entries only: triangle-list entries bring the mesh columns.
    experiment["algorithms"]
        .as_array_mut()
        .unwrap()
        .retain(|a| {
            !matches!(
                a["name"].as_str(),
                Some("geomipmap" | "chunked" | "vanek" | "stitching-strips")
            )
        });
    experiment["effects"]["audit"]["popping"] = serde_json::json!(true);
    experiment["outputs"] = serde_json::json!({"meshes": {"frames": [5, 0], "entries": ["wu"]}});
    let path = save(dir.path(), "exports", &experiment);
    let out = dir.path().join("out");
    run_to(&path, &out, true);

    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    for row in &rows {
        let popping = row[column("popping_rmse_px")];
        // Frame 0 has no previous frame; every later frame of the circle moves the surface.
        assert_eq!(popping.is_empty(), row[1] == "0", "{row:?}");
    }
    assert!(
        !header.contains(&"triangles_skirt"),
        "4-8 meshes have no mesh columns"
    );
    assert!(!header.contains(&"audit_holes"), "nor coverage columns");

    // wu τ=2px and wu budget=6000 (entries 2 and 3), frames 0 and 5: one PLY each, its faces
    // the frame's triangles.
    for (k, label) in [(2, "wu τ=2px"), (3, "wu budget=6000")] {
        let folder = out
            .join("meshes")
            .join(format!("{k}-{}", label.replace(['τ', ' '], "-")));
        for frame in [0, 5] {
            let ply =
                std::fs::read_to_string(folder.join(format!("frame-{frame:06}.ply"))).unwrap();
            let row = rows
                .iter()
                .find(|r| r[0] == label && r[1] == frame.to_string())
                .unwrap();
            let faces = ply
                .lines()
                .find_map(|l| l.strip_prefix("element face "))
                .unwrap();
            assert_eq!(faces, row[column("triangles")], "{label}, frame {frame}");
            assert!(ply.contains(&format!("entry {label}, frame {frame}")));
        }
    }
    let exported: Vec<_> = std::fs::read_dir(out.join("meshes")).unwrap().collect();
    assert_eq!(exported.len(), 2);

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["effects"]["audit"]["popping"], true);
    for entry in summary["algorithms"].as_array().unwrap() {
        let preprocessing = &entry["preprocessing"];
        assert!(preprocessing["seconds"].as_f64().unwrap() >= 0.0);
        assert!(
            preprocessing["bytes_per_sample"].as_f64().unwrap() > 0.0,
            "{entry}"
        );
        assert!(entry["columns"]["popping_max_m"]["max"].as_f64().unwrap() > 0.0);
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains("## Popping") && report.contains("## Preprocessing"),
        "{report}"
    );
    assert!(out.join("plots/popping.png").exists());
}

/// The faces of an exported PLY file: their corners' (x, y) in metres and their role.
fn ply_faces(ply: &str) -> Vec<([(f64, f64); 3], u32)> {
    let count = |element: &str| -> usize {
        ply.lines()
            .find_map(|l| l.strip_prefix(element))
            .unwrap()
            .parse()
            .unwrap()
    };
    let (n_vertices, n_faces) = (count("element vertex "), count("element face "));
    let mut body = ply.split("end_header\n").nth(1).unwrap().lines();
    let vertices: Vec<(f64, f64)> = (&mut body)
        .take(n_vertices)
        .map(|line| {
            let xyz: Vec<f64> = line.split(' ').map(|v| v.parse().unwrap()).collect();
            (xyz[0], xyz[1])
        })
        .collect();
    let faces: Vec<_> = body
        .map(|line| {
            let fields: Vec<u32> = line.split(' ').map(|v| v.parse().unwrap()).collect();
            assert_eq!(fields[0], 3, "{line}");
            let corners = [1, 2, 3].map(|k| vertices[fields[k] as usize]);
            (corners, fields[4])
        })
        .collect();
    assert_eq!(faces.len(), n_faces);
    faces
}

#[test]
fn exported_meshes_keep_the_winding_every_face_with_area_counter_clockwise_from_above() {
    // One entry of each family, exported at the last frame; the faces read back from the files
    // in the order written, their signed areas in x–y computed from the written vertices.
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(3);
    let families = ["wu", "geomipmap", "chunked", "vanek", "stitching-strips"];
    experiment["algorithms"]
        .as_array_mut()
        .unwrap()
        .retain(|a| families.contains(&a["name"].as_str().unwrap()));
    experiment["outputs"] = serde_json::json!({"meshes": {"frames": [2], "entries": families}});
    let path = save(dir.path(), "winding", &experiment);
    let out = dir.path().join("out");
    run_to(&path, &out, true);
    let mut folders: Vec<_> = std::fs::read_dir(out.join("meshes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    folders.sort();
    assert_eq!(folders.len(), 6, "{folders:?}");
    for folder in folders {
        let ply = std::fs::read_to_string(folder.join("frame-000002.ply")).unwrap();
        let (mut with_area, mut flat) = (0, 0);
        for (k, ([a, b, c], role)) in ply_faces(&ply).into_iter().enumerate() {
            let area2 = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
            // Surface (0) and stitch (3) faces have area; skirts (1) and degenerate faces (2)
            // have none and no winding.
            if role == 0 || role == 3 {
                assert!(area2 > 0.0, "{folder:?}, face {k}: signed area {area2}");
                with_area += 1;
            } else {
                assert_eq!(area2, 0.0, "{folder:?}, face {k}: role {role}");
                flat += 1;
            }
        }
        assert!(
            with_area > 0,
            "{folder:?}: {flat} flat faces and none with area"
        );
    }
}

#[test]
fn the_reference_rendered_count_is_below_its_total_when_culling() {
    let dir = tempfile::tempdir().unwrap();
    let experiment = save(dir.path(), "short", &short_quickstart(3));
    let out = dir.path().join("out");
    run_to(&experiment, &out, false);
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    for line in csv.lines().skip(1) {
        let fields: Vec<u64> = line
            .split(',')
            .skip(2)
            .take(2)
            .map(|v| v.parse().unwrap())
            .collect();
        assert!(fields[1] < fields[0] && fields[1] > 0, "{line}");
    }
}

fn roamsim(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_roamsim"))
        .args(args)
        .current_dir(repository())
        .output()
        .unwrap()
}

#[test]
fn validate_exits_non_zero_on_an_invalid_experiment() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(10);
    experiment["view"]["width_px"] = 0.into();
    let path = save(dir.path(), "invalid", &experiment);
    let output = roamsim(&["validate", path.to_str().unwrap()]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("invalid.json: view.width_px: 0: expected at least 1"),
        "{stderr}"
    );

    let valid = roamsim(&["validate", "experiments/quickstart.json"]);
    assert!(
        valid.status.success(),
        "{}",
        String::from_utf8_lossy(&valid.stderr)
    );
}

#[test]
fn help_shows_an_example() {
    let output = roamsim(&["run", "--help"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("roamsim run experiments/quickstart.json"),
        "{stdout}"
    );
}

#[test]
fn info_reports_preprocessing_time_and_bytes_per_sample() {
    let output = roamsim(&["info", "experiments/data/N48E009.hgt"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains("ns per sample") && stdout.contains("bytes per sample"),
        "{stdout}"
    );
    assert!(
        stdout.contains("1201 columns × 1201 rows") && stdout.contains("2049 × 2049 samples"),
        "{stdout}"
    );
}

/// The label column of `info`'s report.
fn info_labels(stdout: &str) -> Vec<String> {
    stdout
        .lines()
        .map(|l| l.split("  ").next().unwrap().trim().to_string())
        .collect()
}

#[test]
fn info_is_one_plain_report_for_a_terrain_file_an_experiment_and_a_raw_file() {
    let file = roamsim(&["info", "experiments/data/N48E009.hgt"]);
    let experiment = roamsim(&["info", "experiments/quickstart.json"]);
    let dir = tempfile::tempdir().unwrap();
    let raw = dir.path().join("heights.raw");
    let samples: Vec<u8> = (0..17 * 9)
        .flat_map(|k: i16| (k * 3).to_le_bytes())
        .collect();
    std::fs::write(&raw, samples).unwrap();
    let raw_path = raw.to_str().unwrap();
    let refused = roamsim(&["info", raw_path]);
    let raw_info = roamsim(&[
        "info",
        raw_path,
        "--raw-columns",
        "17",
        "--raw-rows",
        "9",
        "--raw-sample",
        "i16le",
    ]);
    assert!(!refused.status.success());
    let refusal = String::from_utf8_lossy(&refused.stderr);
    assert!(refusal.contains("--raw-columns"), "{refusal}");
    let texts: Vec<String> = [&file, &experiment, &raw_info]
        .iter()
        .map(|o| {
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            String::from_utf8_lossy(&o.stdout).into_owned()
        })
        .collect();
    for text in &texts {
        assert!(!text.contains("Some(") && !text.contains("None"), "{text}");
        assert_eq!(info_labels(text), info_labels(&texts[0]), "{text}");
    }
    assert!(
        texts[1].contains("cropped from column 88, row 88"),
        "{}",
        texts[1]
    );
    assert!(texts[2].contains("17 columns × 9 rows"), "{}", texts[2]);
    assert!(texts[2].contains("1 m assumed here"), "{}", texts[2]);
}

#[test]
fn a_sweep_expands_into_labelled_entries_compared_in_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(6);
    experiment["algorithms"] = serde_json::json!([
        {"name": "wu", "label": "wu", "sweep": {"tau_px": [2, 8], "zone": ["paper", "conservative"]}},
        {"name": "reference", "tau_px": 2}
    ]);
    let path = save(dir.path(), "sweep", &experiment);
    let out = dir.path().join("out");
    run_with_threads(&path, &out, true, 2);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let labels: Vec<&str> = summary["algorithms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["label"].as_str().unwrap())
        .collect();
    assert_eq!(
        labels,
        [
            "wu tau_px=2, zone=paper",
            "wu tau_px=2, zone=conservative",
            "wu tau_px=8, zone=paper",
            "wu tau_px=8, zone=conservative",
            "reference",
        ]
    );
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 5 * 6);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    // The comparison table (before the preprocessing section, which lists the entries again).
    let comparison = report.split("\n## ").next().unwrap();
    assert_eq!(
        comparison
            .lines()
            .filter(|l| l.starts_with("| wu tau_px="))
            .count(),
        4
    );
    assert!(report.contains("Pareto front"), "{report}");
    for extension in ["png", "svg"] {
        assert!(
            out.join(format!("plots/accuracy_vs_time.{extension}"))
                .exists()
        );
    }
}

#[test]
fn a_bad_sweep_names_its_entry() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(6);
    experiment["algorithms"] = serde_json::json!([
        {"name": "wu", "sweep": {"tau_px": [2, -1]}}
    ]);
    let path = save(dir.path(), "bad-sweep", &experiment);
    let error = roamsim::edge::experiment::load(&path)
        .err()
        .expect("invalid")
        .to_string();
    assert!(
        error.contains("algorithms[0] (tau_px=-1).tau_px: -1: expected a finite tolerance"),
        "{error}"
    );
}

#[test]
fn a_killed_run_leaves_the_previous_output_untouched_and_the_next_run_cleans_up() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let short = save(dir.path(), "short", &short_quickstart(3));
    run_to(&short, &out, false);
    let read = || std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let before = read();

    // A long run into the same folder, killed while it simulates.
    let long = save(dir.path(), "long", &short_quickstart(400));
    let mut child = Command::new(env!("CARGO_BIN_EXE_roamsim"))
        .args([
            "run",
            long.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the long run ended before it could be killed"
    );
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        read() == before,
        "the killed run touched the previous output"
    );

    // A staging folder left by a run killed while writing is removed by the next run.
    let leftover = dir.path().join(".out.partial-4000000");
    std::fs::create_dir_all(&leftover).unwrap();
    std::fs::write(leftover.join("frames.csv"), "half").unwrap();
    run_to(&short, &out, false);
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(!names.iter().any(|n| n.contains(".partial-")), "{names:?}");
    assert!(counts_only(&read()) == counts_only(&before));
}

/// A small synthetic scene whose terrain size is swept: the scaling experiment in miniature.
fn small_terrain_sweep(levels: &[u32]) -> serde_json::Value {
    serde_json::json!({
        "format_version": 1,
        "name": "mini-scaling",
        "sweep": {"terrain.synthetic.level": levels},
        "terrain": {"synthetic": {"level": 5, "seed": 3, "amplitude_m": 20,
                                  "amplitude_scale_m": 320, "roughness": 0.5,
                                  "spacing_m": {"dx": 10, "dy": 10}}},
        "view": {"width_px": 200, "height_px": 200, "fovy_deg": 60, "near_m": 1, "far_m": 5000},
        "speed_bounds": {"horizontal_m_per_frame": 10, "vertical_m_per_frame": 5},
        "flight": {"frames": 12, "look": {"along_path": {"pitch_deg": -20}},
                   "path": {"circle": {"centre_m": [160, 160], "radius_m": 80,
                                       "altitude_m": 150, "frames_per_lap": 60}}},
        "algorithms": [
            {"name": "wu", "budget_triangles": 200, "tau_px": 2},
            {"name": "roam", "target_triangles": 200},
            {"name": "reference", "tau_px": 2}
        ],
        "effects": {"audit": {"stride": 1}, "culling": true}
    })
}

#[test]
fn a_terrain_sweep_runs_each_size_into_its_own_folder_and_compares_them_at_the_top() {
    let dir = tempfile::tempdir().unwrap();
    let path = save(dir.path(), "mini", &small_terrain_sweep(&[5, 6]));
    let out = dir.path().join("out");
    run_with_threads(&path, &out, true, 2);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["kind"], "sweep");
    let points = summary["points"].as_array().unwrap();
    let sides: Vec<u64> = points
        .iter()
        .map(|p| p["terrain"]["side"].as_u64().unwrap())
        .collect();
    assert_eq!(sides, [33, 65]);
    for (point, level) in points.iter().zip([5, 6]) {
        let folder = out.join(point["folder"].as_str().unwrap());
        assert_eq!(
            folder.file_name().unwrap(),
            format!("terrain.synthetic.level={level}").as_str()
        );
        let own: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(folder.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(own["terrain"]["side"], point["terrain"]["side"]);
        assert_eq!(
            own["experiment"]["sweep_point"]["terrain.synthetic.level"],
            level
        );
        let csv = std::fs::read_to_string(folder.join("frames.csv")).unwrap();
        assert_eq!(csv.lines().count(), 1 + 3 * 12);
        let labels: Vec<&str> = point["algorithms"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a["label"].as_str().unwrap())
            .collect();
        assert_eq!(labels, ["wu", "roam", "reference"]);
        assert!(point["algorithms"][0]["audited_error_px"]["max"].is_f64());
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        report.contains(
            "| terrain.synthetic.level=6 | `terrain.synthetic.level=6` | 65² (4225 samples)"
        ),
        "{report}"
    );
    assert!(report.contains("Median time to a drawn frame"), "{report}");
    for stem in ["sweep_frame_time", "sweep_bytes_per_sample"] {
        assert!(out.join(format!("plots/{stem}.png")).exists(), "{stem}");
    }
}

#[test]
fn a_terrain_sweep_gives_the_same_counts_as_each_point_run_alone() {
    let dir = tempfile::tempdir().unwrap();
    let swept = save(dir.path(), "swept", &small_terrain_sweep(&[5, 6]));
    run_with_threads(&swept, &dir.path().join("swept-out"), false, 3);
    let mut alone = small_terrain_sweep(&[6]);
    alone.as_object_mut().unwrap().remove("sweep");
    alone["terrain"]["synthetic"]["level"] = 6.into();
    let alone = save(dir.path(), "alone", &alone);
    run_with_threads(&alone, &dir.path().join("alone-out"), false, 1);
    let read = |path: &str| std::fs::read_to_string(dir.path().join(path)).unwrap();
    assert_eq!(
        counts_only(&read("swept-out/terrain.synthetic.level=6/frames.csv")),
        counts_only(&read("alone-out/frames.csv"))
    );
}

#[test]
fn a_point_that_cannot_run_is_named_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let path = save(dir.path(), "bad", &small_terrain_sweep(&[5, 20]));
    let out = dir.path().join("out");
    let error = run_experiment(
        &path,
        &RunOptions {
            out_dir: Some(out.clone()),
            check_meshes: false,
            threads: Some(1),
            command_line: None,
            max_frames: None,
            shard: None,
            timing: Default::default(),
        },
        &NoProgress,
    )
    .err()
    .expect("level 20 is out of range")
    .to_string();
    assert!(
        error
            .contains("(terrain.synthetic.level=20) terrain.synthetic.level: 20: expected 1 to 14"),
        "{error}"
    );
    assert!(!out.exists());
}

#[test]
fn the_max_plus_own_nesting_keeps_at_least_the_max_rules_vertices_every_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(8);
    experiment["algorithms"] = serde_json::json!([
        {"name": "lindstrom", "label": "lindstrom", "tau_px": 2, "block_level": 4,
         "sweep": {"nesting": ["max", "max_plus_own"]}},
        {"name": "roam", "label": "roam", "tau_px": 4, "culling_flags": true,
         "sweep": {"nesting": ["max", "max_plus_own"]}},
        {"name": "wu", "label": "wu", "tau_px": 4, "sweep": {"nesting": ["max", "max_plus_own"]}},
        {"name": "reference", "label": "reference", "tau_px": 4,
         "sweep": {"nesting": ["max", "max_plus_own"]}}
    ]);
    let path = save(dir.path(), "nesting", &experiment);
    let out = dir.path().join("out");
    run_with_threads(&path, &out, true, 2);
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    // Rows start with the label, quoted as CSV quotes it when it holds quotes or commas.
    let triangles = |label: &str| -> Vec<u64> {
        let quoted = format!("\"{}\",", label.replace('"', "\"\""));
        let plain = format!("{label},");
        csv.lines()
            .filter_map(|line| line.strip_prefix(&quoted).or(line.strip_prefix(&plain)))
            .map(|rest| rest.split(',').nth(1).unwrap().parse().unwrap())
            .collect()
    };
    for algorithm in ["lindstrom", "roam", "wu", "reference"] {
        let max = triangles(&format!("{algorithm} nesting=max"));
        let plus = triangles(&format!("{algorithm} nesting=max_plus_own"));
        assert_eq!(max.len(), 8, "{algorithm}: {csv}");
        assert_eq!(plus.len(), 8, "{algorithm}");
        assert!(
            max.iter().zip(&plus).all(|(m, p)| p >= m),
            "{algorithm}: {max:?} {plus:?}"
        );
        assert!(
            max.iter().zip(&plus).any(|(m, p)| p > m),
            "{algorithm}: {max:?} {plus:?}"
        );
    }
}

#[test]
fn a_run_killed_while_it_writes_its_outputs_leaves_the_previous_output_whole() {
    // The previous output, then a run killed the moment its staging folder appears: it has
    // finished simulating and is writing frames.csv, summary.json, report.md and the plots.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let short = save(dir.path(), "short", &short_quickstart(3));
    run_to(&short, &out, false);
    let snapshot = || {
        let mut files: Vec<(String, Vec<u8>)> = walk(&out)
            .into_iter()
            .map(|p| {
                let name = p.strip_prefix(&out).unwrap().display().to_string();
                (name, std::fs::read(&p).unwrap())
            })
            .collect();
        files.sort();
        files
    };
    let before = snapshot();
    assert!(before.iter().any(|(name, _)| name.starts_with("plots")));

    let longer_experiment = short_quickstart(40);
    let longer = save(dir.path(), "longer", &longer_experiment);
    let mut child = Command::new(env!("CARGO_BIN_EXE_roamsim"))
        .args([
            "run",
            longer.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--threads",
            "1",
        ])
        .spawn()
        .unwrap();
    let staging = dir.path().join(format!(".out.partial-{}", child.id()));
    let started = std::time::Instant::now();
    while !staging.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it started writing"
        );
        assert!(
            started.elapsed().as_secs() < 300,
            "the run never started writing"
        );
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        snapshot() == before,
        "a run killed while writing changed the previous output"
    );
    // The next run removes what the killed one left and writes a whole output.
    run_to(&longer, &out, false);
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        !names
            .iter()
            .any(|n| n.contains(".partial-") || n.contains(".old-")),
        "{names:?}"
    );
    let frames = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let entries = common::experiment::quickstart()["algorithms"]
        .as_array()
        .unwrap()
        .len();
    assert_eq!(
        frames.lines().count(),
        1 + 40 * entries,
        "a header and 40 frames of {entries} entries"
    );
}

/// Every file under `folder`, recursively.
fn walk(folder: &Path) -> Vec<std::path::PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(folder).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            files.extend(walk(&path));
        } else {
            files.push(path);
        }
    }
    files
}

#[test]
fn an_output_path_taken_by_a_file_is_refused_before_the_run_and_the_file_kept() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::write(&out, "the user's notes").unwrap();
    let short = save(dir.path(), "short", &short_quickstart(3));
    let options = RunOptions {
        out_dir: Some(out.clone()),
        check_meshes: false,
        threads: Some(1),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    let error = run_experiment(&short, &options, &NoProgress)
        .err()
        .expect("a file is in the way")
        .to_string();
    assert!(
        error.contains("out: a file (not a folder) is in the way of the output folder"),
        "{error}"
    );
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "the user's notes");
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
    assert_eq!(names.len(), 2, "only the experiment and the file");
}

/// Records whether the simulation started.
struct StartWatch(std::sync::atomic::AtomicBool);

impl roamsim::edge::session::ProgressSink for StartWatch {
    fn start(&self, _: u64) {
        self.0.store(true, std::sync::atomic::Ordering::SeqCst);
    }
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
}

fn run_refused(experiment: &Path, out: &Path) -> String {
    let watch = StartWatch(std::sync::atomic::AtomicBool::new(false));
    let options = RunOptions {
        out_dir: Some(out.to_path_buf()),
        check_meshes: false,
        threads: Some(1),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    let error = run_experiment(experiment, &options, &watch)
        .err()
        .expect("the output location is refused")
        .to_string();
    assert!(
        !watch.0.load(std::sync::atomic::Ordering::SeqCst),
        "refused only after simulating: {error}"
    );
    error
}

#[test]
fn a_folder_roamsim_did_not_write_is_refused_before_the_run_and_kept_whole() {
    // The case: --out names, by its absolute path, the folder holding the experiment,
    // notes and data in a sub-folder.
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("project");
    std::fs::create_dir_all(project.join("data")).unwrap();
    let experiment = save(&project, "short", &short_quickstart(3));
    std::fs::write(project.join("notes.txt"), "my notes").unwrap();
    std::fs::write(project.join("data/heights.asc"), "ncols 2").unwrap();
    let absolute = project.canonicalize().unwrap();
    let error = run_refused(&experiment, &absolute);
    assert!(error.contains("is not a roamsim output"), "{error}");
    assert!(error.contains("choose another --out"), "{error}");
    let mut names: Vec<String> = walk(&project)
        .iter()
        .map(|p| p.strip_prefix(&project).unwrap().display().to_string())
        .collect();
    names.sort();
    assert_eq!(names, ["data/heights.asc", "notes.txt", "short.json"]);
    let beside: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
    assert_eq!(beside.len(), 1, "nothing staged beside the folder");
}

#[test]
fn a_roamsim_output_is_replaced_but_not_once_the_user_added_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let short = save(dir.path(), "short", &short_quickstart(3));
    run_to(&short, &out, false);
    run_to(&short, &out, false); // its own output: replaced
    assert!(out.join(".roamsim-output").is_file());
    std::fs::write(out.join("plots/annotated.txt"), "mine").unwrap();
    let error = run_refused(&short, &out);
    assert!(error.contains("`plots/annotated.txt`"), "{error}");
    assert_eq!(
        std::fs::read_to_string(out.join("plots/annotated.txt")).unwrap(),
        "mine"
    );
}

#[test]
fn an_output_path_that_cannot_be_created_is_refused_before_the_run_naming_the_cause() {
    let dir = tempfile::tempdir().unwrap();
    let short = save(dir.path(), "short", &short_quickstart(3));
    std::fs::write(dir.path().join("a-file"), "x").unwrap();
    let error = run_refused(&short, &dir.path().join("a-file/results/out"));
    assert!(error.contains("a-file is a file, not a folder"), "{error}");
    if Path::new("/proc/self").is_dir() {
        let error = run_refused(&short, Path::new("/proc/roamsim-out"));
        assert!(
            error.starts_with(
                "/proc/roamsim-out: cannot create the output folder: /proc does \
                               not accept new folders"
            ),
            "{error}"
        );
    }
}

#[test]
fn zero_threads_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let short = save(dir.path(), "short", &short_quickstart(3));
    let options = RunOptions {
        out_dir: Some(dir.path().join("out")),
        check_meshes: false,
        threads: Some(0),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    let error = run_experiment(&short, &options, &NoProgress)
        .err()
        .expect("zero threads")
        .to_string();
    assert!(error.contains("--threads must be at least 1"), "{error}");
    assert!(!dir.path().join("out").exists());
}

#[test]
fn summary_json_records_the_command_threads_and_check_and_echoes_inputs_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(3);
    experiment["view"]["fovy_deg"] = serde_json::json!(60);
    let path = save(dir.path(), "short", &experiment);
    let out = dir.path().join("out");
    let output = Command::new(env!("CARGO_BIN_EXE_roamsim"))
        .args([
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args(["--check", "--threads", "2"])
        .output()
        .unwrap();
    assert!(output.status.success(), "{output:?}");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("every mesh valid"), "{stdout}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let run = &summary["run"];
    assert_eq!(run["threads"], 2);
    if cfg!(target_os = "linux") {
        // At least the 1025² terrain's heights were resident.
        let peak = run["peak_resident_bytes"].as_u64().unwrap();
        assert!(peak > 1025 * 1025 * 4, "{peak}");
    }
    assert_eq!(run["check_meshes"], true);
    let entries = summary["algorithms"].as_array().unwrap().len() as u64;
    assert_eq!(run["meshes_checked"], 3 * entries);
    let command: Vec<&str> = run["command_line"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_str().unwrap())
        .collect();
    assert_eq!(&command[1..3], ["run", path.to_str().unwrap()]);
    assert!(command.contains(&"--check"));
    assert_eq!(
        summary["view"]["fovy_deg"].as_f64(),
        Some(60.0),
        "not 59.99999999999999"
    );
}

#[test]
fn a_budget_the_entry_does_not_hold_is_flagged_in_the_report_and_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(20);
    experiment["algorithms"] = serde_json::json!([
        // 64² patches of at least two triangles each cannot come down to 100 triangles.
        {"name": "geomipmap", "label": "unreachable", "patch_level": 4, "target_triangles": 100},
        {"name": "reference", "tau_px": 2}
    ]);
    let path = save(dir.path(), "budgets", &experiment);
    let out = dir.path().join("out");
    run_to(&path, &out, false);
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let line = report
        .lines()
        .find(|l| l.starts_with("| unreachable | triangles | 100 |"))
        .unwrap_or_else(|| panic!("no goal row:\n{report}"));
    // No frame comes near: one reason, with the mean's distance in it.
    assert!(
        line.contains("**no**: no frame came within 25 % of the 100 goal (its mean triangles is"),
        "{line}"
    );
    assert!(line.contains("% over it) |"), "{line}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["algorithms"][0]["goal"]["held"], false);
    assert_eq!(summary["algorithms"][1]["goal"], serde_json::Value::Null);
}

#[test]
fn an_entry_outgrowing_the_declared_triangle_limit_stops_the_run_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = short_quickstart(40);
    experiment["algorithms"] = serde_json::json!([
        {"name": "roam", "label": "runaway", "tau_px": 1.0}
    ]);
    experiment["limits"] = serde_json::json!({"max_triangles": 20_000});
    let path = save(dir.path(), "runaway", &experiment);
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
    let error = run_experiment(&path, &options, &NoProgress)
        .err()
        .expect("stopped")
        .to_string();
    assert!(error.starts_with("runaway, frame "), "{error}");
    assert!(
        error.contains("over the experiment's limit of 20000 (limits.max_triangles)"),
        "{error}"
    );
    assert!(!out.exists(), "nothing written");

    experiment["limits"] = serde_json::json!({"max_triangles": 0});
    let path = save(dir.path(), "zero", &experiment);
    let error = roamsim::edge::experiment::load(&path)
        .err()
        .expect("invalid")
        .to_string();
    assert!(
        error.contains("limits.max_triangles: 0: expected at least 1"),
        "{error}"
    );
}

#[test]
fn an_output_path_ending_in_a_dot_names_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let short = save(dir.path(), "short", &short_quickstart(2));
    run_to(&short, &dir.path().join("out/."), false);
    assert!(dir.path().join("out/frames.csv").is_file());
    run_to(&short, &dir.path().join("out/."), false); // and replaces its own output
}
