//! The subdivision criterion of Röttger et al. (§2.2, eq. 3): f = l / (d · C · max(c · d2, 1)),
//! a block subdivides when f < 1, and the blend b = 2(1 − f) clamped to [0, 1] that geomorphing
//! uses (§2.3).
//!
//! Shared by the algorithm and its brute-force reference: this file *is* the criterion, nothing
//! of the traversal. Every quantity is a pure function of the block, the eye and the parameters,
//! computed in `f64` in the terrain's local frame:
//!
//! - d, the block's edge length: 2·half·max(dx, dy) metres (the longer edge of a rectangular
//!   block, so that the centres of a block and an adjacent half-size block are at most d apart
//!   in the L1 norm, which the paper's K bound needs);
//! - l, the distance from the eye to the block: horizontally from the block's centre, vertically
//!   from the block's average elevation (the mean of its nine samples at its own level: corners,
//!   edge midpoints, centre), combined by the [`DistanceNorm`];
//! - d2, the block's roughness as stored in the quadtree matrix (`roughness.rs`).

use crate::sim::hierarchy::{GridPoint, Hierarchy};
use glam::DVec3;

/// How the distance l from the eye to a block combines its three components.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DistanceNorm {
    /// |Δx| + |Δy| + |Δz|: the paper's L1 norm (§2.2), with Δz measured against the block's
    /// average elevation (end of §2.2).
    L1,
    /// √(Δx² + Δy² + Δz²) from the same point: the Euclidean distance Röttger's own library
    /// (libMini) uses.
    Euclidean,
}

/// The parameters of eq. 3 for one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Criterion {
    /// C, the minimum global resolution (≥ 2).
    pub minimum_resolution: f64,
    /// c, the desired global resolution (≥ 0).
    pub desired_resolution: f64,
    pub norm: DistanceNorm,
}

/// The blend value of a subdivided block whose f is just below 1 rounds up to this byte: a
/// subdivided block never stores 0, which the matrix keeps for "not subdivided".
pub const SMALLEST_BLEND_BYTE: u8 = 1;

impl Criterion {
    /// f for the block centred at `centre` with half-size `half`, roughness `d2`, seen from
    /// `eye`. 0 when the eye is exactly at the block's reference point; +∞ never (d > 0).
    pub fn decision_variable(
        &self,
        hierarchy: &Hierarchy,
        centre: GridPoint,
        half: u32,
        d2: f64,
        eye: DVec3,
    ) -> f64 {
        let d = block_edge_m(hierarchy, half);
        let l = block_distance(self.norm, hierarchy, centre, half, eye);
        l / (d * self.minimum_resolution * (self.desired_resolution * d2).max(1.0))
    }
}

/// Whether eq. 3 subdivides a block of decision variable `f`: f < 1 (strict).
pub fn subdivides(f: f64) -> bool {
    f < 1.0
}

/// The paper's blend b = 2(1 − f), clamped to [0, 1].
pub fn blend(f: f64) -> f64 {
    (2.0 * (1.0 - f)).clamp(0.0, 1.0)
}

/// The byte the quadtree matrix stores for a block subdivided with decision variable `f` (< 1):
/// ⌈255·b⌉, at least [`SMALLEST_BLEND_BYTE`]. b = 1 (f ≤ ½) stores 255.
pub fn blend_byte(f: f64) -> u8 {
    debug_assert!(
        subdivides(f),
        "only subdivided blocks store a blend, f = {f}"
    );
    ((255.0 * blend(f)).ceil() as u8).max(SMALLEST_BLEND_BYTE)
}

/// The morph factor a stored blend byte stands for: byte / 255.
pub fn morph_factor(byte: u8) -> f64 {
    f64::from(byte) / 255.0
}

/// d: the edge length of a block of half-size `half`, in metres (the longer edge).
pub fn block_edge_m(hierarchy: &Hierarchy, half: u32) -> f64 {
    let spacing = hierarchy.field().spacing();
    2.0 * f64::from(half) * spacing.dx.max(spacing.dy)
}

/// The mean of the block's nine samples at its own level (corners, edge midpoints, centre).
pub fn average_elevation(hierarchy: &Hierarchy, centre: GridPoint, half: u32) -> f64 {
    let mut sum = 0.0;
    for j in [centre.j - half, centre.j, centre.j + half] {
        for i in [centre.i - half, centre.i, centre.i + half] {
            sum += f64::from(hierarchy.height(GridPoint::new(i, j)));
        }
    }
    sum / 9.0
}

/// l: the distance from `eye` to the block, horizontally from its centre and vertically from its
/// average elevation.
pub fn block_distance(
    norm: DistanceNorm,
    hierarchy: &Hierarchy,
    centre: GridPoint,
    half: u32,
    eye: DVec3,
) -> f64 {
    let spacing = hierarchy.field().spacing();
    let dx = eye.x - f64::from(centre.i) * spacing.dx;
    let dy = eye.y - f64::from(centre.j) * spacing.dy;
    let dz = eye.z - average_elevation(hierarchy, centre, half);
    match norm {
        DistanceNorm::L1 => dx.abs() + dy.abs() + dz.abs(),
        DistanceNorm::Euclidean => (dx * dx + dy * dy + dz * dz).sqrt(),
    }
}

/// K = C / (2(C − 1)): the factor by which the paper propagates d2 from a block to the adjacent
/// blocks of twice its size (§2.2, eq. 5). 1 at C = 2, falling towards ½ as C grows.
pub fn propagation_factor(minimum_resolution: f64) -> f64 {
    minimum_resolution / (2.0 * (minimum_resolution - 1.0))
}
