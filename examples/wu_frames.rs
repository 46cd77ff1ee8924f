//! Runs one Wu entry of an experiment (or the from-scratch reference at that entry's τ) over a
//! range of its flight's frames, for instruction counts:
//!
//! ```text
//! valgrind --tool=callgrind --toggle-collect='*measured_update*' \
//!     target/release/examples/wu_frames EXPERIMENT LABEL FIRST END [wu|reference-in-view|reference-everywhere]
//! ```
//!
//! counts only the updates of frames FIRST..END (the frames before bring the algorithm to that
//! point of the flight, uncounted; callgrind's call counts are not toggled and cover every
//! frame). Every frame also keeps the buffers a GPU draws (`prepare_draw`, as the runner does
//! after each update); `--toggle-collect='*measured_prepare_draw*'` counts that upkeep of frames
//! FIRST..END instead. The reference is built as `benches/wu_update.rs` builds it: the entry's nesting, zone
//! and τ (the paper's initial τ in budget mode), split iff ℓ ≤ 0. Prints the frames' mean
//! counters. Times nothing: the criterion bench does. `docs/performance.md` and
//! `docs/reproductions/wu-table1.md` quote its counts.

use roamsim::edge::experiment::{self, Experiment};
use roamsim::sim::algorithm::{
    AlgorithmConfig, BrokenBounds, FrameInput, LodAlgorithm, Reference, ReferenceConfig,
    Refinement, SplitThreshold, ViewThreshold, Wu,
};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::Camera;
use std::path::PathBuf;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (path, label, first, end, mode) = match args.as_slice() {
        [path, label, first, end] => (path, label, first, end, "wu"),
        [path, label, first, end, mode] => (path, label, first, end, mode.as_str()),
        _ => {
            eprintln!(
                "usage: wu_frames EXPERIMENT LABEL FIRST END \
                 [wu|reference-in-view|reference-everywhere]"
            );
            std::process::exit(2);
        }
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
    let AlgorithmConfig::Wu(config) = spec.config else {
        panic!("{label:?} is not a wu entry");
    };
    let wu = Wu::new(&hierarchy, config, &experiment.view, experiment.speed);
    let reference = |refine| {
        let config = ReferenceConfig {
            nesting: config.nesting,
            tau_px: wu.tau_px(),
            zone: config.zone,
            threshold: SplitThreshold::LifeAtMost(0.0),
            refine,
            view_threshold: ViewThreshold::InView,
        };
        Reference::new(&hierarchy, config, &experiment.view, experiment.speed)
    };
    let mut algorithm: Box<dyn LodAlgorithm + '_> = match mode {
        "reference-in-view" => Box::new(reference(Refinement::InView)),
        "reference-everywhere" => Box::new(reference(Refinement::Everywhere)),
        "wu" => Box::new(wu),
        other => panic!("unknown mode {other:?}"),
    };
    let columns = algorithm.extra_columns();
    let mut totals = FrameStats::default();
    let mut extra_totals = vec![0.0; columns.len()];
    for frame in 0..end {
        let stats = if frame < first {
            let stats = unmeasured_update(algorithm.as_mut(), &experiment, frame);
            algorithm.prepare_draw();
            stats
        } else {
            let stats = measured_update(algorithm.as_mut(), &experiment, frame);
            measured_prepare_draw(algorithm.as_mut());
            stats
        };
        if frame >= first {
            totals.triangles += stats.triangles;
            totals.splits += stats.splits;
            totals.merges += stats.merges;
            totals.metric_evaluations += stats.metric_evaluations;
            for (total, value) in extra_totals.iter_mut().zip(&stats.extra) {
                *total += value;
            }
        }
    }
    let n = end.saturating_sub(first).max(1) as f64;
    println!("{mode}, entry {label:?}, frames {first}..{end}, per frame:");
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

/// The buffer upkeep of a frame of the measured range (its own toggle).
#[inline(never)]
fn measured_prepare_draw(algorithm: &mut dyn LodAlgorithm) {
    algorithm.prepare_draw();
}
