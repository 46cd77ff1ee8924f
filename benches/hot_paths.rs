//! The hot paths of every run, on the quickstart's terrain and flight
//! (`experiments/quickstart.json`): each algorithm's per-frame update after a warm-up, the
//! preprocessing pass, and the audit of one mesh (a 4-8 mesh on its fast path, every sample and
//! every 4th, also kept to the baseline instruction set; with popping on, also as a run audits
//! it, told the next camera; the same triangles handed as a triangle list, on the general
//! path).
//!
//! Run with `cargo bench --bench hot_paths`. Compare ratios measured in one run, not absolute
//! times across machines; operation counts are in the run outputs. `docs/performance.md` quotes
//! its figures.

mod common;

use common::drive;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use roamsim::edge::experiment;
use roamsim::sim::audit::reference::ReferenceAuditor;
use roamsim::sim::audit::{AuditSettings, Auditor};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::{CrackPolicy, MeshOutput, TriangleList};
use roamsim::sim::view::Camera;
use std::hint::black_box;
use std::path::Path;

const WARM_UP_FRAMES: u64 = 50;

fn quickstart() -> experiment::Experiment {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/quickstart.json");
    experiment::load(&path).expect("the shipped quickstart loads")
}

/// Every algorithm entry of the quickstart, one frame per iteration along the flight.
fn per_frame_updates(c: &mut Criterion) {
    let experiment = quickstart();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let mut group = c.benchmark_group("per_frame_update_quickstart");
    for spec in &experiment.algorithms {
        let mut algorithm = spec
            .config
            .build(&hierarchy, &experiment.view, experiment.speed);
        for frame in 0..WARM_UP_FRAMES {
            drive(algorithm.as_mut(), &experiment, frame);
        }
        let mut frame = WARM_UP_FRAMES;
        group.bench_function(BenchmarkId::from_parameter(&spec.label), |b| {
            b.iter(|| {
                drive(algorithm.as_mut(), &experiment, frame);
                frame += 1;
            })
        });
    }
    group.finish();
}

/// The O(samples) preprocessing pass on the 1025² crop.
fn preprocessing(c: &mut Criterion) {
    let experiment = quickstart();
    let mut group = c.benchmark_group("preprocessing");
    group.sample_size(20);
    group.bench_function("hierarchy_1025", |b| {
        b.iter(|| Hierarchy::new(black_box(experiment.field.clone())))
    });
    group.finish();
}

/// The audit of the reference's mesh at the quickstart's first pose, every sample and every 4th.
fn audit(c: &mut Criterion) {
    let experiment = quickstart();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let mut reference =
        experiment.algorithms[0]
            .config
            .build(&hierarchy, &experiment.view, experiment.speed);
    drive(reference.as_mut(), &experiment, 0);
    let camera = Camera::new(
        &experiment.field.local_pose(experiment.flight.pose(0)),
        experiment.view,
    );
    let mut group = c.benchmark_group("audit_one_frame");
    group.sample_size(20);
    let settings = |stride, popping| AuditSettings {
        stride,
        popping,
        detail_stride: None,
    };
    for stride in [1, 4] {
        let mut auditor = Auditor::new(&hierarchy, settings(stride, false));
        group.bench_function(BenchmarkId::new("stride", stride), |b| {
            b.iter(|| auditor.audit(&hierarchy, reference.mesh(), &camera))
        });
        // Kept to the baseline instruction set (no 256-bit vectors), as on a CPU without AVX2.
        let mut portable = Auditor::new(&hierarchy, settings(stride, false)).without_wide_vectors();
        group.bench_function(BenchmarkId::new("stride_portable", stride), |b| {
            b.iter(|| portable.audit(&hierarchy, reference.mesh(), &camera))
        });
        // The audit as first written, in the same run: the speed-up is the ratio.
        let mut first_written = ReferenceAuditor::new(&hierarchy, settings(stride, false));
        group.bench_function(BenchmarkId::new("first_written_stride", stride), |b| {
            b.iter(|| first_written.audit(&hierarchy, reference.mesh(), &camera))
        });
    }
    for stride in [1, 4] {
        let mut auditor = Auditor::new(&hierarchy, settings(stride, true));
        group.bench_function(BenchmarkId::new("stride_popping", stride), |b| {
            b.iter(|| auditor.audit(&hierarchy, reference.mesh(), &camera))
        });
        let mut first_written = ReferenceAuditor::new(&hierarchy, settings(stride, true));
        group.bench_function(
            BenchmarkId::new("first_written_stride_popping", stride),
            |b| b.iter(|| first_written.audit(&hierarchy, reference.mesh(), &camera)),
        );
        // As a run audits: told the next frame's camera (here the same pose), popping keeps
        // heights only where the next frame may read them.
        let mut auditor = Auditor::new(&hierarchy, settings(stride, true));
        group.bench_function(BenchmarkId::new("stride_popping_told_next", stride), |b| {
            b.iter(|| auditor.audit_followed_by(&hierarchy, reference.mesh(), &camera, &camera))
        });
    }
    // The same triangles as a triangle list: the general rasteriser with its tie rule, holes
    // and crack gaps.
    let mut list = TriangleList::new(hierarchy.lattice(), CrackPolicy::Closed);
    reference.mesh().for_each_triangle(&hierarchy, |t| {
        let corners = t.corners.map(|c| list.add_vertex(c.position, c.z));
        list.add_triangle(corners, t.info);
    });
    for stride in [1, 4] {
        let mut auditor = Auditor::new(&hierarchy, settings(stride, false));
        group.bench_function(BenchmarkId::new("triangle_list_stride", stride), |b| {
            b.iter(|| auditor.audit(&hierarchy, MeshOutput::triangles(&list), &camera))
        });
        let mut first_written = ReferenceAuditor::new(&hierarchy, settings(stride, false));
        group.bench_function(
            BenchmarkId::new("first_written_triangle_list_stride", stride),
            |b| b.iter(|| first_written.audit(&hierarchy, MeshOutput::triangles(&list), &camera)),
        );
    }
    group.finish();
}

criterion_group!(benches, per_frame_updates, preprocessing, audit);
criterion_main!(benches);
