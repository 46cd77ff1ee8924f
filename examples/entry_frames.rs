//! Runs any entry of an experiment over a range of its flight's frames, for instruction counts:
//!
//! ```text
//! valgrind --tool=callgrind --toggle-collect='*measured_update*' \
//!     target/release/examples/entry_frames EXPERIMENT LABEL FIRST END
//! ```
//!
//! counts only the updates of frames FIRST..END (the frames before bring the algorithm to that
//! point of the flight, uncounted; callgrind's call counts are not toggled and cover every
//! frame). The entry is built as the runner builds it ([`AlgorithmConfig::build`]); the
//! flight's first frame counts as a broken bound. Prints the frames' mean counters and an
//! order-dependent hash of every measured frame's mesh (triangles as the mesh's visitor gives
//! them), so that a change meant to leave the meshes alone can be checked to do so. Times
//! nothing: the criterion benches do. `docs/performance.md` quotes its counts.

use roamsim::edge::experiment::{self, Experiment};
use roamsim::sim::algorithm::{BrokenBounds, FrameInput, LodAlgorithm};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::Camera;
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::PathBuf;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [path, label, first, end] = args.as_slice() else {
        eprintln!("usage: entry_frames EXPERIMENT LABEL FIRST END");
        std::process::exit(2);
    };
    let first: u64 = first.parse().expect("FIRST is a frame number");
    let end: u64 = end.parse().expect("END is a frame number");
    let experiment = experiment::load(&PathBuf::from(path)).expect("the experiment loads");
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let spec = experiment
        .algorithms
        .iter()
        .find(|s| s.label == *label)
        .unwrap_or_else(|| panic!("no entry {label:?}"));
    let mut algorithm = spec
        .config
        .build(&hierarchy, &experiment.view, experiment.speed);
    let columns = algorithm.extra_columns();
    let mut totals = FrameStats::default();
    let mut extra_totals = vec![0.0; columns.len()];
    let mut hasher = DefaultHasher::new();
    for frame in 0..end {
        let stats = if frame < first {
            unmeasured_update(algorithm.as_mut(), &experiment, frame)
        } else {
            measured_update(algorithm.as_mut(), &experiment, frame)
        };
        if frame >= first {
            totals.triangles += stats.triangles;
            totals.splits += stats.splits;
            totals.merges += stats.merges;
            totals.metric_evaluations += stats.metric_evaluations;
            for (total, value) in extra_totals.iter_mut().zip(&stats.extra) {
                *total += value;
            }
            algorithm.triangle_count().hash(&mut hasher);
            algorithm.mesh().for_each_triangle(&hierarchy, |t| {
                for corner in t.corners {
                    corner.position.hash(&mut hasher);
                    corner.z.to_bits().hash(&mut hasher);
                }
                t.info.hash(&mut hasher);
            });
        }
    }
    let n = end.saturating_sub(first).max(1) as f64;
    println!("entry {label:?}, frames {first}..{end}, per frame:");
    println!("  triangles {:.1}", totals.triangles as f64 / n);
    println!("  splits {:.2}", totals.splits as f64 / n);
    println!("  merges {:.2}", totals.merges as f64 / n);
    println!(
        "  metric_evaluations {:.1}",
        totals.metric_evaluations as f64 / n
    );
    for (name, total) in columns.iter().zip(&extra_totals) {
        println!("  {name} {:.2}", total / n);
    }
    println!("  mesh hash {:016x}", hasher.finish());
}

/// One frame's update; the flight's first frame counts as a broken bound, as in the runner.
fn update(algorithm: &mut dyn LodAlgorithm, experiment: &Experiment, frame: u64) -> FrameStats {
    let pose = experiment.field.local_pose(experiment.flight.pose(frame));
    let camera = Camera::new(&pose, experiment.view);
    let mut stats = FrameStats::default();
    algorithm.update(
        &FrameInput {
            frame,
            camera: &camera,
            broken_bounds: BrokenBounds::all_if(frame == 0),
        },
        &mut stats,
    );
    stats
}

/// A frame before the measured range: inlined into `main`, so that it is no function the
/// toggle could match (nor one the compiler could fold with [`measured_update`]).
#[inline(always)]
fn unmeasured_update(
    algorithm: &mut dyn LodAlgorithm,
    experiment: &Experiment,
    frame: u64,
) -> FrameStats {
    update(algorithm, experiment, frame)
}

/// A frame of the measured range: the function callgrind's toggle names.
#[inline(never)]
fn measured_update(
    algorithm: &mut dyn LodAlgorithm,
    experiment: &Experiment,
    frame: u64,
) -> FrameStats {
    update(algorithm, experiment, frame)
}
