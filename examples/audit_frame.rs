//! Audits one frame's mesh of an experiment entry, for instruction counts:
//!
//! ```text
//! valgrind --tool=callgrind --toggle-collect='*measured_audit*' \
//!     target/release/examples/audit_frame EXPERIMENT LABEL FRAME STRIDE [list]
//! ```
//!
//! flies the entry to FRAME (uncounted), then audits its mesh at STRIDE (every STRIDE-th sample)
//! once, counted: as the runner does, or with `list` the same triangles as a triangle list (the
//! general rasteriser). Prints the audit's figures, so that two builds can be compared for
//! identical results as well as for instructions. Times nothing: `benches/hot_paths.rs` does.
//! `docs/performance.md` quotes its counts.

use roamsim::edge::experiment;
use roamsim::sim::algorithm::{BrokenBounds, FrameInput};
use roamsim::sim::audit::{AuditSettings, Auditor};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::{CrackPolicy, MeshOutput, TriangleList};
use roamsim::sim::stats::{AuditFrame, FrameStats};
use roamsim::sim::view::Camera;
use std::path::PathBuf;

#[inline(never)]
fn measured_audit(
    auditor: &mut Auditor,
    hierarchy: &Hierarchy,
    mesh: MeshOutput,
    camera: &Camera,
) -> AuditFrame {
    auditor.audit(hierarchy, mesh, camera)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (path, label, frame, stride, list) = match args.as_slice() {
        [path, label, frame, stride] => (path, label, frame, stride, false),
        [path, label, frame, stride, list] if list == "list" => (path, label, frame, stride, true),
        _ => {
            eprintln!("usage: audit_frame EXPERIMENT LABEL FRAME STRIDE [list]");
            std::process::exit(2);
        }
    };
    let last: u64 = frame.parse().expect("FRAME is a frame number");
    let stride: u32 = stride.parse().expect("STRIDE is a whole number");
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
    let figures = if list {
        let mut triangles = TriangleList::new(hierarchy.lattice(), CrackPolicy::Closed);
        algorithm.mesh().for_each_triangle(&hierarchy, |t| {
            let corners = t.corners.map(|c| triangles.add_vertex(c.position, c.z));
            triangles.add_triangle(corners, t.info);
        });
        measured_audit(
            &mut auditor,
            &hierarchy,
            MeshOutput::triangles(&triangles),
            &camera,
        )
    } else {
        measured_audit(&mut auditor, &hierarchy, algorithm.mesh(), &camera)
    };
    println!("{figures:?}");
}
