//! The chunk pyramid `roamsim prepare` writes (docs/output-formats.md, "Chunk pyramid"): it
//! holds exactly the chunk tree `chunked` builds in memory — every chunk's nested error, height
//! range and heights, bit for bit — for integer and float sources, south- or north-first files,
//! any chunk level (a real SRTM tile cropped to 1025² included); a truncated, foreign or
//! corrupted file is refused with the file and the field named; and a chunked entry whose
//! heights are read from the pyramid on a loader thread draws, every frame, exactly the meshes
//! of the same entry reading the heights in memory, reporting its reads (count, latency, wait)
//! per frame and the run's latency percentiles.

mod common;

use common::algorithms::{chunked, chunked_with_everything};
use common::{step, view_600};
use glam::DVec3;
use proptest::prelude::*;
use roamsim::edge::pyramid::{
    PyramidFile, PyramidLoader, RawSource, StoredSample, chunk_ids, prepare_from_raw,
};
use roamsim::edge::terrain_readers::{RawLayout, RawSample};
use roamsim::sim::algorithm::chunked::{ChunkHeightSource, ChunkId, ChunkRead, LoadingConfig};
use roamsim::sim::algorithm::columns::chunked::{
    CHUNKS_READ, READ_LATENCY_MAX_US, READ_LATENCY_MEAN_US, READ_WAIT_US,
};
use roamsim::sim::algorithm::columns::extra_value;
use roamsim::sim::algorithm::{Chunked, ChunkedConfig, LodAlgorithm};
use roamsim::sim::hierarchy::GridPoint;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::stats::{FrameStats, nearest_rank};
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose};
use std::path::{Path, PathBuf};

const SPACING: Spacing = Spacing { dx: 30.0, dy: 20.0 };

/// A terrain as a raw file and as the in-memory hierarchy of the same heights.
struct Terrain {
    side: usize,
    /// Row by row from the south, as the grid has them.
    heights: Vec<f32>,
}

impl Terrain {
    /// Integer heights with bumps and noise, as SRTM's are.
    fn integer(level: u32) -> Terrain {
        let side = (1usize << level) + 1;
        let heights = (0..side * side)
            .map(|k| {
                let (i, j) = ((k % side) as f32, (k / side) as f32);
                // `+ 0.0` makes a rounded −0 the +0 an integer file holds.
                (300.0 * (0.31 * i).sin() * (0.23 * j).cos() + ((k * 2654435761) % 97) as f32)
                    .round()
                    + 0.0
            })
            .collect();
        Terrain { side, heights }
    }

    fn hierarchy(&self) -> Hierarchy {
        Hierarchy::new(Heightfield::new(self.side, self.heights.clone(), SPACING).unwrap())
    }

    /// Writes the raw file of `sample` type, north row first or not.
    fn write_raw(&self, path: &Path, sample: RawSample, north_first: bool) -> RawSource {
        let mut bytes = Vec::new();
        for row in 0..self.side {
            let j = if north_first {
                self.side - 1 - row
            } else {
                row
            };
            for &z in &self.heights[j * self.side..(j + 1) * self.side] {
                match sample {
                    RawSample::I16Le => bytes.extend_from_slice(&(z as i16).to_le_bytes()),
                    RawSample::I16Be => bytes.extend_from_slice(&(z as i16).to_be_bytes()),
                    RawSample::F32Le => bytes.extend_from_slice(&z.to_le_bytes()),
                    other => unreachable!("the tests write no {other:?}"),
                }
            }
        }
        std::fs::write(path, bytes).unwrap();
        RawSource {
            path: path.to_path_buf(),
            layout: RawLayout {
                columns: self.side,
                rows: self.side,
                sample,
                north_first,
            },
            spacing: SPACING,
        }
    }
}

/// Prepares `terrain` in a fresh folder; the folder (kept alive) and the pyramid's path.
fn prepare(
    terrain: &Terrain,
    sample: RawSample,
    north_first: bool,
    chunk_level: u32,
) -> (tempfile::TempDir, PathBuf) {
    let folder = tempfile::tempdir().unwrap();
    let source = terrain.write_raw(&folder.path().join("terrain.raw"), sample, north_first);
    let out = folder.path().join("terrain.pyramid");
    prepare_from_raw(&source, chunk_level, &out, &mut |_, _| {}).unwrap();
    (folder, out)
}

/// Every chunk of the pyramid equals the in-memory tree's: record and heights, bit for bit.
fn assert_same_tree(terrain: &Terrain, chunk_level: u32, pyramid: &PyramidFile) {
    let hierarchy = terrain.hierarchy();
    let memory = Chunked::new(&hierarchy, chunked(1.0, chunk_level), &view_600());
    let header = pyramid.header();
    assert_eq!(
        (header.leaf_level(), header.n_chunks()),
        (memory.leaf_level(), memory.n_chunks() as u64)
    );
    assert_eq!((header.dx, header.dy), (SPACING.dx, SPACING.dy));
    let side = header.cells() + 1;
    let mut heights = Vec::new();
    for id in chunk_ids(header.leaf_level()) {
        let (file, tree) = (pyramid.record(id).unwrap(), memory.chunk(id).unwrap());
        let bits = |r: &roamsim::sim::algorithm::chunked::ChunkRecord| {
            (r.error.to_bits(), r.z_min.to_bits(), r.z_max.to_bits())
        };
        assert_eq!(bits(&file), bits(tree), "chunk {id:?}: {file:?} ≠ {tree:?}");
        pyramid.read_heights(id, &mut heights).unwrap();
        for b in 0..side {
            for a in 0..side {
                assert_eq!(
                    heights[(b * side + a) as usize].to_bits(),
                    memory.chunk_height(id, a, b).to_bits(),
                    "chunk {id:?}, vertex ({a}, {b})"
                );
            }
        }
    }
}

#[test]
fn an_integer_terrain_is_stored_as_i16_and_holds_the_in_memory_tree() {
    let terrain = Terrain::integer(6);
    for (sample, north_first) in [(RawSample::I16Le, true), (RawSample::I16Be, false)] {
        for chunk_level in [1, 2, 3, 6, 9] {
            let (_folder, path) = prepare(&terrain, sample, north_first, chunk_level);
            let pyramid = PyramidFile::open(&path).unwrap();
            assert_eq!(pyramid.header().sample, StoredSample::I16);
            assert_same_tree(&terrain, chunk_level, &pyramid);
        }
    }
}

#[test]
fn a_float_terrain_is_stored_as_f32_and_holds_the_in_memory_tree() {
    let mut terrain = Terrain::integer(5);
    for (k, z) in terrain.heights.iter_mut().enumerate() {
        *z += 0.125 * (k % 7) as f32 + 1e-3;
    }
    let (_folder, path) = prepare(&terrain, RawSample::F32Le, true, 2);
    let pyramid = PyramidFile::open(&path).unwrap();
    assert_eq!(pyramid.header().sample, StoredSample::F32);
    assert_same_tree(&terrain, 2, &pyramid);
}

#[test]
fn an_srtm_tile_cropped_to_1025_holds_the_in_memory_tree() {
    // N48E009.hgt: 1201² big-endian i16, north row first; its north-west 1025² square.
    let tile = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/experiments/data/N48E009.hgt"
    ))
    .unwrap();
    let side = 1025;
    let mut heights = vec![0f32; side * side];
    for row in 0..side {
        for column in 0..side {
            let k = 2 * (row * 1201 + column);
            heights[(side - 1 - row) * side + column] =
                f32::from(i16::from_be_bytes([tile[k], tile[k + 1]]));
        }
    }
    let terrain = Terrain { side, heights };
    let (_folder, path) = prepare(&terrain, RawSample::I16Be, true, 6);
    assert_same_tree(&terrain, 6, &PyramidFile::open(&path).unwrap());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Any small float terrain and chunk level: the pyramid is the in-memory tree.
    #[test]
    fn any_small_terrain_round_trips(
        level in 1u32..=5,
        chunk_level in 1u32..=6,
        seed in any::<u64>(),
    ) {
        let side = (1usize << level) + 1;
        let mut state = seed | 1;
        let heights = (0..side * side)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state % 20_000) as f32 * 0.37 - 3000.0
            })
            .collect();
        let terrain = Terrain { side, heights };
        let (_folder, path) = prepare(&terrain, RawSample::F32Le, seed % 2 == 0, chunk_level);
        assert_same_tree(&terrain, chunk_level, &PyramidFile::open(&path).unwrap());
    }
}

/// The error opening `bytes` as a pyramid.
fn open_error(bytes: &[u8]) -> String {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("broken.pyramid");
    std::fs::write(&path, bytes).unwrap();
    let error = PyramidFile::open(&path).unwrap_err().to_string();
    assert!(error.contains("broken.pyramid"), "{error}");
    error
}

#[test]
fn a_truncated_foreign_or_corrupt_pyramid_is_refused_naming_what_is_wrong() {
    let (_folder, path) = prepare(&Terrain::integer(4), RawSample::I16Le, true, 2);
    let good = std::fs::read(&path).unwrap();

    let error = open_error(&good[..good.len() - 1]);
    assert!(error.contains("truncated"), "{error}");
    let error = open_error(&good[..20]);
    assert!(
        error.contains("fewer than a pyramid's 48-byte header"),
        "{error}"
    );

    let mut foreign = good.clone();
    foreign[0] = b'X';
    assert!(open_error(&foreign).contains("not a roamsim chunk pyramid"));

    let mut newer = good.clone();
    newer[8] = 2;
    assert!(open_error(&newer).contains("field `version` is 2"));

    let mut levels = good.clone();
    levels[20] = 7; // chunk level above the terrain's 4
    assert!(open_error(&levels).contains("field `chunk_level` is 7"));

    // The root's error (the first record) made smaller than its children's.
    let mut nesting = good.clone();
    nesting[48..52].copy_from_slice(&(-1.0f32).to_le_bytes());
    let error = open_error(&nesting);
    assert!(error.contains("ChunkId { level: 0"), "{error}");

    // A leaf's first height moved far outside its record's range: refused when read.
    let mut height = good.clone();
    let header = PyramidFile::open(&path).unwrap().header().to_owned();
    let leaf = ChunkId {
        level: 2,
        x: 1,
        y: 3,
    };
    let at = header.heights_offset(leaf) as usize;
    height[at..at + 2].copy_from_slice(&i16::MAX.to_le_bytes());
    let folder = tempfile::tempdir().unwrap();
    let corrupt = folder.path().join("corrupt.pyramid");
    std::fs::write(&corrupt, &height).unwrap();
    let pyramid = PyramidFile::open(&corrupt).unwrap();
    let error = pyramid
        .read_heights(leaf, &mut Vec::new())
        .unwrap_err()
        .to_string();
    assert!(error.contains("outside its record's range"), "{error}");
    assert!(pyramid.read_heights(ChunkId::ROOT, &mut Vec::new()).is_ok());
}

#[test]
fn prepare_refuses_a_wrong_source_and_leaves_nothing_behind() {
    let folder = tempfile::tempdir().unwrap();
    let terrain = Terrain::integer(4);
    let mut source = terrain.write_raw(&folder.path().join("t.raw"), RawSample::I16Le, true);
    let out = folder.path().join("t.pyramid");

    source.layout.columns = 18;
    source.layout.rows = 18;
    let error = prepare_from_raw(&source, 2, &out, &mut |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(error.contains("2^n + 1 samples a side"), "{error}");

    source.layout.columns = 33;
    source.layout.rows = 33;
    let error = prepare_from_raw(&source, 2, &out, &mut |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(error.contains("needs 2178"), "{error}");

    // Something of the user's where the pyramid would go is left alone.
    source.layout.columns = 17;
    source.layout.rows = 17;
    std::fs::write(&out, "notes").unwrap();
    let error = prepare_from_raw(&source, 2, &out, &mut |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(error.contains("not a roamsim chunk pyramid"), "{error}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "notes");
    let names: Vec<_> = std::fs::read_dir(folder.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

/// A flight 15 m above the ground along the terrain's diagonal, looking ahead and down.
fn low_flight(hierarchy: &Hierarchy, frames: u32) -> Vec<Camera> {
    let field = hierarchy.field();
    let last = field.side() as u32 - 1;
    (0..frames)
        .map(|k| {
            let t = 0.05 + 0.9 * f64::from(k) / f64::from(frames);
            let i = (t * f64::from(last)).round() as u32;
            let ground = f64::from(hierarchy.height(GridPoint::new(i, i)));
            let position = field.position(i as usize, i as usize);
            Camera::new(
                &Pose {
                    position: DVec3::new(position.x, position.y, ground + 15.0),
                    yaw: std::f64::consts::FRAC_PI_4,
                    pitch: -0.3,
                },
                view_600(),
            )
        })
        .collect()
}

/// The frame's triangles: corners (position, height bits) and info, in draw order.
type Mesh = Vec<([(i64, i64, u32); 3], String)>;

fn mesh_of(algorithm: &Chunked, hierarchy: &Hierarchy) -> Mesh {
    let mut mesh = Vec::new();
    algorithm.mesh().for_each_triangle(hierarchy, |t| {
        let corner = |k: usize| {
            let p = t.corners[k].position;
            (p.raw().0, p.raw().1, t.corners[k].z.to_bits())
        };
        mesh.push(([corner(0), corner(1), corner(2)], format!("{:?}", t.info)));
    });
    mesh
}

/// Flies `config` over `hierarchy`, heights from the shared field or, given a pyramid, read
/// from it on a loader thread; every frame's mesh, and the chunks read.
fn fly(
    hierarchy: &Hierarchy,
    config: ChunkedConfig,
    pyramid: Option<&Path>,
    cameras: &[Camera],
) -> (Vec<Mesh>, u64) {
    let mut algorithm = Chunked::new(hierarchy, config, &view_600());
    if let Some(path) = pyramid {
        let loader = PyramidLoader::start(PyramidFile::open(path).unwrap());
        algorithm = algorithm.with_disk_heights(Box::new(loader)).unwrap();
    }
    let mut read = 0;
    let meshes = cameras
        .iter()
        .enumerate()
        .map(|(frame, camera)| {
            step(&mut algorithm, frame as u64, camera, false);
            read += algorithm.disk_frame().map_or(0, |d| d.chunks_arrived);
            mesh_of(&algorithm, hierarchy)
        })
        .collect();
    (meshes, read)
}

fn with_loading(config: ChunkedConfig) -> ChunkedConfig {
    ChunkedConfig {
        loading: Some(LoadingConfig {
            latency_frames: 2,
            bandwidth_chunks_per_frame: 8,
            resident_chunks: 48,
        }),
        ..config
    }
}

#[test]
fn heights_read_from_the_pyramid_on_a_loader_thread_draw_the_in_memory_meshes_every_frame() {
    let terrain = Terrain::integer(8);
    let hierarchy = terrain.hierarchy();
    let cameras = low_flight(&hierarchy, 80);
    let (_folder, path) = prepare(&terrain, RawSample::I16Le, true, 4);
    for (name, config) in [
        ("paper's", with_loading(chunked(0.5, 4))),
        ("everything", with_loading(chunked_with_everything(0.5, 4))),
    ] {
        let (memory, _) = fly(&hierarchy, config, None, &cameras);
        let (disk, read) = fly(&hierarchy, config, Some(&path), &cameras);
        assert!(read > 20, "{name}: only {read} chunks read");
        for (frame, (memory, disk)) in memory.iter().zip(&disk).enumerate() {
            assert_eq!(memory.len(), disk.len(), "{name}, frame {frame}: counts");
            if let Some(k) = (0..memory.len()).find(|&k| memory[k] != disk[k]) {
                panic!(
                    "{name}, frame {frame}: triangle {k} differs: {:?} ≠ {:?}",
                    memory[k], disk[k]
                );
            }
        }
    }
}

#[test]
fn the_heights_drawn_are_the_ones_read_from_the_file() {
    // A pyramid of the same terrain raised by 1 m: the same errors, every height read 1 m up.
    let terrain = Terrain::integer(7);
    let hierarchy = terrain.hierarchy();
    let raised = Terrain {
        side: terrain.side,
        heights: terrain.heights.iter().map(|z| z + 1.0).collect(),
    };
    let (_folder, path) = prepare(&raised, RawSample::I16Le, true, 3);
    let cameras = low_flight(&hierarchy, 30);
    let config = with_loading(chunked(0.5, 3));
    let (memory, _) = fly(&hierarchy, config, None, &cameras);
    let (disk, _) = fly(&hierarchy, config, Some(&path), &cameras);
    let last = memory.len() - 1;
    assert_eq!(memory[last].len(), disk[last].len());
    for (m, d) in memory[last].iter().zip(&disk[last]) {
        for k in 0..3 {
            let (zm, zd) = (f32::from_bits(m.0[k].2), f32::from_bits(d.0[k].2));
            assert_eq!((m.0[k].0, m.0[k].1), (d.0[k].0, d.0[k].1));
            // Skirt bottoms hang the chunk's (record's) depth below the raised border.
            assert_eq!(zd - zm, 1.0, "{m:?} vs {d:?}");
        }
    }
}

/// The loader over a pyramid with each read's latency stamped from its chunk (1 ms a level,
/// plus 1 ms), so the reported latencies are known; the chunks taken, in order.
struct StampedReads {
    loader: PyramidLoader,
    taken: std::sync::Arc<std::sync::Mutex<Vec<ChunkId>>>,
}

fn stamped_latency_ns(id: ChunkId) -> u64 {
    1_000_000 * u64::from(id.level + 1)
}

impl ChunkHeightSource for StampedReads {
    fn request(&mut self, id: ChunkId) {
        self.loader.request(id);
    }

    fn take(&mut self, id: ChunkId) -> Result<ChunkRead, String> {
        self.taken.lock().unwrap().push(id);
        let read = self.loader.take(id)?;
        Ok(ChunkRead {
            latency_ns: stamped_latency_ns(id),
            ..read
        })
    }
}

#[test]
fn a_flight_reading_from_disk_reports_each_frames_reads_and_the_runs_latency_percentiles() {
    let terrain = Terrain::integer(8);
    let hierarchy = terrain.hierarchy();
    let cameras = low_flight(&hierarchy, 60);
    let (_folder, path) = prepare(&terrain, RawSample::I16Le, true, 4);
    let config = with_loading(chunked(0.5, 4));
    let in_memory = Chunked::new(&hierarchy, config, &view_600());
    assert!(!in_memory.extra_columns().contains(&CHUNKS_READ));
    let taken = std::sync::Arc::default();
    let source = StampedReads {
        loader: PyramidLoader::start(PyramidFile::open(&path).unwrap()),
        taken: std::sync::Arc::clone(&taken),
    };
    let mut algorithm = in_memory.with_disk_heights(Box::new(source)).unwrap();
    let declared = algorithm.extra_columns();
    let column = |stats: &FrameStats, name| extra_value(declared, stats, name).unwrap();
    taken.lock().unwrap().clear(); // The root, read before the flight.
    let mut all_us = Vec::new();
    for (frame, camera) in cameras.iter().enumerate() {
        let stats = step(&mut algorithm, frame as u64, camera, false);
        let this_frame: Vec<f64> = taken
            .lock()
            .unwrap()
            .drain(..)
            .map(|id| stamped_latency_ns(id) as f64 * 1e-3)
            .collect();
        let n = this_frame.len() as f64;
        let max = this_frame.iter().copied().fold(0.0, f64::max);
        let mean = if n > 0.0 {
            this_frame.iter().sum::<f64>() / n
        } else {
            0.0
        };
        assert_eq!(column(&stats, CHUNKS_READ), n, "frame {frame}: reads");
        assert_eq!(column(&stats, READ_LATENCY_MAX_US), max, "frame {frame}");
        assert_eq!(column(&stats, READ_LATENCY_MEAN_US), mean, "frame {frame}");
        assert!(column(&stats, READ_WAIT_US) >= 0.0);
        all_us.extend(this_frame);
    }
    assert!(all_us.len() > 20, "only {} chunks read", all_us.len());
    all_us.sort_by(f64::total_cmp);
    let facts = algorithm.run_facts();
    let fact = |name| facts.iter().find(|(k, _)| *k == name).unwrap().1;
    assert_eq!(fact("chunks_read"), all_us.len() as f64);
    assert_eq!(fact("read_latency_p50_us"), nearest_rank(&all_us, 0.5));
    assert_eq!(fact("read_latency_p95_us"), nearest_rank(&all_us, 0.95));
    assert_eq!(fact("read_latency_max_us"), *all_us.last().unwrap());
    assert!(fact("read_latency_p50_us") < fact("read_latency_max_us"));
}

#[test]
fn heights_from_disk_need_the_loading_effect() {
    let terrain = Terrain::integer(4);
    let hierarchy = terrain.hierarchy();
    let (_folder, path) = prepare(&terrain, RawSample::I16Le, true, 2);
    let loader = PyramidLoader::start(PyramidFile::open(&path).unwrap());
    let error = Chunked::new(&hierarchy, chunked(1.0, 2), &view_600())
        .with_disk_heights(Box::new(loader))
        .err()
        .unwrap();
    assert!(error.contains("`loading` effect"), "{error}");
}

#[test]
fn the_prepare_command_writes_the_pyramid_and_reports_progress() {
    let folder = tempfile::tempdir().unwrap();
    Terrain::integer(6).write_raw(&folder.path().join("t.raw"), RawSample::I16Le, true);
    let args = [
        "prepare",
        "t.raw",
        "--raw-side",
        "65",
        "--raw-sample",
        "i16le",
        "--spacing-m",
        "30,20",
        "--chunk-level",
        "4",
        "--out",
        "t.pyramid",
    ];
    let output = common::cli::roamsim(&args, folder.path());
    let (stdout, stderr) = (
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr),
    );
    assert!(output.status.success(), "{stderr}");
    assert!(
        stdout.contains("chunks of 17² (3 levels, 21 chunks)"),
        "{stdout}"
    );
    assert!(stderr.contains("prepare: 65/65 rows (100%)"), "{stderr}");
    let pyramid = PyramidFile::open(&folder.path().join("t.pyramid")).unwrap();
    assert_eq!(pyramid.header().n_chunks(), 21);

    let args_wrong_side = {
        let mut args = args;
        args[3] = "64";
        args
    };
    common::cli::fails_with(
        &args_wrong_side,
        folder.path(),
        &["t.raw", "2^n + 1 samples a side"],
    );
}

/// The shipped SRTM tile, by its absolute path.
fn shipped_tile() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/data/N48E009.hgt")
}

#[test]
fn prepare_from_the_shipped_hgt_equals_prepare_from_the_same_heights_as_raw_bit_for_bit() {
    let folder = tempfile::tempdir().unwrap();
    let cwd = folder.path();
    let tile = shipped_tile();
    let tile_path = tile.to_str().unwrap();
    common::cli::succeeds(
        &[
            "prepare",
            tile_path,
            "--fit",
            "crop",
            "--chunk-level",
            "5",
            "--out",
            "hgt.pyr",
        ],
        cwd,
    );
    // The heights a run reads: the centred 1025² crop (columns and rows 88..=1112 of the tile,
    // north row first), its 21 voids filled with their nearest sample's height.
    let file = serde_json::json!({"path": tile_path, "fit": "crop"});
    let (field, _) = roamsim::edge::experiment::load_terrain_file(&tile, &file).unwrap();
    assert_eq!(field.side(), 1025);
    let bytes = std::fs::read(&tile).unwrap();
    let mut raw = Vec::with_capacity(1025 * 1025 * 2);
    let mut from_tile = 0;
    for row_from_north in 0..1025 {
        for column in 0..1025 {
            let z = field.height(column, 1024 - row_from_north);
            let k = 2 * ((88 + row_from_north) * 1201 + 88 + column);
            let stored = i16::from_be_bytes([bytes[k], bytes[k + 1]]);
            if stored != -32768 {
                assert_eq!(
                    z,
                    f32::from(stored),
                    "column {column}, row {row_from_north}"
                );
                from_tile += 1;
            }
            raw.extend_from_slice(&(z as i16).to_le_bytes());
        }
    }
    assert!(from_tile > 1025 * 1025 - 22);
    std::fs::write(cwd.join("same.raw"), raw).unwrap();
    let spacing = field.spacing();
    let spacing = format!("{:?},{:?}", spacing.dx, spacing.dy);
    let raw_args = [
        "prepare",
        "same.raw",
        "--raw-side",
        "1025",
        "--raw-sample",
        "i16le",
        "--spacing-m",
        &spacing,
        "--chunk-level",
        "5",
        "--out",
        "raw.pyr",
    ];
    common::cli::succeeds(&raw_args, cwd);
    let from_hgt = std::fs::read(cwd.join("hgt.pyr")).unwrap();
    let from_raw = std::fs::read(cwd.join("raw.pyr")).unwrap();
    assert_eq!(from_hgt.len(), from_raw.len());
    let first_difference = (0..from_hgt.len()).find(|&k| from_hgt[k] != from_raw[k]);
    assert_eq!(first_difference, None, "the pyramids differ");
    let header = *PyramidFile::open(&cwd.join("hgt.pyr")).unwrap().header();
    assert_eq!(header.sample, StoredSample::I16);
}

#[test]
fn prepare_refuses_an_unknown_or_unreadable_terrain_naming_the_file() {
    let folder = tempfile::tempdir().unwrap();
    let cwd = folder.path();
    std::fs::write(cwd.join("notes.txt"), "not a terrain").unwrap();
    common::cli::fails_with(
        &["prepare", "notes.txt", "--out", "t.pyr"],
        cwd,
        &["notes.txt", "unknown terrain format"],
    );
    std::fs::write(cwd.join("short.hgt"), [0u8; 100]).unwrap();
    common::cli::fails_with(
        &["prepare", "short.hgt", "--out", "t.pyr"],
        cwd,
        &["short.hgt"],
    );
    common::cli::fails_with(
        &["prepare", "absent.tif", "--out", "t.pyr"],
        cwd,
        &["absent.tif"],
    );
    assert!(!cwd.join("t.pyr").exists());
}

#[test]
fn prepare_refuses_a_terrain_too_large_to_read_whole_before_reading_it() {
    // A header that declares 300 000² samples: 360 GB as f32, more than any machine here.
    let folder = tempfile::tempdir().unwrap();
    let cwd = folder.path();
    std::fs::write(
        cwd.join("huge.asc"),
        "ncols 300000\nnrows 300000\nxllcorner 0\nyllcorner 0\ncellsize 30\n1 2 3\n",
    )
    .unwrap();
    common::cli::fails_with(
        &["prepare", "huge.asc", "--fit", "crop", "--out", "t.pyr"],
        cwd,
        &[
            "huge.asc",
            "300000×300000 samples",
            "of memory",
            "raw file",
            "--raw-side",
        ],
    );
    assert!(!cwd.join("t.pyr").exists());
}
