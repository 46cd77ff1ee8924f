//! Golden determinism: every quickstart entry over the first 60 frames of its flight, hashed —
//! every per-frame count and algorithm column (never the timings) and every frame's mesh — must
//! equal the hash pinned for it in `tests/golden/quickstart-60.sha256`, whatever the thread
//! count (SPEC §8: the same experiment gives the same counts and meshes every time). The
//! test-only triangle-list and morphed-lattice algorithms (`tests/common/patches.rs`) are pinned
//! the same way in `tests/golden/patches-40.sha256`.
//!
//! Each `.sha256` file holds one line per entry: the entry's hash, two spaces, its label. So a
//! change to one algorithm re-pins its own entries' lines and leaves the others alone, and a new
//! entry adds a line. Beside it, `*.frames.tsv` pins every entry's frames one per line (counts,
//! the algorithm's columns as bits, a digest of the mesh), so that a mismatch names each entry
//! that moved, the first frame where it diverges and what differs there, not only that a hash
//! moved.
//!
//! A 4-8 mesh is hashed by its active vertex ids (and the heights of morphing vertices, when
//! it has any); a triangle list through the mesh visitor, triangle by triangle (corner positions
//! and heights, role, group, level).
//!
//! A change that alters any decision of any algorithm changes the hash. If the change is
//! intended, re-pin with `ROAMSIM_BLESS=1 cargo test --test golden` and say why in the commit.
//! Pinned on x86_64 Linux; a platform whose libm rounds sin/cos/atan2 differently in the last bit
//! could in principle flip a decision that sits exactly on a threshold.

mod common;

use common::experiment::{repository, save, short_quickstart};
use common::patches::{Borders, MorphingLattice, PatchConfig, Patches};
use common::{bumpy_terrain, step, view_600};
use glam::DVec3;
use rayon::prelude::*;
use roamsim::edge::experiment::{self, Experiment};
use roamsim::sim::algorithm::LodAlgorithm;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::MeshOutput;
use roamsim::sim::view::{Camera, Pose};
use sha2::{Digest, Sha256};
use std::fmt::Write;
use std::path::Path;

const FRAMES: u64 = 60;

/// One entry's frames as pinned: per frame its counts, its columns' bits and its mesh digest.
struct EntryRecord {
    label: String,
    frames: Vec<FrameRecord>,
}

#[derive(Clone, Debug, PartialEq)]
struct FrameRecord {
    counts: [u64; 6],
    extra_bits: Vec<u64>,
    mesh: String,
}

/// The names of [`FrameRecord::counts`], in order.
const COUNT_NAMES: [&str; 6] = [
    "triangles",
    "splits",
    "merges",
    "vertices_inserted",
    "vertices_deleted",
    "metric_evaluations",
];

impl EntryRecord {
    /// The entry's bytes as the hash takes them: its label, then per frame the counts, the
    /// columns and the mesh digest.
    fn hash_bytes(&self) -> Vec<u8> {
        let mut bytes = self.label.as_bytes().to_vec();
        for frame in &self.frames {
            for count in frame.counts {
                bytes.extend(count.to_le_bytes());
            }
            for bits in &frame.extra_bits {
                bytes.extend(bits.to_le_bytes());
            }
            bytes.extend(hex_to_bytes(&frame.mesh));
        }
        bytes
    }
}

/// Runs `algorithm` through `cameras` and records every frame.
fn record(
    label: &str,
    hierarchy: &Hierarchy,
    algorithm: &mut dyn LodAlgorithm,
    cameras: &[Camera],
) -> EntryRecord {
    let frames = cameras
        .iter()
        .enumerate()
        .map(|(frame, camera)| {
            let stats = step(algorithm, frame as u64, camera, false);
            FrameRecord {
                counts: [
                    stats.triangles,
                    stats.splits,
                    stats.merges,
                    stats.vertices_inserted,
                    stats.vertices_deleted,
                    stats.metric_evaluations,
                ],
                extra_bits: stats.extra.iter().map(|v| v.to_bits()).collect(),
                mesh: mesh_digest(hierarchy, algorithm.mesh()),
            }
        })
        .collect();
    EntryRecord {
        label: label.to_string(),
        frames,
    }
}

/// SHA-256 of a mesh, as hex.
fn mesh_digest(hierarchy: &Hierarchy, mesh: MeshOutput) -> String {
    let mut hash = Sha256::new();
    match mesh {
        MeshOutput::Lattice(lattice_mesh) => {
            for id in lattice_mesh.vertices.iter() {
                hash.update(id.to_le_bytes());
            }
            if let Some(morphed) = lattice_mesh.morphed {
                for id in morphed.sorted_ids() {
                    hash.update(id.to_le_bytes());
                    hash.update(morphed.get(id).unwrap_or(f32::NAN).to_bits().to_le_bytes());
                }
            }
        }
        MeshOutput::Triangles(_) => mesh.for_each_triangle(hierarchy, |triangle| {
            for corner in triangle.corners {
                let (x, y) = corner.position.raw();
                hash.update(x.to_le_bytes());
                hash.update(y.to_le_bytes());
                hash.update(corner.z.to_bits().to_le_bytes());
            }
            let info = triangle.info;
            hash.update([info.role.index() as u8]);
            hash.update(info.group.to_le_bytes());
            hash.update(info.level.to_le_bytes());
        }),
    }
    hex(&hash.finalize())
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn hex_to_bytes(text: &str) -> Vec<u8> {
    (0..text.len())
        .step_by(2)
        .map(|k| u8::from_str_radix(&text[k..k + 2], 16).unwrap())
        .collect()
}

/// Every entry's line of the `.sha256` file: the hash of its bytes, two spaces, its label.
fn hash_lines(entries: &[EntryRecord]) -> Vec<String> {
    entries
        .iter()
        .map(|entry| {
            format!(
                "{}  {}",
                hex(&Sha256::digest(entry.hash_bytes())),
                entry.label
            )
        })
        .collect()
}

/// The records as the `.frames.tsv` file holds them.
fn frames_tsv(entries: &[EntryRecord]) -> String {
    let mut text = format!(
        "entry\tframe\t{}\textra_bits\tmesh\n",
        COUNT_NAMES.join("\t")
    );
    for entry in entries {
        for (frame, record) in entry.frames.iter().enumerate() {
            let counts: Vec<String> = record.counts.iter().map(u64::to_string).collect();
            let bits: Vec<String> = record.extra_bits.iter().map(|b| format!("{b:x}")).collect();
            let _ = writeln!(
                text,
                "{}\t{frame}\t{}\t{}\t{}",
                entry.label,
                counts.join("\t"),
                bits.join(","),
                record.mesh
            );
        }
    }
    text
}

/// The header and the lines of entry `label` in a `.frames.tsv` text.
fn entry_frames(frames_tsv: &str, label: &str) -> String {
    let mut lines = frames_tsv.lines();
    let mut text = format!("{}\n", lines.next().unwrap_or(""));
    for line in lines.filter(|line| line.split('\t').next() == Some(label)) {
        text.push_str(line);
        text.push('\n');
    }
    text
}

/// The first line of `actual` that differs from `pinned`, described: entry, frame, and each
/// field that moved with its pinned value.
fn first_divergence(pinned: &str, actual: &str) -> String {
    let header: Vec<&str> = actual.lines().next().unwrap_or("").split('\t').collect();
    for (was, now) in pinned.lines().zip(actual.lines()).skip(1) {
        if was == now {
            continue;
        }
        let (was, now): (Vec<&str>, Vec<&str>) =
            (was.split('\t').collect(), now.split('\t').collect());
        let moved: Vec<String> = header
            .iter()
            .enumerate()
            .filter(|&(k, _)| was.get(k) != now.get(k))
            .map(|(k, name)| {
                format!(
                    "{name} {} (pinned {})",
                    now.get(k).unwrap_or(&"—"),
                    was.get(k).unwrap_or(&"—")
                )
            })
            .collect();
        return format!(
            "first divergence: entry {:?}, frame {}: {}",
            now.first().unwrap_or(&"?"),
            now.get(1).unwrap_or(&"?"),
            moved.join("; ")
        );
    }
    let (pinned_lines, actual_lines) = (pinned.lines().count(), actual.lines().count());
    if pinned_lines == actual_lines {
        "every frame matches the pinned frames file, so the pinned hash itself is out of date"
            .to_string()
    } else {
        format!(
            "{} frames pinned, {} in this run",
            pinned_lines.saturating_sub(1),
            actual_lines.saturating_sub(1)
        )
    }
}

/// Compares a run with its pinned hashes (`<stem>.sha256`, a line per entry) and frames
/// (`<stem>.frames.tsv`); with `ROAMSIM_BLESS` set, pins this run first. Fails naming every
/// entry whose hash moved (with its first diverging frame), every entry not pinned, and every
/// pinned entry the run no longer has.
fn check_pinned(stem: &str, entries: &[EntryRecord]) {
    let dir = repository().join("tests/golden");
    let hash_path = dir.join(format!("{stem}.sha256"));
    let frames_path = dir.join(format!("{stem}.frames.tsv"));
    let lines = hash_lines(entries);
    let frames = frames_tsv(entries);
    if std::env::var_os("ROAMSIM_BLESS").is_some() {
        std::fs::write(&hash_path, format!("{}\n", lines.join("\n"))).unwrap();
        std::fs::write(&frames_path, &frames).unwrap();
    }
    let pinned = std::fs::read_to_string(&hash_path).unwrap();
    let pinned_frames = std::fs::read_to_string(&frames_path).ok();
    let pinned_hash = |label: &str| {
        pinned
            .lines()
            .filter_map(|line| line.split_once("  "))
            .find(|(_, pinned_label)| *pinned_label == label)
            .map(|(hash, _)| hash)
    };
    let mut problems = Vec::new();
    for (entry, line) in entries.iter().zip(&lines) {
        let label = entry.label.as_str();
        let (hash, _) = line.split_once("  ").unwrap();
        match pinned_hash(label) {
            Some(pinned) if pinned == hash => {}
            Some(_) => {
                let where_ = match &pinned_frames {
                    Some(pinned_frames) => first_divergence(
                        &entry_frames(pinned_frames, label),
                        &entry_frames(&frames, label),
                    ),
                    None => format!("({} is missing: no frame to name)", display(&frames_path)),
                };
                problems.push(format!("entry {label:?}: a decision changed; {where_}"));
            }
            None => problems.push(format!("entry {label:?} is not pinned")),
        }
    }
    for (_, label) in pinned.lines().filter_map(|line| line.split_once("  ")) {
        if !entries.iter().any(|entry| entry.label == label) {
            problems.push(format!("pinned entry {label:?} is no longer run"));
        }
    }
    if problems.is_empty() && pinned_frames.as_deref() != Some(frames.as_str()) {
        problems.push(format!(
            "every hash matches but {} does not: it is out of date",
            display(&frames_path)
        ));
    }
    assert!(
        problems.is_empty(),
        "{stem}:\n{}\nIf intended, re-pin with ROAMSIM_BLESS=1 (see the module docs)",
        problems.join("\n")
    );
}

fn display(path: &Path) -> String {
    path.display().to_string()
}

/// Every quickstart entry over its first frames, on `threads` threads.
fn quickstart_records(
    threads: usize,
    experiment: &Experiment,
    hierarchy: &Hierarchy,
) -> Vec<EntryRecord> {
    let cameras: Vec<Camera> = (0..experiment.flight.n_frames())
        .map(|frame| {
            let pose = hierarchy.field().local_pose(experiment.flight.pose(frame));
            Camera::new(&pose, experiment.view)
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        experiment
            .algorithms
            .par_iter()
            .map(|spec| {
                let mut algorithm =
                    spec.config
                        .build(hierarchy, &experiment.view, experiment.speed);
                record(&spec.label, hierarchy, algorithm.as_mut(), &cameras)
            })
            .collect()
    })
}

#[test]
fn the_quickstart_counts_and_meshes_match_the_pinned_hashes_on_one_and_four_threads() {
    let dir = tempfile::tempdir().unwrap();
    let path = save(dir.path(), "golden", &short_quickstart(FRAMES));
    let experiment = experiment::load(&path).unwrap();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let one = quickstart_records(1, &experiment, &hierarchy);
    let four = quickstart_records(4, &experiment, &hierarchy);
    assert_eq!(
        frames_tsv(&one),
        frames_tsv(&four),
        "the thread count changed a count or a mesh"
    );
    check_pinned("quickstart-60", &one);
}

#[test]
fn the_test_only_triangle_list_and_morphing_algorithms_match_their_pinned_hashes() {
    let hierarchy = bumpy_terrain(6);
    let cameras: Vec<Camera> = (0..40)
        .map(|k| {
            let angle = 0.05 * f64::from(k);
            let pose = Pose {
                position: DVec3::new(
                    320.0 + 250.0 * angle.cos(),
                    320.0 + 250.0 * angle.sin(),
                    60.0,
                ),
                yaw: angle + std::f64::consts::FRAC_PI_2,
                pitch: -0.4,
            };
            Camera::new(&pose, view_600())
        })
        .collect();
    let config = PatchConfig {
        patch_level: 3,
        borders: Borders::Skirts { depth_m: 15.0 },
        morph: true,
        strip_joins: true,
        detail_distance_m: 60.0,
    };
    let collapsed = PatchConfig {
        borders: Borders::Collapsed,
        morph: false,
        strip_joins: false,
        ..config
    };
    let run = || -> Vec<EntryRecord> {
        vec![
            record(
                "skirts",
                &hierarchy,
                &mut Patches::new(&hierarchy, config),
                &cameras,
            ),
            record(
                "collapsed",
                &hierarchy,
                &mut Patches::new(&hierarchy, collapsed),
                &cameras,
            ),
            record(
                "morphing lattice",
                &hierarchy,
                &mut MorphingLattice::new(&hierarchy, 1, 100.0, 300.0),
                &cameras,
            ),
        ]
    };
    let first = run();
    assert_eq!(
        frames_tsv(&first),
        frames_tsv(&run()),
        "a second run differs"
    );
    check_pinned("patches-40", &first);
}

#[test]
fn a_divergence_is_named_by_entry_frame_and_field() {
    let pinned = "entry\tframe\ttriangles\tmesh\nwu\t0\t10\taa\nwu\t1\t12\tbb\n";
    let actual = "entry\tframe\ttriangles\tmesh\nwu\t0\t10\taa\nwu\t1\t14\tcc\n";
    assert_eq!(
        first_divergence(pinned, actual),
        "first divergence: entry \"wu\", frame 1: triangles 14 (pinned 12); mesh cc \
         (pinned bb)"
    );
}

#[test]
fn an_entry_s_frames_are_cut_from_the_frames_file_with_its_header() {
    let frames = "entry\tframe\tmesh\nwu\t0\taa\nroam\t0\tbb\nwu\t1\tcc\n";
    assert_eq!(
        entry_frames(frames, "wu"),
        "entry\tframe\tmesh\nwu\t0\taa\nwu\t1\tcc\n"
    );
    assert_eq!(entry_frames(frames, "lindstrom"), "entry\tframe\tmesh\n");
}
