//! `roam` and `roam-rebuild`: Duchaineau et al.'s ROAM (1997) on the shared 4-8 mesh family.
//!
//! **Data.** A triangle bintree in a slot map (`bintree.rs`), split with recursive forced splits
//! (`split.rs`), merged by diamonds (`merge.rs`), two priority queues (`queues.rs`): leaves that
//! can split, largest priority first; mergeable diamonds, smallest first. The mesh is the set of
//! split vertices (hypotenuse midpoints) plus the corners, a [`VertexSet`] of the shared family;
//! the triangle count is the number of leaves.
//!
//! **Priorities** are ROAM's eq. 3 wedgie bound with the `MaxPlusOwn` nested thickness of the
//! triangle's split vertex, in pixels (`priority.rs`); a diamond's is the larger of its parents'.
//!
//! **Frame loop (`roam`).** Recompute the priorities that are due (all of them without deferral),
//! then:
//! - fixed τ: split the top triangle while its priority exceeds τ, merge the bottom diamond while
//!   its priority is at most τ;
//! - target triangle count: the paper's dual-queue loop. While the mesh is too large, merge the
//!   bottom diamond; while the top split fits in the budget (forced splits included), split it;
//!   when it does not fit but beats the bottom diamond, merge that diamond to make room. The
//!   mesh never ends above the target unless it started above it with nothing left to merge.
//!
//! **Oscillation guard.** Priorities are monotone (a child's never exceeds its parent's, a
//! diamond's never falls below its parents') and totally ordered by the tie rule of
//! `queues.rs`. Within a frame, a triangle is split only if its key is above every key merged so
//! far this frame, and a diamond is merged only if its key is below every key split so far. So a
//! diamond merged in a frame is not split again in that frame and vice versa: each element
//! changes at most once per frame and the loop ends. An iteration cap (twice the number of grid
//! vertices: each vertex inserted and removed at most once) backs that up; refusals and cap hits
//! are counted in `oscillation_guard_stops`. The paper's loop as written (split while too small
//! or while the top split beats the bottom merge, merge while too large) flips forever between
//! two meshes when the target cannot be met exactly; a unit test runs it with the guard off to
//! show that.
//!
//! **Effects**, each costing nothing when off:
//! - deferral (§7.3, fixed τ only): every priority is recomputed only when the bound of
//!   `priority.rs` says it could have crossed τ, from the speed bound v = √(v_h² + v_v²) metres
//!   per frame. A frame that broke the speed bounds, or whose camera orientation changed, or the
//!   first frame, recomputes everything (`revalidations`);
//! - culling flags (§7.1): IN/OUT/DONT-KNOW per triangle, inherited down the bintree; OUT
//!   triangles get priority 0;
//! - strips (§7.2): leaves per strip, for swap-free strips along the leaves' curve order. The
//!   bintree keeps its leaves in a curve-order list and counts the *joined junctions*
//!   (consecutive leaves that continue a strip, a local rule); each split or merge repairs that
//!   count around itself in O(1), so strips cost O(splits + merges) per frame (see `strips.rs`).
//!   `roam-rebuild` recounts them from scratch, O(leaves), once per frame.
//!
//! **`roam-rebuild`** resets the bintree to the two base triangles every frame and splits greedily
//! from the split queue only (no merges, no coherence): the reference of "what incremental
//! split/merge saves".
//!
//! Culling flags have no column of their own: the runner's `triangles_rendered` shows their
//! effect. Without them, eq. 3's near-plane rule gives every triangle behind the eye +∞, so a
//! budget is spent behind the camera: scenes that care should turn them on.
//!
//! Counters: `splits`/`merges` are diamond operations (forced ones included), so for `roam`
//! `vertices_inserted = splits` and `vertices_deleted = merges`; `roam-rebuild` reports the
//! difference from the previous frame's mesh. `metric_evaluations` = priority recomputations.

mod bintree;
mod merge;
mod priority;
mod queues;
mod split;
mod strips;
mod validate;

pub use validate::{BintreeError, PriorityCheck};

use super::{FrameInput, LodAlgorithm};
use crate::sim::hierarchy::{Hierarchy, NestingRule};
use crate::sim::mesh::MeshOutput;
use crate::sim::mesh::VertexSet;
use crate::sim::stats::FrameStats;
use crate::sim::view::Camera;
use crate::sim::zone::SpeedBound;
use bintree::{Bintree, CullFlag, TriangleKey};
use glam::DVec3;
use merge::{diamond_parents, is_mergeable, primary_parent};
use priority::PriorityContext;
use queues::{QueueKey, Queues};
use split::{SplitLog, split_cost};
use std::cmp::Reverse;
use std::collections::BTreeMap;

pub(super) const NAME: &str = "roam";
pub(super) const REBUILD_NAME: &str = "roam-rebuild";

/// What the mesh adapts to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RoamGoal {
    /// Keep the mesh at (at most) this many triangles.
    TargetTriangles(u64),
    /// Split every triangle whose priority exceeds τ pixels, merge every diamond at or below.
    TolerancePx(f64),
}

/// Parameters of `roam` and `roam-rebuild` (the rebuild never defers: its constructor turns
/// `deferral` off, and the experiment validator refuses it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoamConfig {
    pub goal: RoamGoal,
    /// Deferred priority recomputation (§7.3); only with [`RoamGoal::TolerancePx`].
    pub deferral: bool,
    /// Frustum-culling flags (§7.1).
    pub culling_flags: bool,
    /// Triangle-strip counting (§7.2).
    pub strips: bool,
    /// How the wedgie thickness nests over descendants: the paper's [`NestingRule::MaxPlusOwn`]
    /// (a true bound of the surface's distance) or [`NestingRule::Max`] (to measure what the
    /// bound costs).
    pub nesting: NestingRule,
}

/// Counters of one frame.
#[derive(Clone, Copy, Debug, Default)]
struct FrameCounters {
    splits: u64,
    merges: u64,
    forced: u64,
    evaluations: u64,
    guard_stops: u64,
    revalidations: u64,
    deferred: u64,
}

/// A queue element whose priority is due for recomputation.
#[derive(Clone, Copy, Debug)]
enum Due {
    Split(TriangleKey),
    Merge(TriangleKey),
}

/// The state `roam` and `roam-rebuild` share: bintree, queues, thicknesses, counters.
struct Core<'h> {
    hierarchy: &'h Hierarchy,
    config: RoamConfig,
    /// Bound on the eye's displacement per frame, metres.
    speed_per_frame: f64,
    thickness: Vec<f32>,
    bintree: Bintree,
    queues: Queues,
    log: SplitLog,
    /// Buffers of the rebuild's from-scratch strip count.
    strip_buffers: (Vec<(TriangleKey, bool)>, Vec<TriangleKey>),
    /// `false` for the rebuild: it has no merge queue.
    track_merges: bool,
    /// Deferred recomputations by frame (deferral only).
    wheel: BTreeMap<u64, Vec<Due>>,
    frame: u64,
    counters: FrameCounters,
    scratch: Vec<TriangleKey>,
    /// Key of the last split, for tests.
    last_split: Option<QueueKey>,
    /// Always on; a unit test turns it off to show the paper's literal loop oscillating.
    oscillation_guard: bool,
}

impl<'h> Core<'h> {
    /// Heap bytes held (slot map, queues and the deferral wheel estimated from their lengths
    /// and element sizes; the priority queues keep an index map beside their heap).
    fn memory_bytes(&self) -> usize {
        use std::mem::size_of;
        let queue_entry = size_of::<TriangleKey>() + size_of::<QueueKey>() + 3 * size_of::<usize>();
        self.thickness.capacity() * size_of::<f32>()
            + self.bintree.triangles.capacity()
                * (size_of::<bintree::BinTriangle>() + size_of::<u32>())
            + self.bintree.mesh.memory_bytes()
            + (self.queues.split.capacity() + self.queues.merge.capacity()) * queue_entry
            + self
                .wheel
                .values()
                .map(|v| v.capacity() * size_of::<Due>() + 4 * size_of::<usize>())
                .sum::<usize>()
            + self.scratch.capacity() * size_of::<TriangleKey>()
            + self.strip_buffers.0.capacity() * size_of::<(TriangleKey, bool)>()
            + self.strip_buffers.1.capacity() * size_of::<TriangleKey>()
    }

    fn new(
        hierarchy: &'h Hierarchy,
        config: RoamConfig,
        speed: SpeedBound,
        track_merges: bool,
    ) -> Core<'h> {
        // The rebuild recounts strips from scratch once per frame instead: keeping the list
        // through its ≈1500 splits per frame costs more than one O(leaves) walk.
        let bintree = Bintree::new(hierarchy.lattice(), config.strips && track_merges);
        Core {
            hierarchy,
            config,
            speed_per_frame: speed.horizontal.hypot(speed.vertical),
            thickness: hierarchy.nested_vertex_errors(config.nesting),
            bintree,
            queues: Queues::default(),
            log: SplitLog::default(),
            strip_buffers: (Vec::new(), Vec::new()),
            track_merges,
            wheel: BTreeMap::new(),
            frame: 0,
            counters: FrameCounters::default(),
            scratch: Vec::new(),
            last_split: None,
            oscillation_guard: true,
        }
    }

    fn context<'a>(&'a self, camera: &'a Camera) -> PriorityContext<'a> {
        PriorityContext {
            camera,
            field: self.hierarchy.field(),
            lattice: self.hierarchy.lattice(),
            thickness: &self.thickness,
            culling_flags: self.config.culling_flags,
        }
    }

    fn tau(&self) -> Option<f64> {
        match self.config.goal {
            RoamGoal::TolerancePx(tau) => Some(tau),
            RoamGoal::TargetTriangles(_) => None,
        }
    }

    fn deferring(&self) -> bool {
        self.config.deferral && self.tau().is_some()
    }

    /// Sets the flag of `key`: inherited from an IN or OUT parent (whose flag is current),
    /// tested otherwise. Deferral never trusts inherited flags (the parent's may be old).
    fn refresh_flag(&mut self, camera: &Camera, key: TriangleKey) -> CullFlag {
        if !self.config.culling_flags {
            return CullFlag::DontKnow;
        }
        let triangle = self.bintree.get(key);
        let inherited = match triangle.parent.map(|p| self.bintree.get(p).flag) {
            Some(flag @ (CullFlag::Inside | CullFlag::Outside)) if !self.deferring() => Some(flag),
            _ => None,
        };
        let flag = inherited.unwrap_or_else(|| self.context(camera).classify(triangle));
        self.bintree.set_flag(key, flag);
        flag
    }

    /// Flags of every triangle, top-down from the roots (§7.1).
    fn refresh_all_flags(&mut self, camera: &Camera) {
        if !self.config.culling_flags {
            return;
        }
        let mut stack = std::mem::take(&mut self.scratch);
        stack.clear();
        stack.extend(self.bintree.roots());
        while let Some(key) = stack.pop() {
            self.refresh_flag(camera, key);
            if let Some(children) = self.bintree.get(key).children {
                stack.extend(children);
            }
        }
        self.scratch = stack;
    }

    fn triangle_key(&mut self, camera: &Camera, key: TriangleKey) -> Option<QueueKey> {
        let flag = self.refresh_flag(camera, key);
        let triangle = self.bintree.get(key);
        let split = triangle.split_vertex()?;
        let apex = triangle.shape.apex;
        let value = self.context(camera).priority(triangle, flag);
        self.counters.evaluations += 1;
        if self.deferring() {
            self.schedule_triangle(camera, key, value);
        }
        Some(QueueKey::triangle(
            self.bintree.lattice(),
            value,
            split,
            apex,
        ))
    }

    fn diamond_key(&mut self, camera: &Camera, primary: TriangleKey) -> Option<QueueKey> {
        let vertex = self.bintree.get(primary).split_vertex()?;
        let context = self.context(camera);
        let value = diamond_priority_fresh(&self.bintree, &context, primary);
        self.counters.evaluations += 1;
        if self.deferring() {
            self.schedule_diamond(camera, primary, value);
        }
        Some(QueueKey::diamond(self.bintree.lattice(), value, vertex))
    }

    fn schedule_triangle(&mut self, camera: &Camera, key: TriangleKey, value: f64) {
        let tau = self.tau().unwrap_or(0.0);
        let context = self.context(camera);
        let frames = context.safe_frames(self.bintree.get(key), value, tau, self.speed_per_frame);
        self.schedule(frames, Due::Split(key));
    }

    fn schedule_diamond(&mut self, camera: &Camera, primary: TriangleKey, value: f64) {
        let tau = self.tau().unwrap_or(0.0);
        let context = self.context(camera);
        let speed = self.speed_per_frame;
        let mut frames = if value <= tau { u64::MAX } else { 0 };
        for parent in diamond_parents(&self.bintree, primary)
            .into_iter()
            .flatten()
        {
            let triangle = self.bintree.get(parent);
            let flag = if self.config.culling_flags {
                context.classify(triangle)
            } else {
                CullFlag::DontKnow
            };
            let parent_value = context.priority(triangle, flag);
            let safe = context.safe_frames(triangle, parent_value, tau, speed);
            // At or below τ: every parent must stay below. Above: one parent staying above is
            // enough.
            frames = if value <= tau {
                frames.min(safe)
            } else if parent_value > tau {
                frames.max(safe)
            } else {
                frames
            };
        }
        self.schedule(frames, Due::Merge(primary));
    }

    /// Queues `due` for the first frame its priority may have crossed τ. A priority that can
    /// never change (zero thickness: always 0) is not queued at all, so the wheel holds at most
    /// the recomputations of the next [`priority::MAX_DEFERRAL_FRAMES`] frames.
    fn schedule(&mut self, safe_frames: u64, due: Due) {
        if safe_frames == u64::MAX {
            return;
        }
        self.wheel
            .entry(self.frame + 1 + safe_frames)
            .or_default()
            .push(due);
    }

    /// Recomputes every queued priority (and every flag).
    fn revalidate_all(&mut self, camera: &Camera) {
        self.wheel.clear();
        self.refresh_all_flags(camera);
        let mut keys = std::mem::take(&mut self.scratch);
        keys.clear();
        keys.extend(self.queues.split.iter().map(|(k, _)| *k));
        for &key in &keys {
            if let Some(priority) = self.triangle_key(camera, key) {
                self.queues.split.change_priority(&key, priority);
            }
        }
        keys.clear();
        keys.extend(self.queues.merge.iter().map(|(k, _)| *k));
        for &key in &keys {
            if let Some(priority) = self.diamond_key(camera, key) {
                self.queues.merge.change_priority(&key, Reverse(priority));
            }
        }
        self.scratch = keys;
    }

    /// Recomputes the priorities that are due this frame (deferral).
    fn recompute_due(&mut self, camera: &Camera) {
        let later = self.wheel.split_off(&(self.frame + 1));
        let due = std::mem::replace(&mut self.wheel, later);
        for (_, entries) in due {
            for entry in entries {
                match entry {
                    Due::Split(key) if self.queues.split.contains(&key) => {
                        if let Some(priority) = self.triangle_key(camera, key) {
                            self.queues.split.change_priority(&key, priority);
                        }
                    }
                    Due::Merge(key) if self.queues.merge.contains(&key) => {
                        if let Some(priority) = self.diamond_key(camera, key) {
                            self.queues.merge.change_priority(&key, Reverse(priority));
                        }
                    }
                    _ => {}
                }
            }
        }
    }

    /// Splits `key` (with forced splits) and brings the queues up to date.
    fn split(&mut self, camera: &Camera, key: TriangleKey) {
        let top = self.queues.split.get_priority(&key).copied();
        self.log.diamonds.clear();
        let forced_before = self.log.forced;
        split::split(&mut self.bintree, key, &mut self.log);
        self.counters.forced += self.log.forced - forced_before;
        let diamonds = std::mem::take(&mut self.log.diamonds);
        for diamond in &diamonds {
            self.counters.splits += 1;
            for parent in diamond.parents.into_iter().flatten() {
                self.queues.split.remove(&parent);
                if self.track_merges
                    && let Some(grandparent) = self.bintree.get(parent).parent
                {
                    let primary = primary_parent(&self.bintree, grandparent);
                    self.queues.merge.remove(&primary);
                }
                if let Some(children) = self.bintree.get(parent).children {
                    for child in children {
                        if let Some(priority) = self.triangle_key(camera, child) {
                            self.queues.split.push(child, priority);
                        }
                    }
                }
            }
            if self.track_merges
                && let Some(parent) = diamond.parents[0]
            {
                let primary = primary_parent(&self.bintree, parent);
                if let Some(priority) = self.diamond_key(camera, primary) {
                    self.queues.merge.push(primary, Reverse(priority));
                }
            }
        }
        self.log.diamonds = diamonds;
        if top.is_some() {
            self.last_split = top;
        }
    }

    /// Merges the diamond queued under `primary` and brings the queues up to date.
    fn merge(&mut self, camera: &Camera, primary: TriangleKey) {
        let parents = diamond_parents(&self.bintree, primary);
        let mut children = [None; 4];
        for (k, parent) in parents.iter().enumerate() {
            if let Some(pair) = parent.and_then(|p| self.bintree.get(p).children) {
                children[2 * k] = Some(pair[0]);
                children[2 * k + 1] = Some(pair[1]);
            }
        }
        self.queues.merge.remove(&primary);
        if merge::merge(&mut self.bintree, primary).is_none() {
            return;
        }
        self.counters.merges += 1;
        for child in children.into_iter().flatten() {
            self.queues.split.remove(&child);
        }
        for parent in parents.into_iter().flatten() {
            if let Some(priority) = self.triangle_key(camera, parent) {
                self.queues.split.push(parent, priority);
            }
            if let Some(grandparent) = self.bintree.get(parent).parent
                && is_mergeable(&self.bintree, grandparent)
            {
                let primary = primary_parent(&self.bintree, grandparent);
                if !self.queues.merge.contains(&primary)
                    && let Some(priority) = self.diamond_key(camera, primary)
                {
                    self.queues.merge.push(primary, Reverse(priority));
                }
            }
        }
    }

    /// An upper bound on split/merge iterations in one frame: under the guard each vertex is
    /// inserted at most once and removed at most once per frame.
    fn iteration_cap(&self) -> u64 {
        2 * self.bintree.lattice().n_vertices() as u64 + 64
    }

    /// Fixed τ: split above τ, merge at or below.
    fn adapt_to_tolerance(&mut self, camera: &Camera, tau: f64, split_only: bool) {
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
                self.split(camera, key);
                continue;
            }
            if !split_only
                && let Some((key, priority)) = self.queues.bottom_merge()
                && priority.value <= tau
            {
                self.merge(camera, key);
                continue;
            }
            break;
        }
    }

    /// Target count: the dual-queue loop with the oscillation guard (see the module comment).
    fn adapt_to_target(&mut self, camera: &Camera, target: u64, split_only: bool) {
        if !self.oscillation_guard {
            self.adapt_to_target_unguarded(camera, target);
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
            let top = self.queues.top_split();
            let bottom = if split_only {
                None
            } else {
                self.queues.bottom_merge()
            };
            let may_merge = |key: QueueKey| lowest_split.is_none_or(|s| key < s);
            if self.bintree.n_leaves() > target {
                match bottom {
                    Some((diamond, key)) if may_merge(key) => {
                        self.merge(camera, diamond);
                        highest_merge = highest_merge.max(Some(key));
                        continue;
                    }
                    Some(_) => self.counters.guard_stops += 1,
                    None => {}
                }
                break;
            }
            let Some((triangle, key)) = top else {
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
                self.split(camera, triangle);
                lowest_split = Some(lowest_split.map_or(key, |s| s.min(key)));
                continue;
            }
            // It does not fit: make room if it beats the least useful diamond.
            match bottom {
                Some((diamond, bottom_key)) if bottom_key < key => {
                    if may_merge(bottom_key) {
                        self.merge(camera, diamond);
                        highest_merge = highest_merge.max(Some(bottom_key));
                        continue;
                    }
                    self.counters.guard_stops += 1;
                }
                _ => {}
            }
            break;
        }
    }

    /// The paper's loop as written, without the guard: while too large merge, while too small
    /// or the top split beats the bottom merge split. Only the iteration cap stops it.
    fn adapt_to_target_unguarded(&mut self, camera: &Camera, target: u64) {
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
                self.merge(camera, diamond);
                continue;
            }
            let beats = matches!((top, bottom), (Some((_, t)), Some((_, b))) if t > b);
            match top {
                Some((triangle, _)) if self.bintree.n_leaves() < target || beats => {
                    self.split(camera, triangle);
                }
                _ => break,
            }
        }
    }

    fn adapt(&mut self, camera: &Camera, split_only: bool) {
        match self.config.goal {
            RoamGoal::TolerancePx(tau) => self.adapt_to_tolerance(camera, tau, split_only),
            RoamGoal::TargetTriangles(n) => self.adapt_to_target(camera, n, split_only),
        }
    }

    /// Leaves per strip: the incremental count (`roam`), or a recount (`roam-rebuild`).
    fn triangles_per_strip(&mut self) -> f64 {
        if self.bintree.tracks_strips() {
            return strips::triangles_per_strip(&self.bintree);
        }
        let (stack, leaves) = &mut self.strip_buffers;
        let strips = strips::count_strips(&self.bintree, stack, leaves);
        self.bintree.n_leaves() as f64 / strips.max(1) as f64
    }

    /// The extra columns' values in the order of [`columns`].
    ///
    /// # Panics
    /// On a column this function does not know (a list in [`columns`] that grew without it):
    /// loudly, never as a silent NaN.
    fn extras(&mut self, columns: &[&str]) -> Vec<f64> {
        use super::columns::roam::{
            DEFERRED, FORCED_SPLITS, MERGE_QUEUE, OSCILLATION_GUARD_STOPS, PRIORITY_RECOMPUTATIONS,
            REVALIDATIONS, SPLIT_QUEUE, TRIANGLES_PER_STRIP,
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
                TRIANGLES_PER_STRIP => self.triangles_per_strip(),
                other => unreachable!("ROAM fills no column {other:?}"),
            })
            .collect()
    }
}

/// A diamond's priority with freshly tested flags: the larger of its parents'.
fn diamond_priority_fresh(
    bintree: &Bintree,
    context: &PriorityContext,
    primary: TriangleKey,
) -> f64 {
    diamond_parents(bintree, primary)
        .into_iter()
        .flatten()
        .map(|parent| {
            let triangle = bintree.get(parent);
            let flag = if context.culling_flags {
                context.classify(triangle)
            } else {
                CullFlag::DontKnow
            };
            context.priority(triangle, flag)
        })
        .fold(0.0, f64::max)
}

/// The extra columns of a run: the base ones, then those of the effects that are on.
fn columns(config: &RoamConfig, incremental: bool) -> &'static [&'static str] {
    use super::columns::roam::{
        DEFERRED, FORCED_SPLITS, MERGE_QUEUE, OSCILLATION_GUARD_STOPS, PRIORITY_RECOMPUTATIONS,
        REVALIDATIONS, SPLIT_QUEUE, TRIANGLES_PER_STRIP,
    };
    const INCREMENTAL: [&[&str]; 4] = [
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            DEFERRED,
            REVALIDATIONS,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            TRIANGLES_PER_STRIP,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            DEFERRED,
            REVALIDATIONS,
            TRIANGLES_PER_STRIP,
        ],
    ];
    const REBUILD: [&[&str]; 2] = [
        &[FORCED_SPLITS, SPLIT_QUEUE, PRIORITY_RECOMPUTATIONS],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            TRIANGLES_PER_STRIP,
        ],
    ];
    let strips = usize::from(config.strips);
    if incremental {
        let deferral = config.deferral && matches!(config.goal, RoamGoal::TolerancePx(_));
        INCREMENTAL[usize::from(deferral) + 2 * strips]
    } else {
        REBUILD[strips]
    }
}

/// `roam`: the incremental dual-queue algorithm. Per frame: O((recomputed priorities + splits +
/// merges) · log queue size), plus O(leaves) for the flag pass (culling flags without deferral)
/// and the OUT count when those are on; strips add O(1) per split or merge.
pub struct Roam<'h> {
    core: Core<'h>,
    /// The orientation priorities were last computed for (deferral).
    orientation: Option<(DVec3, DVec3)>,
}

impl<'h> Roam<'h> {
    pub fn new(hierarchy: &'h Hierarchy, config: RoamConfig, speed: SpeedBound) -> Roam<'h> {
        let mut core = Core::new(hierarchy, config, speed, true);
        // Placeholder priorities: the first frame always revalidates.
        for root in core.bintree.roots() {
            let triangle = core.bintree.get(root);
            if let Some(split) = triangle.split_vertex() {
                let key =
                    QueueKey::triangle(core.bintree.lattice(), 0.0, split, triangle.shape.apex);
                core.queues.split.push(root, key);
            }
        }
        Roam {
            core,
            orientation: None,
        }
    }

    /// Checks the bintree, the mesh and the queues (see `validate.rs`) against `camera`.
    pub fn validate(&self, camera: &Camera, check: PriorityCheck) -> Result<(), BintreeError> {
        validate::validate(
            &self.core.bintree,
            &self.core.queues,
            &self.core.context(camera),
            check,
        )
    }

    /// The largest priority in the split queue (0 when empty).
    pub fn max_split_priority(&self) -> f64 {
        self.core.queues.top_split().map_or(0.0, |(_, k)| k.value)
    }

    /// The smallest priority in the merge queue, if any diamond is mergeable.
    pub fn min_merge_priority(&self) -> Option<f64> {
        self.core.queues.bottom_merge().map(|(_, k)| k.value)
    }
}

impl Roam<'_> {
    /// The current 4-8 mesh (what [`LodAlgorithm::mesh`] hands the runner).
    pub fn vertex_set(&self) -> &VertexSet {
        self.core.bintree.mesh()
    }
}

impl LodAlgorithm for Roam<'_> {
    fn memory_bytes(&self) -> usize {
        self.core.memory_bytes()
    }

    fn name(&self) -> &'static str {
        NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        columns(&self.core.config, true)
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let camera = input.camera;
        let core = &mut self.core;
        core.frame = input.frame;
        core.counters = FrameCounters::default();
        let orientation = (camera.forward, camera.up);
        let revalidate =
            !core.deferring() || input.speed_bound_broken || self.orientation != Some(orientation);
        self.orientation = Some(orientation);
        if revalidate {
            core.counters.revalidations = 1;
            core.revalidate_all(camera);
        } else {
            core.recompute_due(camera);
        }
        let queued = (core.queues.split.len() + core.queues.merge.len()) as u64;
        core.counters.deferred = queued.saturating_sub(core.counters.evaluations);
        core.adapt(camera, false);

        let counters = core.counters;
        stats.triangles = core.bintree.n_leaves();
        stats.splits = counters.splits;
        stats.merges = counters.merges;
        stats.vertices_inserted = counters.splits;
        stats.vertices_deleted = counters.merges;
        stats.metric_evaluations = counters.evaluations;
        stats.extra = core.extras(columns(&core.config, true));
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::lattice(self.core.bintree.mesh())
    }

    fn triangle_count(&self) -> u64 {
        self.core.bintree.n_leaves()
    }
}

/// `roam-rebuild`: split-only greedy refinement from the base mesh every frame. Per frame:
/// O(splits · log queue size) plus O(grid/64) for the inserted/deleted counts, plus O(leaves)
/// for a from-scratch strip count when strips are on.
pub struct RoamRebuild<'h> {
    core: Core<'h>,
    previous_mesh: VertexSet,
}

impl<'h> RoamRebuild<'h> {
    pub fn new(hierarchy: &'h Hierarchy, config: RoamConfig, speed: SpeedBound) -> RoamRebuild<'h> {
        let config = RoamConfig {
            deferral: false,
            ..config
        };
        let core = Core::new(hierarchy, config, speed, false);
        let previous_mesh = core.bintree.mesh().clone();
        RoamRebuild {
            core,
            previous_mesh,
        }
    }

    /// The largest priority in the split queue (0 when empty).
    pub fn max_split_priority(&self) -> f64 {
        self.core.queues.top_split().map_or(0.0, |(_, k)| k.value)
    }

    /// The priority of the last triangle this frame's rebuild chose to split.
    pub fn last_split_priority(&self) -> Option<f64> {
        self.core.last_split.map(|k| k.value)
    }
}

impl RoamRebuild<'_> {
    /// The current 4-8 mesh (what [`LodAlgorithm::mesh`] hands the runner).
    pub fn vertex_set(&self) -> &VertexSet {
        self.core.bintree.mesh()
    }
}

impl LodAlgorithm for RoamRebuild<'_> {
    fn memory_bytes(&self) -> usize {
        self.core.memory_bytes() + self.previous_mesh.memory_bytes()
    }

    fn name(&self) -> &'static str {
        REBUILD_NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        columns(&self.core.config, false)
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let camera = input.camera;
        let core = &mut self.core;
        core.frame = input.frame;
        core.counters = FrameCounters::default();
        core.last_split = None;
        self.previous_mesh.clone_from(core.bintree.mesh());
        core.bintree.reset();
        core.queues.clear();
        for root in core.bintree.roots() {
            if let Some(priority) = core.triangle_key(camera, root) {
                core.queues.split.push(root, priority);
            }
        }
        core.adapt(camera, true);

        let counters = core.counters;
        let mesh = core.bintree.mesh();
        stats.triangles = core.bintree.n_leaves();
        stats.splits = counters.splits;
        stats.merges = 0;
        stats.vertices_inserted = mesh
            .iter()
            .filter(|&id| !self.previous_mesh.contains(id))
            .count() as u64;
        stats.vertices_deleted = self
            .previous_mesh
            .iter()
            .filter(|&id| !mesh.contains(id))
            .count() as u64;
        stats.metric_evaluations = counters.evaluations;
        stats.extra = core.extras(columns(&core.config, false));
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::lattice(self.core.bintree.mesh())
    }

    fn triangle_count(&self) -> u64 {
        self.core.bintree.n_leaves()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};
    use crate::sim::view::{Pose, ViewSettings};

    fn bumpy(level: u32) -> Hierarchy {
        let side = (1usize << level) + 1;
        let heights = (0..side * side)
            .map(|k| {
                let (i, j) = ((k % side) as f32, (k / side) as f32);
                15.0 * (0.8 * i).sin() * (0.6 * j).cos() + ((k * 7919) % 13) as f32
            })
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
    }

    fn camera(x: f64, y: f64, yaw: f64) -> Camera {
        Camera::new(
            &Pose {
                position: DVec3::new(x, y, 60.0),
                yaw,
                pitch: -0.4,
            },
            ViewSettings {
                width_px: 600,
                height_px: 600,
                fovy: 60f64.to_radians(),
                near: 1.0,
                far: 10_000.0,
            },
        )
    }

    fn config(culling_flags: bool) -> RoamConfig {
        RoamConfig {
            nesting: crate::sim::hierarchy::NestingRule::MaxPlusOwn,
            goal: RoamGoal::TolerancePx(2.0),
            deferral: false,
            culling_flags,
            // On, so that the validator checks the curve-order list after every operation.
            strips: true,
        }
    }

    const STILL: SpeedBound = SpeedBound {
        horizontal: 1.0,
        vertical: 1.0,
    };

    fn assert_valid(core: &Core, camera: &Camera) {
        let context = core.context(camera);
        if let Err(error) =
            validate::validate(&core.bintree, &core.queues, &context, PriorityCheck::Exact)
        {
            panic!("{error}");
        }
    }

    #[test]
    fn every_combination_of_options_fills_exactly_its_declared_columns() {
        let hierarchy = bumpy(4);
        let view = camera(40.0, 30.0, 0.7);
        for (goal, deferral, strips) in [
            (RoamGoal::TolerancePx(2.0), false, false),
            (RoamGoal::TolerancePx(2.0), true, false),
            (RoamGoal::TolerancePx(2.0), false, true),
            (RoamGoal::TolerancePx(2.0), true, true),
            (RoamGoal::TargetTriangles(100), false, true),
        ] {
            let options = RoamConfig {
                goal,
                deferral,
                strips,
                ..config(false)
            };
            let input = FrameInput {
                frame: 0,
                camera: &view,
                speed_bound_broken: true,
            };
            let algorithms: [Box<dyn LodAlgorithm>; 2] = [
                Box::new(Roam::new(&hierarchy, options, STILL)),
                Box::new(RoamRebuild::new(&hierarchy, options, STILL)),
            ];
            for mut algorithm in algorithms {
                let mut stats = FrameStats::default();
                algorithm.update(&input, &mut stats);
                let declared = algorithm.extra_columns();
                assert_eq!(stats.extra.len(), declared.len(), "{options:?}");
                assert!(declared.iter().all(|c| super::super::columns::is_known(c)));
            }
        }
    }

    /// Splits the top triangle, then merges the bottom diamond, in a pseudo-random mix, checking
    /// everything after every operation.
    fn exercise(culling_flags: bool) {
        let hierarchy = bumpy(4);
        let mut roam = Roam::new(&hierarchy, config(culling_flags), STILL);
        let camera = camera(40.0, 30.0, 0.7);
        roam.core.revalidate_all(&camera);
        assert_valid(&roam.core, &camera);
        let mut state = 12345u64;
        let (mut splits, mut merges) = (0, 0);
        for _ in 0..400 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let choice = (state >> 33) % 10;
            if choice < 6 {
                // Split a leaf picked by grid position, not by priority.
                let leaves: Vec<TriangleKey> =
                    roam.core.queues.split.iter().map(|(k, _)| *k).collect();
                let mut ordered: Vec<(u64, TriangleKey)> = leaves
                    .iter()
                    .map(|&k| {
                        let t = roam.core.bintree.get(k).shape;
                        let lattice = hierarchy.lattice();
                        (
                            (u64::from(lattice.id(t.apex)) << 32) | u64::from(lattice.id(t.left)),
                            k,
                        )
                    })
                    .collect();
                ordered.sort();
                if let Some(&(_, key)) = ordered.get((state >> 20) as usize % ordered.len().max(1))
                {
                    roam.core.split(&camera, key);
                    splits += 1;
                }
            } else if let Some((key, _)) = roam.core.queues.bottom_merge() {
                roam.core.merge(&camera, key);
                merges += 1;
            }
            assert_valid(&roam.core, &camera);
        }
        assert!(
            splits > 100 && merges > 50,
            "{splits} splits, {merges} merges"
        );
        assert!(
            roam.core.counters.forced > 0,
            "no forced split was exercised"
        );
    }

    #[test]
    fn every_split_and_merge_keeps_the_bintree_and_queues_valid() {
        exercise(false);
    }

    #[test]
    fn every_split_and_merge_keeps_the_flags_valid_with_culling() {
        exercise(true);
    }

    fn run_frame(roam: &mut Roam, frame: u64, camera: &Camera) -> FrameStats {
        let mut stats = FrameStats::default();
        roam.update(
            &FrameInput {
                frame,
                camera,
                speed_bound_broken: false,
            },
            &mut stats,
        );
        stats
    }

    #[test]
    fn the_papers_loop_oscillates_on_an_odd_budget_and_the_guard_stops_it() {
        let hierarchy = bumpy(4);
        let camera = camera(40.0, 30.0, 0.7);
        let budget = RoamConfig {
            goal: RoamGoal::TargetTriangles(41),
            ..config(false)
        };
        let mut literal = Roam::new(&hierarchy, budget, STILL);
        literal.core.oscillation_guard = false;
        let stats = run_frame(&mut literal, 0, &camera);
        // Split to 42, merge to 40, split to 42, … until the cap.
        assert_eq!(literal.core.counters.guard_stops, 1, "{stats:?}");
        assert!(stats.splits + stats.merges >= literal.core.iteration_cap() - 1);

        let mut guarded = Roam::new(&hierarchy, budget, STILL);
        let first = run_frame(&mut guarded, 0, &camera);
        assert!(first.triangles <= 41 && first.splits < 41, "{first:?}");
        let second = run_frame(&mut guarded, 1, &camera);
        assert_eq!((second.splits, second.merges), (0, 0));
        assert_valid(&guarded.core, &camera);
    }

    #[test]
    fn a_forced_split_costs_what_the_split_adds() {
        let hierarchy = bumpy(4);
        let mut roam = Roam::new(&hierarchy, config(false), STILL);
        let camera = camera(40.0, 30.0, 0.7);
        roam.core.revalidate_all(&camera);
        // Refine one corner deeply so that its neighbours must be forced.
        for _ in 0..12 {
            let Some((key, _)) = roam.core.queues.top_split() else {
                break;
            };
            let before = roam.core.bintree.n_leaves();
            let cost = split_cost(&roam.core.bintree, key);
            roam.core.split(&camera, key);
            assert_eq!(roam.core.bintree.n_leaves(), before + cost);
        }
        assert_valid(&roam.core, &camera);
    }
}
