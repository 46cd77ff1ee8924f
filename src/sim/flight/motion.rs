//! A flight's motion frame by frame: how far the eye moved (horizontally and vertically) and how
//! far the look direction turned since the previous frame, with the bounds each step breaks, and
//! the largest of each figure over the flight. The motion check ([`super::speed_violations`]) is
//! these steps filtered to the broken ones, so `flight.csv`, `validate` and the run's warnings
//! say the same thing about every frame.
//!
//! The horizontal step is the Euclidean length of the eye's move in the plane, the vertical step
//! its absolute change in z, the turn the angle between consecutive look directions. Frame 0 has
//! no previous frame and no step. What the figures are compared with is the caller's
//! [`SpeedBound`]; nothing here decides what an algorithm does about a broken bound.

use super::Flight;
use super::speed::BrokenBounds;
use crate::sim::view::Pose;
use crate::sim::zone::SpeedBound;

/// The change from the previous frame to frame `frame` (≥ 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameStep {
    pub frame: u64,
    /// Horizontal displacement from the previous frame, metres.
    pub horizontal: f64,
    /// Absolute vertical displacement from the previous frame, metres.
    pub vertical: f64,
    /// Angle between the previous frame's look direction and this one's, radians.
    pub turn: f64,
    /// Which bounds these figures break.
    pub broken: BrokenBounds,
}

/// One of a flight's largest steps: the figure and the first frame that reaches it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Largest {
    pub value: f64,
    pub frame: u64,
}

/// The largest horizontal move, vertical move and turn of a flight's steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LargestSteps {
    pub horizontal: Largest,
    pub vertical: Largest,
    pub turn: Largest,
}

/// Every step of `flight` (frames 1 to the last, in order), judged against `bound`. O(frames),
/// allocates nothing.
pub fn flight_steps(flight: &Flight, bound: SpeedBound) -> impl Iterator<Item = FrameStep> + '_ {
    flight.poses().windows(2).enumerate().map(move |(k, pair)| {
        let d = pair[1].position - pair[0].position;
        let horizontal = d.truncate().length();
        let vertical = d.z.abs();
        let turn = turn(&pair[0], &pair[1]);
        FrameStep {
            frame: k as u64 + 1,
            horizontal,
            vertical,
            turn,
            broken: BrokenBounds {
                horizontal: horizontal > bound.horizontal,
                vertical: vertical > bound.vertical,
                rotation: turn > bound.rotation,
            },
        }
    })
}

/// The largest step of each kind (the first frame reaching it); `None` for a one-frame flight,
/// which has no step.
pub fn largest_steps(flight: &Flight) -> Option<LargestSteps> {
    // The bound is irrelevant to the figures; π and infinity break nothing.
    let bound = SpeedBound {
        horizontal: f64::INFINITY,
        vertical: f64::INFINITY,
        rotation: std::f64::consts::PI,
    };
    let mut steps = flight_steps(flight, bound);
    let first = steps.next()?;
    let start = |value: f64| Largest {
        value,
        frame: first.frame,
    };
    let keep_larger = |largest: &mut Largest, value: f64, frame: u64| {
        if value > largest.value {
            *largest = Largest { value, frame };
        }
    };
    let mut largest = LargestSteps {
        horizontal: start(first.horizontal),
        vertical: start(first.vertical),
        turn: start(first.turn),
    };
    for step in steps {
        keep_larger(&mut largest.horizontal, step.horizontal, step.frame);
        keep_larger(&mut largest.vertical, step.vertical, step.frame);
        keep_larger(&mut largest.turn, step.turn, step.frame);
    }
    Some(largest)
}

/// The angle between two poses' look directions, radians.
fn turn(from: &Pose, to: &Pose) -> f64 {
    let (from, to) = (from.forward(), to.forward());
    // atan2 of sine and cosine: accurate for the tiny angles of a smooth flight.
    from.cross(to).length().atan2(from.dot(to))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn pose(x: f64, y: f64, z: f64, yaw_deg: f64) -> Pose {
        Pose {
            position: DVec3::new(x, y, z),
            yaw: yaw_deg.to_radians(),
            pitch: 0.0,
        }
    }

    fn bound(horizontal: f64, vertical: f64, rotation_deg: f64) -> SpeedBound {
        SpeedBound {
            horizontal,
            vertical,
            rotation: rotation_deg.to_radians(),
        }
    }

    #[test]
    fn each_step_measures_the_move_and_turn_since_the_previous_frame() {
        let flight = Flight::from_poses(vec![
            pose(0.0, 0.0, 100.0, 0.0),
            pose(3.0, 4.0, 98.0, 10.0),
            pose(3.0, 4.0, 98.0, 10.0),
        ])
        .unwrap();
        let steps: Vec<FrameStep> = flight_steps(&flight, bound(4.0, 5.0, 5.0)).collect();
        assert_eq!(steps.len(), 2);
        assert_eq!(steps[0].frame, 1);
        assert!((steps[0].horizontal - 5.0).abs() < 1e-12);
        assert!((steps[0].vertical - 2.0).abs() < 1e-12);
        assert!((steps[0].turn.to_degrees() - 10.0).abs() < 1e-9);
        assert_eq!(
            steps[0].broken,
            BrokenBounds {
                horizontal: true,
                vertical: false,
                rotation: true
            }
        );
        assert_eq!(steps[1].broken, BrokenBounds::NONE);
        assert_eq!(steps[1].horizontal, 0.0);
    }

    #[test]
    fn the_largest_steps_name_the_first_frame_that_reaches_them() {
        let flight = Flight::from_poses(vec![
            pose(0.0, 0.0, 0.0, 0.0),
            pose(1.0, 0.0, 7.0, 0.0),
            pose(9.0, 0.0, 7.0, 30.0),
            pose(17.0, 0.0, 7.0, 0.0),
        ])
        .unwrap();
        let largest = largest_steps(&flight).unwrap();
        assert_eq!(largest.horizontal.frame, 2);
        assert!((largest.horizontal.value - 8.0).abs() < 1e-12);
        assert_eq!(largest.vertical.frame, 1);
        assert_eq!(largest.turn.frame, 2);
        assert!((largest.turn.value.to_degrees() - 30.0).abs() < 1e-9);
    }

    #[test]
    fn a_one_frame_flight_has_no_step() {
        let flight = Flight::from_poses(vec![pose(0.0, 0.0, 0.0, 0.0)]).unwrap();
        assert_eq!(largest_steps(&flight), None);
        assert_eq!(flight_steps(&flight, bound(1.0, 1.0, 1.0)).count(), 0);
    }
}
