//! Per-frame update of Wu's algorithm at a 6000-triangle budget on the Table 1 flight
//! (`experiments/wu-table1.json`), against the from-scratch reference at the same τ.
//!
//! Three measurements: `wu` as the experiment runs it (budget counted on cone-culled triangles,
//! which adds the hierarchical cone count of `wu/cone_count.rs` per frame),
//! `wu_budget_on_all_triangles` (the same budget on the whole mesh: the queue work alone), and the
//! reference at the same τ.
//! All start from the same warmed-up point of the flight (Wu's queues in steady state) and then
//! advance one frame per iteration along the circle, so every measured update is a real frame.
//! Run with `cargo bench --bench wu_update`.

mod common;

use common::drive;
use criterion::{Criterion, criterion_group, criterion_main};
use roamsim::edge::experiment;
use roamsim::sim::algorithm::{AlgorithmConfig, Reference, ReferenceConfig, SplitThreshold, Wu};
use roamsim::sim::hierarchy::Hierarchy;
use std::path::Path;

const WARM_UP_FRAMES: u64 = 300;

fn per_frame_update(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/wu-table1.json");
    let experiment = experiment::load(&path).expect("the shipped experiment loads");
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let spec = experiment
        .algorithms
        .iter()
        .find(|s| s.label == "wu budget=6000")
        .expect("the 6000-triangle entry");
    let AlgorithmConfig::Wu(config) = spec.config else {
        panic!("not a wu entry");
    };
    let mut wu = Wu::new(&hierarchy, config, &experiment.view, experiment.speed);
    // The same budget counted on all triangles: the queue work without the cone count.
    let uncounted = roamsim::sim::algorithm::WuConfig {
        cone_culling: false,
        ..config
    };
    let mut wu_no_cone = Wu::new(&hierarchy, uncounted, &experiment.view, experiment.speed);
    let mut reference = Reference::new(
        &hierarchy,
        ReferenceConfig {
            nesting: roamsim::sim::hierarchy::NestingRule::Max,
            tau_px: wu.tau_px(),
            zone: config.zone,
            threshold: SplitThreshold::LifeAtMost(0.0),
        },
        &experiment.view,
        experiment.speed,
    );
    for frame in 0..WARM_UP_FRAMES {
        drive(&mut wu, &experiment, frame);
        drive(&mut wu_no_cone, &experiment, frame);
        drive(&mut reference, &experiment, frame);
    }
    let mut group = c.benchmark_group("per_frame_update_6000_triangles");
    let mut frame = WARM_UP_FRAMES;
    group.bench_function("wu", |b| {
        b.iter(|| {
            drive(&mut wu, &experiment, frame);
            frame += 1;
        })
    });
    let mut frame = WARM_UP_FRAMES;
    group.bench_function("wu_budget_on_all_triangles", |b| {
        b.iter(|| {
            drive(&mut wu_no_cone, &experiment, frame);
            frame += 1;
        })
    });
    let mut frame = WARM_UP_FRAMES;
    group.bench_function("reference_same_tau", |b| {
        b.iter(|| {
            drive(&mut reference, &experiment, frame);
            frame += 1;
        })
    });
    group.finish();
}

criterion_group!(benches, per_frame_update);
criterion_main!(benches);
