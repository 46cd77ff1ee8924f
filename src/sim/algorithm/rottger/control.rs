//! The constant-load controller: c, the desired global resolution of eq. 3, chosen every frame
//! so that the fans hold a target number of triangles or vertices. The rule is roamsim's: the
//! paper gives none.
//!
//! The paper adjusts c "to the current system load" (§2.2) to hold 25 Hz (§3) and gives no rule.
//! roamsim holds a count instead of a frame rate (counts are reproducible, times are not), with
//! this rule: after a frame that drew n (triangles or vertices, as the target says) with c,
//!
//!   c ← c · √(target / n), the factor clamped to [½, 2], c clamped to [`DESIRED_RESOLUTION_MIN`,
//!   [`DESIRED_RESOLUTION_MAX`]].
//!
//! The square root is the paper's own observation that the load grows quadratically with the
//! resolution parameter (§2.2: "as C increases, the total number of vertices per frame grows
//! quadratically"; c scales the distance within which a rough block subdivides, as C does): if
//! n ∝ c², one step lands on the target. The factor's clamp keeps a frame whose load collapsed
//! (nothing in view) or exploded from throwing c by more than an octave. Where c stops mattering
//! (c·d2 < 1 everywhere: the mesh is the minimum resolution C's) or cannot reach the target
//! (above the full mesh), c runs into its bounds; the frame that wanted to go further reports
//! the clamp. A frame with nothing drawn doubles c. `sqrt` is correctly rounded, so the sequence
//! of c is the same on every platform.

/// The smallest c the controller sets (2^-20).
pub const DESIRED_RESOLUTION_MIN: f64 = 1.0 / 1_048_576.0;
/// The largest c the controller sets (2^40).
pub const DESIRED_RESOLUTION_MAX: f64 = 1_099_511_627_776.0;

/// What the controller holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadCount {
    /// Triangles drawn by the fans (all the mesh's without clipping).
    Triangles,
    /// Vertices sent by the fans (the paper's count).
    FanVertices,
}

/// A constant load: hold `count` at `target`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadTarget {
    pub count: LoadCount,
    /// At least 1.
    pub target: u64,
}

/// The controller's decision for the next frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControlStep {
    pub desired_resolution: f64,
    /// c wanted to leave [`DESIRED_RESOLUTION_MIN`, `DESIRED_RESOLUTION_MAX`].
    pub clamped: bool,
}

/// The next c after a frame that drew `drawn` with `desired_resolution` (> 0).
pub fn next_desired_resolution(desired_resolution: f64, drawn: u64, target: u64) -> ControlStep {
    let factor = if drawn == 0 {
        2.0
    } else {
        (target as f64 / drawn as f64).sqrt().clamp(0.5, 2.0)
    };
    let wanted = desired_resolution * factor;
    let next = wanted.clamp(DESIRED_RESOLUTION_MIN, DESIRED_RESOLUTION_MAX);
    ControlStep {
        desired_resolution: next,
        clamped: next != wanted,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quadratic_load_reaches_its_target_in_one_step() {
        // n = 40 c²: at c = 10, n = 4000; the target 16 000 needs c = 20.
        let step = next_desired_resolution(10.0, 4000, 16_000);
        assert_eq!(step.desired_resolution, 20.0);
        assert!(!step.clamped);
        assert_eq!(
            next_desired_resolution(20.0, 16_000, 16_000).desired_resolution,
            20.0
        );
    }

    #[test]
    fn one_step_moves_c_by_at_most_an_octave() {
        assert_eq!(
            next_desired_resolution(8.0, 1, 1_000_000).desired_resolution,
            16.0
        );
        assert_eq!(
            next_desired_resolution(8.0, 1_000_000, 1).desired_resolution,
            4.0
        );
        assert_eq!(
            next_desired_resolution(8.0, 0, 100).desired_resolution,
            16.0
        );
    }

    #[test]
    fn c_stays_within_its_bounds_and_says_when_it_clamps() {
        let top = next_desired_resolution(DESIRED_RESOLUTION_MAX, 10, 1000);
        assert_eq!(top.desired_resolution, DESIRED_RESOLUTION_MAX);
        assert!(top.clamped);
        let bottom = next_desired_resolution(DESIRED_RESOLUTION_MIN, 1000, 10);
        assert_eq!(bottom.desired_resolution, DESIRED_RESOLUTION_MIN);
        assert!(bottom.clamped);
    }
}
