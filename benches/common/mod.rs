//! What the benches share: driving an algorithm one real frame of an experiment's flight.
//! Not a bench target itself (Cargo only discovers `benches/*.rs`).

use roamsim::edge::experiment::Experiment;
use roamsim::sim::algorithm::BrokenBounds;
use roamsim::sim::algorithm::{FrameInput, LodAlgorithm};
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::Camera;

/// Updates `algorithm` for `frame` of the flight, which wraps from its last frame to its first;
/// the wrap is flagged as a speed-bound break, so algorithms that rely on the bound revalidate
/// there (once per pass over the flight, nothing a median notices).
pub fn drive(algorithm: &mut dyn LodAlgorithm, experiment: &Experiment, frame: u64) {
    let n_frames = experiment.flight.n_frames();
    let pose = experiment
        .field
        .local_pose(experiment.flight.pose(frame % n_frames));
    let camera = Camera::new(&pose, experiment.view);
    let mut stats = FrameStats::default();
    algorithm.update(
        &FrameInput {
            frame,
            camera: &camera,
            broken_bounds: BrokenBounds::all_if(frame > 0 && frame.is_multiple_of(n_frames)),
        },
        &mut stats,
    );
}
