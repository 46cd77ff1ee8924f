//! Every frame of every `lindstrom` entry of the given experiments against the brute force: the
//! block-based mesh must equal Lindstrom's criterion evaluated from scratch at every vertex.
//!
//! ```sh
//! cargo run --release --example lindstrom_brute_force -- experiments/*.json
//! ```
//!
//! Experiments without a `lindstrom` entry are skipped; a top-level sweep is checked point by
//! point. Prints one line per entry and point (frames checked, mean triangles) and exits with
//! status 1 at the first frame whose meshes differ, naming the experiment, point, entry, frame and
//! the first vertex that differs. The brute force is O(samples) per frame, its rows of the grid
//! shared between threads. `docs/reproductions/lindstrom.md` quotes its verdict on
//! `experiments/lindstrom-tau-sweep.json`.

use rayon::prelude::*;
use roamsim::edge::experiment::{Experiment, plan};
use roamsim::sim::algorithm::lindstrom::Tolerance;
use roamsim::sim::algorithm::{AlgorithmConfig, FrameInput};
use roamsim::sim::hierarchy::{GridPoint, Hierarchy};
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::Camera;
use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let paths: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    if paths.is_empty() {
        eprintln!("usage: lindstrom_brute_force EXPERIMENT...");
        return ExitCode::from(2);
    }
    for path in &paths {
        let plan = match plan(path) {
            Ok(plan) => plan,
            Err(error) => {
                eprintln!("{error}");
                return ExitCode::from(2);
            }
        };
        for point in 0..plan.n_points() {
            let experiment = match plan.load_point(point) {
                Ok(experiment) => experiment,
                Err(error) => {
                    eprintln!("{error}");
                    return ExitCode::from(2);
                }
            };
            if let Err(message) = check(&experiment, point) {
                eprintln!("{}: {message}", path.display());
                return ExitCode::from(1);
            }
        }
    }
    ExitCode::SUCCESS
}

/// Checks every `lindstrom` entry of one loaded point, every frame.
fn check(experiment: &Experiment, point: usize) -> Result<(), String> {
    let entries: Vec<_> = experiment
        .algorithms
        .iter()
        .filter_map(|spec| match spec.config {
            AlgorithmConfig::Lindstrom(config) => Some((spec, config)),
            _ => None,
        })
        .collect();
    if entries.is_empty() {
        return Ok(());
    }
    let hierarchy = Hierarchy::new(experiment.field.clone());
    let lattice = hierarchy.lattice();
    let lambda = experiment.view.pixels_per_unit();
    for (spec, config) in entries {
        let mut algorithm = spec
            .config
            .build(&hierarchy, &experiment.view, experiment.speed);
        let nested = hierarchy.nested_vertex_errors(config.nesting);
        let tolerance = Tolerance::new(lambda, config.tau_px);
        let mut triangles = 0u64;
        for frame in 0..experiment.flight.n_frames() {
            let camera = Camera::new(
                &experiment.field.local_pose(experiment.flight.pose(frame)),
                experiment.view,
            );
            let mut stats = FrameStats::default();
            algorithm.update(
                &FrameInput {
                    frame,
                    camera: &camera,
                    broken_bounds: roamsim::sim::algorithm::BrokenBounds::NONE,
                },
                &mut stats,
            );
            triangles += stats.triangles;
            // Brute force: every vertex kept for itself, then closure, compared with the mesh.
            let side = lattice.side();
            let kept: Vec<u32> = (0..side)
                .into_par_iter()
                .flat_map_iter(|j| {
                    let (field, nested) = (hierarchy.field(), &nested);
                    (0..side).filter_map(move |i| {
                        let id = lattice.id(GridPoint::new(i, j));
                        let offset = field.position(i as usize, j as usize) - camera.eye;
                        tolerance.keeps(nested[id as usize], offset).then_some(id)
                    })
                })
                .collect();
            let mut expected = roamsim::sim::mesh::VertexSet::base_mesh(lattice);
            let mut stack = Vec::new();
            for id in kept {
                stack.push(lattice.point(id));
                while let Some(vertex) = stack.pop() {
                    if expected.insert(lattice.id(vertex)) {
                        stack.extend(lattice.parents(vertex).as_slice());
                    }
                }
            }
            let drawn = algorithm
                .mesh()
                .lattice_vertices()
                .expect("lindstrom draws a 4-8 mesh");
            if drawn != &expected {
                let first = (0..lattice.n_vertices() as u32)
                    .find(|&id| drawn.contains(id) != expected.contains(id))
                    .map(|id| lattice.point(id));
                return Err(format!(
                    "point {point}, entry {:?}, frame {frame}: the mesh differs from the brute \
                     force, first at {first:?}",
                    spec.label
                ));
            }
        }
        println!(
            "{} point {point} {:?}: {} frames identical to the brute force, {:.0} triangles on average",
            experiment.name,
            spec.label,
            experiment.flight.n_frames(),
            triangles as f64 / experiment.flight.n_frames().max(1) as f64
        );
    }
    Ok(())
}
