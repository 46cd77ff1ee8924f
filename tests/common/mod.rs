//! Helpers shared by the integration tests: small terrains and scenes that read like the domain.

#![allow(
    dead_code,
    reason = "each test binary uses a different subset of the helpers"
)]

pub mod algorithms;
pub mod experiment;

use glam::DVec3;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose, ViewSettings};

/// A deterministic bumpy terrain of side 2^level + 1 with 10 m posts.
pub fn bumpy_terrain(level: u32) -> Hierarchy {
    let side = (1usize << level) + 1;
    let heights = (0..side * side)
        .map(|k| {
            let (i, j) = ((k % side) as f32, (k / side) as f32);
            20.0 * (0.9 * i).sin() * (0.7 * j).cos() + ((k * 2654435761) % 97) as f32 * 0.3
        })
        .collect();
    let field = Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap();
    Hierarchy::new(field)
}

pub fn view_600() -> ViewSettings {
    ViewSettings {
        width_px: 600,
        height_px: 600,
        fovy: 60f64.to_radians(),
        near: 1.0,
        far: 100_000.0,
    }
}

/// A camera at `eye` looking along +x, slightly down.
pub fn camera_at(eye: DVec3) -> Camera {
    Camera::new(
        &Pose {
            position: eye,
            yaw: 0.0,
            pitch: -0.3,
        },
        view_600(),
    )
}
