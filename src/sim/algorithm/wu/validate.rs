//! The validator of Wu's queues: every splittable node is in exactly one split link, every
//! mergeable node in exactly one merge link, nothing else is queued, the link counts match a
//! recount, (at a fixed base) every node sits in a link that comes due no later than its key
//! allows under the speed bounds, and the per-block triangle counts of the cone count (when kept)
//! equal a recount from the mesh.

use super::Wu;
use super::cone_count::BlockTriangleCounts;
use super::wheel::Queue;

pub(super) fn validate(wu: &Wu, check_lives: bool) -> Result<(), String> {
    wu.wheels.check_structure()?;
    if !wu.split_work.is_empty() || !wu.merge_work.is_empty() {
        return Err("work lists are not empty between frames".into());
    }
    if let Some(counts) = &wu.block_counts
        && *counts != BlockTriangleCounts::new(&wu.lattice, &wu.mesh)
    {
        return Err("per-block triangle counts differ from a recount of the mesh".into());
    }
    let n_links = u64::from(wu.wheels.n_links());
    for node in 0..wu.nodes.count() as u32 {
        let expected = if wu.is_splittable(node) {
            Some(Queue::Split)
        } else if wu.is_mergeable(node) {
            Some(Queue::Merge)
        } else {
            None
        };
        let slot = wu.wheels.slot(node);
        if slot.map(|s| s.queue) != expected {
            let (centre, half) = wu.nodes.centre(node);
            return Err(format!(
                "node {node} ({centre:?}, half {half}) should be in {expected:?} but is in {slot:?}"
            ));
        }
        let Some(slot) = slot else { continue };
        if !check_lives || !wu.started {
            continue;
        }
        let life = wu.rule.life(wu.hierarchy, &wu.nodes, node, wu.eye);
        let key = match slot.queue {
            Queue::Split => life - wu.base as f64,
            Queue::Merge => wu.base as f64 + 1.0 - life,
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
        if key <= (due - wu.frame - 1) as f64 {
            return Err(format!(
                "node {node} in {:?} link {} (due at frame {due}) has key {key} at frame {}: \
                 it could need acting on before it is looked at",
                slot.queue, slot.link, wu.frame
            ));
        }
    }
    Ok(())
}
