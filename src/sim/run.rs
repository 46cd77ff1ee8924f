//! The simulation runner: one algorithm over one flight, frame by frame (SPEC §1's replay, with
//! SPEC §7's effects, each on only when the experiment asks). It is not the session: building the
//! algorithm, timing its preprocessing, the timing passes, running entries side by side and
//! writing outputs are the edge's (`edge::session`).
//!
//! Per frame: the camera from the flight's pose, moved once into the terrain's local frame
//! (`Heightfield::local_pose`) → the algorithm's update (timed, nothing else inside the timed
//! span) → optional effects in a fixed order: mesh validation (`check`), culling, audit (with
//! popping when asked; and, for an entry that synthesises detail, a second audit against the
//! detail-extended surface). Every effect reads the mesh through its triangle visitor
//! ([`MeshOutput::for_each_triangle`]), whatever its form. An effect that is off costs nothing.
//! A mesh over the run's limit (`limits.max_triangles`) stops the run before any effect.
//! Progress is reported through a callback; the runner itself does no IO.
//!
//! Rendered triangles (`triangles_rendered`, culling on) are the triangles not rejected by a
//! plane test against the view frustum, rejected only when all three corners are outside one
//! plane ([`Camera::may_see_triangle`]): a conservative count, the same test for every family.
//! With culling off every triangle counts as rendered.
//!
//! The mesh counts of the families beyond plain 4-8 meshes (triangles by role, draw batches,
//! morphing vertices; triangle lists and morphed 4-8 meshes only) are read off the mesh by the
//! runner, in O(1), so no algorithm counts them itself ([`MeshOutput::counts`]).
//!
//! The audit is told the flight's next pose (`Auditor::audit_followed_by`): with popping on, it
//! then keeps this frame's drawn heights only where the next frame may read them, which spares
//! work and changes no figure. The last frame has no next pose and is audited plainly.

use crate::sim::algorithm::chunked::detail::DetailField;
use crate::sim::algorithm::{BrokenBounds, FrameInput, LodAlgorithm};
use crate::sim::audit::{AuditSettings, Auditor};
use crate::sim::draw::check::{DrawMismatch, check_buffers_draw_mesh};
use crate::sim::flight::{Flight, SpeedViolation};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::MeshOutput;
use crate::sim::mesh::check::{MeshCheckError, MeshChecker};
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
    /// Validate the mesh, the algorithm's triangle count and its extra columns after every
    /// frame.
    pub check_meshes: bool,
}

/// Everything one algorithm's run needs besides the algorithm.
#[derive(Clone, Copy)]
pub struct RunInputs<'a> {
    pub hierarchy: &'a Hierarchy,
    pub view: &'a ViewSettings,
    pub flight: &'a Flight,
    /// The frames (sorted) that broke the motion bounds, with the bounds each broke.
    pub violations: &'a [SpeedViolation],
    pub effects: Effects,
    /// Most triangles a frame's mesh may have; more stops the run ([`CheckError::TooManyTriangles`]).
    pub max_triangles: Option<u64>,
    /// The surface an entry that synthesises detail draws beyond the source: with the audit on,
    /// the frame is audited against it too (`FrameStats::audit_detail`).
    pub detail_truth: Option<&'a DetailField>,
}

/// A run stopped: a checked frame found a broken mesh, or a mesh outgrew the run's limit.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{algorithm}, frame {frame}: {error}")]
pub struct RunError {
    pub algorithm: String,
    pub frame: u64,
    pub error: CheckError,
}

/// What a checked frame found wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CheckError {
    #[error("mesh check failed: {0}")]
    Mesh(#[from] MeshCheckError),
    #[error("buffer check failed: {0}")]
    Buffers(#[from] DrawMismatch),
    #[error(
        "mesh check failed: the algorithm declares {declared} extra columns but filled {filled}"
    )]
    ExtraColumns { declared: usize, filled: usize },
    #[error(
        "the mesh has {triangles} triangles, over the experiment's limit of {limit} \
         (limits.max_triangles): stopped rather than run on; raise the limit, or give the entry a \
         coarser tolerance, a budget or a target"
    )]
    TooManyTriangles { triangles: u64, limit: u64 },
    #[error(
        "a timing pass (the same flight without effects, to time the updates) drew {timed} \
         triangles where the measured pass drew {measured}: the algorithm's decisions are not \
         deterministic"
    )]
    TimingPassDiverged { measured: u64, timed: u64 },
    #[error("tuning: {0}")]
    Tuning(String),
    #[error("the algorithm's own check failed: {0}")]
    Own(String),
}

/// Runs `algorithm` over the whole flight; `progress` is called after every frame with the
/// number of frames done.
pub fn run_algorithm(
    inputs: &RunInputs,
    label: &str,
    algorithm: &mut dyn LodAlgorithm,
    progress: &mut dyn FnMut(u64),
) -> Result<Vec<FrameStats>, RunError> {
    run_algorithm_with(inputs, label, algorithm, &mut |outcome, _| {
        progress(outcome.stats.frame + 1)
    })
}

/// [`run_algorithm`], calling `after_frame` after every frame with what the frame produced and
/// the algorithm, whose mesh is that frame's (to export it, say).
pub fn run_algorithm_with(
    inputs: &RunInputs,
    label: &str,
    algorithm: &mut dyn LodAlgorithm,
    after_frame: &mut dyn FnMut(&FrameOutcome, &dyn LodAlgorithm),
) -> Result<Vec<FrameStats>, RunError> {
    let mut runner = FrameRunner::new(inputs);
    let mut frames = Vec::with_capacity(inputs.flight.n_frames() as usize);
    while let Some(outcome) = runner.step(label, algorithm) {
        let outcome = outcome?;
        after_frame(&outcome, algorithm);
        frames.push(outcome.stats);
    }
    Ok(frames)
}

/// One algorithm's run, one frame at a time: what [`run_algorithm`] loops over, and what the
/// preview drives to look at each frame's mesh between steps. The algorithm is passed to every
/// step rather than held, so the caller can read its mesh in between.
pub struct FrameRunner<'a> {
    inputs: RunInputs<'a>,
    auditor: Option<Auditor>,
    /// The auditor against the detail-extended surface, when there is one and the audit is on.
    detail_auditor: Option<Auditor>,
    /// The mesh checks' buffers, when meshes are checked.
    checker: Option<MeshChecker>,
    /// Index into `inputs.violations` of the first violation not yet reached.
    next_violation: usize,
    next_frame: u64,
}

/// What one step produced.
#[derive(Clone, Debug)]
pub struct FrameOutcome {
    pub stats: FrameStats,
    /// The camera the algorithm saw, in terrain-local coordinates.
    pub camera: Camera,
}

impl<'a> FrameRunner<'a> {
    /// A runner at frame 0. Allocates the auditor's buffers when the audit is on.
    pub fn new(inputs: &RunInputs<'a>) -> FrameRunner<'a> {
        FrameRunner {
            inputs: *inputs,
            auditor: inputs
                .effects
                .audit
                .map(|settings| Auditor::new(inputs.hierarchy, settings)),
            detail_auditor: inputs.effects.audit.zip(inputs.detail_truth).map(
                |(settings, truth)| {
                    let settings = AuditSettings {
                        stride: settings.detail_stride.unwrap_or(settings.stride),
                        popping: false,
                        detail_stride: None,
                    };
                    Auditor::refined(inputs.hierarchy, settings, truth.depth())
                },
            ),
            checker: inputs.effects.check_meshes.then(MeshChecker::new),
            next_violation: 0,
            next_frame: 0,
        }
    }

    /// The frame the next step runs (the number of frames done).
    pub fn next_frame(&self) -> u64 {
        self.next_frame
    }

    /// Runs the next frame of the flight on `algorithm` (which must be the one every earlier
    /// step ran): update (timed), then the effects. `None` once the flight is over.
    pub fn step(
        &mut self,
        label: &str,
        algorithm: &mut dyn LodAlgorithm,
    ) -> Option<Result<FrameOutcome, RunError>> {
        let inputs = &self.inputs;
        let frame = self.next_frame;
        if frame >= inputs.flight.n_frames() {
            return None;
        }
        self.next_frame += 1;
        let hierarchy = inputs.hierarchy;
        let pose = hierarchy.field().local_pose(inputs.flight.pose(frame));
        let camera = Camera::new(&pose, *inputs.view);
        let broken_bounds = match inputs.violations.get(self.next_violation) {
            Some(violation) if violation.frame == frame => {
                self.next_violation += 1;
                violation.broken
            }
            _ => BrokenBounds::NONE,
        };
        let input = FrameInput {
            frame,
            camera: &camera,
            broken_bounds,
        };
        let mut stats = FrameStats {
            frame,
            ..FrameStats::default()
        };
        let start = Instant::now();
        algorithm.update(&input, &mut stats);
        stats.update_ns = start.elapsed().as_nanos() as u64;
        let draw = algorithm.prepare_draw();
        stats.frame_ns = start.elapsed().as_nanos() as u64;
        algorithm.draw_columns(&mut stats.extra);
        stats.upload_bytes = draw.upload_bytes;
        stats.draw_calls = draw.draw_calls;
        stats.triangles_submitted = draw.triangles_submitted;
        if let Some(limit) = inputs.max_triangles
            && stats.triangles > limit
        {
            return Some(Err(RunError {
                algorithm: label.to_string(),
                frame,
                error: CheckError::TooManyTriangles {
                    triangles: stats.triangles,
                    limit,
                },
            }));
        }

        let mesh = algorithm.mesh();
        if let Some(checker) = self.checker.as_mut()
            && let Err(error) = check_frame(checker, hierarchy, algorithm, mesh, &stats)
        {
            return Some(Err(RunError {
                algorithm: label.to_string(),
                frame,
                error,
            }));
        }
        stats.triangles_rendered = if inputs.effects.culling {
            let spacing = hierarchy.field().spacing();
            let mut rendered = 0;
            mesh.for_each_triangle(hierarchy, |t| {
                let corners = t.corners.map(|c| c.local(spacing));
                rendered += u64::from(camera.may_see_triangle(corners));
            });
            rendered
        } else {
            stats.triangles
        };
        stats.mesh = mesh.counts(stats.triangles);
        if let Some(auditor) = self.auditor.as_mut() {
            // The next pose is known: popping keeps heights only where the next frame may read.
            stats.audit = Some(if frame + 1 < inputs.flight.n_frames() {
                let pose = hierarchy.field().local_pose(inputs.flight.pose(frame + 1));
                let next = Camera::new(&pose, *inputs.view);
                auditor.audit_followed_by(hierarchy, mesh, &camera, &next)
            } else {
                auditor.audit(hierarchy, mesh, &camera)
            });
        }
        if let (Some(auditor), Some(truth)) = (self.detail_auditor.as_mut(), inputs.detail_truth) {
            stats.audit_detail = Some(auditor.audit_against(hierarchy, mesh, &camera, Some(truth)));
        }
        Some(Ok(FrameOutcome { stats, camera }))
    }
}

/// The checks of a checked frame: the mesh (and the algorithm's triangle count), and that the
/// algorithm filled exactly the extra columns it declares.
fn check_frame(
    checker: &mut MeshChecker,
    hierarchy: &Hierarchy,
    algorithm: &dyn LodAlgorithm,
    mesh: MeshOutput,
    stats: &FrameStats,
) -> Result<(), CheckError> {
    checker.check(hierarchy, mesh, algorithm.triangle_count())?;
    check_buffers_draw_mesh(algorithm.buffers(), mesh, hierarchy)?;
    algorithm.check_own().map_err(CheckError::Own)?;
    let declared = algorithm.extra_columns().len();
    if stats.extra.len() != declared {
        return Err(CheckError::ExtraColumns {
            declared,
            filled: stats.extra.len(),
        });
    }
    Ok(())
}
