//! An experiment whose terrain is a chunk pyramid (`"terrain": {"pyramid": {"file": …}}`): it
//! draws exactly the meshes, counts and audit figures of the same chunked entry flying the raw
//! file in memory, without ever holding the whole terrain; entries that need the whole terrain,
//! a chunk level other than the pyramid's, and missing or damaged pyramids are refused before
//! anything runs, naming the entry, the file and the field.

mod common;

use common::cli::{fails_with, frames_without_timing, roamsim};
use common::experiment::save;
use roamsim::edge::experiment::plan;
use roamsim::edge::pyramid::{PyramidFile, PyramidSamples, RawSource, prepare_from_raw};
use roamsim::edge::session::{NoProgress, RunOptions, run_experiment};
use roamsim::edge::terrain_readers::{RawLayout, RawSample};
use roamsim::sim::terrain::paged::PagedSamples;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// A 257² terrain of integer heights, written south row first as little-endian `i16`, and its
/// pyramid in chunks of 17² (chunk level 4), in a fresh folder.
struct Prepared {
    folder: tempfile::TempDir,
}

const LEVEL: u32 = 8;
const CHUNK_LEVEL: u32 = 4;

impl Prepared {
    fn new() -> Prepared {
        let folder = tempfile::tempdir().unwrap();
        let side = (1usize << LEVEL) + 1;
        let mut bytes = Vec::with_capacity(side * side * 2);
        for j in 0..side {
            for i in 0..side {
                let (x, y) = (i as f64, j as f64);
                let z = 400.0 * (0.021 * x).sin() * (0.017 * y).cos()
                    + 60.0 * (0.13 * x + 0.07 * y).sin()
                    + ((i * 7919 + j * 104_729) % 13) as f64;
                bytes.extend_from_slice(&(z.round() as i16).to_le_bytes());
            }
        }
        let raw = folder.path().join("terrain.raw");
        std::fs::write(&raw, bytes).unwrap();
        let source = RawSource {
            path: raw,
            layout: RawLayout {
                columns: side,
                rows: side,
                sample: RawSample::I16Le,
                north_first: false,
            },
            spacing: roamsim::sim::terrain::Spacing { dx: 30.0, dy: 30.0 },
        };
        let pyramid = folder.path().join("terrain.pyr");
        prepare_from_raw(&source, CHUNK_LEVEL, &pyramid, &mut |_, _| {}).unwrap();
        Prepared { folder }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.folder.path().join(name)
    }

    /// The experiment over `terrain` with `algorithms`: 40 frames across the terrain, 25 m
    /// above the ground, audited (stride 1) and culled, meshes exported at three frames.
    fn experiment(&self, name: &str, terrain: Value, algorithms: Value) -> PathBuf {
        let experiment = json!({
            "format_version": 1,
            "name": "pyramid-or-file",
            "terrain": terrain,
            "view": { "width_px": 640, "height_px": 480, "fovy_deg": 60, "near_m": 0.5, "far_m": 8000 },
            "speed_bounds": { "horizontal_m_per_frame": 200, "vertical_m_per_frame": 200 },
            "flight": {
                "frames": 40,
                "altitude": "above_ground",
                "look": { "along_path": { "pitch_deg": -10 } },
                "path": { "line": { "from_m": [600, 700, 25], "to_m": [7000, 6500, 25] } }
            },
            "algorithms": algorithms,
            "effects": { "audit": { "stride": 1 }, "culling": true },
            "outputs": { "plots": false, "meshes": { "frames": [0, 17, 39] } }
        });
        save(self.folder.path(), name, &experiment)
    }

    fn raw_terrain(&self) -> Value {
        json!({ "file": {
            "path": "terrain.raw",
            "format": { "raw": { "columns": 257, "rows": 257, "sample": "i16le", "north_first": false } },
            "spacing_m": { "dx": 30, "dy": 30 },
            "fit": "pad"
        } })
    }

    fn pyramid_terrain(&self) -> Value {
        json!({ "pyramid": { "file": "terrain.pyr" } })
    }
}

/// A chunked entry with out-of-core loading, of chunk level `chunk_level`.
fn chunked_loading(label: &str, chunk_level: u32) -> Value {
    json!({
        "name": "chunked", "label": label, "tau_px": 2, "chunk_level": chunk_level,
        "box_culling": true, "front_to_back": true, "morph": true, "skirt_depth": "covering",
        "loading": { "latency_frames": 2, "bandwidth_chunks_per_frame": 8, "resident_chunks": 64 }
    })
}

fn run(experiment: &Path, out: &Path) {
    let options = RunOptions {
        out_dir: Some(out.to_path_buf()),
        check_meshes: true,
        threads: Some(2),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    run_experiment(experiment, &options, &NoProgress).unwrap();
}

/// The problems `plan` finds in `experiment`, one line each.
fn refusal(experiment: &Path) -> String {
    match plan(experiment) {
        Ok(_) => panic!("{} was accepted", experiment.display()),
        Err(error) => error.to_string(),
    }
}

#[test]
fn a_pyramid_flies_exactly_as_the_same_terrain_in_memory() {
    let prepared = Prepared::new();
    let entries = json!([chunked_loading("out of core", CHUNK_LEVEL)]);
    let in_memory = prepared.experiment("in-memory", prepared.raw_terrain(), entries.clone());
    let on_disk = prepared.experiment("on-disk", prepared.pyramid_terrain(), entries);
    let (memory_out, disk_out) = (prepared.path("out-memory"), prepared.path("out-disk"));
    run(&in_memory, &memory_out);
    run(&on_disk, &disk_out);

    let memory_frames = frames_without_timing(&memory_out.join("frames.csv"));
    let disk_frames = frames_without_timing(&disk_out.join("frames.csv"));
    assert_eq!(memory_frames.len(), 41, "a header and 40 frames");
    // Every column of the run in memory, by name, is the same in the run from disk, which adds
    // only its count of reads (its latencies are timings), and whose `resident_bytes` also
    // counts the reads' own bookkeeping (8 bytes a read).
    let (header, disk_header) = (&memory_frames[0], &disk_frames[0]);
    let column = |name: &str| disk_header.iter().position(|h| h == name).unwrap();
    for (k, name) in header.iter().enumerate() {
        if name == "resident_bytes" {
            continue;
        }
        let d = column(name);
        for (frame, (a, b)) in memory_frames.iter().zip(&disk_frames).enumerate().skip(1) {
            assert_eq!(a[k], b[d], "frame {}, column {name}", frame - 1);
        }
    }
    let disk_only: Vec<&String> = disk_header.iter().filter(|h| !header.contains(h)).collect();
    assert_eq!(disk_only, ["chunks_read"]);
    // The figures are not empty: the audit measured, chunks were loaded.
    let loaded: f64 = disk_frames[1..]
        .iter()
        .map(|row| row[column("chunks_loaded")].parse::<f64>().unwrap())
        .sum();
    assert!(loaded > 0.0, "no chunk was loaded");
    assert!(
        disk_frames[1..]
            .iter()
            .any(|row| row[column("audit_projected_max_px")]
                .parse::<f64>()
                .unwrap()
                > 0.0),
        "the audit measured nothing"
    );

    // The pyramid run says it read the terrain on demand, and what that held.
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(disk_out.join("summary.json")).unwrap())
            .unwrap();
    let held = summary["terrain"]["read_on_demand_bytes"].as_f64().unwrap();
    let samples = 257.0 * 257.0;
    assert!(
        held < 4.0 * samples,
        "the cache and records hold {held} bytes, as much as the heights"
    );
    let report = std::fs::read_to_string(disk_out.join("report.md")).unwrap();
    assert!(
        report.contains("read on demand from its chunk pyramid"),
        "{report}"
    );

    let meshes = |out: &Path| -> Vec<String> {
        let folder = out.join("meshes/0-out-of-core");
        ["frame-000000.ply", "frame-000017.ply", "frame-000039.ply"]
            .iter()
            .map(|name| std::fs::read_to_string(folder.join(name)).unwrap())
            .collect()
    };
    assert_eq!(
        meshes(&memory_out),
        meshes(&disk_out),
        "the exported meshes differ"
    );

    // `roamsim info` describes it without building what needs the whole terrain.
    let output = roamsim(&["info", on_disk.to_str().unwrap()], prepared.folder.path());
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{output:?}");
    assert!(
        stdout.contains("a chunk pyramid is read on demand"),
        "{stdout}"
    );
}

#[test]
fn a_pyramid_read_on_demand_gives_every_sample_of_the_raw_file() {
    let prepared = Prepared::new();
    let side = (1usize << LEVEL) + 1;
    let raw = std::fs::read(prepared.path("terrain.raw")).unwrap();
    let expected = |i: usize, j: usize| {
        let k = 2 * (j * side + i);
        f32::from(i16::from_le_bytes([raw[k], raw[k + 1]]))
    };
    let samples = PyramidSamples::new(PyramidFile::open(&prepared.path("terrain.pyr")).unwrap());
    // 48 leaves cached of 256: reading every row and then every column evicts as it goes.
    assert_eq!(samples.cache_chunks(), 48);
    let mut row = Vec::new();
    for j in 0..side {
        samples.row(j, &mut row);
        let want: Vec<f32> = (0..side).map(|i| expected(i, j)).collect();
        assert_eq!(row, want, "row {j}");
    }
    for i in (0..side).rev() {
        for j in 0..side {
            assert_eq!(samples.height(i, j), expected(i, j), "sample ({i}, {j})");
        }
    }
    let lowest = (0..side * side)
        .map(|k| expected(k % side, k / side))
        .fold(f32::MAX, f32::min);
    assert_eq!(samples.height_range().0, lowest);
    assert_eq!(samples.failure(), None);
}

#[test]
fn an_entry_that_needs_the_whole_terrain_is_refused_by_name() {
    let prepared = Prepared::new();
    let experiment = prepared.experiment(
        "geomipmap",
        prepared.pyramid_terrain(),
        json!([
            chunked_loading("fine", CHUNK_LEVEL),
            { "name": "geomipmap", "label": "gm", "tau_px": 2, "patch_level": 4 },
            { "name": "chunked", "label": "in memory", "tau_px": 2, "chunk_level": CHUNK_LEVEL }
        ]),
    );
    let error = refusal(&experiment);
    for part in [
        "algorithms[1]",
        "entry `gm` (geomipmap) cannot fly a pyramid",
        "its in-memory hierarchy needs the whole terrain",
        "257² samples",
        "crop the terrain to a file",
        "algorithms[2]",
        "entry `in memory` (chunked) flies a pyramid only with its `loading` effect on",
    ] {
        assert!(error.contains(part), "{error:?} lacks {part:?}");
    }
    assert!(!error.contains("algorithms[0]"), "{error}");
    // `roamsim validate` refuses it the same way, before anything runs.
    fails_with(
        &["validate", experiment.to_str().unwrap()],
        prepared.folder.path(),
        &["entry `gm` (geomipmap) cannot fly a pyramid"],
    );
}

#[test]
fn a_chunk_level_other_than_the_pyramids_is_refused_naming_both() {
    let prepared = Prepared::new();
    let experiment = prepared.experiment(
        "chunk-level",
        prepared.pyramid_terrain(),
        json!([chunked_loading("coarse chunks", 5)]),
    );
    let error = refusal(&experiment);
    for part in [
        "algorithms[0]",
        "entry `coarse chunks` has chunk_level 5 (chunks of 33²)",
        "the pyramid's chunks are level 4 (17²)",
    ] {
        assert!(error.contains(part), "{error:?} lacks {part:?}");
    }
}

#[test]
fn a_missing_or_damaged_pyramid_is_refused_naming_the_file_and_the_field() {
    let prepared = Prepared::new();
    let entries = json!([chunked_loading("out of core", CHUNK_LEVEL)]);
    let missing = prepared.experiment(
        "missing",
        json!({ "pyramid": { "file": "nowhere.pyr" } }),
        entries.clone(),
    );
    let error = refusal(&missing);
    for part in [
        "terrain.pyramid.file",
        "nowhere.pyr",
        "cannot open the pyramid",
    ] {
        assert!(error.contains(part), "{error:?} lacks {part:?}");
    }

    let bytes = std::fs::read(prepared.path("terrain.pyr")).unwrap();
    std::fs::write(prepared.path("truncated.pyr"), &bytes[..bytes.len() - 1]).unwrap();
    let mut other_version = bytes.clone();
    other_version[8] = 9;
    std::fs::write(prepared.path("version.pyr"), other_version).unwrap();
    for (file, expected) in [
        ("truncated.pyr", "truncated"),
        ("version.pyr", "field `version` is 9"),
    ] {
        let experiment = prepared.experiment(
            file,
            json!({ "pyramid": { "file": file } }),
            entries.clone(),
        );
        let error = refusal(&experiment);
        for part in ["terrain.pyramid.file", file, expected] {
            assert!(error.contains(part), "{error:?} lacks {part:?}");
        }
    }
}

/// A pyramid of a 65 537² terrain (level 16) in chunks of 65² (level 6), every height 0, as a
/// sparse file: the header of the 257² pyramid with its levels and chunk count changed, the
/// 1 398 101 chunk records (zeros: error 0, range 0..0, nested), and the heights left as a
/// hole (11.8 GB long, about 17 MB on disk). The format is docs/output-formats.md's.
fn sparse_65537_pyramid(prepared: &Prepared) -> &'static str {
    let (terrain_level, chunk_level) = (16u32, 6u32);
    let leaf_level = terrain_level - chunk_level;
    let n_chunks = ((1u64 << (2 * (leaf_level + 1))) - 1) / 3;
    let chunk_bytes = ((1u64 << chunk_level) + 1).pow(2) * 2;
    let mut header = std::fs::read(prepared.path("terrain.pyr")).unwrap()[..48].to_vec();
    header[16..20].copy_from_slice(&terrain_level.to_le_bytes());
    header[20..24].copy_from_slice(&chunk_level.to_le_bytes());
    header[40..48].copy_from_slice(&n_chunks.to_le_bytes());
    let name = "terrain-65537.pyr";
    let file = std::fs::File::create(prepared.path(name)).unwrap();
    let mut writer = std::io::BufWriter::new(&file);
    std::io::Write::write_all(&mut writer, &header).unwrap();
    std::io::Write::write_all(&mut writer, &vec![0u8; (n_chunks * 12) as usize]).unwrap();
    drop(writer);
    file.set_len(48 + n_chunks * (12 + chunk_bytes)).unwrap();
    name
}

#[test]
fn a_65537_pyramid_flies_with_chunked_and_refuses_what_numbers_its_samples_with_32_bits() {
    let prepared = Prepared::new();
    let file = sparse_65537_pyramid(&prepared);
    let terrain = json!({ "pyramid": { "file": file } });
    let experiment = |name: &str, algorithms: Value, audit_stride: u32| {
        let experiment = json!({
            "format_version": 1,
            "name": name,
            "terrain": terrain,
            "view": { "width_px": 320, "height_px": 240, "fovy_deg": 60, "near_m": 0.5, "far_m": 30000 },
            "speed_bounds": { "horizontal_m_per_frame": 200, "vertical_m_per_frame": 200 },
            "flight": {
                "frames": 3,
                "altitude": "above_ground",
                "look": { "along_path": { "pitch_deg": -10 } },
                "path": { "line": { "from_m": [980000, 980000, 30], "to_m": [980300, 980200, 30] } }
            },
            "algorithms": algorithms,
            "effects": { "audit": { "stride": audit_stride }, "culling": true },
            "outputs": { "plots": false }
        });
        save(prepared.folder.path(), name, &experiment)
    };

    // Every entry that needs the 4-8 lattice, and an audit of the whole grid, refused by name.
    let refused = experiment(
        "refused",
        json!([
            chunked_loading("from disk", 6),
            { "name": "wu", "label": "wu", "tau_px": 2 },
        ]),
        1,
    );
    let error = refusal(&refused);
    for part in [
        "algorithms[1]",
        "entry `wu` (wu) cannot fly a pyramid",
        "65537² samples",
        "above 32769² no in-memory hierarchy holds it",
        "effects.audit.stride",
        "set a stride of at least 2",
    ] {
        assert!(error.contains(part), "{error:?} lacks {part:?}");
    }
    assert!(!error.contains("algorithms[0]"), "{error}");

    // Chunked LOD with loading flies it, audited every 4096th sample; `--check`, whose
    // validator counts owners at every sample, is refused naming the limit.
    let flown = experiment("flown", json!([chunked_loading("from disk", 6)]), 4096);
    plan(&flown).unwrap();
    let out = prepared.path("out-65537");
    let mut options = RunOptions {
        out_dir: Some(out.clone()),
        check_meshes: true,
        threads: Some(2),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    let Err(checked) = run_experiment(&flown, &options, &NoProgress) else {
        panic!("a 65537² run with `--check` was accepted");
    };
    let message = checked.to_string();
    for part in ["`--check`", "65537² pyramid", "at most 32769²"] {
        assert!(message.contains(part), "{message:?} lacks {part:?}");
    }
    assert!(!out.exists(), "a refused run wrote {}", out.display());
    options.check_meshes = false;
    run_experiment(&flown, &options, &NoProgress).unwrap();
    let frames = frames_without_timing(&out.join("frames.csv"));
    assert_eq!(frames.len(), 4, "a header and 3 frames");
    let column = |name: &str| frames[0].iter().position(|h| h == name).unwrap();
    let triangles: f64 = frames[1..]
        .iter()
        .map(|row| row[column("triangles")].parse::<f64>().unwrap())
        .sum();
    assert!(triangles > 0.0, "nothing was drawn");
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let held = summary["terrain"]["read_on_demand_bytes"].as_f64().unwrap();
    assert!(
        held < 100e6,
        "the cache and records of a 17 GB terrain hold {held} bytes"
    );
}
