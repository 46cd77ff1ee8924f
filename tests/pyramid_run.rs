//! An experiment whose terrain is a chunk pyramid (`"terrain": {"pyramid": {"file": …}}`): it
//! draws exactly the meshes, counts and audit figures of the same chunked entry flying the raw
//! file in memory, without ever holding the whole terrain; entries that need the whole terrain,
//! a chunk level other than the pyramid's, and missing or damaged pyramids are refused before
//! anything runs, naming the entry, the file and the field; a chunk damaged where only the
//! loader thread reads it, mid-flight, fails the run naming the file, the chunk and what was
//! expected, and writes nothing.
//! Its map reads the coarsest pyramid level whose samples are no farther apart than a pixel:
//! the leaves, drawing the in-memory map, when the pixels are finer; every 4th sample when
//! they are 5 samples wide. A run's peak resident set does not grow with the pyramid's size.

mod common;

use common::cli::{fails_with, frames_without_timing, roamsim};
use common::experiment::save;
use roamsim::edge::experiment::plan;
use roamsim::edge::output::flight_map::{FlightOnMap, map_chart};
use roamsim::edge::output::plots::HeightRaster;
use roamsim::edge::pyramid::{PyramidFile, PyramidSamples, RawSource, prepare_from_raw};
use roamsim::edge::session::{NoProgress, RunOptions, run_experiment};
use roamsim::edge::terrain_readers::{RawLayout, RawSample};
use roamsim::sim::algorithm::chunked::ChunkId;
use roamsim::sim::algorithm::chunked::{ChunkHeightSource, ChunkRead, ChunkRecord};
use roamsim::sim::flight::Flight;
use roamsim::sim::terrain::paged::PagedSamples;
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Pose, ViewSettings};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// A 257² terrain of integer heights, written south row first as little-endian `i16`, and its
/// pyramid in chunks of 17² (chunk level 4), in a fresh folder.
struct Prepared {
    folder: tempfile::TempDir,
}

const LEVEL: u32 = 8;
const CHUNK_LEVEL: u32 = 4;

impl Prepared {
    fn new() -> Prepared {
        Prepared::of_level(LEVEL)
    }

    /// The same kind of terrain, (2^`level` + 1)² samples.
    fn of_level(level: u32) -> Prepared {
        let folder = tempfile::tempdir().unwrap();
        let side = (1usize << level) + 1;
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
    run_result(experiment, out).unwrap();
}

/// Runs `experiment` into `out`; the run's error as the user reads it.
fn run_result(experiment: &Path, out: &Path) -> Result<(), String> {
    let options = RunOptions {
        out_dir: Some(out.to_path_buf()),
        check_meshes: true,
        threads: Some(2),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    run_experiment(experiment, &options, &NoProgress)
        .map(|_| ())
        .map_err(|error| error.to_string())
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
    // The disk run adds the measured reads' one count column (its latency columns are timing);
    // every other column is the in-memory run's, value for value.
    let (header, disk_header) = (&memory_frames[0], &disk_frames[0]);
    let extra: Vec<&String> = disk_header.iter().filter(|h| !header.contains(h)).collect();
    assert_eq!(extra, ["chunks_read"], "columns only the disk run has");
    assert_eq!(disk_frames.len(), memory_frames.len());
    let column = |name: &str| disk_header.iter().position(|h| h == name).unwrap();
    let number = |row: &[String], name: &str| row[column(name)].parse::<f64>().unwrap();
    let mut reads_so_far = 0.0;
    for (frame, (a, b)) in memory_frames.iter().zip(&disk_frames).enumerate().skip(1) {
        reads_so_far += number(b, "chunks_read");
        for (k, name) in header.iter().enumerate() {
            if name == "resident_bytes" {
                // The disk run also keeps each read's latency for the run's percentiles: 8 bytes
                // a read, in a vector of at most twice their number.
                let more = number(b, name) - a[k].parse::<f64>().unwrap();
                assert!(
                    (0.0..=16.0 * reads_so_far).contains(&more),
                    "frame {}: {more} resident bytes more for {reads_so_far} reads",
                    frame - 1
                );
                continue;
            }
            assert_eq!(a[k], b[column(name)], "frame {}, column {name}", frame - 1);
        }
    }
    // The figures are not empty: the audit measured, chunks were loaded and read from disk.
    let read: f64 = disk_frames[1..]
        .iter()
        .map(|row| row[column("chunks_read")].parse::<f64>().unwrap())
        .sum();
    assert!(read > 0.0, "no chunk was read from the pyramid");
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

#[test]
fn a_chunk_damaged_after_the_pyramid_was_checked_fails_the_run_naming_it_and_writes_nothing() {
    // The four chunks of level 1 get a first height far above their records' ranges: the open
    // (header, length, records) passes, and only the loader thread reads them, mid-flight.
    let prepared = Prepared::new();
    let path = prepared.path("terrain.pyr");
    let header = *PyramidFile::open(&path).unwrap().header();
    let mut bytes = std::fs::read(&path).unwrap();
    for (x, y) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let at = header.heights_offset(ChunkId { level: 1, x, y }) as usize;
        bytes[at..at + 2].copy_from_slice(&i16::MAX.to_le_bytes());
    }
    std::fs::write(&path, bytes).unwrap();
    let experiment = prepared.experiment(
        "damaged",
        prepared.pyramid_terrain(),
        json!([chunked_loading("out of core", CHUNK_LEVEL)]),
    );
    let listing = || {
        let mut names: Vec<_> = std::fs::read_dir(prepared.folder.path())
            .unwrap()
            .map(|entry| entry.unwrap().file_name())
            .collect();
        names.sort();
        names
    };
    let before = listing();
    let out = prepared.path("out");
    let error = run_result(&experiment, &out).expect_err("the damaged chunk fails the run");
    for part in [
        "terrain.pyramid.file",
        "a read failed during the run",
        "terrain.pyr",
        "chunk at level 1, x ",
        "heights at bytes ",
        "has height 32767, outside its record's range: expected ",
        "prepare it again",
    ] {
        assert!(error.contains(part), "{error:?} lacks {part:?}");
    }
    assert!(!out.exists(), "a failed run left {}", out.display());
    assert_eq!(
        listing(),
        before,
        "a failed run left something beside its output"
    );
}

/// A pyramid's samples that count what is read: samples through the full-resolution cache,
/// and whole chunks through the readers it hands out, by level.
#[derive(Debug)]
struct CountingSamples {
    inner: PyramidSamples,
    samples_read: AtomicU64,
    chunks_read: Arc<std::sync::Mutex<Vec<u32>>>,
}

struct CountingReader {
    inner: Box<dyn ChunkHeightSource>,
    chunks_read: Arc<std::sync::Mutex<Vec<u32>>>,
}

impl ChunkHeightSource for CountingReader {
    fn request(&mut self, id: ChunkId) {
        self.inner.request(id);
    }

    fn take(&mut self, id: ChunkId) -> Result<ChunkRead, String> {
        self.chunks_read.lock().unwrap().push(id.level);
        self.inner.take(id)
    }
}

impl PagedSamples for CountingSamples {
    fn height(&self, i: usize, j: usize) -> f32 {
        self.samples_read.fetch_add(1, Ordering::Relaxed);
        self.inner.height(i, j)
    }
    fn row(&self, j: usize, row: &mut Vec<f32>) {
        self.inner.row(j, row);
        self.samples_read
            .fetch_add(row.len() as u64, Ordering::Relaxed);
    }
    fn height_range(&self) -> (f32, f32) {
        self.inner.height_range()
    }
    fn memory_bytes(&self) -> usize {
        self.inner.memory_bytes()
    }
    fn failure(&self) -> Option<String> {
        self.inner.failure()
    }
    fn chunk_level(&self) -> u32 {
        self.inner.chunk_level()
    }
    fn chunk_records(&self) -> &[ChunkRecord] {
        self.inner.chunk_records()
    }
    fn chunk_reader(&self) -> Result<Box<dyn ChunkHeightSource>, String> {
        Ok(Box::new(CountingReader {
            inner: self.inner.chunk_reader()?,
            chunks_read: Arc::clone(&self.chunks_read),
        }))
    }
}

/// The raw file's terrain in memory, every `stride`-th sample of it each way.
fn raw_field(prepared: &Prepared, stride: usize) -> Heightfield {
    let side = (1usize << LEVEL) + 1;
    let raw = std::fs::read(prepared.path("terrain.raw")).unwrap();
    let kept = (side - 1) / stride + 1;
    let heights = (0..kept * kept)
        .map(|k| {
            let (i, j) = (k % kept * stride, k / kept * stride);
            let at = 2 * (j * side + i);
            f32::from(i16::from_le_bytes([raw[at], raw[at + 1]]))
        })
        .collect();
    let spacing = 30.0 * stride as f64;
    Heightfield::new(
        kept,
        heights,
        Spacing {
            dx: spacing,
            dy: spacing,
        },
    )
    .unwrap()
}

fn raster_bits(raster: &HeightRaster) -> (usize, usize, Vec<u64>) {
    let bits = raster.heights.iter().map(|h| h.to_bits()).collect();
    (raster.columns, raster.rows, bits)
}

#[test]
fn the_map_of_a_pyramid_reads_its_coarsest_level_as_fine_as_the_pixels() {
    let prepared = Prepared::new();
    let samples = Arc::new(CountingSamples {
        inner: PyramidSamples::new(PyramidFile::open(&prepared.path("terrain.pyr")).unwrap()),
        samples_read: AtomicU64::new(0),
        chunks_read: Arc::default(),
    });
    let spacing = Spacing { dx: 30.0, dy: 30.0 };
    let paged = Heightfield::paged(LEVEL, samples.clone(), spacing).unwrap();
    let levels_read = || std::mem::take(&mut *samples.chunks_read.lock().unwrap());

    // The terrain alone: 7680 m on 860 pixels, 8.9 m a pixel, finer than the 30 m samples:
    // the leaves (level 4 of 17² chunks, 16 × 16 of them), and the map drawn in memory.
    let in_memory = map_chart(&raw_field(&prepared, 1), "map", None).unwrap();
    let from_pyramid = map_chart(&paged, "map", None).unwrap();
    assert_eq!(
        raster_bits(&from_pyramid.raster),
        raster_bits(&in_memory.raster)
    );
    assert_eq!(from_pyramid, in_memory);
    assert_eq!(levels_read(), vec![4; 256]);

    // A flight reaching 125 km east: 154 m a pixel, so every 4th sample (120 m) is enough:
    // level 2's 16 chunks, the heights of the terrain in memory kept every 4th sample.
    let poses = (0..41)
        .map(|k| Pose {
            position: glam::DVec3::new(f64::from(k) * 3125.0, 3840.0, 600.0),
            yaw: 0.0,
            pitch: -0.3,
        })
        .collect();
    let flight = Flight::from_poses(poses).unwrap();
    let on_map = FlightOnMap {
        flight: &flight,
        view: ViewSettings {
            width_px: 640,
            height_px: 480,
            fovy: 1.0,
            near: 1.0,
            far: 8000.0,
        },
        violations: &[],
    };
    let from_pyramid = map_chart(&paged, "map", Some(on_map)).unwrap();
    let every_4th = map_chart(&raw_field(&prepared, 4), "map", Some(on_map)).unwrap();
    let every_sample = map_chart(&raw_field(&prepared, 1), "map", Some(on_map)).unwrap();
    assert_eq!(levels_read(), vec![2; 16]);
    let drawn = raster_bits(&from_pyramid.raster);
    assert_eq!(drawn, raster_bits(&every_4th.raster));
    assert_ne!(
        drawn,
        raster_bits(&every_sample.raster),
        "the map read the leaves"
    );
    let on_terrain = from_pyramid.raster.heights.iter().filter(|h| h.is_finite());
    assert!(
        on_terrain.count() > 1000,
        "the terrain is hardly on the map"
    );
    assert_eq!(samples.samples_read.load(Ordering::Relaxed), 0);
}

/// The peak resident set of `roamsim run` over `prepared`'s pyramid: a chunked entry with loading
/// flies the same 40 frames (no audit, no plots, no mesh checks), in a process of its own.
fn peak_resident_of_a_run(prepared: &Prepared) -> f64 {
    let experiment = json!({
        "format_version": 1,
        "name": "pyramid-memory",
        "terrain": prepared.pyramid_terrain(),
        "view": { "width_px": 640, "height_px": 480, "fovy_deg": 60, "near_m": 0.5, "far_m": 8000 },
        "speed_bounds": { "horizontal_m_per_frame": 200, "vertical_m_per_frame": 200 },
        "flight": {
            "frames": 40,
            "altitude": "above_ground",
            "look": { "along_path": { "pitch_deg": -10 } },
            "path": { "line": { "from_m": [600, 700, 25], "to_m": [7000, 6500, 25] } }
        },
        "algorithms": [chunked_loading("out of core", CHUNK_LEVEL)],
        "effects": { "culling": true },
        "outputs": { "plots": false }
    });
    save(prepared.folder.path(), "memory", &experiment);
    let output = roamsim(
        &["run", "memory.json", "--out", "out", "--threads", "2"],
        prepared.folder.path(),
    );
    assert!(output.status.success(), "{output:?}");
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(prepared.path("out/summary.json")).unwrap())
            .unwrap();
    summary["run"]["peak_resident_bytes"].as_f64().unwrap()
}

#[test]
fn a_pyramid_runs_resident_set_does_not_grow_with_the_terrain() {
    // 2049² samples are 16.8 MB as f32 in memory; the run over their pyramid peaks within 6 MB
    // of the same run over a 257² pyramid (the leaf cache grows by 224 leaves of 17², 260 kB).
    let small = peak_resident_of_a_run(&Prepared::of_level(LEVEL));
    let large = peak_resident_of_a_run(&Prepared::of_level(11));
    let grown = large - small;
    assert!(
        grown < 6e6,
        "the run over 2049² peaks at {large} bytes, {grown} more than over 257²"
    );
}

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
