//! Camera flights: parametric paths and recorded logs, replayed exactly, frame by frame (SPEC §8),
//! and the check of a flight against the experiment's motion bounds ([`speed_violations`]). A
//! flight is data: it knows nothing of the algorithms that fly it.
//!
//! A [`Flight`] is built once from a [`FlightPath`] and a [`Look`] rule; it evaluates every
//! frame's [`Pose`] up front (40 bytes a frame: 40 MB for a 10^6-frame flight) so replay is a
//! lookup and the speed check sees the whole flight before anything runs. Non-finite poses are
//! rejected at construction. The frame index is the simulation clock. Poses are in world
//! coordinates; the runner moves each into the terrain's local frame.
//!
//! An eye below the ground is one of SPEC §9's hard cases, not an error: such a flight runs, and
//! [`Flight::frames_below_ground`] lists the frames for the run to report.

mod motion;
mod path;
mod speed;

pub use motion::{FrameStep, Largest, LargestSteps, flight_steps, largest_steps};
pub use path::{Altitude, FlightPath, Interpolation, Look, Waypoint};
pub use speed::{BrokenBounds, SpeedViolation, largest_turn, speed_violations};

use crate::sim::terrain::Heightfield;
use crate::sim::view::Pose;

/// A replayable flight: one pose per frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Flight {
    poses: Vec<Pose>,
}

/// Why a flight could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FlightError {
    #[error("a flight needs at least one frame")]
    NoFrames,
    #[error("the pose of frame {frame} is not finite ({pose:?})")]
    NotFinite { frame: u64, pose: Pose },
    #[error("waypoint {index}: frame {frame} does not come after the previous waypoint's frame")]
    WaypointsOutOfOrder { index: usize, frame: u64 },
    #[error("the first waypoint must be at frame 0, not {frame}")]
    WaypointsStartLate { frame: u64 },
    #[error("a waypoint flight needs at least two waypoints")]
    TooFewWaypoints,
}

impl Flight {
    /// Evaluates `path` over `n_frames` frames (recorded paths bring their own frame count and
    /// poses, and ignore `n_frames` and `look`).
    pub fn new(path: &FlightPath, look: &Look, n_frames: u64) -> Result<Flight, FlightError> {
        Flight::with_altitude(path, look, n_frames, Altitude::Absolute)
    }

    /// [`Flight::new`] with the path's heights read as `altitude` says (recorded paths keep
    /// their own heights).
    pub fn with_altitude(
        path: &FlightPath,
        look: &Look,
        n_frames: u64,
        altitude: Altitude,
    ) -> Result<Flight, FlightError> {
        let poses = path::evaluate(path, look, n_frames, altitude)?;
        Flight::from_poses(poses)
    }

    /// The frames whose eye is below the ground ([`Heightfield::ground_height`]), over the
    /// terrain only (no ground is defined beyond its border).
    pub fn frames_below_ground(&self, field: &Heightfield) -> Vec<u64> {
        self.poses
            .iter()
            .enumerate()
            .filter(|(_, pose)| {
                let xy = pose.position.truncate();
                field.covers(xy) && pose.position.z < field.ground_height(xy)
            })
            .map(|(frame, _)| frame as u64)
            .collect()
    }

    /// A flight from explicit poses (a recorded camera log).
    pub fn from_poses(poses: Vec<Pose>) -> Result<Flight, FlightError> {
        if poses.is_empty() {
            return Err(FlightError::NoFrames);
        }
        for (frame, pose) in poses.iter().enumerate() {
            if !(pose.position.is_finite() && pose.yaw.is_finite() && pose.pitch.is_finite()) {
                return Err(FlightError::NotFinite {
                    frame: frame as u64,
                    pose: *pose,
                });
            }
        }
        Ok(Flight { poses })
    }

    pub fn n_frames(&self) -> u64 {
        self.poses.len() as u64
    }

    pub fn pose(&self, frame: u64) -> &Pose {
        &self.poses[frame as usize]
    }

    pub fn poses(&self) -> &[Pose] {
        &self.poses
    }

    /// Keeps the first `n_frames` frames (at least one; a flight already that short is left
    /// as it is). The frames kept are exactly those of the whole flight: a shortened run is the
    /// start of the full run, not a compressed one.
    pub fn keep_first(&mut self, n_frames: u64) {
        let n_frames = n_frames.max(1) as usize;
        self.poses.truncate(n_frames);
    }
}
