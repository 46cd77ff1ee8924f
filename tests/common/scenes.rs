//! Terrains and flights that several suites share, beside `mod.rs`'s `bumpy_terrain` and
//! `camera_at`. Scenes only: what a suite checks over them stays in the suite.

use super::view_600;
use glam::DVec3;
use roamsim::sim::hierarchy::{GridPoint, Hierarchy};
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose, ViewSettings};

/// A bumpy terrain of 2^level + 1 samples a side (10 m posts) whose height at a sample does
/// not depend on the terrain's size: a larger one extends a smaller one, so the same view over
/// both sees the same ground.
pub fn extended_terrain(level: u32) -> Hierarchy {
    let side = (1usize << level) + 1;
    let heights = (0..side * side)
        .map(|k| {
            let (i, j) = (k % side, k / side);
            20.0 * (0.9 * i as f32).sin() * (0.7 * j as f32).cos()
                + ((i * 7919 + j * 104_729) % 97) as f32 * 0.3
        })
        .collect();
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

/// A camera 80 m up over the south-west of an [`extended_terrain`], looking north-east and down
/// with its far plane at 600 m: it sees the same few patches of a terrain of level 7 as of one
/// 16 times larger, so what a frame costs can be compared between them.
pub fn short_sighted_camera() -> Camera {
    Camera::new(
        &Pose {
            position: DVec3::new(300.0, 300.0, 80.0),
            yaw: 0.6,
            pitch: -0.3,
        },
        ViewSettings {
            far: 600.0,
            ..view_600()
        },
    )
}

/// A flight along the terrain's south-west–north-east diagonal, a fixed height above the
/// ground, looking ahead (north-east) and down.
#[derive(Clone, Copy, Debug)]
pub struct DiagonalFlight {
    pub frames: u32,
    /// Metres above the ground sample under the eye.
    pub above_ground_m: f64,
    /// Where the flight starts, as a fraction of the diagonal, and how much of it it covers
    /// (frame k is at `start + span · k / frames`).
    pub start: f64,
    pub span: f64,
    pub pitch: f64,
    /// The yaw swings by up to this many radians around north-east (sin(0.2 k)); 0 keeps it.
    pub yaw_swing: f64,
}

/// The cameras of `flight` over `hierarchy`, one a frame (600 × 600 px, `view_600`).
pub fn diagonal_flight(hierarchy: &Hierarchy, flight: DiagonalFlight) -> Vec<Camera> {
    let field = hierarchy.field();
    let last = field.side() as u32 - 1;
    (0..flight.frames)
        .map(|k| {
            let t = flight.start + flight.span * f64::from(k) / f64::from(flight.frames);
            let i = (t * f64::from(last)).round() as u32;
            let ground = f64::from(hierarchy.height(GridPoint::new(i, i)));
            let position = field.position(i as usize, i as usize);
            Camera::new(
                &Pose {
                    position: DVec3::new(position.x, position.y, ground + flight.above_ground_m),
                    yaw: std::f64::consts::FRAC_PI_4
                        + flight.yaw_swing * (f64::from(k) * 0.2).sin(),
                    pitch: flight.pitch,
                },
                view_600(),
            )
        })
        .collect()
}
