//! The simulation runner: one algorithm over one flight, frame by frame.
//!
//! Per frame: the camera from the flight's pose → the algorithm's update (timed, nothing else
//! inside the timed span) → optional effects in a fixed order: mesh validation (`check`),
//! culling (triangles meeting the view volume), audit. An effect that is off costs nothing.
//! Progress is reported through a callback; the runner itself does no IO.

use crate::sim::algorithm::{FrameInput, LodAlgorithm};
use crate::sim::audit::{AuditSettings, Auditor};
use crate::sim::flight::Flight;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::triangles::for_each_triangle;
use crate::sim::mesh::validate::{MeshError, validate_reported};
use crate::sim::stats::FrameStats;
use crate::sim::view::{Camera, ViewSettings};
use std::time::Instant;

/// The effects a scene asks for. Each costs nothing when off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Effects {
    pub audit: Option<AuditSettings>,
    /// Count the triangles that meet the view volume (`triangles_rendered`); when off, every
    /// triangle counts as rendered.
    pub culling: bool,
    /// Validate the mesh and the algorithm's triangle count after every frame.
    pub check_meshes: bool,
}

/// Everything one algorithm's run needs besides the algorithm.
#[derive(Clone, Copy)]
pub struct RunInputs<'a> {
    pub hierarchy: &'a Hierarchy,
    pub view: &'a ViewSettings,
    pub flight: &'a Flight,
    /// Frames (sorted) that broke the speed bounds.
    pub violation_frames: &'a [u64],
    pub effects: Effects,
}

/// A checked run found a broken mesh.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{algorithm}, frame {frame}: {error}")]
pub struct RunError {
    pub algorithm: String,
    pub frame: u64,
    pub error: MeshError,
}

/// Runs `algorithm` over the whole flight; `progress` is called after every frame with the
/// number of frames done.
pub fn run_algorithm(
    inputs: &RunInputs,
    label: &str,
    algorithm: &mut dyn LodAlgorithm,
    progress: &mut dyn FnMut(u64),
) -> Result<Vec<FrameStats>, RunError> {
    let hierarchy = inputs.hierarchy;
    let lattice = hierarchy.lattice();
    let mut auditor = inputs
        .effects
        .audit
        .map(|settings| Auditor::new(hierarchy, settings));
    let n_frames = inputs.flight.n_frames();
    let mut frames = Vec::with_capacity(n_frames as usize);
    let mut violations = inputs.violation_frames.iter().peekable();
    for frame in 0..n_frames {
        let pose = hierarchy.field().local_pose(inputs.flight.pose(frame));
        let camera = Camera::new(&pose, *inputs.view);
        let speed_bound_broken = violations.next_if_eq(&&frame).is_some();
        let input = FrameInput {
            frame,
            camera: &camera,
            speed_bound_broken,
        };
        let mut stats = FrameStats {
            frame,
            ..FrameStats::default()
        };
        let start = Instant::now();
        algorithm.update(&input, &mut stats);
        stats.update_ns = start.elapsed().as_nanos() as u64;

        let mesh = algorithm.mesh();
        if inputs.effects.check_meshes {
            validate_reported(lattice, mesh, algorithm.triangle_count()).map_err(|error| {
                RunError {
                    algorithm: label.to_string(),
                    frame,
                    error,
                }
            })?;
        }
        stats.triangles_rendered = if inputs.effects.culling {
            let mut rendered = 0;
            for_each_triangle(lattice, mesh, |t| {
                let corners = [t.apex, t.left, t.right]
                    .map(|p| hierarchy.field().position(p.i as usize, p.j as usize));
                rendered += u64::from(camera.may_see_triangle(corners));
            });
            rendered
        } else {
            stats.triangles
        };
        if let Some(auditor) = auditor.as_mut() {
            stats.audit = Some(auditor.audit(hierarchy, mesh, &camera));
        }
        frames.push(stats);
        progress(frame + 1);
    }
    Ok(frames)
}
