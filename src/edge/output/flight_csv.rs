//! `flight.csv`: the camera's flight, one row per frame (`docs/output-formats.md`, "flight.csv"):
//! where the eye was (world metres, and its height above the ground under it), where it looked,
//! how far it moved and turned since the previous frame, and which motion bounds that step broke.
//! The figures are the core's ([`flight_steps`], the motion check's own steps), so the
//! `broken_bounds` column lists exactly the frames `validate`, summary.json and the run's warning
//! list. Not the flight itself (`sim::flight`), nor anything an algorithm did.

use super::columns::format_number;
use crate::sim::flight::{Flight, flight_steps};
use crate::sim::terrain::Heightfield;
use crate::sim::zone::SpeedBound;
use std::fmt::Write;

/// The header of `flight.csv`, column by column.
pub const FLIGHT_COLUMNS: [&str; 11] = [
    "frame",
    "x_m",
    "y_m",
    "z_m",
    "height_above_ground_m",
    "yaw_deg",
    "pitch_deg",
    "horizontal_m",
    "vertical_m",
    "turn_rad",
    "broken_bounds",
];

/// The whole file as text: a row per frame of `flight`, its steps judged against `bound`. The
/// height above the ground is empty where the eye is not over `field`; frame 0's step columns
/// are empty (it has no previous frame), and so is `broken_bounds` where no bound is broken.
pub fn flight_csv(flight: &Flight, field: &Heightfield, bound: SpeedBound) -> String {
    let mut out = FLIGHT_COLUMNS.join(",");
    out.push('\n');
    let mut steps = flight_steps(flight, bound);
    for (frame, pose) in flight.poses().iter().enumerate() {
        let p = pose.position;
        let xy = p.truncate();
        let above_ground = if field.covers(xy) {
            format_number(p.z - field.ground_height(xy))
        } else {
            String::new()
        };
        let _ = write!(
            out,
            "{frame},{},{},{},{above_ground},{},{}",
            format_number(p.x),
            format_number(p.y),
            format_number(p.z),
            format_number(pose.yaw.to_degrees()),
            format_number(pose.pitch.to_degrees()),
        );
        if frame == 0 {
            out.push_str(",,,,\n");
            continue;
        }
        if let Some(step) = steps.next() {
            let _ = writeln!(
                out,
                ",{},{},{},{}",
                format_number(step.horizontal),
                format_number(step.vertical),
                format_number(step.turn),
                step.broken.names().join("+"),
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::Spacing;
    use crate::sim::view::Pose;
    use glam::DVec3;

    fn flat_field(height: f32) -> Heightfield {
        Heightfield::new(3, vec![height; 9], Spacing { dx: 10.0, dy: 10.0 }).unwrap()
    }

    fn pose(x: f64, z: f64, yaw_deg: f64) -> Pose {
        Pose {
            position: DVec3::new(x, 5.0, z),
            yaw: yaw_deg.to_radians(),
            pitch: 0.0,
        }
    }

    #[test]
    fn each_frame_is_a_row_with_its_step_and_the_bounds_it_broke() {
        let flight = Flight::from_poses(vec![
            pose(0.0, 30.0, 0.0),
            pose(2.0, 30.0, 0.0),
            pose(50.0, 20.0, 90.0),
        ])
        .unwrap();
        let bound = SpeedBound {
            horizontal: 5.0,
            vertical: 50.0,
            rotation: 0.5,
        };
        let text = flight_csv(&flight, &flat_field(10.0), bound);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        assert_eq!(
            lines[0],
            "frame,x_m,y_m,z_m,height_above_ground_m,yaw_deg,pitch_deg,horizontal_m,vertical_m,\
             turn_rad,broken_bounds"
        );
        assert_eq!(lines[1], "0,0,5,30,20,0,0,,,,");
        assert_eq!(lines[2], "1,2,5,30,20,0,0,2,0,0,");
        // Beyond the terrain's 20 m: no ground under the eye.
        let third: Vec<&str> = lines[3].split(',').collect();
        assert_eq!(third[4], "");
        assert_eq!(third[10], "horizontal+rotation");
    }
}
