//! The validator of Wu's queues and counts (SPEC §5's queues, and Wu et al. 2001 §3.1's
//! splittable and mergeable nodes): what the tests call after every frame through
//! `Wu::validate_queues`, and the unit tests between operations. It recounts every node, O(nodes);
//! no frame of a run calls it.
//!
//! It checks that every splittable node is in exactly one split link,
//! every mergeable node in exactly one merge link, every other active node in a view link when
//! the view is followed and nowhere otherwise, nothing else is queued; the link counts match a
//! recount; the paper's splittable count matches a recount; when the view is followed, every
//! in-view flag equals a fresh test against this frame's cone and the in-view triangle count
//! equals a recount from the flags and the mesh; and (with `check_lives`) every queued node sits
//! in a link that comes due no later than its key allows under the motion bounds.

use super::Wu;
use super::visibility::owned_triangles;
use super::wheel::Queue;

/// Slack, in frames, allowed between a key recomputed now and the link it sits in: the view
/// keys subtract a rounding slack relative to a distance that changes from frame to frame.
const KEY_SLACK_FRAMES: f64 = 1e-6;

pub(super) fn validate(wu: &Wu, check_lives: bool) -> Result<(), String> {
    if !wu.split_work.is_empty() || !wu.merge_work.is_empty() {
        return Err("work lists are not empty between frames".into());
    }
    validate_between_operations(wu, check_lives)
}

/// [`validate`] between two operations of a frame: a node listed for splitting or merging this
/// frame may be out of the queues.
pub(super) fn validate_between_operations(wu: &Wu, check_lives: bool) -> Result<(), String> {
    wu.wheels.check_structure()?;
    let listed = |node: u32| {
        wu.split_work.iter().any(|&(n, _, _)| n == node)
            || wu.merge_work.iter().any(|&(n, _)| n == node)
    };
    let cone = wu.view.as_ref().and_then(|view| view.cone);
    let root = wu.nodes.root();
    let n_links = u64::from(wu.wheels.n_links());
    let mut paper_splittable = 0u64;
    let mut in_view_triangles = 0u64;
    for node in 0..wu.nodes.count() as u32 {
        let (centre, half) = wu.nodes.centre(node);
        let active = wu.is_active(node);
        paper_splittable += u64::from(!active && wu.has_active_parents(centre));
        let expected = if wu.is_splittable(node) {
            Some(Queue::Split)
        } else if wu.is_mergeable(node) {
            Some(Queue::Merge)
        } else if active && wu.counts_in_view() {
            Some(Queue::View)
        } else {
            None
        };
        let slot = wu.wheels.slot(node);
        if slot.map(|s| s.queue) != expected && !(slot.is_none() && listed(node)) {
            return Err(format!(
                "node {node} ({centre:?}, half {half}) should be in {expected:?} but is in {slot:?}"
            ));
        }
        let flagged = wu.flagged_in_view(node);
        if let Some(cone) = &cone
            && wu.counts_in_view()
            && (active || node == root)
        {
            let in_view = wu.rule.sight(wu.hierarchy, &wu.nodes, node, cone).in_view();
            if flagged != in_view {
                return Err(format!(
                    "node {node} ({centre:?}, half {half}) is flagged in view = {flagged} but \
                     its sphere {} the cone",
                    if in_view { "meets" } else { "misses" }
                ));
            }
        } else if flagged && !active && node != root {
            return Err(format!("inactive node {node} is flagged in view"));
        }
        if flagged {
            in_view_triangles += if active {
                owned_triangles(&wu.lattice, &wu.mesh, centre, half)
            } else {
                2
            };
        }
        let Some(slot) = slot else { continue };
        if !check_lives || !wu.started {
            continue;
        }
        let key = match slot.queue {
            Queue::Split => {
                let look = look(wu, node, wu.in_view_refinement());
                wu.split_key(&look)
            }
            Queue::Merge => wu.merge_key(&look(wu, node, wu.active_needs_sight())),
            Queue::View => match (&cone, &wu.view) {
                (Some(cone), Some(view)) => wu
                    .rule
                    .sight(wu.hierarchy, &wu.nodes, node, cone)
                    .frames_until_view_changes(&view.motion),
                _ => f64::INFINITY,
            },
        };
        if slot.link == wu.wheels.parked_link() {
            if key != f64::INFINITY {
                return Err(format!("node {node} is parked with a finite key {key}"));
            }
            continue;
        }
        // The first frame after this one at which the node will be looked at again.
        let due = if slot.link == wu.wheels.overflow_link() {
            (wu.frame / n_links + 1) * n_links
        } else {
            let link = u64::from(slot.link);
            let current = wu.frame % n_links;
            wu.frame
                + if link > current {
                    link - current
                } else {
                    link + n_links - current
                }
        };
        // Its key can fall by at most one a frame: it must stay positive until then.
        if key + KEY_SLACK_FRAMES <= (due - wu.frame - 1) as f64 {
            return Err(format!(
                "node {node} in {:?} link {} (due at frame {due}) has key {key} at frame {}: \
                 it could need acting on before it is looked at",
                slot.queue, slot.link, wu.frame
            ));
        }
    }
    if paper_splittable != wu.paper_splittable {
        return Err(format!(
            "{} nodes counted as splittable, {paper_splittable} by a recount",
            wu.paper_splittable
        ));
    }
    if let Some(view) = &wu.view
        && view.counting
        && cone.is_some()
        && view.in_view_triangles != in_view_triangles
    {
        return Err(format!(
            "{} triangles counted in view, {in_view_triangles} by a recount",
            view.in_view_triangles
        ));
    }
    Ok(())
}

/// A node's look recomputed for the check, counting nothing.
fn look(wu: &Wu, node: u32, with_sight: bool) -> super::NodeLook {
    match wu.view.as_ref().and_then(|view| view.cone.as_ref()) {
        Some(cone) if with_sight => {
            let (life, sight) = wu.rule.life_and_sight(wu.hierarchy, &wu.nodes, node, cone);
            super::NodeLook {
                life,
                sight: Some(sight),
            }
        }
        _ => super::NodeLook {
            life: wu.rule.life(wu.hierarchy, &wu.nodes, node, wu.eye),
            sight: None,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::algorithm::wu::{Refinement, WuConfig};
    use crate::sim::algorithm::{BrokenBounds, FrameInput, LodAlgorithm};
    use crate::sim::hierarchy::{Hierarchy, NestingRule};
    use crate::sim::stats::FrameStats;
    use crate::sim::terrain::Spacing;
    use crate::sim::terrain::synthetic::{SyntheticTerrain, generate};
    use crate::sim::view::{Camera, Pose, ViewSettings};
    use crate::sim::zone::{SpeedBound, ZoneVariant};
    use glam::DVec3;

    fn camera(frame: u64) -> Camera {
        let k = frame as f64;
        Camera::new(
            &Pose {
                position: DVec3::new(200.0 + 8.0 * k, 300.0, 120.0),
                yaw: 0.4 + 0.03 * k,
                pitch: -0.5,
            },
            ViewSettings {
                width_px: 600,
                height_px: 400,
                fovy: 50f64.to_radians(),
                near: 1.0,
                far: 1e6,
            },
        )
    }

    fn update(wu: &mut Wu, frame: u64) {
        let mut stats = FrameStats::default();
        wu.update(
            &FrameInput {
                frame,
                camera: &camera(frame),
                broken_bounds: BrokenBounds::NONE,
            },
            &mut stats,
        );
    }

    /// Splits and merges nodes picked pseudo-randomly (not by their keys), checking the queues,
    /// the in-view flags and the counts after every operation, and after the splits and merges
    /// each one made due; every 40 operations a real frame moves and turns the camera.
    fn exercise(refine: Refinement) {
        let hierarchy = Hierarchy::new(
            generate(&SyntheticTerrain {
                level: 5,
                seed: 8,
                amplitude: 80.0,
                roughness: 0.6,
                spacing: Spacing { dx: 20.0, dy: 20.0 },
            })
            .unwrap(),
        );
        let config = WuConfig {
            tau_px: Some(10.0),
            // A budget keeps the in-view count; b cannot move from 0 (a fixed τ).
            budget: Some(crate::sim::algorithm::wu::BudgetConfig {
                triangles: 1,
                dead_band: 0,
                base_limit: 0,
                initial_tau_k: 1.5,
                tau_recentring: None,
            }),
            zone: ZoneVariant::Conservative,
            block_priority: false,
            depth_limit: None,
            cone_culling: true,
            refine,
            wheel_links: 16,
            nesting: NestingRule::Max,
            morph_frames: None,
            strips: false,
        };
        let speed = SpeedBound {
            horizontal: 10.0,
            vertical: 5.0,
            rotation: 0.05,
        };
        let mut wu = Wu::new(&hierarchy, config, &camera(0).settings, speed);
        update(&mut wu, 0);
        validate(&wu, false).unwrap();
        let (mut splits, mut merges, mut frame) = (0, 0, 0);
        let mut state = 99u64;
        for operation in 0..600 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let pick = (state >> 33) as usize;
            let candidates: Vec<u32> = (0..wu.nodes.count() as u32)
                .filter(|&n| {
                    if pick % 10 < 6 {
                        wu.is_splittable(n)
                    } else {
                        wu.is_mergeable(n)
                    }
                })
                .collect();
            if let Some(&node) = candidates.get(pick / 10 % candidates.len().max(1)) {
                if pick % 10 < 6 {
                    let look = wu.split_look(node);
                    wu.split(node, look, 0);
                    splits += 1;
                } else {
                    wu.wheels.remove(node);
                    let look = wu.active_look(node);
                    wu.apply_sight(node, look.sight);
                    wu.merge(node, look);
                    merges += 1;
                }
            }
            if let Err(error) = validate_between_operations(&wu, false) {
                panic!("after operation {operation}: {error}");
            }
            wu.run_split_work();
            wu.run_merge_work();
            if let Err(error) = validate(&wu, false) {
                panic!("after the work of operation {operation}: {error}");
            }
            if operation % 40 == 39 {
                frame += 1;
                update(&mut wu, frame);
                validate(&wu, true).unwrap();
            }
        }
        assert!(
            splits > 200 && merges > 100,
            "{splits} splits, {merges} merges"
        );
    }

    #[test]
    fn every_split_and_merge_keeps_the_queues_flags_and_counts_valid_in_view() {
        exercise(Refinement::InView);
    }

    #[test]
    fn every_split_and_merge_keeps_the_queues_flags_and_counts_valid_everywhere() {
        exercise(Refinement::Everywhere);
    }
}
