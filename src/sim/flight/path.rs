//! Parametric flight paths and the rules for where the camera looks (SPEC §8: circle, line,
//! spiral, waypoints, recorded poses). They are evaluated once, into a [`super::Flight`]; reading
//! a recorded camera log is the edge's (`edge::flight_log`), not this module's.
//!
//! The look that follows the motion aims where the path goes one frame later, computed from the
//! path's own formula even past the flight's last frame, so the last frame looks as it would in
//! a longer flight. A height above the ground is interpolated as a clearance, and the bilinear
//! ground under the eye is added after ([`Altitude`]).

use super::FlightError;
use crate::sim::terrain::Heightfield;
use crate::sim::view::Pose;
use glam::{DVec2, DVec3};
use std::f64::consts::{FRAC_PI_2, TAU};

/// Where the camera looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Look {
    /// Yaw follows the horizontal direction of motion: towards where the path is one frame
    /// later (evaluated from the path even past the flight's last frame, so that frame k of a
    /// flight does not depend on how many frames follow it), kept from the last moving frame
    /// while hovering; pitch is fixed.
    AlongPath { pitch: f64 },
    /// Always at a world point.
    At { target: DVec3 },
    /// A fixed direction.
    Fixed { yaw: f64, pitch: f64 },
}

/// How waypoints are joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Linear,
    /// Cubic Hermite with Catmull-Rom tangents scaled to each segment's duration.
    CatmullRom,
}

/// A waypoint: a position reached at a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waypoint {
    pub frame: u64,
    pub position: DVec3,
}

/// A camera path.
#[derive(Clone, Debug, PartialEq)]
pub enum FlightPath {
    /// Counter-clockwise circle at constant altitude; one lap takes `frames_per_lap` frames.
    Circle {
        centre: DVec2,
        radius: f64,
        altitude: f64,
        frames_per_lap: f64,
        /// Start angle, radians from +x.
        phase: f64,
    },
    /// Straight line from `from` (frame 0) to `to` (last frame).
    Line { from: DVec3, to: DVec3 },
    /// Counter-clockwise spiral: radius and altitude change linearly over the flight.
    Spiral {
        centre: DVec2,
        radius_start: f64,
        radius_end: f64,
        altitude_start: f64,
        altitude_end: f64,
        turns: f64,
        phase: f64,
    },
    /// Through waypoints (the first at frame 0); the flight ends at the last waypoint.
    Waypoints {
        points: Vec<Waypoint>,
        interpolation: Interpolation,
    },
    /// One pose per frame, as recorded.
    Recorded { poses: Vec<Pose> },
}

/// What a path's heights mean.
#[derive(Clone, Copy, Debug)]
pub enum Altitude<'a> {
    /// World heights (z), as written.
    Absolute,
    /// Heights above the ground under the eye: each frame's z is the path's z plus the
    /// terrain's [`Heightfield::ground_height`] at the frame's (x, y), evaluated after the path
    /// is interpolated (the path interpolates the clearance, not the world height).
    AboveGround(&'a Heightfield),
}

pub(super) fn evaluate(
    path: &FlightPath,
    look: &Look,
    n_frames: u64,
    altitude: Altitude,
) -> Result<Vec<Pose>, FlightError> {
    if let FlightPath::Recorded { poses } = path {
        return Ok(poses.clone());
    }
    let n_frames = match path {
        FlightPath::Waypoints { points, .. } => {
            check_waypoints(points)?;
            points[points.len() - 1].frame + 1
        }
        _ => n_frames,
    };
    if n_frames == 0 {
        return Err(FlightError::NoFrames);
    }
    let positions: Vec<DVec3> = (0..n_frames)
        .map(|f| {
            let p = position(path, f, n_frames);
            match altitude {
                Altitude::Absolute => p,
                Altitude::AboveGround(field) => {
                    DVec3::new(p.x, p.y, p.z + field.ground_height(p.truncate()))
                }
            }
        })
        .collect();
    let mut poses = Vec::with_capacity(positions.len());
    let mut last_yaw = 0.0;
    for (f, &position) in positions.iter().enumerate() {
        let (yaw, pitch) = match *look {
            Look::Fixed { yaw, pitch } => (yaw, pitch),
            Look::At { target } => look_at(position, target),
            Look::AlongPath { pitch } => {
                let motion = motion(path, f as u64, n_frames);
                if motion.truncate().length_squared() > 0.0 {
                    last_yaw = motion.y.atan2(motion.x);
                }
                (last_yaw, pitch)
            }
        };
        poses.push(Pose {
            position,
            yaw,
            pitch,
        });
    }
    Ok(poses)
}

fn look_at(from: DVec3, target: DVec3) -> (f64, f64) {
    let d = target - from;
    let horizontal = d.truncate().length();
    if horizontal == 0.0 {
        // Straight above or below the target (or on it): look down or up, yaw 0.
        return (0.0, if d.z > 0.0 { FRAC_PI_2 } else { -FRAC_PI_2 });
    }
    (d.y.atan2(d.x), d.z.atan2(horizontal))
}

fn position(path: &FlightPath, frame: u64, n_frames: u64) -> DVec3 {
    let f = frame as f64;
    let t = if n_frames > 1 {
        f / (n_frames - 1) as f64
    } else {
        0.0
    };
    match path {
        FlightPath::Circle {
            centre,
            radius,
            altitude,
            frames_per_lap,
            phase,
        } => {
            let angle = phase + TAU * f / frames_per_lap;
            let (s, c) = angle.sin_cos();
            DVec3::new(centre.x + radius * c, centre.y + radius * s, *altitude)
        }
        FlightPath::Line { from, to } => from.lerp(*to, t),
        FlightPath::Spiral {
            centre,
            radius_start,
            radius_end,
            altitude_start,
            altitude_end,
            turns,
            phase,
        } => {
            let angle = phase + TAU * turns * t;
            let radius = radius_start + (radius_end - radius_start) * t;
            let (s, c) = angle.sin_cos();
            DVec3::new(
                centre.x + radius * c,
                centre.y + radius * s,
                altitude_start + (altitude_end - altitude_start) * t,
            )
        }
        FlightPath::Waypoints {
            points,
            interpolation,
        } => waypoint_position(points, *interpolation, frame),
        FlightPath::Recorded { poses } => poses[frame as usize].position,
    }
}

/// Where the path goes from `frame`: from this frame's position to the next one's, both from
/// the path's own formula, so that the last frame of a flight looks where the path would go
/// next, exactly as it does when the flight is longer. (Past its last waypoint a waypoint path
/// stays put, so its last frame keeps the yaw it arrived with.)
fn motion(path: &FlightPath, frame: u64, n_frames: u64) -> DVec3 {
    position(path, frame + 1, n_frames) - position(path, frame, n_frames)
}

fn check_waypoints(points: &[Waypoint]) -> Result<(), FlightError> {
    if points.len() < 2 {
        return Err(FlightError::TooFewWaypoints);
    }
    if points[0].frame != 0 {
        return Err(FlightError::WaypointsStartLate {
            frame: points[0].frame,
        });
    }
    for (index, pair) in points.windows(2).enumerate() {
        if pair[1].frame <= pair[0].frame {
            return Err(FlightError::WaypointsOutOfOrder {
                index: index + 1,
                frame: pair[1].frame,
            });
        }
    }
    Ok(())
}

fn waypoint_position(points: &[Waypoint], interpolation: Interpolation, frame: u64) -> DVec3 {
    let k = points
        .partition_point(|w| w.frame <= frame)
        .saturating_sub(1);
    if k + 1 >= points.len() {
        return points[points.len() - 1].position;
    }
    let (a, b) = (points[k], points[k + 1]);
    let duration = (b.frame - a.frame) as f64;
    let u = (frame - a.frame) as f64 / duration;
    match interpolation {
        Interpolation::Linear => a.position.lerp(b.position, u),
        Interpolation::CatmullRom => {
            // Tangents in metres per frame, scaled to this segment's duration.
            let tangent = |index: usize| {
                let before = points[index.saturating_sub(1)];
                let after = points[(index + 1).min(points.len() - 1)];
                (after.position - before.position) / (after.frame - before.frame) as f64
            };
            let (m0, m1) = (tangent(k) * duration, tangent(k + 1) * duration);
            let (u2, u3) = (u * u, u * u * u);
            a.position * (2.0 * u3 - 3.0 * u2 + 1.0)
                + m0 * (u3 - 2.0 * u2 + u)
                + b.position * (-2.0 * u3 + 3.0 * u2)
                + m1 * (u3 - u2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Flight, speed_violations};
    use super::*;
    use crate::sim::zone::SpeedBound;

    #[test]
    fn a_frame_of_a_circle_does_not_depend_on_how_many_frames_follow_it() {
        let path = FlightPath::Circle {
            centre: DVec2::new(500.0, 500.0),
            radius: 300.0,
            altitude: 900.0,
            frames_per_lap: 400.0,
            phase: 0.3,
        };
        let look = Look::AlongPath { pitch: -0.3 };
        let short = evaluate(&path, &look, 100, Altitude::Absolute).unwrap();
        let long = evaluate(&path, &look, 101, Altitude::Absolute).unwrap();
        assert_eq!(short[..], long[..100]);
        // The last frame looks along the chord to where the circle goes next: a quarter turn
        // and half a frame's angle ahead of its angle from the centre.
        let last = short[99];
        let angle = 0.3 + TAU * 99.5 / 400.0 + FRAC_PI_2;
        let expected = angle.sin().atan2(angle.cos());
        assert!(
            (last.yaw - expected).abs() < 1e-12,
            "{} vs {expected}",
            last.yaw
        );
    }

    #[test]
    fn a_circle_returns_to_its_start_after_one_lap_and_looks_ahead() {
        let path = FlightPath::Circle {
            centre: DVec2::new(100.0, 100.0),
            radius: 50.0,
            altitude: 300.0,
            frames_per_lap: 100.0,
            phase: 0.0,
        };
        let flight = Flight::new(&path, &Look::AlongPath { pitch: -0.2 }, 101).unwrap();
        let start = flight.pose(0).position;
        assert!((flight.pose(100).position - start).length() < 1e-9);
        assert!((start - DVec3::new(150.0, 100.0, 300.0)).length() < 1e-12);
        // Counter-clockwise from +x: moving towards +y, so yaw ≈ +90°.
        assert!((flight.pose(0).yaw - FRAC_PI_2).abs() < 0.05);
    }

    #[test]
    fn waypoints_are_reached_at_their_frames_with_either_interpolation() {
        let points = vec![
            Waypoint {
                frame: 0,
                position: DVec3::new(0.0, 0.0, 100.0),
            },
            Waypoint {
                frame: 10,
                position: DVec3::new(100.0, 0.0, 100.0),
            },
            Waypoint {
                frame: 30,
                position: DVec3::new(100.0, 100.0, 120.0),
            },
        ];
        for interpolation in [Interpolation::Linear, Interpolation::CatmullRom] {
            let path = FlightPath::Waypoints {
                points: points.clone(),
                interpolation,
            };
            let flight = Flight::new(&path, &Look::AlongPath { pitch: 0.0 }, 0).unwrap();
            assert_eq!(flight.n_frames(), 31);
            for w in &points {
                assert!((flight.pose(w.frame).position - w.position).length() < 1e-9);
            }
        }
    }

    #[test]
    fn waypoints_out_of_order_are_rejected() {
        let path = FlightPath::Waypoints {
            points: vec![
                Waypoint {
                    frame: 0,
                    position: DVec3::ZERO,
                },
                Waypoint {
                    frame: 0,
                    position: DVec3::ONE,
                },
            ],
            interpolation: Interpolation::Linear,
        };
        assert_eq!(
            Flight::new(&path, &Look::AlongPath { pitch: 0.0 }, 0).unwrap_err(),
            FlightError::WaypointsOutOfOrder { index: 1, frame: 0 }
        );
    }

    #[test]
    fn a_teleport_is_reported_with_its_frame() {
        let mut poses: Vec<Pose> = (0..5)
            .map(|f| Pose {
                position: DVec3::new(f as f64, 0.0, 10.0),
                yaw: 0.0,
                pitch: 0.0,
            })
            .collect();
        poses[3].position.x = 1000.0;
        let flight = Flight::from_poses(poses).unwrap();
        let bound = SpeedBound {
            horizontal: 2.0,
            vertical: 1.0,
            rotation: SpeedBound::NO_ROTATION_BOUND,
        };
        let frames: Vec<u64> = speed_violations(&flight, bound)
            .iter()
            .map(|v| v.frame)
            .collect();
        assert_eq!(frames, vec![3, 4]);
    }

    #[test]
    fn a_nan_pose_is_rejected_with_its_frame() {
        let poses = vec![
            Pose {
                position: DVec3::ZERO,
                yaw: 0.0,
                pitch: 0.0,
            },
            Pose {
                position: DVec3::new(f64::NAN, 0.0, 0.0),
                yaw: 0.0,
                pitch: 0.0,
            },
        ];
        assert!(matches!(
            Flight::from_poses(poses),
            Err(FlightError::NotFinite { frame: 1, .. })
        ));
    }

    #[test]
    fn looking_at_a_point_straight_below_is_defined() {
        assert_eq!(
            look_at(DVec3::new(0.0, 0.0, 10.0), DVec3::ZERO),
            (0.0, -FRAC_PI_2)
        );
    }
}
