//! Wu §7's incremental triangle strips ("we also adopt incremental triangle stripping … in
//! average there are 3.7 triangles in a strip"), kept over the leaves of Wu's buffers
//! (`draw.rs`) by the linking shared with ROAM (`sim::draw::strips`, ROAM'97 §7.2's rule: new
//! triangles start as singletons and are glued to the neighbouring strip ends). Counted, not
//! drawn (`draw.rs` says why): they feed only `triangles_per_strip`. Not the mesh, not the
//! buffers: a triangle's strip changes nothing that is drawn.
//!
//! **Where the links live.** One entry per leaf slot of the buffers (`links[s]` belongs to the
//! leaf in slot `s`), keyed by slot, so a strip link costs no hashing; when the buffers move
//! their last leaf into a hole (swap-remove), [`WuStrips::remove`] moves its links with it and
//! points its strip neighbours at the new slot (O(1)).
//!
//! **Neighbours** follow from the 4-8 mesh's structure, looked up through the vertices' slots
//! (`draw.rs` keeps, per active vertex, the leaves whose right angle it is, by direction): a leaf
//! with right angle a and hypotenuse (e0, e1), midpoint h, has across its hypotenuse (as in
//! ROAM's bintree: the same level or one coarser) either the other half of its diamond, right
//! angle e0 + e1 − a, or the coarser leaf with that hypotenuse as a leg, right angle e0 or e1
//! (its other leg pointing away from a, length |e1 − e0|); across its leg (a, e) (e one end, o
//! the other; the same level or one finer) either the finer leaf with that leg as hypotenuse,
//! right angle a + e − h, or a leaf of its own size with that leg as a leg, right angle a
//! (hypotenuse ends e and 2a − o) or e (ends a and e + a − o). Each candidate is checked against
//! the leaf its slot holds. Sides are tried in the order hypotenuse, leg to `ends[0]`, leg to
//! `ends[1]`.
//!
//! `draw.rs` detaches the leaves a vertex change removes before it changes the buffers and
//! attaches the new ones after, in the order written, so the strips are deterministic and cost
//! O(leaves changed) a frame (times the strips' lengths where two strips join).

use super::draw::{Leaf, NO_SLOT, Slots};
use crate::sim::draw::incremental::LeafBuffer;
use crate::sim::draw::strips::{self, StripCounts, StripLinks, StripMesh};
use crate::sim::hierarchy::{GridPoint, Lattice};

/// The strips over the buffers' leaves (see the module docs).
#[derive(Debug, Default)]
pub(super) struct WuStrips {
    /// By leaf slot: the leaf's place in its strip (`None` only between a detach and the
    /// attach that follows it within one vertex change).
    links: Vec<Option<StripLinks<u32>>>,
    counts: StripCounts,
}

/// What the shared linking needs: the strips and, read-only, the leaves and their vertices.
struct Host<'a> {
    strips: &'a mut WuStrips,
    buffer: &'a LeafBuffer<Leaf>,
    slots: &'a Slots,
    lattice: &'a Lattice,
}

impl WuStrips {
    pub fn counts(&self) -> StripCounts {
        self.counts
    }

    pub fn memory_bytes(&self) -> usize {
        self.links.capacity() * size_of::<Option<StripLinks<u32>>>()
    }

    /// Takes the leaves in `old` out of their strips (before the buffers change them).
    pub fn detach(
        &mut self,
        buffer: &LeafBuffer<Leaf>,
        slots: &Slots,
        lattice: &Lattice,
        old: &[u32],
    ) {
        let mut host = Host {
            strips: self,
            buffer,
            slots,
            lattice,
        };
        for &slot in old {
            strips::detach(&mut host, slot);
        }
    }

    /// Strips the leaves in `new`, in that order (the buffers hold them already).
    pub fn attach(
        &mut self,
        buffer: &LeafBuffer<Leaf>,
        slots: &Slots,
        lattice: &Lattice,
        new: &[u32],
    ) {
        self.links.resize(buffer.leaves(), None);
        let mut host = Host {
            strips: self,
            buffer,
            slots,
            lattice,
        };
        for &slot in new {
            strips::attach(&mut host, slot);
        }
    }

    /// Follows the buffers' swap-remove of the (detached) leaf in `hole`: the last slot's links
    /// move into it and its strip neighbours point at it. Called before the buffers move it.
    pub fn remove(&mut self, hole: u32) {
        let last = self.links.len() as u32 - 1;
        let removed = self.links.swap_remove(hole as usize);
        debug_assert!(
            removed.is_none(),
            "slot {hole} removed while still stripped"
        );
        if hole == last {
            return;
        }
        if let Some(moved) = self.links[hole as usize] {
            if let Some(prev) = moved.prev
                && let Some(s) = self.links[prev as usize].as_mut()
            {
                s.next = Some(hole);
            }
            if let Some(next) = moved.next
                && let Some(s) = self.links[next as usize].as_mut()
            {
                s.prev = Some(hole);
            }
        }
    }

    /// Checks that the strips cover exactly the buffers' leaves, each once, and the shared
    /// checks (consecutive triangles continue each other's vertex sequence, so each pair shares
    /// the edge the strip crosses; links symmetric; strips end; counts match); and that each
    /// consecutive pair are neighbours in the mesh. O(leaves).
    pub fn check(
        &self,
        buffer: &LeafBuffer<Leaf>,
        slots: &Slots,
        lattice: &Lattice,
    ) -> Result<(), String> {
        let leaves = buffer.leaves();
        if self.links.len() != leaves {
            return Err(format!(
                "strips: links for {} slots, the buffers hold {leaves} leaves",
                self.links.len()
            ));
        }
        if let Some(slot) = self.links.iter().position(Option::is_none) {
            return Err(format!(
                "strips: the leaf {:?} (slot {slot}) is in no strip",
                buffer.owner(slot as u32)
            ));
        }
        // The shared check reads only; `Host` wants `&mut`, so it checks a copy.
        let mut copy = WuStrips {
            links: self.links.clone(),
            counts: self.counts,
        };
        let host = Host {
            strips: &mut copy,
            buffer,
            slots,
            lattice,
        };
        let name = |slot: u32| format!("{:?} (slot {slot})", buffer.owner(slot));
        strips::check(&host, 0..leaves as u32, self.counts, name)
            .map_err(|e| format!("strips: {e}"))?;
        for slot in 0..leaves as u32 {
            let Some(next) = host.links(slot).and_then(|s| s.next) else {
                continue;
            };
            if !(0..3).any(|side| host.neighbour(slot, side).map(|(n, _)| n) == Some(next)) {
                return Err(format!(
                    "strips: {} is followed by {}, not a neighbour",
                    name(slot),
                    name(next)
                ));
            }
        }
        Ok(())
    }
}

impl Host<'_> {
    /// The slot of `candidate`, if it is a leaf of the buffers. Points off the lattice (or not on
    /// its grid) are `None`.
    fn find(&self, apex: [i64; 2], ends: [[i64; 2]; 2]) -> Option<u32> {
        let max = i64::from(self.lattice.cells());
        let point = |[i, j]: [i64; 2]| {
            ((0..=max).contains(&i) && (0..=max).contains(&j))
                .then(|| GridPoint::new(i as u32, j as u32))
        };
        let candidate = Leaf {
            apex: point(apex)?,
            ends: [point(ends[0])?, point(ends[1])?],
        };
        let slot =
            self.slots.get(&self.lattice.id(candidate.apex))?.triangles[candidate.direction()];
        if slot == NO_SLOT {
            return None;
        }
        let held = self.buffer.owner(slot);
        let same_ends =
            held.ends == candidate.ends || held.ends == [candidate.ends[1], candidate.ends[0]];
        (held.apex == candidate.apex && same_ends).then_some(slot)
    }
}

/// A point's coordinates, signed (candidates may fall off the lattice).
fn xy(p: GridPoint) -> [i64; 2] {
    [i64::from(p.i), i64::from(p.j)]
}

impl StripMesh for Host<'_> {
    type Key = u32;

    /// Right angle, `ends[0]`, `ends[1]`.
    fn corners(&self, slot: u32) -> [GridPoint; 3] {
        let leaf = self.buffer.owner(slot);
        [leaf.apex, leaf.ends[0], leaf.ends[1]]
    }

    fn neighbour(&self, slot: u32, side: usize) -> Option<(u32, [GridPoint; 2])> {
        let leaf = self.buffer.owner(slot);
        let (a, e0, e1) = (xy(leaf.apex), xy(leaf.ends[0]), xy(leaf.ends[1]));
        let add = |p: [i64; 2], q: [i64; 2], r: [i64; 2]| [p[0] + q[0] - r[0], p[1] + q[1] - r[1]];
        if side == 0 {
            // The other half of the diamond, or a coarser leaf with this edge as a leg.
            let away = [e0[0] + e1[0] - 2 * a[0], e0[1] + e1[1] - 2 * a[1]];
            let found = self
                .find(add(e0, e1, a), [e0, e1])
                .or_else(|| self.find(e0, [e1, add(e0, away, [0, 0])]))
                .or_else(|| self.find(e1, [e0, add(e1, away, [0, 0])]))?;
            return Some((found, leaf.ends));
        }
        let (e, o) = if side == 1 { (e0, e1) } else { (e1, e0) };
        let edge = [leaf.apex, leaf.ends[side - 1]];
        // Finer: right angle a + e − h, h = (e0 + e1) / 2, when h is on the grid.
        let twice = [
            2 * (a[0] + e[0]) - e0[0] - e1[0],
            2 * (a[1] + e[1]) - e0[1] - e1[1],
        ];
        if twice[0] % 2 == 0
            && twice[1] % 2 == 0
            && let Some(found) = self.find([twice[0] / 2, twice[1] / 2], [a, e])
        {
            return Some((found, edge));
        }
        let across_a = [2 * a[0] - o[0], 2 * a[1] - o[1]];
        if let Some(found) = self.find(a, [e, across_a]) {
            return Some((found, edge));
        }
        let found = self.find(e, [a, add(e, a, o)])?;
        Some((found, edge))
    }

    fn links(&self, slot: u32) -> Option<StripLinks<u32>> {
        self.strips.links[slot as usize]
    }

    fn links_mut(&mut self, slot: u32) -> Option<&mut StripLinks<u32>> {
        self.strips.links[slot as usize].as_mut()
    }

    fn set_links(&mut self, slot: u32, links: Option<StripLinks<u32>>) {
        self.strips.links[slot as usize] = links;
    }

    fn counts_mut(&mut self) -> &mut StripCounts {
        &mut self.strips.counts
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Refinement, Wu, WuConfig};
    use crate::sim::algorithm::{BrokenBounds, FrameInput, LodAlgorithm};
    use crate::sim::hierarchy::{Hierarchy, NestingRule};
    use crate::sim::stats::FrameStats;
    use crate::sim::terrain::Spacing;
    use crate::sim::terrain::synthetic::{SyntheticTerrain, generate};
    use crate::sim::view::{Camera, Pose, ViewSettings};
    use crate::sim::zone::{SpeedBound, ZoneVariant};
    use glam::DVec3;

    /// A stripped Wu after a few frames of a low flight (so with splits and strips of several
    /// triangles).
    fn stripped(hierarchy: &Hierarchy) -> Wu<'_> {
        let view = ViewSettings {
            width_px: 600,
            height_px: 400,
            fovy: 50f64.to_radians(),
            near: 1.0,
            far: 1e6,
        };
        let config = WuConfig {
            tau_px: Some(2.0),
            budget: None,
            zone: ZoneVariant::Paper,
            block_priority: false,
            depth_limit: None,
            cone_culling: false,
            refine: Refinement::Everywhere,
            wheel_links: 16,
            nesting: NestingRule::Max,
            morph_frames: None,
            strips: true,
        };
        let speed = SpeedBound {
            horizontal: 10.0,
            vertical: 5.0,
            rotation: SpeedBound::NO_ROTATION_BOUND,
        };
        let mut wu = Wu::new(hierarchy, config, &view, speed);
        for frame in 0..5 {
            let pose = Pose {
                position: DVec3::new(100.0 + 8.0 * frame as f64, 200.0, 60.0),
                yaw: 0.3,
                pitch: -0.4,
            };
            let input = FrameInput {
                frame,
                camera: &Camera::new(&pose, view),
                broken_bounds: BrokenBounds::NONE,
            };
            wu.update(&input, &mut FrameStats::default());
            wu.prepare_draw();
        }
        wu
    }

    fn terrain() -> Hierarchy {
        Hierarchy::new(
            generate(&SyntheticTerrain {
                level: 5,
                seed: 3,
                amplitude: 80.0,
                roughness: 0.6,
                spacing: Spacing { dx: 20.0, dy: 20.0 },
            })
            .unwrap(),
        )
    }

    #[test]
    fn the_validator_accepts_kept_strips_and_refuses_a_leaf_left_out_or_a_broken_link() {
        let hierarchy = terrain();
        let mut wu = stripped(&hierarchy);
        wu.check_own().unwrap();
        let strips = wu.draw.strips_mut().unwrap();
        assert!(strips.counts.triangles > 100 && strips.counts.strips < strips.counts.triangles);

        // A leaf left out of every strip.
        let kept = strips.links[7].take();
        let error = wu.check_own().unwrap_err();
        assert!(error.contains("is in no strip"), "{error}");
        wu.draw.strips_mut().unwrap().links[7] = kept;
        wu.check_own().unwrap();

        // A strip that continues into a triangle whose sequence does not follow.
        let strips = wu.draw.strips_mut().unwrap();
        let head = (0..strips.links.len())
            .find(|&s| strips.links[s].is_some_and(|l| l.next.is_some()))
            .unwrap();
        let next = strips.links[head].unwrap().next.unwrap() as usize;
        strips.links[next].as_mut().unwrap().order.rotate_left(1);
        let error = wu.check_own().unwrap_err();
        assert!(error.contains("do not continue"), "{error}");
    }
}
