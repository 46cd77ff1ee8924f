//! Wu §7's incremental triangle strips (`strips: true`, `src/sim/algorithm/wu/strips.rs`): over
//! flights with splits, merges, a teleport, morphing and a budget, the strips cover exactly the
//! drawn leaves every frame (checked by `check_own` inside `checked_step`, as `--check` does),
//! and they change nothing else: the same meshes, counts, uploads and draw calls as without them.

mod common;

use common::algorithms::{wu, wu_budget, wu_in_view};
use common::{bumpy_terrain, checked_step, extra, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::columns::wu::TRIANGLES_PER_STRIP;
use roamsim::sim::algorithm::{LodAlgorithm, Refinement, Wu, WuConfig};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::{Camera, Pose};
use roamsim::sim::zone::{SpeedBound, ZoneVariant};

const TURNING: SpeedBound = SpeedBound {
    horizontal: 10.0,
    vertical: 5.0,
    rotation: 0.05,
};

/// Across the terrain low and turning, then on beyond its edge climbing 4 m a frame (the first
/// half splits, the second merges), with a teleport (flagged) at frame 100.
fn flight() -> Vec<(Pose, bool)> {
    (0..240)
        .map(|k| {
            let t = k as f64;
            let climb = 4.0 * (t - 120.0).max(0.0);
            let jump = if k >= 100 { 60.0 } else { 0.0 };
            let pose = Pose {
                position: DVec3::new(30.0 + 4.0 * t, 60.0 + 2.0 * t + jump, 120.0 + climb),
                yaw: 0.02 * t,
                pitch: -0.3,
            };
            (pose, k == 100)
        })
        .collect()
}

/// Flies `config`, checked every frame; each frame's statistics.
fn fly(hierarchy: &Hierarchy, config: WuConfig) -> (Wu<'_>, Vec<FrameStats>) {
    let config = WuConfig {
        wheel_links: 16,
        ..config
    };
    let mut wu = Wu::new(hierarchy, config, &view_600(), TURNING);
    let frames = flight()
        .iter()
        .enumerate()
        .map(|(frame, (pose, teleport))| {
            let camera = Camera::new(pose, view_600());
            checked_step(
                hierarchy,
                &mut wu,
                frame as u64,
                &camera,
                *teleport,
                "wu strips",
            )
        })
        .collect();
    (wu, frames)
}

#[test]
fn strips_cover_the_drawn_leaves_every_frame_and_change_nothing_else() {
    let hierarchy = bumpy_terrain(6);
    let configs = [
        ("fixed τ everywhere", wu(2.0, ZoneVariant::Paper)),
        ("fixed τ in the cone", wu_in_view(2.0, ZoneVariant::Paper)),
        (
            "budget in the cone",
            WuConfig {
                tau_px: None,
                zone: ZoneVariant::Paper,
                cone_culling: true,
                refine: Refinement::InView,
                ..wu_budget(1.0, 1500, 1000)
            },
        ),
        (
            "morphing",
            WuConfig {
                morph_frames: Some(4),
                ..wu(2.0, ZoneVariant::Paper)
            },
        ),
    ];
    for (name, config) in configs {
        let (plain, plain_frames) = fly(&hierarchy, config);
        let (stripped, frames) = fly(
            &hierarchy,
            WuConfig {
                strips: true,
                ..config
            },
        );
        let operations: u64 = frames.iter().map(|s| s.splits + s.merges).sum();
        let merges: u64 = frames.iter().map(|s| s.merges).sum();
        assert!(
            operations > 300 && merges > 20,
            "{name}: {operations} splits and merges, {merges} merges"
        );
        assert_eq!(
            stripped.extra_columns().len(),
            plain.extra_columns().len() + 1,
            "{name}"
        );
        let mut per_strip = Vec::new();
        for (frame, (with, without)) in frames.iter().zip(&plain_frames).enumerate() {
            let same = |s: &FrameStats| {
                (
                    s.triangles,
                    s.splits,
                    s.merges,
                    s.upload_bytes,
                    s.draw_calls,
                    s.triangles_submitted,
                )
            };
            assert_eq!(same(with), same(without), "{name}, frame {frame}");
            let n = plain.extra_columns().len();
            assert_eq!(with.extra[..n], without.extra[..n], "{name}, frame {frame}");
            per_strip.push(extra(&stripped, with, TRIANGLES_PER_STRIP));
        }
        let mean = per_strip.iter().sum::<f64>() / per_strip.len() as f64;
        // Wu reports 3.7 triangles a strip; any strip holds at least one.
        assert!(
            (2.0..8.0).contains(&mean) && per_strip.iter().all(|&t| t >= 1.0),
            "{name}: {mean} triangles a strip on average"
        );
    }
}
