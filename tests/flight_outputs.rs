//! The flight, seen (issue #32): `flight.csv` lists every frame of the flight with the bound its
//! step broke, in agreement with `validate`; `plots/map.png` and `.svg` show the terrain and the
//! flight; `roamsim info` reads a terrain as an experiment's `terrain.file` keys say and draws
//! its map.

mod common;

use common::cli::{files, roamsim};
use roamsim::edge::experiment::load;
use roamsim::edge::session::{NoProgress, RunOptions, run_experiment};
use serde_json::{Value, json};
use std::path::Path;

/// A synthetic 65² terrain and a recorded flight of ten frames 1 m apart looking east: a 1 km
/// teleport at frame 5, a quarter turn at frame 6, a 100 m climb at frame 8, against bounds of
/// 40 m, 20 m and 0.1 rad a frame.
fn tight_bounds_experiment(dir: &Path) -> std::path::PathBuf {
    let mut log = String::from("frame,x_m,y_m,z_m,yaw_deg,pitch_deg\n");
    for frame in 0..10 {
        let x = 300 + frame + if frame >= 5 { 600 } else { 0 };
        let z = 200 + if frame >= 8 { 100 } else { 0 };
        let yaw = if frame >= 6 { 90 } else { 0 };
        log.push_str(&format!("{frame},{x},600,{z},{yaw},-20\n"));
    }
    std::fs::write(dir.join("log.csv"), log).unwrap();
    let experiment = json!({
        "format_version": 1,
        "name": "tight",
        "terrain": { "synthetic": { "level": 6, "seed": 3, "amplitude_m": 60, "roughness": 0.7,
                                    "spacing_m": { "dx": 20, "dy": 20 } } },
        "view": { "width_px": 300, "height_px": 200, "fovy_deg": 60, "near_m": 1, "far_m": 2000 },
        "speed_bounds": { "horizontal_m_per_frame": 40, "vertical_m_per_frame": 20,
                          "rotation_rad_per_frame": 0.1 },
        "flight": { "path": { "recorded": { "path": "log.csv" } } },
        "algorithms": [ { "name": "reference", "tau_px": 4 } ],
        "effects": {}
    });
    common::experiment::save(dir, "tight", &experiment)
}

fn run_into(path: &Path, out: &Path) {
    let options = RunOptions {
        out_dir: Some(out.to_path_buf()),
        check_meshes: false,
        threads: Some(1),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    run_experiment(path, &options, &NoProgress).unwrap();
}

/// flight.csv as a header and rows of named fields.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

#[test]
fn flight_csv_has_a_row_per_frame_and_its_bound_column_agrees_with_validate() {
    let dir = tempfile::tempdir().unwrap();
    let path = tight_bounds_experiment(dir.path());
    let out = dir.path().join("out");
    run_into(&path, &out);
    let experiment = load(&path).unwrap();

    let (header, rows) = read_csv(&out.join("flight.csv"));
    let column = |name: &str| header.iter().position(|c| c == name).unwrap();
    assert_eq!(rows.len() as u64, experiment.flight.n_frames());
    for (frame, (row, pose)) in rows.iter().zip(experiment.flight.poses()).enumerate() {
        assert_eq!(row[column("frame")], frame.to_string());
        let number = |name: &str| row[column(name)].parse::<f64>().unwrap();
        assert_eq!(number("x_m"), pose.position.x);
        assert_eq!(number("y_m"), pose.position.y);
        assert_eq!(number("z_m"), pose.position.z);
        assert!((number("yaw_deg") - pose.yaw.to_degrees()).abs() < 1e-9);
        let ground = experiment.field.ground_height(pose.position.truncate());
        assert!((number("height_above_ground_m") - (pose.position.z - ground)).abs() < 1e-9);
    }
    let broken: Vec<(u64, String)> = rows
        .iter()
        .filter(|row| !row[column("broken_bounds")].is_empty())
        .map(|row| {
            (
                row[0].parse().unwrap(),
                row[column("broken_bounds")].clone(),
            )
        })
        .collect();
    let violations: Vec<(u64, String)> = experiment
        .violations
        .iter()
        .map(|v| (v.frame, v.broken.names().join("+")))
        .collect();
    assert_eq!(broken, violations);
    assert_eq!(
        broken,
        vec![
            (5, "horizontal".to_string()),
            (6, "rotation".to_string()),
            (8, "vertical".to_string())
        ]
    );

    let validate = roamsim(&["validate", path.to_str().unwrap()], dir.path());
    assert!(validate.status.success(), "{validate:?}");
    let stdout = String::from_utf8(validate.stdout).unwrap();
    for expected in [
        "3 frame(s) break the speed or rotation bounds (first: frame 5, horizontal)",
        "horizontal in 1 frame(s) (first: frame 5)",
        "rotation in 1 frame(s) (first: frame 6)",
        "vertical in 1 frame(s) (first: frame 8)",
        "601 m (frame 5)",
        "bound 40 m",
        "100 m (frame 8)",
        "bound 0.1 rad",
    ] {
        assert!(stdout.contains(expected), "{expected:?} not in {stdout}");
    }
}

/// A PNG's size and whether its pixels are not all one colour.
fn png_size_and_variety(path: &Path) -> ((u32, u32), bool) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    let pixels = &pixels[..info.buffer_size()];
    let first = &pixels[..3];
    let varied = pixels.chunks(3).any(|p| p != first);
    ((info.width, info.height), varied)
}

#[test]
fn every_point_of_a_sweep_writes_its_flight_and_its_map() {
    let dir = tempfile::tempdir().unwrap();
    let path = tight_bounds_experiment(dir.path());
    let mut experiment: Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    experiment["sweep"] = json!({ "view.fovy_deg": [40, 60] });
    let path = common::experiment::save(dir.path(), "swept", &experiment);
    let out = dir.path().join("out");
    run_into(&path, &out);
    let written = files(&out);
    let named = |name: &str| -> Vec<&std::path::PathBuf> {
        written.iter().filter(|p| p.ends_with(name)).collect()
    };
    assert_eq!(named("flight.csv").len(), 2, "{written:?}");
    assert_eq!(named("plots/map.png").len(), 2, "{written:?}");
    assert_eq!(named("plots/map.svg").len(), 2, "{written:?}");
    for png in named("plots/map.png") {
        let (size, varied) = png_size_and_variety(&out.join(png));
        assert_eq!(size, (1200, 1000));
        assert!(varied, "{png:?} is one colour");
    }
    for svg in named("plots/map.svg") {
        let text = std::fs::read_to_string(out.join(svg)).unwrap();
        assert!(text.starts_with("<svg") && text.trim_end().ends_with("</svg>"));
        assert!(text.contains("data:image/png;base64,"), "no terrain image");
        assert!(
            text.contains("<polyline") || text.contains("<path"),
            "no flight path"
        );
    }
}

#[test]
fn no_map_is_drawn_when_plots_are_off() {
    let dir = tempfile::tempdir().unwrap();
    let path = tight_bounds_experiment(dir.path());
    let mut experiment: Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    experiment["outputs"] = json!({ "plots": false });
    let path = common::experiment::save(dir.path(), "quiet", &experiment);
    let out = dir.path().join("out");
    run_into(&path, &out);
    assert!(out.join("flight.csv").is_file());
    assert!(!out.join("plots").exists());
}

/// A 33 × 17 raw file of unsigned 16-bit heights 0, 100, 200, … (u16le).
fn raw_terrain(dir: &Path) -> std::path::PathBuf {
    let raw = dir.join("heights.raw");
    let samples: Vec<u8> = (0..33 * 17)
        .flat_map(|k: u16| (k * 100).to_le_bytes())
        .collect();
    std::fs::write(&raw, samples).unwrap();
    raw
}

const RAW_LAYOUT: [&str; 6] = [
    "--raw-columns",
    "33",
    "--raw-rows",
    "17",
    "--raw-sample",
    "u16le",
];

#[test]
fn info_reads_heights_with_the_experiments_scale_offset_and_spacing() {
    let dir = tempfile::tempdir().unwrap();
    let raw = raw_terrain(dir.path());
    let raw = raw.to_str().unwrap();
    let info = |extra: &[&str]| {
        let args: Vec<&str> = ["info", raw]
            .iter()
            .chain(RAW_LAYOUT.iter())
            .chain(extra)
            .copied()
            .collect();
        let output = roamsim(&args, dir.path());
        assert!(output.status.success(), "{output:?}");
        String::from_utf8(output.stdout).unwrap()
    };
    let stored = info(&[]);
    assert!(stored.contains("0 m to 56000 m"), "{stored}");
    let scaled = info(&[
        "--height-scale",
        "0.1",
        "--height-offset-m",
        "-50",
        "--spacing-m",
        "92.7",
    ]);
    assert!(scaled.contains("-50 m to 5550 m"), "{scaled}");
    assert!(
        scaled.contains("dx 92.700 m, dy 92.700 m (from the experiment)"),
        "{scaled}"
    );

    let refused = roamsim(
        &["info", raw, "--height-scale", "0"]
            .iter()
            .chain(RAW_LAYOUT.iter())
            .copied()
            .collect::<Vec<_>>(),
        dir.path(),
    );
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert!(stderr.contains("terrain.file.height_scale"), "{stderr}");
}

#[test]
fn info_draws_the_map_of_a_terrain_and_of_an_experiments_flight() {
    let dir = tempfile::tempdir().unwrap();
    let raw = raw_terrain(dir.path());
    let map = dir.path().join("plan.png");
    let args: Vec<&str> = [
        "info",
        raw.to_str().unwrap(),
        "--map",
        map.to_str().unwrap(),
    ]
    .iter()
    .chain(RAW_LAYOUT.iter())
    .copied()
    .collect();
    let output = roamsim(&args, dir.path());
    assert!(output.status.success(), "{output:?}");
    let (size, varied) = png_size_and_variety(&map);
    assert_eq!(size, (1200, 1000));
    assert!(varied);

    let experiment = tight_bounds_experiment(dir.path());
    let svg = dir.path().join("flight.svg");
    let output = roamsim(
        &[
            "info",
            experiment.to_str().unwrap(),
            "--map",
            svg.to_str().unwrap(),
        ],
        dir.path(),
    );
    assert!(output.status.success(), "{output:?}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("The flight over"), "no title");

    let refused = roamsim(
        &["info", experiment.to_str().unwrap(), "--map", "plan.gif"],
        dir.path(),
    );
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains(".png or .svg"));
}
