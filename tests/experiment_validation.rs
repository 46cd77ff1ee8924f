//! Experiment files checked before anything runs (SPEC §8; `docs/experiment-format.md`): every
//! error names the file, the field path and what was expected, and every problem in a file is
//! reported at once.

mod common;

use common::experiment::{quickstart, save};
use roamsim::edge::experiment::{BoundOrigin, ExperimentError, load};
use roamsim::sim::flight::largest_turn;
use serde_json::{Value, json};

/// Loads an edited quickstart and returns its problems as `field: problem` lines.
fn problems_of(edit: impl FnOnce(&mut Value)) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = quickstart();
    edit(&mut experiment);
    let path = save(dir.path(), "edited", &experiment);
    match load(&path) {
        Ok(_) => Vec::new(),
        Err(ExperimentError { file, problems }) => {
            assert_eq!(file, path, "the error names the experiment file");
            problems
                .iter()
                .map(|p| format!("{}: {}", p.field, p.problem))
                .collect()
        }
    }
}

fn assert_one_problem(edit: impl FnOnce(&mut Value), field: &str, expected: &str) {
    let problems = problems_of(edit);
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert!(
        problems[0].starts_with(&format!("{field}: ")) && problems[0].contains(expected),
        "expected {field}: …{expected}…, got {problems:#?}"
    );
}

#[test]
fn the_shipped_quickstart_is_valid() {
    assert_eq!(problems_of(|_| {}), Vec::<String>::new());
}

/// Every experiment the project ships parses and checks (stages 1 and 2, every sweep point; the
/// terrains are not read, so the 16385² points cost nothing here).
#[test]
fn every_shipped_experiment_is_valid() {
    let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments");
    let mut checked = 0;
    for file in std::fs::read_dir(&folder).unwrap() {
        let path = file.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            if let Err(error) = roamsim::edge::experiment::plan(&path) {
                panic!("{error}");
            }
            checked += 1;
        }
    }
    assert!(
        checked >= 20,
        "only {checked} experiments found in {folder:?}"
    );
}

#[test]
fn a_future_format_version_is_refused() {
    assert_one_problem(
        |e| e["format_version"] = json!(2),
        "format_version",
        "expected 1",
    );
}

#[test]
fn a_misspelt_field_is_named_with_its_path() {
    assert_one_problem(
        |e| {
            e["view"]["fov_deg"] = json!(60);
        },
        "view.fov_deg",
        "unknown field `fov_deg`, expected one of `width_px`",
    );
}

#[test]
fn a_wrong_type_is_named_with_its_path() {
    assert_one_problem(
        |e| e["flight"]["path"]["circle"]["radius_m"] = json!("far"),
        "flight.path.circle.radius_m",
        "expected f64",
    );
}

#[test]
fn every_semantic_problem_is_reported_at_once() {
    let problems = problems_of(|e| {
        e["view"]["fovy_deg"] = json!(180);
        e["view"]["far_m"] = json!(0.5);
        e["effects"]["audit"]["stride"] = json!(0);
        e["name"] = json!("../escape");
    });
    let fields: Vec<&str> = problems
        .iter()
        .map(|p| p.split(": ").next().unwrap())
        .collect();
    assert_eq!(
        fields,
        [
            "name",
            "view.fovy_deg",
            "view.far_m",
            "effects.audit.stride"
        ],
        "{problems:#?}"
    );
    assert!(problems[1].contains("strictly between 0 and 180"));
}

#[test]
fn an_unknown_algorithm_lists_the_known_ones() {
    assert_one_problem(
        |e| e["algorithms"][1]["name"] = json!("roam2"),
        "algorithms[1].name",
        "expected one of reference",
    );
}

#[test]
fn duplicate_labels_are_refused() {
    assert_one_problem(
        |e| e["algorithms"][1]["label"] = json!("reference τ=2px"),
        "algorithms[1].label",
        "expected unique labels",
    );
}

#[test]
fn an_algorithm_parameter_error_carries_the_entry_path() {
    assert_one_problem(
        |e| e["algorithms"][0]["tau_px"] = json!(-1),
        "algorithms[0].tau_px",
        "at least 0 pixels",
    );
    assert_one_problem(
        |e| e["algorithms"][0]["zone"] = json!("round"),
        "algorithms[0].zone",
        "unknown variant `round`, expected `paper` or `conservative`",
    );
}

#[test]
fn a_missing_frame_count_is_reported() {
    assert_one_problem(
        |e| {
            e["flight"].as_object_mut().unwrap().remove("frames");
        },
        "flight.frames",
        "expected the number of frames",
    );
}

#[test]
fn waypoints_out_of_order_are_reported_by_index() {
    assert_one_problem(
        |e| {
            e["flight"] = json!({
                "look": {"along_path": {"pitch_deg": -10}},
                "path": {"waypoints": {"interpolation": "linear", "points": [
                    {"frame": 0, "position_m": [0, 0, 1000]},
                    {"frame": 10, "position_m": [100, 0, 1000]},
                    {"frame": 5, "position_m": [200, 0, 1000]}
                ]}}
            });
        },
        "flight.path.waypoints.points[2].frame",
        "expected a frame after the previous waypoint's (10)",
    );
}

#[test]
fn a_missing_terrain_file_is_named() {
    let problems = problems_of(|e| e["terrain"]["file"]["path"] = json!("nowhere/N00E000.hgt"));
    assert_eq!(problems.len(), 1);
    assert!(
        problems[0].starts_with("terrain.file: ")
            && problems[0].contains("nowhere/N00E000.hgt")
            && problems[0].contains("cannot read the file"),
        "{problems:#?}"
    );
}

#[test]
fn a_file_that_is_not_json_reports_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("broken.json");
    std::fs::write(&path, "{\"format_version\": 1,\n  \"name\": }").unwrap();
    let error = load(&path)
        .err()
        .expect("the experiment is invalid")
        .to_string();
    assert!(
        error.contains("broken.json") && error.contains("line 2"),
        "{error}"
    );
}

#[test]
fn a_recorded_log_with_a_nan_is_refused_before_anything_runs() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("log.csv"),
        "frame,x_m,y_m,z_m,yaw_deg,pitch_deg\n0,1000,1000,2000,0,-10\n1,1001,1000,nan,0,-10\n",
    )
    .unwrap();
    let mut experiment = quickstart();
    experiment["flight"] = json!({"path": {"recorded": {"path": "log.csv"}}});
    let path = save(dir.path(), "recorded", &experiment);
    let error = load(&path)
        .err()
        .expect("the experiment is invalid")
        .to_string();
    assert!(
        error.contains("flight.path.recorded.path") && error.contains("log.csv, line 3"),
        "{error}"
    );
}

#[test]
fn a_negative_rotation_bound_is_reported_with_its_path() {
    assert_one_problem(
        |e| e["speed_bounds"]["rotation_rad_per_frame"] = json!(-0.1),
        "speed_bounds.rotation_rad_per_frame",
        "expected a finite number of at least 0",
    );
}

#[test]
fn an_experiment_without_a_rotation_bound_gets_its_flights_largest_turn() {
    // The quickstart's circle, looking along its path, turns by the same angle every frame.
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = quickstart();
    experiment["speed_bounds"]
        .as_object_mut()
        .unwrap()
        .remove("rotation_rad_per_frame");
    let loaded = load(&save(dir.path(), "undeclared", &experiment)).unwrap();
    assert_eq!(loaded.rotation_bound, BoundOrigin::Derived);
    assert_eq!(loaded.speed.rotation, largest_turn(&loaded.flight));
    let lap = experiment["flight"]["path"]["circle"]["frames_per_lap"]
        .as_f64()
        .unwrap();
    // Yawing by 2π/lap a frame, pitched 15° down: the look direction turns by
    // 2·asin(cos 15° · sin(π/lap)), a little under the declared 0.0033.
    let per_frame = 2.0 * (15f64.to_radians().cos() * (std::f64::consts::PI / lap).sin()).asin();
    assert!(
        (loaded.speed.rotation - per_frame).abs() < 1e-9 * per_frame,
        "{} against {per_frame}",
        loaded.speed.rotation
    );
    assert!(loaded.violations.iter().all(|v| !v.broken.rotation));
}

#[test]
fn a_declared_rotation_bound_is_kept_as_declared() {
    let dir = tempfile::tempdir().unwrap();
    let experiment = quickstart();
    let loaded = load(&save(dir.path(), "declared", &experiment)).unwrap();
    assert_eq!(loaded.rotation_bound, BoundOrigin::Declared);
    assert_eq!(
        loaded.speed.rotation,
        experiment["speed_bounds"]["rotation_rad_per_frame"]
            .as_f64()
            .unwrap()
    );
}

#[test]
fn wu_refinement_and_tau_recentring_are_checked_against_what_they_need() {
    assert_one_problem(
        |e| e["algorithms"][2]["recentre_tau"] = json!(true),
        "algorithms[2].recentre_tau",
        "expected budget_triangles as well",
    );
    assert_one_problem(
        |e| e["algorithms"][3]["recentre_tau_window_frames"] = json!(32),
        "algorithms[3].recentre_tau_window_frames",
        "expected \"recentre_tau\": true as well",
    );
    assert_one_problem(
        |e| e["algorithms"][3]["refine"] = json!("behind"),
        "algorithms[3].refine",
        "unknown variant `behind`, expected `in_view` or `everywhere`",
    );
}

#[test]
fn wu_refines_in_view_by_default_when_it_culls_by_the_cone() {
    use roamsim::sim::algorithm::{AlgorithmConfig, Refinement};
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = quickstart();
    experiment["algorithms"] = json!([
        { "name": "wu", "label": "plain", "tau_px": 2 },
        { "name": "wu", "label": "cone", "tau_px": 2, "cone_culling": true },
        { "name": "wu", "label": "in view", "tau_px": 2, "refine": "in_view" },
        { "name": "wu", "label": "cone everywhere", "tau_px": 2, "cone_culling": true,
          "refine": "everywhere" },
        { "name": "wu", "label": "in view, whole mesh", "tau_px": 2, "refine": "in_view",
          "cone_culling": false },
    ]);
    let loaded = load(&save(dir.path(), "defaults", &experiment)).unwrap();
    let modes: Vec<(Refinement, bool)> = loaded
        .algorithms
        .iter()
        .map(|spec| match spec.config {
            AlgorithmConfig::Wu(c) => (c.refine, c.cone_culling),
            _ => unreachable!("only wu entries"),
        })
        .collect();
    assert_eq!(
        modes,
        vec![
            (Refinement::Everywhere, false),
            (Refinement::InView, true),
            (Refinement::InView, true),
            (Refinement::Everywhere, true),
            (Refinement::InView, false),
        ]
    );
}

#[test]
fn mesh_exports_name_entries_that_exist_and_frames_inside_the_flight() {
    assert_eq!(
        problems_of(|e| {
            e["outputs"] =
                json!({"meshes": {"frames": [0, 399], "entries": ["wu", "roam target=6000"]}})
        }),
        Vec::<String>::new()
    );
    assert_one_problem(
        |e| e["outputs"] = json!({"meshes": {"frames": [3], "entries": ["wu", "röttger"]}}),
        "outputs.meshes.entries[1]",
        "\"röttger\" names no algorithm entry",
    );
    assert_one_problem(
        |e| e["outputs"] = json!({"meshes": {"frames": []}}),
        "outputs.meshes.frames",
        "empty: expected at least one frame",
    );
    assert_one_problem(
        |e| e["outputs"] = json!({"meshes": {"frames": [12, 400]}}),
        "outputs.meshes.frames",
        "400 is past the flight's last frame 399",
    );
}

#[test]
fn popping_is_an_option_of_the_audit() {
    assert_eq!(
        problems_of(|e| e["effects"]["audit"]["popping"] = json!(true)),
        Vec::<String>::new()
    );
    assert_one_problem(
        |e| e["effects"]["popping"] = json!(true),
        "effects.popping",
        "unknown field `popping`, expected `audit` or `culling`",
    );
}

/// The quickstart's first entry replaced by a `chunked` entry with runtime detail and
/// out-of-core loading, as `detail` and `loading` say.
fn chunked_with(e: &mut Value, detail: Value, loading: Value) {
    e["algorithms"][0] = json!({
        "name": "chunked", "label": "chunked", "tau_px": 4,
        "detail": detail, "loading": loading
    });
}

fn good_detail() -> Value {
    json!({"levels": 2, "seed": 1, "amplitude_m": 3, "max_queued_chunks": 8,
           "cache_chunks": 256})
}

fn good_loading() -> Value {
    json!({"latency_frames": 3, "bandwidth_chunks_per_frame": 16, "resident_chunks": 512})
}

#[test]
fn chunked_detail_and_loading_are_checked_field_by_field() {
    assert_eq!(
        problems_of(|e| chunked_with(e, good_detail(), good_loading())),
        Vec::<String>::new()
    );
    let mut bad_detail = good_detail();
    bad_detail["levels"] = json!(0);
    bad_detail["amplitude_m"] = json!(-1);
    bad_detail["roughness"] = json!(1.5);
    bad_detail["max_queued_chunks"] = json!(3);
    bad_detail["max_speed_per_spacing"] = json!(0);
    bad_detail["max_created_per_frame"] = json!(8);
    bad_detail["cache_chunks"] = json!(0);
    let mut bad_loading = good_loading();
    bad_loading["latency_frames"] = json!(0);
    bad_loading["bandwidth_chunks_per_frame"] = json!(2);
    bad_loading["resident_chunks"] = json!(1);
    let problems = problems_of(|e| chunked_with(e, bad_detail, bad_loading));
    for expected in [
        "algorithms[0].detail.levels: 0: expected 1 to 8 synthesised levels",
        "algorithms[0].detail.amplitude_m: -1: expected a finite amplitude of at least 0 m",
        "algorithms[0].detail.roughness: 1.5: expected a ratio from 0 to 1",
        "algorithms[0].detail.max_queued_chunks: 3: expected at least 4 chunks",
        "algorithms[0].detail.max_speed_per_spacing: 0: expected a finite number of sample \
         spacings per frame above 0",
        "algorithms[0].detail.max_created_per_frame: 8: no longer a key; the creation limit is \
         `max_queued_chunks`",
        "algorithms[0].detail.cache_chunks: 0: expected at least 4 chunks",
        "algorithms[0].loading.latency_frames: 0: expected at least 1 frame",
        "algorithms[0].loading.bandwidth_chunks_per_frame: 2: expected at least 4 chunks",
        "algorithms[0].loading.resident_chunks: 1: expected at least 4 chunks",
    ] {
        assert!(
            problems.iter().any(|p| p.starts_with(expected)),
            "{expected} not in {problems:#?}"
        );
    }
    assert_eq!(problems.len(), 10, "{problems:#?}");
    let mut missing_seed = good_detail();
    missing_seed.as_object_mut().unwrap().remove("seed");
    assert_one_problem(
        |e| chunked_with(e, missing_seed, good_loading()),
        "algorithms[0].detail",
        "missing field `seed`",
    );
    assert_one_problem(
        |e| e["effects"]["audit"]["detail_stride"] = json!(0),
        "effects.audit.detail_stride",
        "0: expected at least 1",
    );
}

/// A 9 × 9 ESRI ASCII grid of 3-arc-second cells at 8.5° E, 47° N, written into `dir`.
fn degree_grid(dir: &std::path::Path) -> std::path::PathBuf {
    let mut text =
        String::from("ncols 9\nnrows 9\nxllcorner 8.5\nyllcorner 47.0\ncellsize 0.000833333333\n");
    for j in 0..9 {
        let row: Vec<String> = (0..9).map(|i| (400 + 3 * i + 5 * j).to_string()).collect();
        text.push_str(&(row.join(" ") + "\n"));
    }
    let path = dir.join("grid.asc");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_grid_in_degrees_is_never_read_as_metres_without_a_word() {
    let dir = tempfile::tempdir().unwrap();
    let grid = degree_grid(dir.path());
    let mut experiment = quickstart();
    experiment["terrain"] = json!({"file": {"path": grid.display().to_string(), "fit": "pad"}});
    let path = save(dir.path(), "degrees", &experiment);
    let error = load(&path)
        .err()
        .expect("refused without a .prj")
        .to_string();
    assert!(error.contains("terrain.file.spacing_m"), "{error}");
    assert!(error.contains("may be degrees"), "{error}");

    std::fs::write(
        dir.path().join("grid.prj"),
        "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\"],UNIT[\"degree\",0.0174532925199433]]",
    )
    .unwrap();
    let loaded = load(&path).expect("converted with the .prj");
    let spacing = loaded.terrain.spacing;
    assert!((spacing.dy - 92.6).abs() < 0.1, "{spacing:?}");
    assert!((spacing.dx - 63.1).abs() < 0.2, "{spacing:?}");
    assert!(
        loaded
            .terrain
            .spacing_from
            .contains("geographic, from the .prj"),
        "{}",
        loaded.terrain.spacing_from
    );
}
