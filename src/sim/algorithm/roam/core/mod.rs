//! The state `roam` and `roam-rebuild` share and the operations on it (ROAM'97 as SPEC §6 fixes
//! it): the bintree with its queues, thicknesses, effects and counters, and splits and merges
//! with everything that follows them (queues, culling flags, strips, buffers). Which priorities
//! are computed when, and how deferral schedules them, is `recompute.rs`; the dual-queue loops
//! with their oscillation guard and tie rule (`../mod.rs` states them) are `adapt.rs`.
//!
//! Nothing here knows which algorithm runs it beyond `track_merges` (the rebuild has no merge
//! queue) and whether a [`Deferral`] exists. `../mod.rs` decides, per frame, what is recomputed.

mod adapt;
mod recompute;

use super::bintree::Geometry;
use super::bintree::{Bintree, TriangleKey};
use super::cull::{self, CullFlags};
use super::deferral::{Deferral, MotionBound};
use super::draw::LeafBuffers;
use super::merge::{self, diamond_parents, is_mergeable, primary_parent};
use super::priority::{PriorityContext, ViewFrame};
use super::queues::{QueueKey, Queues};
use super::split::{self, SplitLog};
use super::strips;
use super::thickness::Thicknesses;
use super::{RoamConfig, RoamGoal};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::view::Camera;

/// Counters of one frame.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct FrameCounters {
    pub splits: u64,
    pub merges: u64,
    pub forced: u64,
    /// Priority evaluations (eq. 3), scheduling passes included.
    pub evaluations: u64,
    pub guard_stops: u64,
    /// Full recomputations: of both queues at the start of a frame, or of one queue mid-frame.
    pub revalidations: u64,
    pub deferred: u64,
    /// Wedgie classifications: the frame's flag traversal and new children of DONT-KNOW parents.
    pub flag_tests: u64,
    /// Queue elements (triangles and diamonds) whose priority was recomputed.
    pub elements: u64,
}

/// Whether a queue's deferred priorities are scheduled, or were all recomputed this frame and
/// still await their schedules (which the end of the frame computes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scheduling {
    Scheduled,
    AwaitingSchedule,
}

/// Bintree, queues, thicknesses, effects and counters.
pub(super) struct Core<'h> {
    pub hierarchy: &'h Hierarchy,
    pub config: RoamConfig,
    pub motion: MotionBound,
    pub thicknesses: Thicknesses,
    pub bintree: Bintree,
    /// The buffers a GPU draws the leaves from, changed by every split and merge (`draw.rs`).
    pub draw: LeafBuffers,
    pub queues: Queues,
    pub log: SplitLog,
    /// `false` for the rebuild: it has no merge queue.
    pub track_merges: bool,
    /// Deferral's lists and band (`roam` with deferral only).
    pub deferral: Option<Deferral>,
    /// Per queue (split, merge): scheduled, or recomputed this frame and awaiting schedules.
    pub scheduling: [Scheduling; 2],
    pub frame: u64,
    pub view: ViewFrame,
    pub counters: FrameCounters,
    scratch: Vec<TriangleKey>,
    /// A full recomputation's new priorities, before they replace the queue's.
    priorities: Vec<(TriangleKey, QueueKey)>,
    flag_stack: Vec<(TriangleKey, u8)>,
    pub flag_changes: Vec<TriangleKey>,
    /// Key of the last split, for tests.
    pub last_split: Option<QueueKey>,
    /// Always on; a unit test turns it off to show the paper's literal loop oscillating.
    pub oscillation_guard: bool,
}

impl<'h> Core<'h> {
    pub fn new(
        hierarchy: &'h Hierarchy,
        config: RoamConfig,
        motion: MotionBound,
        track_merges: bool,
        camera: &Camera,
    ) -> Core<'h> {
        let tau = match config.goal {
            RoamGoal::TolerancePx(tau) => Some(tau),
            RoamGoal::TargetTriangles(_) => None,
        };
        let bintree = Bintree::new(hierarchy.lattice());
        let draw = LeafBuffers::new(&bintree, hierarchy);
        let mut core = Core {
            hierarchy,
            config,
            motion,
            thicknesses: Thicknesses::new(
                hierarchy,
                config.thickness,
                config.nesting,
                config.culling_flags,
            ),
            bintree,
            draw,
            queues: Queues::new(config.queue),
            log: SplitLog::default(),
            track_merges,
            deferral: config.deferral.then(|| Deferral::new(tau)),
            scheduling: [Scheduling::AwaitingSchedule; 2],
            frame: 0,
            view: ViewFrame::new(camera),
            counters: FrameCounters::default(),
            scratch: Vec::new(),
            priorities: Vec::new(),
            flag_stack: Vec::new(),
            flag_changes: Vec::new(),
            last_split: None,
            oscillation_guard: true,
        };
        core.fill_root_geometry();
        core
    }

    /// Heap bytes held (slot map, queues, thicknesses, deferral lists, buffers).
    pub fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        self.thicknesses.memory_bytes()
            + self.bintree.triangles.capacity()
                * (size_of::<super::bintree::BinTriangle>() + size_of::<u32>())
            + self.bintree.mesh.memory_bytes()
            + self.draw.memory_bytes()
            + self.queues.memory_bytes()
            + self.deferral.as_ref().map_or(0, Deferral::memory_bytes)
            + (self.scratch.capacity() + self.flag_changes.capacity()) * size_of::<TriangleKey>()
            + self.priorities.capacity() * size_of::<(TriangleKey, QueueKey)>()
            + self.flag_stack.capacity() * size_of::<(TriangleKey, u8)>()
    }

    pub fn context(&self) -> PriorityContext<'_> {
        PriorityContext {
            view: &self.view,
            culling_flags: self.config.culling_flags,
        }
    }

    /// Copies a new triangle's corners and thicknesses into its slot.
    pub fn fill_geometry(&mut self, key: TriangleKey) {
        let shape = self.bintree.get(key).shape;
        let geometry = Geometry::of(
            &shape,
            self.hierarchy.field(),
            &self.thicknesses,
            self.bintree.lattice(),
        );
        self.bintree.get_mut(key).geometry = geometry;
    }

    /// Fills the geometry of the two roots (after construction or a reset).
    pub fn fill_root_geometry(&mut self) {
        for root in self.bintree.roots() {
            self.fill_geometry(root);
        }
    }

    /// Whether a leaf belongs in a strip: strips on, and drawn (always with culling flags off,
    /// when not `Out` with them on).
    fn stripped(&self, key: TriangleKey) -> bool {
        self.config.strips && (!self.config.culling_flags || !self.bintree.get(key).flags.is_out())
    }

    // ----- Splits and merges --------------------------------------------------------------

    /// Splits `key` (with forced splits) and brings queues, flags and strips up to date.
    pub fn split(&mut self, key: TriangleKey) {
        let top = self.queues.split.priority(key);
        self.log.diamonds.clear();
        let forced_before = self.log.forced;
        split::split(&mut self.bintree, key, &mut self.log);
        self.counters.forced += self.log.forced - forced_before;
        let diamonds = std::mem::take(&mut self.log.diamonds);
        for diamond in &diamonds {
            self.draw
                .split_diamond(&self.bintree, diamond.parents, self.hierarchy);
        }
        // Geometry and flags first (children from their parents, in the order the splits
        // happened), then strips and queues.
        let frustum = self.view.frustum;
        for diamond in &diamonds {
            for parent in diamond.parents.into_iter().flatten() {
                let flags: CullFlags = self.bintree.get(parent).flags;
                let Some(children) = self.bintree.get(parent).children else {
                    continue;
                };
                for child in children {
                    self.fill_geometry(child);
                    if self.config.culling_flags {
                        let child_flags =
                            cull::classify_child(&frustum, &self.bintree, child, flags);
                        // A child of a DONT-KNOW parent is tested; others inherit.
                        self.counters.flag_tests +=
                            u64::from(flags.label == cull::CullLabel::DontKnow);
                        self.bintree.get_mut(child).flags = child_flags;
                    }
                }
            }
        }
        for diamond in &diamonds {
            self.counters.splits += 1;
            for parent in diamond.parents.into_iter().flatten() {
                strips::detach(&mut self.bintree, parent);
                self.queues.split.remove(parent);
                if self.track_merges
                    && let Some(grandparent) = self.bintree.get(parent).parent
                {
                    let primary = primary_parent(&self.bintree, grandparent);
                    self.queues.merge.remove(primary);
                }
            }
        }
        for diamond in &diamonds {
            for parent in diamond.parents.into_iter().flatten() {
                let Some(children) = self.bintree.get(parent).children else {
                    continue;
                };
                for child in children {
                    if !self.bintree.get(child).is_leaf() {
                        continue;
                    }
                    if self.stripped(child) {
                        strips::attach(&mut self.bintree, child);
                    }
                    self.queue_triangle(child);
                }
            }
            if self.track_merges
                && let Some(parent) = diamond.parents[0]
                && is_mergeable(&self.bintree, parent)
            {
                let primary = primary_parent(&self.bintree, parent);
                self.queue_diamond(primary);
            }
        }
        self.log.diamonds = diamonds;
        if top.is_some() {
            self.last_split = top;
        }
    }

    /// Merges the diamond queued under `primary` and brings queues and strips up to date.
    pub fn merge(&mut self, primary: TriangleKey) {
        if !is_mergeable(&self.bintree, primary) {
            self.queues.merge.remove(primary);
            return;
        }
        let parents = diamond_parents(&self.bintree, primary);
        for parent in parents.into_iter().flatten() {
            if let Some(children) = self.bintree.get(parent).children {
                for child in children {
                    strips::detach(&mut self.bintree, child);
                    self.queues.split.remove(child);
                }
            }
        }
        self.queues.merge.remove(primary);
        self.draw.merge_diamond(&self.bintree, parents);
        if merge::merge(&mut self.bintree, primary).is_none() {
            return;
        }
        self.counters.merges += 1;
        for parent in parents.into_iter().flatten() {
            if self.stripped(parent) {
                strips::attach(&mut self.bintree, parent);
            }
            self.queue_triangle(parent);
            if let Some(grandparent) = self.bintree.get(parent).parent
                && is_mergeable(&self.bintree, grandparent)
            {
                let primary = primary_parent(&self.bintree, grandparent);
                if !self.queues.merge.contains(primary) {
                    self.queue_diamond(primary);
                }
            }
        }
    }
}
