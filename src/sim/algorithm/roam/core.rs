//! The state `roam` and `roam-rebuild` share and the operations on it (ROAM'97 as SPEC §6 fixes
//! it): priorities into the queues, splits and merges with everything that follows them (queues,
//! culling flags, strips, deferral schedules), full and due recomputation, and the dual-queue
//! loops with their oscillation guard and tie rule (`mod.rs` states them).
//!
//! Nothing here knows which algorithm runs it beyond `track_merges` (the rebuild has no merge
//! queue) and whether a [`Deferral`] exists. `mod.rs` decides, per frame, what is recomputed.

use super::bintree::Geometry;
use super::bintree::{Bintree, TriangleKey};
use super::cull::{self, CullFlags};
use super::deferral::{BAND_MARGIN, Deferral, MotionBound, Schedule, frames_above, frames_at_most};
use super::draw::LeafBuffers;
use super::merge::{self, diamond_parents, is_mergeable, primary_parent};
use super::priority::{PriorityContext, ViewFrame, Wedgie};
use super::queues::{QueueKey, Queues};
use super::split::{self, SplitLog, split_cost};
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

    // ----- Priorities into the queues -----------------------------------------------------

    /// Whether new priorities of `queue` (0 split, 1 merge) are scheduled as they are computed.
    fn schedules(&self, queue: usize) -> bool {
        self.deferral.is_some() && self.scheduling[queue] == Scheduling::Scheduled
    }

    /// Computes the priority of the leaf `key` and puts it in the split queue (scheduling it under
    /// deferral). Leaves that cannot split (finest level) are not queued.
    pub fn queue_triangle(&mut self, key: TriangleKey) {
        if let Some(priority) = self.triangle_priority(key) {
            self.queues.split.push(key, priority);
        }
    }

    /// The priority of the leaf `key` (scheduled under deferral); `None` when it cannot split.
    fn triangle_priority(&mut self, key: TriangleKey) -> Option<QueueKey> {
        let triangle = self.bintree.get(key);
        if triangle.geometry.tie == 0 {
            return None; // finest level: cannot split
        }
        let tie = triangle.geometry.tie;
        self.counters.evaluations += 1;
        self.counters.elements += 1;
        let value = if self.schedules(0) {
            let wedgie = self.context().measure(triangle);
            self.schedule_triangle(key, &wedgie);
            wedgie.value
        } else {
            self.context().priority(triangle)
        };
        Some(QueueKey::with_tie(value, tie))
    }

    /// Computes the priority of the diamond queued under `primary` and puts it in the merge
    /// queue (scheduling it under deferral).
    pub fn queue_diamond(&mut self, primary: TriangleKey) {
        if let Some(priority) = self.diamond_priority(primary) {
            self.queues.merge.push(primary, priority);
        }
    }

    /// The priority of the diamond queued under `primary` (scheduled under deferral).
    fn diamond_priority(&mut self, primary: TriangleKey) -> Option<QueueKey> {
        let vertex = self.bintree.get(primary).split_vertex()?;
        let parents = diamond_parents(&self.bintree, primary);
        let scheduling = self.schedules(1);
        self.counters.elements += 1;
        let mut wedgies: [Option<Wedgie>; 2] = [None, None];
        let mut value: f64 = 0.0;
        for (slot, parent) in parents.into_iter().enumerate() {
            let Some(parent) = parent else {
                continue;
            };
            self.counters.evaluations += 1;
            let triangle = self.bintree.get(parent);
            if scheduling {
                let wedgie = self.context().measure(triangle);
                value = value.max(wedgie.value);
                wedgies[slot] = Some(wedgie);
            } else {
                value = value.max(self.context().priority(triangle));
            }
        }
        if scheduling {
            self.schedule_diamond(primary, value, &wedgies);
        }
        Some(QueueKey::diamond(self.bintree.lattice(), value, vertex))
    }

    fn schedule_triangle(&mut self, key: TriangleKey, wedgie: &Wedgie) {
        let Some(deferral) = &self.deferral else {
            return;
        };
        let schedule = frames_at_most(
            wedgie,
            deferral.floor,
            self.motion,
            self.view.scale(),
            self.view.near(),
        );
        self.put_on_ring(key, schedule);
    }

    fn schedule_diamond(
        &mut self,
        primary: TriangleKey,
        value: f64,
        wedgies: &[Option<Wedgie>; 2],
    ) {
        let Some(deferral) = &self.deferral else {
            return;
        };
        // At or below H: due next frame. Above: as long as one parent provably stays above.
        let mut schedule = Schedule::After(0);
        if value > deferral.ceiling {
            for wedgie in wedgies.iter().flatten() {
                let parent = frames_above(
                    wedgie,
                    deferral.ceiling,
                    self.motion,
                    self.view.scale(),
                    self.view.near(),
                );
                schedule = match (schedule, parent) {
                    (_, Schedule::Never) | (Schedule::Never, _) => Schedule::Never,
                    (Schedule::After(a), Schedule::After(b)) => Schedule::After(a.max(b)),
                };
            }
        } else if wedgies.iter().flatten().all(|w| w.constant) {
            schedule = Schedule::Never;
        }
        self.put_on_ring(primary, schedule);
    }

    fn put_on_ring(&mut self, key: TriangleKey, schedule: Schedule) {
        let frame = self.frame;
        let Some(deferral) = &mut self.deferral else {
            return;
        };
        let due = match schedule {
            Schedule::Never => u64::MAX,
            Schedule::After(frames) => deferral.schedule(frame, frames, key),
        };
        self.bintree.get_mut(key).due = due;
    }

    // ----- Recomputation ------------------------------------------------------------------

    /// Recomputes every priority of the split queue (`queue` 0) or the merge queue (1). With
    /// `schedule`, each is scheduled now (the band must be set); without, the queue waits for
    /// the end of the frame's schedules (or for the next frame's full recomputation).
    pub fn recompute_queue(&mut self, queue: usize, schedule: bool) {
        if queue == 1 && !self.track_merges {
            return;
        }
        self.scheduling[queue] = if schedule {
            Scheduling::Scheduled
        } else {
            Scheduling::AwaitingSchedule
        };
        let mut keys = std::mem::take(&mut self.scratch);
        let mut priorities = std::mem::take(&mut self.priorities);
        keys.clear();
        priorities.clear();
        if queue == 0 {
            // The bucketed queue lists its keys in slot order, so the triangles' slots are read
            // one after the other.
            self.queues.split.keys_into(&mut keys);
            for &key in &keys {
                if let Some(priority) = self.triangle_priority(key) {
                    priorities.push((key, priority));
                }
            }
            self.queues.split.replace_all(&priorities);
        } else {
            self.queues.merge.keys_into(&mut keys);
            for &key in &keys {
                if let Some(priority) = self.diamond_priority(key) {
                    priorities.push((key, priority));
                }
            }
            self.queues.merge.replace_all(&priorities);
        }
        self.scratch = keys;
        self.priorities = priorities;
    }

    /// Recomputes the priorities that are due this frame (deferral).
    pub fn recompute_due(&mut self) {
        let frame = self.frame;
        let Some(deferral) = &mut self.deferral else {
            return;
        };
        let due = deferral.take_due(frame);
        for &key in &due {
            let Some(triangle) = self.bintree.triangles.get(key) else {
                continue;
            };
            if triangle.due != frame {
                continue;
            }
            if triangle.is_leaf() {
                if self.queues.split.contains(key) {
                    self.queue_triangle(key);
                }
            } else if self.queues.merge.contains(key) {
                self.queue_diamond(key);
            }
        }
        if let Some(deferral) = &mut self.deferral {
            deferral.give_back(frame, due);
        }
    }

    /// Recomputes what a change of culling flags affects: a leaf's priority and strip, a split
    /// triangle's diamond. `skip_priorities` when every priority is recomputed anyway.
    pub fn apply_flag_changes(&mut self, skip_priorities: bool) {
        let changes = std::mem::take(&mut self.flag_changes);
        for &key in &changes {
            let triangle = self.bintree.get(key);
            if triangle.is_leaf() {
                if self.stripped(key) {
                    strips::attach(&mut self.bintree, key);
                } else {
                    strips::detach(&mut self.bintree, key);
                }
                if !skip_priorities && self.queues.split.contains(key) {
                    self.queue_triangle(key);
                }
            } else if !skip_priorities && self.track_merges {
                let primary = primary_parent(&self.bintree, key);
                if self.queues.merge.contains(primary) {
                    self.queue_diamond(primary);
                }
            }
        }
        self.flag_changes = changes;
        self.flag_changes.clear();
    }

    /// §7.1: brings every triangle's culling flags up to date for this frame.
    pub fn update_flags(&mut self) {
        if !self.config.culling_flags {
            return;
        }
        let mut stack = std::mem::take(&mut self.flag_stack);
        let mut changes = std::mem::take(&mut self.flag_changes);
        let frustum = self.view.frustum;
        let counts = cull::update_flags(&mut self.bintree, &frustum, &mut stack, &mut changes);
        self.counters.flag_tests += counts.tests;
        self.flag_stack = stack;
        self.flag_changes = changes;
    }

    /// After the frame's loop: schedules the queues that were recomputed without schedules, and
    /// moves the band (target mode) with the final crossover. Raising G or lowering H is always
    /// safe; a queue awaiting schedules takes the band the crossover asks for.
    pub fn finish_deferral(&mut self) {
        let Some(deferral) = &mut self.deferral else {
            return;
        };
        if self.config.goal_is_target() {
            let crossover = self.queues.top_split().map_or(0.0, |(_, k)| k.value);
            let (floor, ceiling) = if crossover.is_finite() && crossover > 0.0 {
                (
                    crossover / (1.0 + BAND_MARGIN),
                    crossover * (1.0 + BAND_MARGIN),
                )
            } else {
                (0.0, f64::INFINITY)
            };
            if self.scheduling[0] == Scheduling::AwaitingSchedule || floor > deferral.floor {
                deferral.floor = floor;
            }
            if self.scheduling[1] == Scheduling::AwaitingSchedule || ceiling < deferral.ceiling {
                deferral.ceiling = ceiling;
            }
        }
        for queue in [0, 1] {
            if self.scheduling[queue] == Scheduling::AwaitingSchedule {
                self.schedule_queue(queue);
            }
        }
    }

    /// Schedules every element of a queue whose priorities are exact this frame.
    fn schedule_queue(&mut self, queue: usize) {
        if queue == 1 && !self.track_merges {
            self.scheduling[1] = Scheduling::Scheduled;
            return;
        }
        self.scheduling[queue] = Scheduling::Scheduled;
        let mut keys = std::mem::take(&mut self.scratch);
        keys.clear();
        if queue == 0 {
            self.queues.split.keys_into(&mut keys);
            for &key in &keys {
                self.counters.evaluations += 1;
                let wedgie = self.context().measure(self.bintree.get(key));
                self.schedule_triangle(key, &wedgie);
            }
        } else {
            self.queues.merge.keys_into(&mut keys);
            for &key in &keys {
                self.queue_diamond(key);
            }
        }
        self.scratch = keys;
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

    // ----- The dual-queue loops -------------------------------------------------------------

    /// An upper bound on split/merge iterations in one frame: under the guard each vertex is
    /// inserted at most once and removed at most once per frame.
    pub fn iteration_cap(&self) -> u64 {
        2 * self.bintree.lattice().n_vertices() as u64 + 64
    }

    /// The split queue's top, exact: under deferral in target mode, a top at or below the floor
    /// G might hide a stale priority, so the split queue is recomputed first.
    fn known_top_split(&mut self) -> Option<(TriangleKey, QueueKey)> {
        let top = self.queues.top_split();
        if let Some(deferral) = &self.deferral
            && self.scheduling[0] == Scheduling::Scheduled
            && top.is_some_and(|(_, key)| key.value <= deferral.floor)
        {
            self.counters.revalidations += 1;
            self.recompute_queue(0, false);
            return self.queues.top_split();
        }
        top
    }

    /// The merge queue's bottom, exact (see [`Self::known_top_split`]): a bottom above the
    /// ceiling H might hide a stale one below it.
    fn known_bottom_merge(&mut self) -> Option<(TriangleKey, QueueKey)> {
        let bottom = self.queues.bottom_merge();
        if let Some(deferral) = &self.deferral
            && self.scheduling[1] == Scheduling::Scheduled
            && bottom.is_some_and(|(_, key)| key.value > deferral.ceiling)
        {
            self.counters.revalidations += 1;
            self.recompute_queue(1, false);
            return self.queues.bottom_merge();
        }
        bottom
    }

    /// The bottom diamond if its priority *value* is below `key`'s (a tie in value, +∞ against
    /// +∞ behind the near plane above all, never makes room: trading equals only moves the mesh
    /// from frame to frame). Under deferral, when every stale merge priority is above H and `key`
    /// is at most H, there is none, and the merge queue need not be recomputed.
    fn merge_below(&mut self, key: QueueKey) -> Option<(TriangleKey, QueueKey)> {
        if let Some(deferral) = &self.deferral
            && self.scheduling[1] == Scheduling::Scheduled
            && key.value <= deferral.ceiling
            && self
                .queues
                .bottom_merge()
                .is_none_or(|(_, bottom)| bottom.value > deferral.ceiling)
        {
            return None;
        }
        self.known_bottom_merge()
            .filter(|(_, bottom)| bottom.value < key.value)
    }

    /// Fixed τ: split above τ, merge at or below. Under deferral every stale split priority is
    /// at most τ and every stale merge priority above it, so the queues' ends decide exactly.
    pub fn adapt_to_tolerance(&mut self, tau: f64, split_only: bool) {
        let mut remaining = self.iteration_cap();
        loop {
            if remaining == 0 {
                self.counters.guard_stops += 1;
                break;
            }
            remaining -= 1;
            if let Some((key, priority)) = self.queues.top_split()
                && priority.value > tau
            {
                self.split(key);
                continue;
            }
            if !split_only
                && let Some((key, priority)) = self.queues.bottom_merge()
                && priority.value <= tau
            {
                self.merge(key);
                continue;
            }
            break;
        }
    }

    /// Target count: the dual-queue loop with the oscillation guard (see `mod.rs`).
    pub fn adapt_to_target(&mut self, target: u64, split_only: bool) {
        if !self.oscillation_guard {
            self.adapt_to_target_unguarded(target);
            return;
        }
        let mut lowest_split: Option<QueueKey> = None;
        let mut highest_merge: Option<QueueKey> = None;
        let mut remaining = self.iteration_cap();
        loop {
            if remaining == 0 {
                self.counters.guard_stops += 1;
                break;
            }
            remaining -= 1;
            let may_merge = |key: QueueKey| lowest_split.is_none_or(|s| key < s);
            if self.bintree.n_leaves() > target {
                let bottom = if split_only {
                    None
                } else {
                    self.known_bottom_merge()
                };
                match bottom {
                    Some((diamond, key)) if may_merge(key) => {
                        self.merge(diamond);
                        highest_merge = highest_merge.max(Some(key));
                        continue;
                    }
                    Some(_) => self.counters.guard_stops += 1,
                    None => {}
                }
                break;
            }
            let Some((triangle, key)) = self.known_top_split() else {
                break;
            };
            if key.value <= 0.0 {
                break;
            }
            if highest_merge.is_some_and(|m| key <= m) {
                self.counters.guard_stops += 1;
                break;
            }
            if self.bintree.n_leaves() + split_cost(&self.bintree, triangle) <= target {
                self.split(triangle);
                lowest_split = Some(lowest_split.map_or(key, |s| s.min(key)));
                continue;
            }
            if split_only {
                break;
            }
            // It does not fit: make room if it beats the least useful diamond.
            if let Some((diamond, bottom_key)) = self.merge_below(key) {
                if may_merge(bottom_key) {
                    self.merge(diamond);
                    highest_merge = highest_merge.max(Some(bottom_key));
                    continue;
                }
                self.counters.guard_stops += 1;
            }
            break;
        }
    }

    /// The paper's loop as written, without the guard: while too large merge, while too small
    /// or the top split beats the bottom merge split. Only the iteration cap stops it.
    fn adapt_to_target_unguarded(&mut self, target: u64) {
        let mut remaining = self.iteration_cap();
        loop {
            if remaining == 0 {
                self.counters.guard_stops += 1;
                break;
            }
            remaining -= 1;
            let top = self.queues.top_split().filter(|(_, key)| key.value > 0.0);
            let bottom = self.queues.bottom_merge();
            if self.bintree.n_leaves() > target {
                let Some((diamond, _)) = bottom else {
                    break;
                };
                self.merge(diamond);
                continue;
            }
            let beats = matches!((top, bottom), (Some((_, t)), Some((_, b))) if t > b);
            match top {
                Some((triangle, _)) if self.bintree.n_leaves() < target || beats => {
                    self.split(triangle);
                }
                _ => break,
            }
        }
    }

    pub fn adapt(&mut self, split_only: bool) {
        match self.config.goal {
            RoamGoal::TolerancePx(tau) => self.adapt_to_tolerance(tau, split_only),
            RoamGoal::TargetTriangles(n) => self.adapt_to_target(n, split_only),
        }
    }

    /// The extra columns' values in the order of `columns`.
    ///
    /// # Panics
    /// On a column this function does not know (a list in `columns` that grew without it):
    /// loudly, never as a silent NaN.
    pub fn extras(&self, columns: &[&str]) -> Vec<f64> {
        use super::super::columns::roam::{
            DEFERRED, FLAG_TESTS, FORCED_SPLITS, MERGE_QUEUE, OSCILLATION_GUARD_STOPS,
            PRIORITY_RECOMPUTATIONS, REVALIDATIONS, SPLIT_QUEUE, TRIANGLES_PER_STRIP,
        };
        let counters = self.counters;
        columns
            .iter()
            .map(|&column| match column {
                FORCED_SPLITS => counters.forced as f64,
                SPLIT_QUEUE => self.queues.split.len() as f64,
                MERGE_QUEUE => self.queues.merge.len() as f64,
                PRIORITY_RECOMPUTATIONS => counters.evaluations as f64,
                OSCILLATION_GUARD_STOPS => counters.guard_stops as f64,
                DEFERRED => counters.deferred as f64,
                REVALIDATIONS => counters.revalidations as f64,
                FLAG_TESTS => counters.flag_tests as f64,
                TRIANGLES_PER_STRIP => strips::triangles_per_strip(&self.bintree),
                other => unreachable!("ROAM fills no column {other:?}"),
            })
            .collect()
    }
}
