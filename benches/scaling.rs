//! Per-frame update of Wu (6000-triangle budget) and ROAM (6000-triangle target) on the flight of
//! `experiments/scaling.json`, over its 1025² and 16385² synthetic terrains, in one run, so that
//! the ratio 16385²/1025² (issue #6: at most 1.5) comes from criterion's statistics rather than
//! from one flight's median. The flight is made one whole lap (2400 frames) so that criterion's
//! iterations wrap around it without a jump; every measured update is a real frame after 300
//! warm-up frames, with nothing else running between frames.
//!
//! Needs about 5 GiB (the 16385² terrain, its hierarchy and ROAM's thickness). Run with
//! `cargo bench --bench scaling`; `docs/performance.md` quotes its figures.

mod common;

use common::drive;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use roamsim::edge::experiment::{self, Experiment};
use roamsim::sim::hierarchy::Hierarchy;
use std::path::Path;

const WARM_UP_FRAMES: u64 = 300;
const LAP_FRAMES: u64 = 2400;

/// The scaling experiment at one terrain level, its flight one whole lap.
fn scaling_experiment(dir: &Path, level: u32) -> Experiment {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/scaling.json");
    let text = std::fs::read_to_string(&shipped).expect("the shipped scaling experiment");
    let mut document: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let top = document.as_object_mut().expect("an object");
    top.remove("sweep");
    document["terrain"]["synthetic"]["level"] = level.into();
    document["flight"]["frames"] = LAP_FRAMES.into();
    let path = dir.join(format!("scaling-{level}.json"));
    std::fs::write(&path, document.to_string()).expect("a temporary file");
    experiment::load(&path).expect("the edited experiment loads")
}

fn per_frame_update_by_terrain_size(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut group = c.benchmark_group("per_frame_update_by_terrain_size");
    for level in [10, 14] {
        let experiment = scaling_experiment(dir.path(), level);
        let hierarchy = Hierarchy::new(experiment.field.clone());
        let side = experiment.field.side();
        for name in ["wu", "roam"] {
            let spec = experiment
                .algorithms
                .iter()
                .find(|s| s.config.name() == name)
                .expect("the scaling experiment has this algorithm");
            let mut algorithm = spec
                .config
                .build(&hierarchy, &experiment.view, experiment.speed);
            for frame in 0..WARM_UP_FRAMES {
                drive(algorithm.as_mut(), &experiment, frame);
            }
            let mut frame = WARM_UP_FRAMES;
            group.bench_function(BenchmarkId::new(name, format!("{side}²")), |b| {
                b.iter(|| {
                    drive(algorithm.as_mut(), &experiment, frame);
                    frame += 1;
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, per_frame_update_by_terrain_size);
criterion_main!(benches);
