//! `wu`: Wu, Liu, Zhan and Gao's view-dependent terrain algorithm (Graphics Interface 2001), the
//! incremental engine: split and merge queues of valid lives, carried from frame to frame. It
//! implements Wu et al. 2001 §3 (nodes, traversal, culling), §5 (valid lives) and §6 (base
//! shifting) as SPEC §5 fixes them. Not here: the split zones and lives (`zone.rs`), the node
//! errors (`hierarchy`), and the from-scratch ground truth it is tested against (`reference.rs`).
//!
//! **Nodes** are the quadtree blocks, represented by their centre vertices (the square diamonds of
//! the 4-8 hierarchy). Wu's node hierarchy is the quadtree: a node is queued as **splittable** when
//! it is inactive and its quadtree parent is active (the root: when inactive), and **mergeable**
//! when it is active and no vertex depends on it, i.e. none of its boundary vertices (edge
//! midpoints) has an active child — neither one of its own sub-blocks nor a sub-block of the
//! neighbour across that edge. Boundary vertices are free, as in the reference: one is active
//! exactly when all its parents are. Splitting a node first activates what closure needs (its 4-8
//! parents, which forces the neighbouring blocks up the hierarchy: the forced splits, never
//! refused); merging deletes the node and its boundary vertices. The mesh is always a valid 4-8
//! mesh. Because boundary vertices are free, a split never cascades along a level, only up it: a
//! split block whose neighbour is not split draws its side of the shared edge without the
//! midpoint, which is exactly the 4-8 mesh. The paper's own *splittable* statistic (§3.1) is
//! narrower — inactive with both corner parents active, i.e. splittable without forcing anything
//! — and is reported beside the split queue's length (`splittable`, `split_queue`).
//!
//! **Valid lives.** A node's signed life ℓ (see `zone.rs`) is how many frames the eye needs, at
//! the speed bounds, to reach its split zone. A splittable node splits when ℓ ≤ b; a mergeable node
//! merges when ℓ ≥ b + 1. Split key = ℓ − b, merge key = b + 1 − ℓ: a node is looked at again
//! only when its key runs out, i.e. after ⌈key⌉ frames, which is safe because ℓ changes by at most
//! one per frame while the speed bounds hold. Keys ≤ 0 are acted on in the same frame (a node's
//! split can make its children due at once: the top-down traversal). The queues are timing wheels
//! (`wheel.rs`). On a frame that broke a motion bound every queued key is recomputed.
//!
//! **Refinement that follows the view** (`refine`, `visibility.rs`). `in_view`, the paper's way
//! (§3.2: the view decides "whether to split or merge" the nodes rendered at the previous frame):
//! a node splits only when its bounding sphere meets the view cone, and a mergeable node merges
//! once its sphere misses the cone at the frame it is looked at, whatever its life: the same
//! exact test as the split's, so what is shown never depends on the declared bounds (issue #30
//! item 3: under a bound of π a margin of one frame of cone motion let nothing merge for leaving
//! the view, and the whole mesh grew every frame). Both conditions are scheduled on the same
//! wheels: a splittable node's key is max(ℓ − b, frames before it can enter the view), a mergeable
//! node's min(b + 1 − ℓ, frames before it can leave the view) and 0 out of view, where the view
//! keys come from the speed bounds and the rotation bound (how fast the look direction may turn):
//! the bounds decide only when a node is looked at again, and a bound of π means every frame. No
//! node is tested against the cone on a frame its key says nothing can have changed. Spheres
//! nest, so a node in view has every ancestor in view. `everywhere` splits and merges by life alone (the mesh behind
//! the camera is refined like the rest), kept so that its cost stays measurable.
//!
//! **The in-view count** (with `cone_culling` and a budget, the only reader of it): the triangles of the
//! active blocks whose sphere meets the view cone, each triangle counted with the smallest active
//! block holding it — what a renderer culling Wu's nodes against the cone draws. Every active node
//! carries an in-view flag, kept exact by view keys (non-mergeable active nodes wait in a third
//! wheel, the view queue), and the count is updated by ±(the block's own triangles) when a flag
//! changes and by the triangles each vertex insertion or deletion moves between blocks: O(1) per
//! change, no walk over the mesh or over blocks. With `cone_culling` the budget counts this;
//! without, the whole mesh. It is not the runner's `triangles_rendered` (`in_view.rs` says why).
//!
//! **Constant budget** (`budget.rs`): with a triangle budget n, b moves by one every frame towards
//! the budget (the paper's MobilizeQueues as published): n_prev > n lowers b, recomputes the two
//! top links of the merge queue and defers the due splits by a frame; n_prev ≤ n raises b,
//! recomputes the two top links of the split queue and defers the due merges (their view flags
//! are still brought up to date). An optional dead band restores the paper's third branch (the top
//! link of each queue); b is clamped and the clamp reported. Optional τ re-centring moves τ slowly
//! so that b's mean stays near 0. Without a budget, b stays 0 (fixed τ). A budget entry without a
//! given τ starts from the smallest τ whose first frame holds the budget, searched at the first
//! frame from the paper's initial τ (`search_initial_tau`; roamsim's choice: the paper's formula
//! alone can start several times over the budget, and b then needs hundreds of frames).
//!
//! **GPU buffers** (`draw.rs`, issue #31): a vertex buffer with a slot per active vertex and an
//! index buffer with a slot per leaf triangle, drawn as one triangle list, changed in place by
//! each vertex a split or merge inserts or deletes (at most 300 bytes a split or merge), so that
//! the upkeep is O(splits + merges), as a renderer of Wu's incremental mesh keeps it. The whole
//! mesh is in them (the in-view refinement already keeps what is outside the cone coarse). The
//! paper's incremental strips (§7) are option `strips` (`strips.rs`, off by default): kept in
//! `prepare_draw`, counted in `triangles_per_strip`, not drawn; `draw.rs` says why a list. The
//! slots are the shared `sim::draw::incremental::LeafBuffer` (ROAM's too).
//!
//! **Morphing** (`morph.rs`, option `morph_frames`, off by default): Wu §7's "simple geometry
//! morphing similar to [2, 5]", read as ROAM's: the drawn mesh follows the vertex set over N
//! frames, a new vertex rising from its edge's midpoint, a deleted one sinking back before it
//! leaves. With it on, `mesh`, the buffers and `triangles` are the drawn mesh's; the budget and
//! every queue still work on the vertex set.
//!
//! **Traversal options.** Block-priority traversal tests a split node's children by decreasing
//! error and stops at the first whose life does not let it split: its untested siblings take its
//! key (the paper's premise that siblings' errors go the same way), or wait one frame when that
//! key is infinite. A heuristic: a sibling may need splitting before that key runs out. A depth
//! limit caps the chain of splits one frame makes below a node split from the queues. Splits and
//! merges that come due through a revalidation or an overflow wrap are acted on even in a frame
//! whose base shift defers the other kind (only the due wheel link is deferred).
//!
//! Per frame: O(nodes whose key ran out + operations · their neighbourhood). Memory, on top of
//! the shared hierarchy (heights and the node data above the finest level, 5 bytes per sample):
//! a 4-byte queue handle per node (1.33 bytes per sample); a 12-byte link entry per queued node
//! (the frontier, and with view tracking every active node, the view queue holding the
//! non-mergeable ones: O(mesh size)) in a slab that keeps its peak size rounded up to a power of
//! two, with at most as many removed entries awaiting their link's walk (`wheel.rs`); one bit
//! per vertex for the mesh (0.125 bytes per sample); with view tracking, one in-view bit per node
//! (0.04 bytes per sample); the work lists; and with the
//! `max_plus_own` nesting, the centres' nested errors (4 bytes per sample, `zone.rs`). A mesh
//! near full resolution (τ → 0) queues most nodes, and the slab then grows towards 12 bytes per
//! node. The measured totals are in `docs/performance.md`.

mod budget;
mod cull;
mod draw;
mod in_view;
mod merge;
mod morph;
mod nodes;
mod split;
mod strips;
mod validate;
mod visibility;
mod wheel;

use crate::sim::draw::{DrawCounts, GpuBuffers};
pub use budget::initial_tau_px;
pub(super) use cull::Cone;
use draw::WuBuffers;
use visibility::SphereShape;
pub(super) use visibility::{ConeMotion, NodeSphere, Sight};

use super::columns::wu as columns;
use super::{FrameInput, LodAlgorithm};
use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice, NestingRule, VertexClass};
use crate::sim::mesh::MeshOutput;
use crate::sim::mesh::VertexSet;
use crate::sim::stats::FrameStats;
use crate::sim::view::ViewSettings;
use crate::sim::zone::{NodeErrors, SpeedBound, ZoneVariant, radius_per_error};
use glam::DVec3;
use in_view::ViewTracking;
use morph::Morphing;
use nodes::{LifeRule, NO_NODE, Nodes};
use wheel::{Queue, Wheels};

pub(super) const NAME: &str = "wu";

/// Where refinement happens.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refinement {
    /// Split only nodes whose bounding sphere meets the view cone, merge those that leave it
    /// (the paper's way; needs the view cone).
    InView,
    /// Split and merge by life alone, wherever the node is.
    Everywhere,
}

impl Refinement {
    pub fn name(self) -> &'static str {
        match self {
            Refinement::InView => "in_view",
            Refinement::Everywhere => "everywhere",
        }
    }
}

/// Parameters of Wu's algorithm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WuConfig {
    /// τ in pixels; `None` in budget mode: searched at the first frame, from the paper's
    /// initial τ, for the smallest τ that holds the budget on that frame.
    pub tau_px: Option<f64>,
    /// A triangle budget (constant frame rate by base shifting), or `None` for fixed τ (b = 0).
    pub budget: Option<BudgetConfig>,
    pub zone: ZoneVariant,
    pub block_priority: bool,
    /// Most levels one frame may split below a node taken from the queues; `None`: no limit.
    pub depth_limit: Option<u32>,
    /// With a budget, keep the in-view count (triangles of active blocks whose sphere meets the
    /// view cone) and let the budget count those, else the whole mesh. Without a budget nothing
    /// would read the count, so it is not kept ([`WuConfig::keeps_in_view_count`]).
    /// [`Refinement::InView`] follows the cone either way.
    pub cone_culling: bool,
    pub refine: Refinement,
    /// Wheel links per queue (≥ 2).
    pub wheel_links: u32,
    /// How δ nests: Wu's [`NestingRule::Max`], or [`NestingRule::MaxPlusOwn`] (a true bound, to
    /// measure what it costs; 4 more bytes per sample).
    pub nesting: NestingRule,
    /// Wu §7's geometry morphing over this many frames (`morph.rs`); `None`: off (the default).
    pub morph_frames: Option<u32>,
    /// Wu §7's incremental triangle strips over the leaves (`strips.rs`): counted
    /// (`triangles_per_strip`), not drawn; off by default (`draw.rs` says why).
    pub strips: bool,
}

impl WuConfig {
    /// Whether the run follows the view cone (for the count, the refinement, or both).
    pub fn tracks_view(&self) -> bool {
        self.cone_culling || self.refine == Refinement::InView
    }

    /// Whether the in-view flags and count are kept: only when a budget counts them
    /// (`cone_culling` with a budget). A fixed-τ entry's mesh does not depend on them (they
    /// only schedule when a flag is brought up to date), so leaving them out changes no mesh and
    /// saves their cone tests and view queue.
    pub fn keeps_in_view_count(&self) -> bool {
        self.cone_culling && self.budget.is_some()
    }
}

/// The constant-budget settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BudgetConfig {
    /// Rendered triangles per frame to aim at.
    pub triangles: u64,
    /// |n_prev − n| ≤ dead band leaves b alone (0: b moves every frame, as published).
    pub dead_band: u64,
    /// b stays within [−base_limit, base_limit].
    pub base_limit: i64,
    /// The coefficient k of the paper's initial-τ formula (1.5 in the paper).
    pub initial_tau_k: f64,
    /// Re-centre τ so that b's mean stays near 0; `None`: the paper's fixed τ.
    pub tau_recentring: Option<TauRecentring>,
}

/// The outer loop that re-centres τ (see `budget.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TauRecentring {
    /// Frames over which b's mean is taken before each adjustment (≥ 1).
    pub window_frames: u32,
}

/// A node's life and, when the run needs it, where it is in the view.
#[derive(Clone, Copy, Debug)]
struct NodeLook {
    life: f64,
    sight: Option<Sight>,
}

/// Counters of one frame.
#[derive(Clone, Copy, Debug, Default)]
struct Counters {
    splits: u64,
    forced_splits: u64,
    merges: u64,
    inserted: u64,
    deleted: u64,
    lives: u64,
    cone_tests: u64,
}

/// The columns every run has, then the optional ones in this order: `cone_tests` (the view cone
/// is followed), `triangles_in_view_blocks` (the in-view count is kept), `tau_px` (τ re-centring), `triangles_per_strip` (strips, filled by `draw_columns`).
macro_rules! column_list {
    ($($optional:expr),*) => {
        &[
            columns::BASE_B,
            columns::BASE_CLAMPED,
            columns::SPLITTABLE,
            columns::SPLIT_QUEUE,
            columns::MERGEABLE,
            columns::LIFE_RECOMPUTATIONS,
            columns::FORCED_SPLITS,
            $($optional),*
        ]
    };
}
const COLUMNS: &[&str] = column_list!();
const COLUMNS_CONE: &[&str] = column_list!(columns::CONE_TESTS);
const COLUMNS_COUNT: &[&str] = column_list!(columns::CONE_TESTS, columns::TRIANGLES_IN_VIEW_BLOCKS);
const COLUMNS_TAU: &[&str] = column_list!(columns::TAU_PX);
const COLUMNS_CONE_TAU: &[&str] = column_list!(columns::CONE_TESTS, columns::TAU_PX);
const COLUMNS_COUNT_TAU: &[&str] = column_list!(
    columns::CONE_TESTS,
    columns::TRIANGLES_IN_VIEW_BLOCKS,
    columns::TAU_PX
);
/// The same lists with `triangles_per_strip` last (strips on; filled after `prepare_draw`).
const COLUMNS_STRIPS: &[&str] = column_list!(columns::TRIANGLES_PER_STRIP);
const COLUMNS_CONE_STRIPS: &[&str] =
    column_list!(columns::CONE_TESTS, columns::TRIANGLES_PER_STRIP);
const COLUMNS_COUNT_STRIPS: &[&str] = column_list!(
    columns::CONE_TESTS,
    columns::TRIANGLES_IN_VIEW_BLOCKS,
    columns::TRIANGLES_PER_STRIP
);
const COLUMNS_TAU_STRIPS: &[&str] = column_list!(columns::TAU_PX, columns::TRIANGLES_PER_STRIP);
const COLUMNS_CONE_TAU_STRIPS: &[&str] = column_list!(
    columns::CONE_TESTS,
    columns::TAU_PX,
    columns::TRIANGLES_PER_STRIP
);
const COLUMNS_COUNT_TAU_STRIPS: &[&str] = column_list!(
    columns::CONE_TESTS,
    columns::TRIANGLES_IN_VIEW_BLOCKS,
    columns::TAU_PX,
    columns::TRIANGLES_PER_STRIP
);
/// By view (not followed, followed, counted), τ re-centring, strips.
type ColumnList = &'static [&'static str];
const COLUMN_LISTS: [[[ColumnList; 2]; 2]; 3] = [
    [[COLUMNS, COLUMNS_STRIPS], [COLUMNS_TAU, COLUMNS_TAU_STRIPS]],
    [
        [COLUMNS_CONE, COLUMNS_CONE_STRIPS],
        [COLUMNS_CONE_TAU, COLUMNS_CONE_TAU_STRIPS],
    ],
    [
        [COLUMNS_COUNT, COLUMNS_COUNT_STRIPS],
        [COLUMNS_COUNT_TAU, COLUMNS_COUNT_TAU_STRIPS],
    ],
];

/// Wu's algorithm over one terrain.
pub struct Wu<'h> {
    /// The buffers a GPU draws the mesh from, kept incrementally (`draw.rs`).
    draw: WuBuffers,
    /// The drawn mesh following the vertex set over a few frames (`morph.rs`), when on.
    morph: Option<Morphing>,
    hierarchy: &'h Hierarchy,
    lattice: Lattice,
    nodes: Nodes,
    rule: LifeRule,
    config: WuConfig,
    pixel_angle: f64,
    tau_px: f64,
    /// The τ the run started from (τ re-centring moves `tau_px`).
    initial_tau_px: f64,
    /// With a budget and no τ given: the paper's initial τ, from which the first frame searches
    /// for a τ that meets the budget (`None` once searched, or when τ was given).
    tau_search_from: Option<f64>,
    /// The paper's initial τ, when the run searched from it.
    paper_tau_px: Option<f64>,
    view_settings: ViewSettings,
    speed: SpeedBound,
    mesh: VertexSet,
    n_triangles: u64,
    /// Inactive nodes with both corner parents active (the paper's splittable nodes).
    paper_splittable: u64,
    /// The view cone, the in-view flags and count; only when the run follows the view.
    view: Option<ViewTracking>,
    wheels: Wheels,
    base: i64,
    /// τ re-centring's window (only used with the option).
    recentring: budget::Recentring,
    frame: u64,
    eye: DVec3,
    started: bool,
    previous_count: u64,
    counters: Counters,
    due: Vec<u32>,
    due_marked: Vec<u32>,
    split_work: Vec<(u32, NodeLook, u32)>,
    merge_work: Vec<(u32, NodeLook)>,
}

impl<'h> Wu<'h> {
    pub fn new(
        hierarchy: &'h Hierarchy,
        config: WuConfig,
        view: &ViewSettings,
        speed: SpeedBound,
    ) -> Wu<'h> {
        let errors = NodeErrors::new(hierarchy, config.nesting);
        let tau_px = match (config.tau_px, config.budget) {
            (Some(tau), _) => tau,
            (None, Some(budget)) => initial_tau_px(hierarchy, &errors, view, budget),
            (None, None) => 1.0,
        };
        let lattice = *hierarchy.lattice();
        let nodes = Nodes::new(hierarchy);
        Wu {
            draw: WuBuffers::new(&lattice, hierarchy, config.strips),
            morph: config.morph_frames.map(|n| Morphing::new(&lattice, n)),
            hierarchy,
            lattice,
            nodes,
            rule: LifeRule {
                radius_per_error: radius_per_error(tau_px * view.pixel_angle()),
                zone: config.zone,
                speed,
                errors,
                spheres: SphereShape::new(hierarchy),
            },
            config,
            pixel_angle: view.pixel_angle(),
            tau_px,
            initial_tau_px: tau_px,
            tau_search_from: (config.tau_px.is_none() && config.budget.is_some()).then_some(tau_px),
            paper_tau_px: None,
            view_settings: *view,
            speed,
            mesh: VertexSet::base_mesh(&lattice),
            n_triangles: 2,
            // The root: inactive, its parents (two corners) always active.
            paper_splittable: 1,
            view: config.tracks_view().then(|| {
                ViewTracking::new(
                    nodes.count(),
                    ConeMotion::new(speed),
                    config.keeps_in_view_count(),
                )
            }),
            wheels: Wheels::new(nodes.count(), config.wheel_links.max(2)),
            base: 0,
            recentring: budget::Recentring::default(),
            frame: 0,
            eye: DVec3::ZERO,
            started: false,
            previous_count: 2,
            counters: Counters::default(),
            due: Vec::new(),
            due_marked: Vec::new(),
            split_work: Vec::new(),
            merge_work: Vec::new(),
        }
    }

    /// The threshold in use (given, or from the budget formula until the first frame's search,
    /// or as last re-centred).
    pub fn tau_px(&self) -> f64 {
        self.tau_px
    }

    /// The current base b.
    pub fn base(&self) -> i64 {
        self.base
    }

    fn in_view_refinement(&self) -> bool {
        self.config.refine == Refinement::InView
    }

    /// Makes a vertex active; returns whether it was not. Keeps the paper's splittable count and
    /// (for an edge midpoint) the in-view count; a block centre's in-view bookkeeping is the
    /// caller's (`in_view.rs`).
    fn insert_vertex(&mut self, p: GridPoint) -> bool {
        if !self.mesh.insert(self.lattice.id(p)) {
            return false;
        }
        self.draw.record(p, true);
        match self.lattice.classify(p) {
            VertexClass::Corner => {}
            // A node that activates was splittable (its parents are active).
            VertexClass::Square { .. } => self.paper_splittable -= 1,
            VertexClass::Rotated { half, .. } => {
                // Sub-blocks whose other corner parent was already active become splittable.
                self.paper_splittable += self.children_with_other_parent_active(p, half);
                self.boundary_vertex_changed(p, true);
            }
        }
        true
    }

    /// Makes a vertex inactive; returns whether it was active. The counterpart of
    /// [`Wu::insert_vertex`].
    fn remove_vertex(&mut self, p: GridPoint) -> bool {
        if !self.mesh.contains_point(&self.lattice, p) {
            return false;
        }
        match self.lattice.classify(p) {
            VertexClass::Corner => {}
            VertexClass::Square { .. } => self.paper_splittable += 1,
            VertexClass::Rotated { half, .. } => {
                self.paper_splittable -= self.children_with_other_parent_active(p, half);
                self.boundary_vertex_changed(p, false);
            }
        }
        self.mesh.remove(self.lattice.id(p));
        self.draw.record(p, false);
        true
    }

    /// The children of the edge midpoint `m` (of blocks of half-size `half`) whose other corner
    /// parent is active. A child is the centre of a sub-block with `m` at one corner, m + s·half/2
    /// for a diagonal direction s; its other corner parent is the opposite corner, m + s·half
    /// (inside the grid exactly when the child is).
    fn children_with_other_parent_active(&self, m: GridPoint, half: u32) -> u64 {
        if half < 2 {
            return 0;
        }
        let cells = i64::from(self.lattice.cells());
        let (i, j, h) = (i64::from(m.i), i64::from(m.j), i64::from(half));
        let mut count = 0;
        for (si, sj) in [(-1, -1), (1, -1), (-1, 1), (1, 1)] {
            let (oi, oj) = (i + si * h, j + sj * h);
            if (0..=cells).contains(&oi)
                && (0..=cells).contains(&oj)
                && self
                    .mesh
                    .contains_point(&self.lattice, GridPoint::new(oi as u32, oj as u32))
            {
                count += 1;
            }
        }
        count
    }

    /// Whether every 4-8 parent of `p` is active.
    fn has_active_parents(&self, p: GridPoint) -> bool {
        self.lattice
            .parents(p)
            .as_slice()
            .iter()
            .all(|q| self.mesh.contains_point(&self.lattice, *q))
    }

    fn is_active(&self, node: u32) -> bool {
        let (centre, _) = self.nodes.centre(node);
        self.mesh.contains_point(&self.lattice, centre)
    }

    fn is_splittable(&self, node: u32) -> bool {
        let parent = self.nodes.parent(node);
        !self.is_active(node) && (parent == NO_NODE || self.is_active(parent))
    }

    /// Active, and no vertex depends on it: none of its boundary vertices has an active child.
    /// Those children are the centres of its four sub-blocks and of the two sub-blocks of each
    /// neighbour along the shared edge (none at the finest level).
    fn is_mergeable(&self, node: u32) -> bool {
        let (c, h) = self.nodes.centre(node);
        if !self.mesh.contains_point(&self.lattice, c) {
            return false;
        }
        if h == 1 {
            return true;
        }
        let (near, far) = (h / 2, h + h / 2);
        let cells = self.lattice.cells();
        let active = |i: u32, j: u32| {
            self.mesh
                .contains_point(&self.lattice, GridPoint::new(i, j))
        };
        // Own sub-blocks.
        if active(c.i - near, c.j - near)
            || active(c.i + near, c.j - near)
            || active(c.i - near, c.j + near)
            || active(c.i + near, c.j + near)
        {
            return false;
        }
        // The neighbours' sub-blocks along each edge (when the neighbour exists).
        let (west, east) = (c.i >= 2 * h, c.i + 2 * h <= cells);
        let (south, north) = (c.j >= 2 * h, c.j + 2 * h <= cells);
        !((west && (active(c.i - far, c.j - near) || active(c.i - far, c.j + near)))
            || (east && (active(c.i + far, c.j - near) || active(c.i + far, c.j + near)))
            || (south && (active(c.i - near, c.j - far) || active(c.i + near, c.j - far)))
            || (north && (active(c.i - near, c.j + far) || active(c.i + near, c.j + far))))
    }

    /// A node's life, with its sight when `with_sight` (and the run follows the view).
    fn look(&mut self, node: u32, with_sight: bool) -> NodeLook {
        self.counters.lives += 1;
        match self.view.as_ref().and_then(|view| view.cone.as_ref()) {
            Some(cone) if with_sight => {
                self.counters.cone_tests += 1;
                let (life, sight) =
                    self.rule
                        .life_and_sight(self.hierarchy, &self.nodes, node, cone);
                NodeLook {
                    life,
                    sight: Some(sight),
                }
            }
            _ => NodeLook {
                life: self.rule.life(self.hierarchy, &self.nodes, node, self.eye),
                sight: None,
            },
        }
    }

    /// The look a splittable node needs: its sight only for in-view refinement.
    fn split_look(&mut self, node: u32) -> NodeLook {
        let with_sight = self.in_view_refinement();
        self.look(node, with_sight)
    }

    /// Whether an active node's look needs its sight: for its in-view flag, or for in-view
    /// refinement's merge test.
    fn active_needs_sight(&self) -> bool {
        self.counts_in_view() || self.in_view_refinement()
    }

    /// The look an active node needs.
    fn active_look(&mut self, node: u32) -> NodeLook {
        let with_sight = self.active_needs_sight();
        self.look(node, with_sight)
    }

    /// The link a key of `key` frames goes to, or `None` when it is due now.
    fn link_for(&self, key: f64) -> Option<u32> {
        if key <= 0.0 {
            return None;
        }
        if key == f64::INFINITY {
            return Some(self.wheels.parked_link());
        }
        let n_links = self.wheels.n_links();
        if key >= f64::from(n_links) {
            return Some(self.wheels.overflow_link());
        }
        // ⌈key⌉ for 0 < key < W, without a call to `ceil`.
        let whole = key as u64;
        let delay = whole + u64::from((whole as f64) < key);
        if delay >= u64::from(n_links) {
            return Some(self.wheels.overflow_link());
        }
        Some(((self.frame + delay) % u64::from(n_links)) as u32)
    }

    /// The wheel link due `delay` frames from now (1 ≤ delay < W).
    fn link_after(&self, delay: u64) -> u32 {
        ((self.frame + delay) % u64::from(self.wheels.n_links())) as u32
    }

    /// A splittable node's key: ℓ − b, and with in-view refinement no sooner than it can enter
    /// the view.
    fn split_key(&self, look: &NodeLook) -> f64 {
        let key = look.life - self.base as f64;
        match (&self.view, look.sight) {
            (Some(view), Some(sight)) if self.in_view_refinement() => {
                key.max(sight.frames_until_in_view(&view.motion))
            }
            _ => key,
        }
    }

    /// A mergeable node's key: b + 1 − ℓ, and with the view followed no later than its in-view
    /// flag can change; with in-view refinement 0 when it is out of view.
    fn merge_key(&self, look: &NodeLook) -> f64 {
        let (life_key, view_key) = self.merge_keys(look);
        life_key.min(view_key)
    }

    /// A mergeable node's life key b + 1 − ℓ and its view key (+∞ without a sight).
    fn merge_keys(&self, look: &NodeLook) -> (f64, f64) {
        let key = self.base as f64 + 1.0 - look.life;
        match (&self.view, look.sight) {
            (Some(view), Some(sight)) => {
                let motion = &view.motion;
                let view_key = match (view.counting, self.in_view_refinement()) {
                    // In-view refinement: a node out of view at this frame merges now (the
                    // exact test, whatever the bounds); one in view is looked at again when it
                    // may have left.
                    (_, true) if !sight.in_view() => 0.0,
                    (true, _) | (_, true) => sight.frames_until_view_changes(motion),
                    (false, false) => f64::INFINITY,
                };
                (key, view_key)
            }
            _ => (key, f64::INFINITY),
        }
    }

    /// Queues a splittable node by its look; due now goes to the split work list (or to the next
    /// frame when the depth limit forbids splitting it now).
    fn schedule_split(&mut self, node: u32, look: NodeLook, chain_depth: u32) {
        match self.link_for(self.split_key(&look)) {
            Some(link) => self.wheels.insert(node, Queue::Split, link),
            None => {
                if self
                    .config
                    .depth_limit
                    .is_some_and(|limit| chain_depth > limit)
                {
                    let next = self.link_after(1);
                    self.wheels.insert(node, Queue::Split, next);
                } else {
                    self.split_work.push((node, look, chain_depth));
                }
            }
        }
    }

    /// Queues a mergeable node by its look (whose sight, if any, is already applied); due now goes
    /// to the merge work list. An entry whose view key comes due in the same link (⌈view key⌉ ≤
    /// ⌈life key⌉) is marked: a deferral must bring its in-view flag up to date.
    fn schedule_merge(&mut self, node: u32, look: NodeLook) {
        let (life_key, view_key) = self.merge_keys(&look);
        match self.link_for(life_key.min(view_key)) {
            Some(link) => {
                let marked = view_key <= life_key.ceil();
                self.wheels.insert_marked(node, Queue::Merge, link, marked);
            }
            None => self.merge_work.push((node, look)),
        }
    }

    /// Recomputes the keys of every node in a link and reschedules them.
    fn recompute_link(&mut self, queue: Queue, link: u32) {
        self.recompute_links(queue, link..link + 1);
    }

    /// Empties the links first, then recomputes each taken node's key once and reschedules it
    /// (a node rescheduled into a later link of the range is not seen twice).
    fn recompute_links(&mut self, queue: Queue, links: std::ops::Range<u32>) {
        let mut due = std::mem::take(&mut self.due);
        due.clear();
        for link in links {
            self.wheels.take_link(queue, link, &mut due);
        }
        for &node in &due {
            match queue {
                Queue::Split => {
                    let look = self.split_look(node);
                    self.schedule_split(node, look, 0);
                }
                Queue::Merge => {
                    let look = self.active_look(node);
                    self.apply_sight(node, look.sight);
                    self.schedule_merge(node, look);
                }
                Queue::View => self.refresh_view(node),
            }
        }
        self.due = due;
    }

    /// Moves a due link's nodes to the next frame's link without acting on them. A deferred merge
    /// entry that its view key brought due still has its in-view flag brought up to date; every
    /// deferred merge entry is marked, since its view key may come due at the next frame.
    fn defer_link(&mut self, queue: Queue, link: u32) {
        let mut marked = std::mem::take(&mut self.due_marked);
        marked.clear();
        let next = self.link_after(1);
        let merging = queue == Queue::Merge;
        self.wheels.defer(queue, link, next, merging, &mut marked);
        if merging && self.counts_in_view() {
            for &node in &marked {
                self.refresh_sight(node);
            }
        }
        self.due_marked = marked;
    }

    /// Recomputes every queued key once (first frame, a broken bound, a new τ); the view queue
    /// only when its keys may be stale (`views_too`).
    fn revalidate_all(&mut self, views_too: bool) {
        let all_links = 0..self.wheels.n_links() + 2;
        self.recompute_links(Queue::Split, all_links.clone());
        self.recompute_links(Queue::Merge, all_links.clone());
        if views_too {
            self.recompute_links(Queue::View, all_links);
        }
        if !self.started {
            let root = self.nodes.root();
            if self.is_splittable(root) && !self.wheels.is_in(root, Queue::Split) {
                let look = self.split_look(root);
                self.schedule_split(root, look, 0);
            }
        }
    }

    fn run_split_work(&mut self) {
        while let Some((node, look, chain_depth)) = self.split_work.pop() {
            // A node re-queued since it was listed follows its newer entry.
            if self.is_splittable(node) && !self.wheels.is_in(node, Queue::Split) {
                self.split(node, look, chain_depth);
            }
        }
    }

    fn run_merge_work(&mut self) {
        while let Some((node, look)) = self.merge_work.pop() {
            if self.wheels.slot(node).is_some() {
                continue; // Re-queued since it was listed.
            }
            if self.is_mergeable(node) {
                self.merge(node, look);
            } else if self.counts_in_view() && self.is_active(node) {
                // Something came to depend on it this frame: it waits in the view queue.
                self.refresh_view(node);
            }
        }
    }

    /// Whether the run re-centres τ.
    fn recentres_tau(&self) -> bool {
        self.config
            .budget
            .is_some_and(|budget| budget.tau_recentring.is_some())
    }

    /// τ re-centring: a node split or merged by its life (see `budget.rs`).
    fn record_for_recentring(&mut self, node: u32) {
        if !self.recentres_tau() {
            return;
        }
        let (centre, half) = self.nodes.centre(node);
        let delta = f64::from(self.rule.errors.error(self.hierarchy, centre, half));
        let two_r = 2.0 * delta * self.rule.radius_per_error;
        self.recentring
            .record(two_r, self.base, self.rule.speed.horizontal);
    }

    /// τ re-centring at the end of a frame: at the end of a window, maybe a new τ and b, and
    /// every queued life recomputed with them.
    fn recentre_tau(&mut self, clamped: bool) {
        let Some(budget) = self.config.budget else {
            return;
        };
        let Some(recentring) = budget.tau_recentring else {
            return;
        };
        let Some(handover) = self.recentring.end_frame(recentring.window_frames, clamped) else {
            return;
        };
        let tau_px = self.tau_px * handover.tau_factor;
        if !tau_px.is_finite() {
            return;
        }
        let limit = budget.base_limit.max(0);
        self.tau_px = tau_px;
        self.base = (self.base + handover.base_change).clamp(-limit, limit);
        self.rule.radius_per_error = radius_per_error(tau_px * self.pixel_angle);
        self.revalidate_all(false);
        self.run_split_work();
        self.run_merge_work();
    }
}

/// Most halvings or doublings of τ while bracketing the budget, and bisection steps after.
const TAU_SEARCH_BRACKET_STEPS: u32 = 40;
const TAU_SEARCH_BISECTIONS: u32 = 14;

impl Wu<'_> {
    /// The count the entry's first frame would have at τ = `tau_px`: a probe run of this entry
    /// with that τ, flown to this frame's camera.
    fn first_frame_count(&self, input: &FrameInput, tau_px: f64) -> u64 {
        let config = WuConfig {
            tau_px: Some(tau_px),
            morph_frames: None,
            strips: false,
            ..self.config
        };
        let mut probe = Wu::new(self.hierarchy, config, &self.view_settings, self.speed);
        probe.update(input, &mut FrameStats::default());
        probe.previous_count
    }

    /// The first frame of a budget entry without a given τ: from the paper's initial τ, find the
    /// smallest τ (to a relative 2^-14 of its bracket) whose first frame holds at most the budget
    /// (what the budget counts: the in-view count with `cone_culling`, else the mesh), so that
    /// the run meets its budget from the first frame; base shifting takes over from there. The
    /// search doubles or halves τ until the budget lies between two τs, then bisects. An
    /// unreachable budget ends the search at the last τ tried. Once, at the first frame; each
    /// probe is a from-scratch first frame (reported: `paper_initial_tau_px`, `initial_tau_px`).
    fn search_initial_tau(&mut self, input: &FrameInput, paper_tau: f64) {
        let Some(budget) = self.config.budget else {
            return;
        };
        let fits = |wu: &Self, tau: f64| wu.first_frame_count(input, tau) <= budget.triangles;
        // `low` does not fit (too many triangles), `high` fits.
        let (mut low, mut high) = (paper_tau, paper_tau);
        if fits(self, paper_tau) {
            let mut steps = 0;
            while fits(self, low) {
                high = low;
                low *= 0.5;
                steps += 1;
                if steps > TAU_SEARCH_BRACKET_STEPS {
                    low = high; // Even the finest mesh fits: keep the smallest τ tried.
                    break;
                }
            }
        } else {
            let mut steps = 0;
            while !fits(self, high) {
                low = high;
                high *= 2.0;
                steps += 1;
                if steps > TAU_SEARCH_BRACKET_STEPS {
                    break; // Nothing fits: the coarsest τ tried.
                }
            }
        }
        if low < high {
            for _ in 0..TAU_SEARCH_BISECTIONS {
                let middle = (low * high).sqrt();
                if fits(self, middle) {
                    high = middle;
                } else {
                    low = middle;
                }
            }
        }
        self.paper_tau_px = Some(paper_tau);
        self.tau_px = high;
        self.initial_tau_px = high;
        self.rule.radius_per_error = radius_per_error(high * self.pixel_angle);
    }
}

impl Wu<'_> {
    /// The current 4-8 mesh as refined (what [`LodAlgorithm::mesh`] hands the runner without
    /// morphing; with it, the drawn mesh follows this one over a few frames).
    pub fn vertex_set(&self) -> &VertexSet {
        &self.mesh
    }
}

impl LodAlgorithm for Wu<'_> {
    fn name(&self) -> &'static str {
        NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        let counting = self.counts_in_view();
        let view = match (self.view.is_some(), counting) {
            (false, _) => 0,
            (true, false) => 1,
            (true, true) => 2,
        };
        COLUMN_LISTS[view][usize::from(self.recentres_tau())][usize::from(self.config.strips)]
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        if let Some(paper_tau) = self.tau_search_from.take() {
            self.search_initial_tau(input, paper_tau);
        }
        self.frame = input.frame;
        self.eye = input.camera.eye;
        self.counters = Counters::default();
        if let Some(view) = &mut self.view {
            view.cone = Some(Cone::new(input.camera));
        }
        let n_links = u64::from(self.wheels.n_links());
        let now = (self.frame % n_links) as u32;
        let next = ((self.frame + 1) % n_links) as u32;

        let shift = budget::base_shift(self.config.budget, self.previous_count, self.base);
        self.base = shift.new_base;
        let first_frame = !self.started;
        let revalidated = !self.started || input.broken_bounds.any();
        if revalidated {
            self.revalidate_all(true);
            self.started = true;
        }
        if self.frame.is_multiple_of(n_links) && !revalidated {
            let overflow = self.wheels.overflow_link();
            self.recompute_link(Queue::Split, overflow);
            self.recompute_link(Queue::Merge, overflow);
            self.recompute_link(Queue::View, overflow);
        }
        match shift.direction {
            // More triangles than the budget: more merges, splits deferred.
            // (The later link first: a node from `now` rescheduled one frame ahead is then not
            // recomputed twice.)
            budget::Direction::Down => {
                self.defer_link(Queue::Split, now);
                self.recompute_link(Queue::Merge, next);
                self.recompute_link(Queue::Merge, now);
            }
            // Fewer: more splits, merges deferred.
            budget::Direction::Up => {
                self.recompute_link(Queue::Split, next);
                self.recompute_link(Queue::Split, now);
                self.defer_link(Queue::Merge, now);
            }
            budget::Direction::Stay => {
                self.recompute_link(Queue::Split, now);
                self.recompute_link(Queue::Merge, now);
            }
        }
        self.recompute_link(Queue::View, now);
        self.run_split_work();
        self.run_merge_work();
        self.recentre_tau(shift.clamped);
        self.refresh_base_view();

        self.previous_count = match &self.view {
            Some(view) if view.counting => view.in_view_triangles,
            _ => self.n_triangles,
        };

        if let Some(morph) = &mut self.morph {
            morph.advance(&self.lattice, self.hierarchy, &mut self.draw, first_frame);
        }

        let c = self.counters;
        stats.triangles = self.triangle_count();
        stats.splits = c.splits;
        stats.merges = c.merges;
        stats.vertices_inserted = c.inserted;
        stats.vertices_deleted = c.deleted;
        stats.metric_evaluations = c.lives;
        stats.extra.clear();
        // One allocation for a fresh `stats` (the runner hands one per frame), not a regrowth
        // per column.
        stats.extra.reserve_exact(self.extra_columns().len());
        stats.extra.extend([
            self.base as f64,
            f64::from(u8::from(shift.clamped)),
            self.paper_splittable as f64,
            self.wheels.len(Queue::Split) as f64,
            self.wheels.len(Queue::Merge) as f64,
            c.lives as f64,
            c.forced_splits as f64,
        ]);
        if let Some(view) = &self.view {
            stats.extra.push(c.cone_tests as f64);
            if view.counting {
                stats.extra.push(view.in_view_triangles as f64);
            }
        }
        if self.recentres_tau() {
            stats.extra.push(self.tau_px);
        }
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.draw.prepare(&self.lattice, self.hierarchy)
    }

    fn draw_columns(&self, extra: &mut Vec<f64>) {
        if let Some(counts) = self.draw.strip_counts() {
            extra.push(counts.triangles_per_strip());
        }
    }

    fn check_own(&self) -> Result<(), String> {
        self.draw.check_strips(&self.lattice)
    }

    fn buffers(&self) -> &GpuBuffers {
        self.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        match &self.morph {
            Some(morph) => morph.mesh(),
            None => MeshOutput::lattice(&self.mesh),
        }
    }

    fn triangle_count(&self) -> u64 {
        self.morph
            .as_ref()
            .map_or(self.n_triangles, Morphing::triangle_count)
    }

    fn memory_bytes(&self) -> usize {
        self.rule.errors.memory_bytes()
            + self.mesh.memory_bytes()
            + self.wheels.memory_bytes()
            + self.view.as_ref().map_or(0, ViewTracking::memory_bytes)
            + self.draw.memory_bytes()
            + self.morph.as_ref().map_or(0, Morphing::memory_bytes)
            + self.due.capacity() * std::mem::size_of::<u32>()
            + self.due_marked.capacity() * std::mem::size_of::<u32>()
            + self.split_work.capacity() * std::mem::size_of::<(u32, NodeLook, u32)>()
            + self.merge_work.capacity() * std::mem::size_of::<(u32, NodeLook)>()
    }

    fn run_facts(&self) -> Vec<(&'static str, f64)> {
        let mut facts = vec![
            ("tau_px", self.tau_px),
            ("wheel_links", f64::from(self.wheels.n_links())),
        ];
        if self.recentres_tau() || self.paper_tau_px.is_some() {
            facts.push(("initial_tau_px", self.initial_tau_px));
        }
        if let Some(paper_tau) = self.paper_tau_px {
            facts.push(("paper_initial_tau_px", paper_tau));
        }
        facts
    }
}

impl Wu<'_> {
    /// Checks the queues, the statistics and the in-view count against a recomputation (see
    /// `validate.rs`); `check_lives` also checks that every queued node sits in a link that comes
    /// due no later than its key allows (only meaningful at a fixed base, without block priority
    /// and without a depth limit, which both delay nodes on purpose).
    pub fn validate_queues(&self, check_lives: bool) -> Result<(), String> {
        validate::validate(self, check_lives)
    }

    /// The number of triangles of active blocks in view, as kept incrementally (`None` when the
    /// run does not follow the view).
    pub fn in_view_triangles(&self) -> Option<u64> {
        self.view
            .as_ref()
            .filter(|view| view.counting)
            .map(|view| view.in_view_triangles)
    }
}
