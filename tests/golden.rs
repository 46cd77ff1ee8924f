//! Golden determinism: every quickstart entry over the first 60 frames of its flight, hashed —
//! every per-frame count and algorithm column (never the timings) and every frame's mesh — must
//! equal the hash pinned for it in `tests/golden/quickstart-60.sha256` (one line per entry:
//! the hash, two spaces, the entry's label), whatever the thread count.
//!
//! A change that alters any decision of any algorithm changes its entry's hash, and only its
//! entry's: a new entry adds a line and leaves the others alone. If the change is intended,
//! re-pin with `ROAMSIM_BLESS=1 cargo test --test golden` and say why in the commit. Pinned on
//! x86_64 Linux; a platform whose libm rounds sin/cos/atan2 differently in the last bit could in
//! principle flip a decision that sits exactly on a threshold.

mod common;

use common::experiment::{repository, save, short_quickstart};
use rayon::prelude::*;
use roamsim::edge::experiment::{self, AlgorithmSpec, Experiment};
use roamsim::sim::algorithm::FrameInput;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::Camera;
use sha2::{Digest, Sha256};

const FRAMES: u64 = 60;

/// One entry's frames, counts and meshes, as bytes.
fn entry_bytes(spec: &AlgorithmSpec, experiment: &Experiment, hierarchy: &Hierarchy) -> Vec<u8> {
    let mut algorithm = spec
        .config
        .build(hierarchy, &experiment.view, experiment.speed);
    let mut bytes = spec.label.as_bytes().to_vec();
    for frame in 0..experiment.flight.n_frames() {
        let pose = hierarchy.field().local_pose(experiment.flight.pose(frame));
        let camera = Camera::new(&pose, experiment.view);
        let mut stats = FrameStats::default();
        algorithm.update(
            &FrameInput {
                frame,
                camera: &camera,
                speed_bound_broken: false,
            },
            &mut stats,
        );
        for count in [
            stats.triangles,
            stats.splits,
            stats.merges,
            stats.vertices_inserted,
            stats.vertices_deleted,
            stats.metric_evaluations,
        ] {
            bytes.extend(count.to_le_bytes());
        }
        for value in &stats.extra {
            bytes.extend(value.to_bits().to_le_bytes());
        }
        let mut mesh = Sha256::new();
        for id in algorithm.mesh().iter() {
            mesh.update(id.to_le_bytes());
        }
        bytes.extend(mesh.finalize());
    }
    bytes
}

fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// Every entry's hash line (`<hash>  <label>`), computed on `threads` threads.
fn quickstart_hashes(threads: usize) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let path = save(dir.path(), "golden", &short_quickstart(FRAMES));
    let experiment = experiment::load(&path).unwrap();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        experiment
            .algorithms
            .par_iter()
            .map(|spec| {
                let digest = Sha256::digest(entry_bytes(spec, &experiment, &hierarchy));
                format!("{}  {}", hex(&digest), spec.label)
            })
            .collect()
    })
}

#[test]
fn the_quickstart_counts_and_meshes_match_the_pinned_hashes_on_one_and_four_threads() {
    let pinned_path = repository().join("tests/golden/quickstart-60.sha256");
    let one = quickstart_hashes(1);
    let four = quickstart_hashes(4);
    assert_eq!(one, four, "the thread count changed a count or a mesh");
    if std::env::var_os("ROAMSIM_BLESS").is_some() {
        std::fs::write(&pinned_path, format!("{}\n", one.join("\n"))).unwrap();
    }
    let pinned = std::fs::read_to_string(&pinned_path).unwrap();
    let pinned: Vec<&str> = pinned.lines().collect();
    for line in &one {
        let label = line.split_once("  ").unwrap().1;
        let pinned_line = pinned
            .iter()
            .find(|p| p.split_once("  ").map(|(_, l)| l) == Some(label));
        assert_eq!(
            pinned_line.copied(),
            Some(line.as_str()),
            "entry {label:?}: a decision changed; if intended, re-pin with ROAMSIM_BLESS=1 (see \
             the module docs)"
        );
    }
    assert_eq!(
        pinned.len(),
        one.len(),
        "pinned entries that the quickstart no longer has"
    );
}
