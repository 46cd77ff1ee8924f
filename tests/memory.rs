//! What a run holds in memory, measured by the operating system in a process of its own (cargo
//! runs tests as threads of one process, so the binary is spawned): a chunked-only run of a
//! 4097² terrain peaks within 7 bytes per sample, loading included; Lindstrom's and ROAM's
//! preprocessing hold nothing beyond the state their frames keep; and a terrain too large for
//! the in-memory hierarchy is refused before it is read, naming the limit and the memory.

mod common;

use common::cli::{fails_with, roamsim, succeeds};
use serde_json::{Value, json};
use std::path::Path;

/// An experiment with one chunked LOD entry over `terrain`, 20 frames of a circle.
fn chunked_experiment(name: &str, terrain: Value, centre_m: f64) -> Value {
    let chunked = json!({"name": "chunked", "label": "chunked", "chunk_level": 4,
                         "box_culling": true, "tau_px": 14.1});
    experiment(name, terrain, centre_m, chunked)
}

/// An experiment with one `entry` over `terrain`, 20 frames of a circle.
fn experiment(name: &str, terrain: Value, centre_m: f64, entry: Value) -> Value {
    json!({
        "format_version": 1,
        "name": name,
        "terrain": terrain,
        "view": {"width_px": 600, "height_px": 600, "fovy_deg": 60, "near_m": 1, "far_m": 40000},
        "speed_bounds": {"horizontal_m_per_frame": 25, "vertical_m_per_frame": 12.5,
                         "rotation_rad_per_frame": 0.0027},
        "flight": {"frames": 20, "look": {"along_path": {"pitch_deg": -20}},
                   "path": {"circle": {"centre_m": [centre_m, centre_m], "radius_m": 8000,
                                       "altitude_m": 3000, "frames_per_lap": 2400}}},
        "algorithms": [entry],
        "outputs": {"plots": false}
    })
}

fn save(dir: &Path, name: &str, experiment: &Value) {
    std::fs::write(dir.join(name), experiment.to_string()).unwrap();
}

#[test]
fn a_chunked_run_of_a_4097_square_terrain_peaks_within_7_bytes_per_sample() {
    let dir = tempfile::tempdir().unwrap();
    let terrain = json!({"synthetic": {"level": 12, "seed": 2001, "amplitude_m": 300,
        "amplitude_scale_m": 30720, "roughness": 0.5, "spacing_m": {"dx": 30, "dy": 30}}});
    save(
        dir.path(),
        "chunked-4097.json",
        &chunked_experiment("chunked-4097", terrain, 61_440.0),
    );
    succeeds(&["run", "chunked-4097.json", "--out", "out"], dir.path());
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let samples = 4097.0 * 4097.0;
    let Some(peak) = summary["run"]["peak_resident_bytes"].as_f64() else {
        // Not Linux: the system does not report a resident set, and the summary says null.
        assert!(summary["run"]["peak_resident_bytes"].is_null());
        return;
    };
    // The heights alone are 4 bytes per sample.
    assert!(peak / samples > 4.0, "{} B/sample", peak / samples);
    assert!(peak / samples <= 7.0, "peak {} B/sample", peak / samples);
    // During the frames the run holds the heights (no node table: chunked LOD reads none) and
    // the entry's own state; the measure is at most the peak.
    assert_eq!(summary["terrain"]["bytes_per_sample"].as_f64(), Some(4.0));
    let frames = summary["run"]["frames_resident_bytes"].as_f64().unwrap();
    assert!(frames <= peak && frames / samples > 4.0, "{frames} bytes");
}

/// `study-scaling`'s synthetic terrain of side 2^`level` + 1 and its centre in metres.
fn synthetic(level: u32) -> (Value, f64) {
    let terrain = json!({"synthetic": {"level": level, "seed": 2001, "amplitude_m": 300,
        "amplitude_scale_m": 30720, "roughness": 0.5, "spacing_m": {"dx": 30, "dy": 30}}});
    (terrain, f64::from(1u32 << level) * 30.0 / 2.0)
}

/// Runs `entry` alone over the terrain of side 2^`level` + 1 on one thread and returns
/// summary.json's peak and frames resident sets in bytes per sample (`None` where the system
/// reports none).
fn resident_per_sample(level: u32, entry: Value) -> Option<(f64, f64)> {
    let dir = tempfile::tempdir().unwrap();
    let (terrain, centre_m) = synthetic(level);
    save(
        dir.path(),
        "one-entry.json",
        &experiment("one-entry", terrain, centre_m, entry),
    );
    let args = ["run", "one-entry.json", "--out", "out", "--threads", "1"];
    succeeds(&args, dir.path());
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let samples = f64::from((1u32 << level) + 1).powi(2);
    let peak = summary["run"]["peak_resident_bytes"].as_f64()?;
    let frames = summary["run"]["frames_resident_bytes"].as_f64().unwrap();
    Some((peak / samples, frames / samples))
}

/// Whether the run's peak is within the resident set of its frames and a tenth: no
/// preprocessing transient above the state the entry keeps. The terrain must be large enough
/// for a transient to show: what the allocator keeps after a transient is freed counts in the
/// frames' resident set too, and weighs less the more samples there are.
fn peaks_at_its_frames_state(level: u32, entry: Value, state_per_sample: f64) {
    let Some((peak, frames)) = resident_per_sample(level, entry) else {
        return; // Not Linux: no resident set to read.
    };
    // The frames hold the heights (4 bytes per sample) and the entry's own state.
    assert!(frames > 4.0 + state_per_sample, "frames {frames} B/sample");
    assert!(
        peak <= frames * 1.1,
        "peak {peak} B/sample against {frames} B/sample during the frames"
    );
}

#[test]
fn lindstroms_preprocessing_peaks_within_its_frames_resident_set_and_a_tenth() {
    // Its δ-sorted blocks keep 8 bytes per sample; building them held 16 more for a moment.
    let lindstrom = json!({"name": "lindstrom", "label": "lindstrom", "block_level": 4,
                           "tau_px": 1.68});
    peaks_at_its_frames_state(11, lindstrom, 8.0);
}

#[test]
fn roams_preprocessing_peaks_within_its_frames_resident_set_and_a_tenth() {
    // Its per-triangle thicknesses keep 8 bytes per sample; their build held 4–8 more, which
    // at 2049² the frames' resident set kept too (freed, not returned): hence 4097².
    let roam = json!({"name": "roam", "label": "roam", "culling_flags": true, "tau_px": 13.2});
    peaks_at_its_frames_state(12, roam, 8.0);
}

#[test]
fn a_40000_square_raw_terrain_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    // 3.2 GB declared, not one byte written: a sparse file.
    let file = std::fs::File::create(dir.path().join("big.raw")).unwrap();
    file.set_len(40_000 * 40_000 * 2).unwrap();
    let terrain = json!({"file": {"path": "big.raw", "fit": "pad",
        "format": {"raw": {"columns": 40000, "rows": 40000, "sample": "i16le", "north_first": true}},
        "spacing_m": {"dx": 30, "dy": 30}}});
    save(
        dir.path(),
        "big.json",
        &chunked_experiment("big", terrain, 600_000.0),
    );
    let expected = [
        "terrain.file",
        "40000×40000 samples, 65537² once padded",
        "32769²",
        "would need about 2",
        "GB",
        "crop",
        "on demand",
    ];
    fails_with(&["validate", "big.json"], dir.path(), &expected);
    fails_with(&["run", "big.json", "--out", "out"], dir.path(), &expected);
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_side_above_the_lattice_limit_is_refused_with_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let file = std::fs::File::create(dir.path().join("big.raw")).unwrap();
    file.set_len(40_000 * 3 * 2).unwrap();
    // 40 000 columns of 3 rows: padding would make 65 537²; the refusal comes before reading.
    let terrain = json!({"file": {"path": "big.raw", "fit": "pad",
        "format": {"raw": {"columns": 40000, "rows": 3, "sample": "i16le", "north_first": true}},
        "spacing_m": {"dx": 30, "dy": 30}}});
    save(
        dir.path(),
        "wide.json",
        &chunked_experiment("wide", terrain, 600_000.0),
    );
    let output = roamsim(&["validate", "wide.json"], dir.path());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("32769²"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
