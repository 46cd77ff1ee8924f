//! One frame to drawable buffers, for every algorithm of the study, at the study's
//! equal-triangle point on the Table 1 circle (`experiments/study-circle.json`: every entry at
//! 6000 rendered triangles), interleaved with the update alone in one run (issue #31, item 6).
//!
//! Each entry is built with the parameter value its `tune` found in the committed run
//! (`plots/study-circle/summary.json`, `tuning.value`), so the bench follows the study when its
//! outputs are regenerated; an entry without a committed tuning runs as the experiment writes it.
//! Every iteration flies one real frame (the flight from frame 300 on, after Wu's queues reached
//! their steady state) through the update and the buffer upkeep; `…/frame` times both (what
//! frames.csv's `frame_ns` measures), `…/update` only the update of the same frames. So the two
//! figures of an entry come from the same work on the same frames, and their ratio is what the
//! buffers cost.
//!
//! Run with `cargo bench --bench frame_to_buffers` (about a minute per entry on 2 cores);
//! `docs/performance.md` quotes its figures with the machine and the date.

mod common;

use common::drive;
use criterion::{Criterion, criterion_group, criterion_main};
use roamsim::edge::experiment::{self, tuned_spec};
use roamsim::sim::algorithm::LodAlgorithm;
use roamsim::sim::hierarchy::Hierarchy;
use std::path::Path;
use std::time::{Duration, Instant};

const WARM_UP_FRAMES: u64 = 300;

/// The value the committed study run's tuning found for the entry labelled `label`.
fn committed_tuning(summary: &serde_json::Value, label: &str) -> Option<f64> {
    summary["algorithms"]
        .as_array()?
        .iter()
        .find(|entry| entry["label"] == label)?["tuning"]["value"]
        .as_f64()
}

fn frame_to_buffers(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let experiment = experiment::load(&root.join("experiments/study-circle.json"))
        .expect("the shipped experiment loads");
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join("plots/study-circle/summary.json"))
            .expect("the committed study run"),
    )
    .expect("summary.json is JSON");
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let mut group = c.benchmark_group("frame_to_buffers_study_circle");
    group.measurement_time(Duration::from_secs(4));
    for spec in &experiment.algorithms {
        let spec = match (&spec.tune, committed_tuning(&summary, &spec.label)) {
            (Some(tune), Some(value)) => tuned_spec(spec, tune, value).expect("the tuned value"),
            _ => spec.clone(),
        };
        let mut algorithm: Box<dyn LodAlgorithm + '_> =
            spec.config
                .build(&hierarchy, &experiment.view, experiment.speed);
        for frame in 0..WARM_UP_FRAMES {
            drive(algorithm.as_mut(), &experiment, frame);
            algorithm.prepare_draw();
        }
        let mut frame = WARM_UP_FRAMES;
        // Times the update alone (`frame` false) or the update and the buffer upkeep, over
        // `iterations` real frames that always do both.
        let mut timed = |iterations: u64, whole_frame: bool| {
            let mut total = Duration::ZERO;
            for _ in 0..iterations {
                let start = Instant::now();
                drive(algorithm.as_mut(), &experiment, frame);
                let updated = start.elapsed();
                algorithm.prepare_draw();
                total += if whole_frame {
                    start.elapsed()
                } else {
                    updated
                };
                frame += 1;
            }
            total
        };
        group.bench_function(format!("{}/update", spec.label), |b| {
            b.iter_custom(|iterations| timed(iterations, false))
        });
        group.bench_function(format!("{}/frame", spec.label), |b| {
            b.iter_custom(|iterations| timed(iterations, true))
        });
    }
    group.finish();
}

criterion_group!(benches, frame_to_buffers);
criterion_main!(benches);
