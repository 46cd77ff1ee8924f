//! `roam` and `roam-rebuild`: Duchaineau et al.'s ROAM (1997) on the shared 4-8 mesh family, as
//! SPEC §6 fixes it: the triangle bintree, eq. (3)'s priorities over eq. (1)'s thicknesses, the
//! dual split and merge queues, and the effects of §7.1 (culling flags), §7.2 (strips) and §7.3
//! (deferral). Not simulated: §7.4's progressive optimisation (stopping when the frame time runs
//! out) and drawing the strips (they are counted).
//!
//! **What a GPU draws** (`draw.rs`, issue #31): a vertex buffer with a slot per active vertex and
//! an index buffer with a slot per leaf, changed in place by every split and merge (a split
//! writes its vertex and its children, a merge its parents and one swap-removed slot: at most
//! [`UPLOAD_BYTES_PER_CHANGE`] bytes each), drawn as one indexed triangle list. A frame that
//! changes nothing uploads nothing. The §7.2 strips stay counted, not drawn (an option not
//! built): §7.2 keeps "non-generalized strips" by "a simple, sub-optimal, incremental approach"
//! (quoted in `strips.rs`), strips that a 1997 renderer sent vertex by vertex every frame, so
//! that a triangle cost about one vertex sent instead of three; a resident indexed list sends
//! each vertex once, when it enters the mesh, and nothing for a frame without change, which is
//! what the strips were for. Drawing them from resident buffers would move index ranges
//! whenever a strip grows, shrinks or splits, which §7.2 does not describe (our reading of the
//! paper, which is not among `/work/shared/papers`). `Out` leaves (§7.1) are drawn too: the
//! buffers draw the mesh the runner culls and `--check` compares. `roam-rebuild` keeps the same
//! buffers and resets them with its bintree every frame: an indexed list rebuilt from scratch,
//! O(mesh) upload per frame by design (the reference of what coherence saves).
//!
//! **Data.** A triangle bintree in a slot map (`bintree.rs`), split with recursive forced splits
//! (`split.rs`), merged by diamonds (`merge.rs`), two priority queues (`queues.rs`): leaves that
//! can split, largest priority first; mergeable diamonds, smallest first. The mesh is the set of
//! split vertices (hypotenuse midpoints) plus the corners, a [`VertexSet`] of the shared family;
//! the triangle count is the number of leaves. `core/` holds the state and its operations,
//! `extras.rs` the extra columns, `rebuild.rs` `roam-rebuild`.
//!
//! **Priorities** are ROAM's eq. (3) wedgie bound over the nested wedgie thickness e_T
//! (`priority.rs`); a diamond's is the larger of its parents'. The thickness is eq. (1) of the
//! paper by default: one value per bintree triangle, nested over the triangle's own two children
//! ([`ThicknessScope::PerTriangle`]); roamsim's former rule, one value per split vertex nested over
//! the four children of its diamond, is the option [`ThicknessScope::PerVertex`] (looser: the same
//! or larger for every triangle). Both take the paper's `max_plus_own` nesting by default, or
//! `max` to measure what the bound costs (`thickness.rs`).
//!
//! **Frame loop (`roam`).** Update the culling flags (§7.1), recompute the priorities that are
//! due (all of them without deferral), then:
//! - fixed τ: split the top triangle while its priority exceeds τ, merge the bottom diamond while
//!   its priority is at most τ;
//! - target triangle count: the paper's dual-queue loop. While the mesh is too large, merge the
//!   bottom diamond; while the top split fits in the budget (forced splits included), split it;
//!   when it does not fit but beats the bottom diamond, merge that diamond to make room. The
//!   mesh never ends above the target unless it started above it with nothing left to merge.
//!   "Beats" compares priority *values*: equal values (+∞ against +∞ behind the near plane above
//!   all) never trade places, since trading equals moved the mesh from frame to frame under a
//!   still camera.
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
//! - deferral (§7.3, `deferral.rs`), with a tolerance or a triangle target: a priority is
//!   recomputed only when its time-dependent bound could reach the crossover (τ, or a band around
//!   the moving crossover of a target), scheduled on a ring of per-frame lists by a closed-form
//!   frame count; the meshes are exactly those of full recomputation. The bound uses the speed
//!   bound v = √(v_h² + v_v²) metres per frame and a rotation bound θ radians per frame
//!   (`speed_bounds.rotation_rad_per_frame`, or when undeclared the flight's largest turn, taken
//!   by [`Roam::new`]; π gives none; tests may pass their own [`MotionBound`] to
//!   [`Roam::with_motion_bound`]). A frame that broke the speed bounds, that turned by more
//!   than θ (the rotation of the camera's whole frame, which may exceed the look direction's
//!   turn the runner checks: then a revalidation, never a wrong deferral), or (without θ) whose
//!   orientation changed at all, and the first frame, recompute everything (`revalidations`);
//!   without θ such a frame schedules nothing, so a turning camera costs what no deferral costs;
//! - culling flags (§7.1, `cull.rs`): per-half-space IN flags and OUT / ALL-IN / DONT-KNOW
//!   labels, updated each frame by a traversal that stops at triangles whose OUT or ALL-IN label
//!   still holds, and inherited by the children of a split; `Out` triangles get priority 0;
//! - strips (§7.2, `strips.rs`): incremental non-generalised strips over the drawn leaves, new
//!   triangles inserted as singletons and glued to neighbouring strip ends;
//!   `triangles_per_strip` reports them.
//!
//! **Queues** (`queues.rs`): Duchaineau's 4096 log-spaced buckets, made exact at the top
//! ([`QueueKind::Buckets`], the default: O(1) updates), or the `priority-queue` crate's heap
//! ([`QueueKind::Heap`]); both give the same meshes bit for bit.
//!
//! **`roam-rebuild`** resets the bintree to the two base triangles every frame and splits greedily
//! from the split queue only (no merges, no coherence): the reference of "what incremental
//! split/merge saves". It keeps flags (classified as triangles are created) and strips the same
//! way, through its splits.
//!
//! Culling flags have no column of their own but `flag_tests`: the runner's `triangles_rendered`
//! shows their effect. Without them, eq. 3's near-plane rule gives every triangle behind the eye
//! +∞, so a budget is spent behind the camera: scenes that care should turn them on.
//!
//! Counters: `splits`/`merges` are diamond operations (forced ones included), so for `roam`
//! `vertices_inserted = splits` and `vertices_deleted = merges`; `roam-rebuild` reports the
//! difference from the previous frame's mesh. `metric_evaluations` = `priority_recomputations` =
//! eq. (3) evaluations (a diamond's two parents count two; deferral's scheduling passes count
//! too); `deferred` = queued elements whose priority the frame did not recompute before its
//! loop; `revalidations` = full recomputations (of both queues at the start of a frame, or of one
//! queue when a target's crossover left deferral's band mid-frame); `flag_tests` =
//! wedgie classifications (the frame's flag traversal, and new children of DONT-KNOW parents).

mod bintree;
mod buckets;
mod core;
mod cull;
mod deferral;
mod draw;
mod extras;
mod merge;
mod priority;
mod queues;
mod rebuild;
mod split;
mod strips;
mod thickness;
mod validate;

pub use deferral::MotionBound;
pub use draw::BYTES_PER_CHANGE as UPLOAD_BYTES_PER_CHANGE;
pub use queues::QueueKind;
pub use rebuild::RoamRebuild;
pub use thickness::ThicknessScope;
pub use validate::{BintreeError, PriorityCheck};

use self::core::{Core, FrameCounters};
use super::{FrameInput, LodAlgorithm};
use crate::sim::draw::{DrawCounts, GpuBuffers};
use crate::sim::hierarchy::{Hierarchy, NestingRule};
use crate::sim::mesh::MeshOutput;
use crate::sim::mesh::VertexSet;
use crate::sim::stats::FrameStats;
use crate::sim::view::Camera;
use crate::sim::zone::SpeedBound;
use extras::columns;
use glam::DVec3;
use priority::ViewFrame;
use queues::QueueKey;

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
    /// Deferred priority recomputation (§7.3).
    pub deferral: bool,
    /// Frustum-culling flags (§7.1).
    pub culling_flags: bool,
    /// Incremental triangle strips (§7.2).
    pub strips: bool,
    /// How the wedgie thickness nests over descendants: the paper's [`NestingRule::MaxPlusOwn`]
    /// (a true bound of the surface's distance) or [`NestingRule::Max`] (to measure what the
    /// bound costs).
    pub nesting: NestingRule,
    /// Whether the thickness is kept per bintree triangle (eq. 1) or per split vertex.
    pub thickness: ThicknessScope,
    /// The priority queues' implementation.
    pub queue: QueueKind,
}

impl RoamConfig {
    fn goal_is_target(&self) -> bool {
        matches!(self.goal, RoamGoal::TargetTriangles(_))
    }
}

/// A camera for the core's frame before the first real one (every frame sets its own).
fn placeholder_camera() -> Camera {
    Camera::new(
        &crate::sim::view::Pose {
            position: DVec3::ZERO,
            yaw: 0.0,
            pitch: 0.0,
        },
        crate::sim::view::ViewSettings {
            width_px: 1,
            height_px: 1,
            fovy: 1.0,
            near: 1.0,
            far: 2.0,
        },
    )
}

/// The camera's orientation: its right, up and forward vectors.
type Orientation = (DVec3, DVec3, DVec3);

/// The angle of the rotation that takes one camera orientation to another.
fn rotation_angle(from: Orientation, to: Orientation) -> f64 {
    let trace = from.0.dot(to.0) + from.1.dot(to.1) + from.2.dot(to.2);
    ((trace - 1.0) / 2.0).clamp(-1.0, 1.0).acos()
}

/// `roam`: the incremental dual-queue algorithm. Per frame: O(recomputed priorities + splits +
/// merges), plus O(triangles straddling the frustum + triangles whose culling label changed)
/// for the flags; strips add O(1) per split, merge or culling change (a strip reversal
/// O(its length)). Without deferral every queued priority is recomputed each frame.
pub struct Roam<'h> {
    core: Core<'h>,
    /// The orientation priorities were last computed for (deferral).
    orientation: Option<Orientation>,
    /// Whether the next frame must recompute everything (the last one turned with no rotation
    /// bound and scheduled nothing).
    needs_full_recomputation: bool,
}

impl<'h> Roam<'h> {
    /// `roam` with the experiment's speed and rotation bounds (a rotation bound of π gives the
    /// deferral none: every turn then recomputes everything; an experiment that declares none
    /// gets its flight's largest turn at load, not π).
    pub fn new(hierarchy: &'h Hierarchy, config: RoamConfig, speed: SpeedBound) -> Roam<'h> {
        let motion = MotionBound {
            metres_per_frame: speed.horizontal.hypot(speed.vertical),
            radians_per_frame: (speed.rotation < SpeedBound::NO_ROTATION_BOUND)
                .then_some(speed.rotation),
        };
        Roam::with_motion_bound(hierarchy, config, motion)
    }

    /// `roam` whose deferral also assumes the camera turns by at most
    /// `motion.radians_per_frame` per frame (the hook for the experiment's rotation bound).
    pub fn with_motion_bound(
        hierarchy: &'h Hierarchy,
        config: RoamConfig,
        motion: MotionBound,
    ) -> Roam<'h> {
        let placeholder = placeholder_camera();
        let mut core = Core::new(hierarchy, config, motion, true, &placeholder);
        // The two roots, priorities placeholders: the first frame recomputes everything.
        for root in core.bintree.roots() {
            let triangle = core.bintree.get(root);
            if let Some(split) = triangle.split_vertex() {
                let key =
                    QueueKey::triangle(core.bintree.lattice(), 0.0, split, triangle.shape.apex);
                core.queues.split.push(root, key);
            }
            if config.strips {
                strips::attach(&mut core.bintree, root);
            }
        }
        Roam {
            core,
            orientation: None,
            needs_full_recomputation: true,
        }
    }

    /// Checks the bintree, the mesh, the flags, the strips and the queues (see `validate.rs`)
    /// against `camera`.
    pub fn validate(&self, camera: &Camera, check: PriorityCheck) -> Result<(), BintreeError> {
        let view = ViewFrame::new(camera);
        let context = priority::PriorityContext {
            view: &view,
            culling_flags: self.core.config.culling_flags,
        };
        let band = match (&self.core.deferral, check) {
            (Some(deferral), PriorityCheck::Deferred) => Some((deferral.floor, deferral.ceiling)),
            _ => None,
        };
        let expected = validate::Expected {
            field: self.core.hierarchy.field(),
            thicknesses: &self.core.thicknesses,
            context,
            check,
            band,
            strips_on: self.core.config.strips,
        };
        validate::validate(&self.core.bintree, &self.core.queues, &expected)
    }

    /// The largest priority in the split queue (0 when empty).
    pub fn max_split_priority(&self) -> f64 {
        self.core.queues.top_split().map_or(0.0, |(_, k)| k.value)
    }

    /// The smallest priority in the merge queue, if any diamond is mergeable.
    pub fn min_merge_priority(&self) -> Option<f64> {
        self.core.queues.bottom_merge().map(|(_, k)| k.value)
    }

    /// Which triangles the frame recomputes: everything, or (deferral) what is due.
    fn recompute(&mut self, input: &FrameInput) {
        let core = &mut self.core;
        let camera = input.camera;
        let orientation = (camera.right, camera.up, camera.forward);
        let previous = self.orientation.replace(orientation);
        if core.deferral.is_none() {
            core.apply_flag_changes(true);
            core.recompute_queue(0, false);
            core.recompute_queue(1, false);
            return;
        }
        let turned = previous.is_some_and(|p| p != orientation);
        let turned_beyond_bound = match (previous, core.motion.radians_per_frame) {
            (Some(p), Some(bound)) => rotation_angle(p, orientation) > bound + 1e-12,
            _ => false,
        };
        let unbounded_turn = turned && core.motion.radians_per_frame.is_none();
        let full = self.needs_full_recomputation
            || previous.is_none()
            || input.broken_bounds.any()
            || turned_beyond_bound
            || unbounded_turn;
        if full {
            core.counters.revalidations += 1;
            if let Some(deferral) = &mut core.deferral {
                deferral.clear();
            }
            core.apply_flag_changes(true);
            // With a fixed τ the band is known: schedule at once, unless the camera turned with
            // no rotation bound (nothing would survive the next turn). A target's band waits for
            // this frame's crossover.
            let schedule_now = !unbounded_turn && !core.config.goal_is_target();
            core.recompute_queue(0, schedule_now);
            core.recompute_queue(1, schedule_now);
            self.needs_full_recomputation = unbounded_turn;
        } else {
            core.recompute_due();
            core.apply_flag_changes(false);
        }
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
        let core = &mut self.core;
        core.frame = input.frame;
        core.counters = FrameCounters::default();
        core.view = ViewFrame::new(input.camera);
        core.update_flags();
        self.recompute(input);
        let core = &mut self.core;
        let queued = (core.queues.split.len() + core.queues.merge.len()) as u64;
        core.counters.deferred = queued.saturating_sub(core.counters.elements);
        core.adapt(false);
        // After a turn with no rotation bound nothing is scheduled: the next frame recomputes
        // everything anyway.
        if !self.needs_full_recomputation {
            core.finish_deferral();
        }

        let counters = core.counters;
        stats.triangles = core.bintree.n_leaves();
        stats.splits = counters.splits;
        stats.merges = counters.merges;
        stats.vertices_inserted = counters.splits;
        stats.vertices_deleted = counters.merges;
        stats.metric_evaluations = counters.evaluations;
        stats.extra = core.extras(columns(&core.config, true));
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.core.draw.prepare()
    }

    fn buffers(&self) -> &GpuBuffers {
        self.core.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::lattice(self.core.bintree.mesh())
    }

    fn triangle_count(&self) -> u64 {
        self.core.bintree.n_leaves()
    }
}

impl Roam<'_> {
    /// The current 4-8 mesh (what [`LodAlgorithm::mesh`] hands the runner).
    pub fn vertex_set(&self) -> &VertexSet {
        self.core.bintree.mesh()
    }
}

#[cfg(test)]
mod tests;
