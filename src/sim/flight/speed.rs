//! The speed check: every frame whose displacement from the previous frame breaks the
//! experiment's speed bounds.

use super::Flight;
use crate::sim::zone::SpeedBound;

/// A frame that moved faster than the bounds allow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedViolation {
    pub frame: u64,
    /// Horizontal displacement from the previous frame, metres.
    pub horizontal: f64,
    /// Absolute vertical displacement from the previous frame, metres.
    pub vertical: f64,
}

/// All frames whose displacement from the previous frame exceeds `bound`, in frame order.
pub fn speed_violations(flight: &Flight, bound: SpeedBound) -> Vec<SpeedViolation> {
    flight
        .poses()
        .windows(2)
        .enumerate()
        .filter_map(|(k, pair)| {
            let d = pair[1].position - pair[0].position;
            let horizontal = d.truncate().length();
            let vertical = d.z.abs();
            (horizontal > bound.horizontal || vertical > bound.vertical).then_some(SpeedViolation {
                frame: k as u64 + 1,
                horizontal,
                vertical,
            })
        })
        .collect()
}
