//! Times the audit against its reference (the audit as first written), interleaved, on one
//! frame's mesh of an experiment entry:
//!
//! ```text
//! cargo run --release --example audit_ratio EXPERIMENT LABEL FRAME STRIDE [ROUNDS]
//! ```
//!
//! flies the entry to FRAME, then audits its mesh at STRIDE ROUNDS times (default 200) with
//! each auditor in turn and prints the best and the median time of each and their ratios. The
//! best of many interleaved rounds is the figure least moved by other work on a shared
//! machine; `benches/hot_paths.rs` (`audit_one_frame`) is the criterion measurement. Checks
//! that both give the same figures. `docs/performance.md` quotes its ratios.

use roamsim::edge::experiment;
use roamsim::sim::algorithm::{BrokenBounds, FrameInput};
use roamsim::sim::audit::reference::ReferenceAuditor;
use roamsim::sim::audit::{AuditSettings, Auditor};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::Camera;
use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (path, label, frame, stride, rounds) = match args.as_slice() {
        [path, label, frame, stride] => (path, label, frame, stride, "200"),
        [path, label, frame, stride, rounds] => (path, label, frame, stride, rounds.as_str()),
        _ => {
            eprintln!("usage: audit_ratio EXPERIMENT LABEL FRAME STRIDE [ROUNDS]");
            std::process::exit(2);
        }
    };
    let last: u64 = frame.parse().expect("FRAME is a frame number");
    let stride: u32 = stride.parse().expect("STRIDE is a whole number");
    let rounds: usize = rounds.parse().expect("ROUNDS is a whole number");
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
    let camera_at = |frame| {
        Camera::new(
            &experiment.field.local_pose(experiment.flight.pose(frame)),
            experiment.view,
        )
    };
    for frame in 0..=last {
        let camera = camera_at(frame);
        let input = FrameInput {
            frame,
            camera: &camera,
            broken_bounds: BrokenBounds::NONE,
        };
        algorithm.update(&input, &mut FrameStats::default());
        algorithm.prepare_draw();
    }
    let camera = camera_at(last);
    let settings = AuditSettings {
        stride,
        popping: false,
        detail_stride: None,
    };
    let mut auditor = Auditor::new(&hierarchy, settings);
    let mut reference = ReferenceAuditor::new(&hierarchy, settings);
    let (mut new_times, mut reference_times) = (Vec::new(), Vec::new());
    for _ in 0..rounds.max(1) {
        let start = Instant::now();
        let a = auditor.audit(&hierarchy, algorithm.mesh(), &camera);
        new_times.push(start.elapsed().as_secs_f64());
        let start = Instant::now();
        let b = reference.audit(&hierarchy, algorithm.mesh(), &camera);
        reference_times.push(start.elapsed().as_secs_f64());
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "the figures differ");
    }
    for times in [&mut new_times, &mut reference_times] {
        times.sort_by(f64::total_cmp);
    }
    let best_and_median = |times: &[f64]| (times[0] * 1e3, times[times.len() / 2] * 1e3);
    let (new_best, new_median) = best_and_median(&new_times);
    let (ref_best, ref_median) = best_and_median(&reference_times);
    println!(
        "audit: best {new_best:.3} ms, median {new_median:.3} ms; reference: best \
         {ref_best:.3} ms, median {ref_median:.3} ms; ratio best {:.2}, median {:.2} \
         ({} rounds, figures identical)",
        ref_best / new_best,
        ref_median / new_median,
        rounds.max(1)
    );
}
