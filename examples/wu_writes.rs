//! Prints, for each frame of one Wu entry of an experiment, what Wu's incremental buffers
//! uploaded and how the drawn mesh changed, as CSV on stdout, and the sums over frames
//! FIRST..END on stderr:
//!
//! ```text
//! cargo build --example wu_writes
//! target/debug/examples/wu_writes EXPERIMENT LABEL FIRST END > frames.csv
//! ```
//!
//! Columns: `splits`, `merges` (the update's counts), `triangles` drawn, `upload_bytes` (what
//! `prepare_draw` wrote), `vertices_in` / `vertices_out` and `leaves_in` / `leaves_out` (the
//! drawn mesh against the previous frame's, read back from the buffers' one draw), and
//! `leaf_writes`: the 12-byte leaf slots written (a new leaf, an overwritten one or a
//! swap-remove's move), the upload less 12 bytes a vertex in. That last column assumes 12-byte
//! vertices (no `morph_frames`) and no vertex both inserted and deleted within one frame (it
//! would count as a leaf write). Two builds compared frame by frame say whether the mesh changed
//! (the `*_in`/`*_out` columns) or only the buffers' upkeep (`leaf_writes`); `docs/performance.md`
//! quotes such a comparison. Not a timing tool (`wu_frames.rs` is the one for callgrind).

use roamsim::edge::experiment;
use roamsim::sim::algorithm::{AlgorithmConfig, BrokenBounds, FrameInput, LodAlgorithm, Wu};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::Camera;
use std::collections::HashSet;
use std::path::PathBuf;

/// A drawn corner's raw plan position.
type Corner = (i64, i64);

/// The sums of the printed columns.
const COLUMNS: [&str; 10] = [
    "splits",
    "merges",
    "triangles",
    "upload_bytes",
    "vertices_in",
    "vertices_out",
    "leaves_in",
    "leaves_out",
    "leaf_writes",
    "frames",
];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [path, label, first, end] = args.as_slice() else {
        eprintln!("usage: wu_writes EXPERIMENT LABEL FIRST END");
        std::process::exit(2);
    };
    let first: u64 = first.parse().expect("FIRST is a frame number");
    let end: u64 = end.parse().expect("END is a frame number");
    let experiment = experiment::load(&PathBuf::from(path)).expect("the experiment loads");
    let end = end.min(experiment.flight.poses().len() as u64);
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let spec = experiment
        .algorithms
        .iter()
        .find(|s| s.label == *label)
        .unwrap_or_else(|| panic!("no entry {label:?}"));
    let AlgorithmConfig::Wu(config) = spec.config else {
        panic!("{label:?} is not a wu entry");
    };
    let mut wu = Wu::new(&hierarchy, config, &experiment.view, experiment.speed);
    let mut vertices: HashSet<Corner> = HashSet::new();
    let mut leaves: HashSet<[Corner; 3]> = HashSet::new();
    let mut sums = [0u64; COLUMNS.len()];
    println!("frame,{}", COLUMNS[..COLUMNS.len() - 1].join(","));
    for frame in 0..end {
        let pose = experiment.field.local_pose(experiment.flight.pose(frame));
        let camera = Camera::new(&pose, experiment.view);
        let mut stats = FrameStats::default();
        let input = FrameInput {
            frame,
            camera: &camera,
            broken_bounds: BrokenBounds::all_if(frame == 0),
        };
        wu.update(&input, &mut stats);
        let counts = wu.prepare_draw();
        let mut now_vertices = HashSet::new();
        let mut now_leaves = HashSet::new();
        wu.buffers().for_each_triangle(|triangle| {
            let mut corners = triangle.map(|c| c.position.raw());
            now_vertices.extend(corners);
            corners.sort_unstable();
            now_leaves.insert(corners);
        });
        let vertices_in = now_vertices.difference(&vertices).count() as u64;
        let row = [
            stats.splits,
            stats.merges,
            now_leaves.len() as u64,
            counts.upload_bytes,
            vertices_in,
            vertices.difference(&now_vertices).count() as u64,
            now_leaves.difference(&leaves).count() as u64,
            leaves.difference(&now_leaves).count() as u64,
            (counts.upload_bytes - 12 * vertices_in) / 12,
            1,
        ];
        let printed: Vec<String> = row[..row.len() - 1].iter().map(u64::to_string).collect();
        println!("{frame},{}", printed.join(","));
        if frame >= first {
            for (sum, value) in sums.iter_mut().zip(row) {
                *sum += value;
            }
        }
        vertices = now_vertices;
        leaves = now_leaves;
    }
    eprintln!("wu, entry {label:?}, frames {first}..{end}, sums:");
    for (name, sum) in COLUMNS.iter().zip(sums) {
        eprintln!("  {name} {sum}");
    }
}
