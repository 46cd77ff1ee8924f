//! The motion check: every frame whose change from the previous frame breaks one of the
//! experiment's bounds — the eye moved too far (horizontally or vertically) or the look direction
//! turned too fast — with which bounds it broke (SPEC §8: the runner checks the flight against
//! the bounds its algorithms may assume). It reports and never corrects: what an algorithm does
//! about a broken bound (revalidate its lives or its deferral) is the algorithm's.
//!
//! The figures are each frame's step (`motion.rs`: the eye's horizontal and vertical move and the
//! look direction's turn since the previous frame), so `flight.csv` and `validate` list the same
//! frames. Frame 0 has no previous frame and is never listed. The runner hands each frame its [`BrokenBounds`].
//! [`largest_turn`] measures the same turn over a whole flight: the rotation bound of an
//! experiment that declares none.

use super::Flight;
use super::motion::{flight_steps, largest_steps};
use crate::sim::zone::SpeedBound;

/// Which of the motion bounds a frame broke (what an algorithm sees in its frame input).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BrokenBounds {
    /// The eye moved farther horizontally than the horizontal bound.
    pub horizontal: bool,
    /// The eye moved farther vertically than the vertical bound.
    pub vertical: bool,
    /// The look direction turned by more than the rotation bound.
    pub rotation: bool,
}

impl BrokenBounds {
    /// No bound broken.
    pub const NONE: BrokenBounds = BrokenBounds {
        horizontal: false,
        vertical: false,
        rotation: false,
    };
    /// Every bound broken (what a first frame or a teleport in a test looks like).
    pub const ALL: BrokenBounds = BrokenBounds {
        horizontal: true,
        vertical: true,
        rotation: true,
    };

    /// [`BrokenBounds::ALL`] when `broken`, else [`BrokenBounds::NONE`].
    pub fn all_if(broken: bool) -> BrokenBounds {
        if broken {
            BrokenBounds::ALL
        } else {
            BrokenBounds::NONE
        }
    }

    /// Whether the eye broke a speed bound (horizontal or vertical): positions may have moved
    /// farther than the bounds say.
    pub fn speed(self) -> bool {
        self.horizontal || self.vertical
    }

    /// Whether any bound was broken.
    pub fn any(self) -> bool {
        self.speed() || self.rotation
    }

    /// The names of the broken bounds, in the order horizontal, vertical, rotation (the words
    /// `flight.csv` and `validate` use).
    pub fn names(self) -> Vec<&'static str> {
        [
            (self.horizontal, "horizontal"),
            (self.vertical, "vertical"),
            (self.rotation, "rotation"),
        ]
        .into_iter()
        .filter_map(|(broken, name)| broken.then_some(name))
        .collect()
    }
}

/// A frame that broke the motion bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedViolation {
    pub frame: u64,
    /// Horizontal displacement from the previous frame, metres.
    pub horizontal: f64,
    /// Absolute vertical displacement from the previous frame, metres.
    pub vertical: f64,
    /// Angle between the previous frame's look direction and this one's, radians.
    pub rotation: f64,
    /// Which bounds these figures break.
    pub broken: BrokenBounds,
}

/// All frames whose change from the previous frame exceeds `bound`, in frame order: the
/// [`flight_steps`] that break a bound.
pub fn speed_violations(flight: &Flight, bound: SpeedBound) -> Vec<SpeedViolation> {
    flight_steps(flight, bound)
        .filter(|step| step.broken.any())
        .map(|step| SpeedViolation {
            frame: step.frame,
            horizontal: step.horizontal,
            vertical: step.vertical,
            rotation: step.turn,
            broken: step.broken,
        })
        .collect()
}

/// The largest turn of the look direction between consecutive frames, radians: the angle the
/// motion check compares with the rotation bound, so no frame of `flight` breaks a rotation bound
/// of this value. 0 for a flight that never turns (or has one frame).
pub fn largest_turn(flight: &Flight) -> f64 {
    largest_steps(flight).map_or(0.0, |largest| largest.turn.value.max(0.0))
}
