//! Golden determinism: every quickstart entry over the first 60 frames of its flight, hashed —
//! every per-frame count and algorithm column (never the timings) and every frame's mesh — must
//! equal the hash pinned in `tests/golden/quickstart-60.sha256`, whatever the thread count.
//!
//! A change that alters any decision of any algorithm changes the hash. If the change is
//! intended, re-pin with `ROAMSIM_BLESS=1 cargo test --test golden` and say why in the commit.
//! Pinned on x86_64 Linux; a platform whose libm rounds sin/cos/atan2 differently in the last bit
//! could in principle flip a decision that sits exactly on a threshold.

mod common;

use common::experiment::{repository, save, short_quickstart};
use rayon::prelude::*;
use roamsim::edge::experiment::{self, AlgorithmSpec, Experiment};
use roamsim::sim::algorithm::BrokenBounds;
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
                broken_bounds: BrokenBounds::NONE,
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

/// The hash of every entry, computed on `threads` threads.
fn quickstart_hash(threads: usize) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = save(dir.path(), "golden", &short_quickstart(FRAMES));
    let experiment = experiment::load(&path).unwrap();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let entries: Vec<Vec<u8>> = pool.install(|| {
        experiment
            .algorithms
            .par_iter()
            .map(|spec| entry_bytes(spec, &experiment, &hierarchy))
            .collect()
    });
    let mut hash = Sha256::new();
    for entry in entries {
        hash.update(&entry);
    }
    hash.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

#[test]
fn the_quickstart_counts_and_meshes_match_the_pinned_hash_on_one_and_four_threads() {
    let pinned_path = repository().join("tests/golden/quickstart-60.sha256");
    let one = quickstart_hash(1);
    let four = quickstart_hash(4);
    assert_eq!(one, four, "the thread count changed a count or a mesh");
    if std::env::var_os("ROAMSIM_BLESS").is_some() {
        std::fs::write(&pinned_path, format!("{one}\n")).unwrap();
    }
    let pinned = std::fs::read_to_string(&pinned_path).unwrap();
    assert_eq!(
        one,
        pinned.trim(),
        "a decision changed; if intended, re-pin with ROAMSIM_BLESS=1 (see the module docs)"
    );
}
