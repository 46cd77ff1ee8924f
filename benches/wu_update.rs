//! Per-frame update of Wu's algorithm at a 6000-triangle budget on the Table 1 flight
//! (`experiments/wu-table1.json`), against the from-scratch reference at the same τ.
//!
//! Four measurements: `wu_in_view` as the experiment runs it (refinement that follows the view
//! cone, the budget counting the triangles of the active blocks in view, both kept incrementally),
//! `wu_everywhere` (the same entry refining everywhere, the paper's queues over the whole terrain,
//! the same O(1) count), and the from-scratch reference at the same τ in both modes
//! (`reference_in_view_same_tau`, `reference_everywhere_same_tau`). All start from the same
//! warmed-up point of the flight (Wu's queues in steady state) and then advance one frame per
//! iteration along the circle, so every measured update is a real frame.
//!
//! Run with `cargo bench --bench wu_update`; `docs/performance.md` and
//! `docs/reproductions/wu-table1.md` quote its figures.

mod common;

use common::drive;
use criterion::{Criterion, criterion_group, criterion_main};
use roamsim::edge::experiment;
use roamsim::sim::algorithm::{
    AlgorithmConfig, LodAlgorithm, Reference, ReferenceConfig, Refinement, SplitThreshold,
    ViewThreshold, Wu, WuConfig,
};
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
    assert_eq!(config.refine, Refinement::InView, "the entry's default");
    let wu_in_view = Wu::new(&hierarchy, config, &experiment.view, experiment.speed);
    let everywhere = WuConfig {
        refine: Refinement::Everywhere,
        ..config
    };
    let wu_everywhere = Wu::new(&hierarchy, everywhere, &experiment.view, experiment.speed);
    let tau_px = wu_in_view.tau_px();
    let reference = |refine| {
        Reference::new(
            &hierarchy,
            ReferenceConfig {
                nesting: config.nesting,
                tau_px,
                zone: config.zone,
                threshold: SplitThreshold::LifeAtMost(0.0),
                refine,
                view_threshold: ViewThreshold::InView,
            },
            &experiment.view,
            experiment.speed,
        )
    };
    let mut entries: Vec<(&str, Box<dyn LodAlgorithm + '_>)> = vec![
        ("wu_in_view", Box::new(wu_in_view)),
        ("wu_everywhere", Box::new(wu_everywhere)),
        (
            "reference_in_view_same_tau",
            Box::new(reference(Refinement::InView)),
        ),
        (
            "reference_everywhere_same_tau",
            Box::new(reference(Refinement::Everywhere)),
        ),
    ];
    let mut group = c.benchmark_group("per_frame_update_6000_triangles");
    for (name, algorithm) in &mut entries {
        for frame in 0..WARM_UP_FRAMES {
            drive(algorithm.as_mut(), &experiment, frame);
        }
        let mut frame = WARM_UP_FRAMES;
        group.bench_function(*name, |b| {
            b.iter(|| {
                drive(algorithm.as_mut(), &experiment, frame);
                frame += 1;
            })
        });
    }
    group.finish();
}

criterion_group!(benches, per_frame_update);
criterion_main!(benches);
