//! `wu`: Wu, Liu, Zhan and Gao's view-dependent terrain algorithm (Graphics Interface 2001).
//!
//! **Nodes** are the quadtree blocks, represented by their centre vertices (the square diamonds of
//! the 4-8 hierarchy). Wu's node hierarchy is the quadtree: a node is **splittable** when it is
//! inactive and its quadtree parent is active (the root: when inactive), and **mergeable** when it
//! is active and no vertex depends on it, i.e. none of its boundary vertices (edge midpoints) has
//! an active child — neither one of its own sub-blocks nor a sub-block of the neighbour across
//! that edge. Boundary vertices are free, as in the reference: one is active exactly when all its
//! parents are. Splitting a node first activates what closure needs (its 4-8 parents, which forces
//! the neighbouring blocks up the hierarchy: the forced splits); merging deletes the node and its
//! boundary vertices. The mesh is always a valid 4-8 mesh.
//!
//! **Valid lives.** A node's signed life ℓ (see `zone.rs`) is how many frames the eye needs, at
//! the speed bounds, to reach its split zone. A splittable node splits when ℓ ≤ b; a mergeable node
//! merges when ℓ ≥ b + 1. Split key = ℓ − b, merge key = b + 1 − ℓ: a node is looked at again
//! only when its key runs out, i.e. after ⌈key⌉ frames, which is safe because ℓ changes by at most
//! one per frame while the speed bounds hold. Keys ≤ 0 are acted on in the same frame (a node's
//! split can make its children due at once: the top-down traversal). The queues are timing wheels
//! (`wheel.rs`). On a frame that broke the speed bounds every queued life is recomputed.
//!
//! **Constant budget** (`budget.rs`): with a triangle budget n, b moves by one per frame towards
//! the budget (the paper's MobilizeQueues): n_prev > n lowers b, recomputes the two top links of
//! the merge queue and defers the due splits by a frame; n_prev < n raises b, recomputes the two
//! top links of the split queue and defers the due merges; otherwise the top link of each queue
//! is processed. An optional dead band restores the paper's third branch; b is clamped and the
//! clamp reported. Without a budget, b stays 0 (fixed τ).
//!
//! **Traversal options.** Block-priority traversal tests a split node's children by decreasing
//! error and stops at the first that does not split; the untested rest take its key (the paper's
//! premise that siblings' errors go the same way), or wait one frame when that key is infinite.
//! A heuristic: a sibling may need splitting before that key runs out. A depth limit caps the
//! chain of splits one frame makes below a node split from the queues. Splits and merges that
//! come due through a revalidation or an overflow wrap are acted on even in a frame whose base
//! shift defers the other kind (only the due wheel link is deferred).
//!
//! **Cone culling** (`cull.rs`), when asked for, counts the triangles inside a cone around the
//! view frustum; the budget then counts those. The count is top-down over the quadtree blocks with
//! per-block triangle counts kept on every vertex change (`cone_count.rs`), not O(triangles).
//!
//! Per frame: O(nodes whose key ran out + operations · their neighbourhood). Memory: a 4-byte
//! queue handle per node (1.33 bytes per sample) and a 16-byte link entry per queued node (the
//! frontier, O(mesh size)), one bit per vertex for the mesh, and with cone culling 4 bytes per
//! block above the finest level (a third of a byte per sample); with the shared hierarchy
//! (heights and the node data above the finest level, 5 bytes per sample) about 7 bytes per
//! sample in all (ARCHITECTURE.md, Memory).

mod budget;
mod cone_count;
mod cull;
mod merge;
mod nodes;
mod split;
mod validate;
mod wheel;

pub use budget::initial_tau_px;

use super::columns::wu as columns;
use super::{FrameInput, LodAlgorithm};
use crate::sim::hierarchy::{GridPoint, Hierarchy, Lattice, NestingRule};
use crate::sim::mesh::MeshOutput;
use crate::sim::mesh::VertexSet;
use crate::sim::stats::FrameStats;
use crate::sim::view::ViewSettings;
use crate::sim::zone::{NodeErrors, SpeedBound, ZoneVariant, radius_per_error};
use cone_count::BlockTriangleCounts;
use glam::DVec3;
use nodes::{LifeRule, NO_NODE, Nodes};
use wheel::{Queue, Wheels};

pub(super) const NAME: &str = "wu";

/// Parameters of Wu's algorithm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WuConfig {
    /// τ in pixels; `None` in budget mode means the paper's initial τ from the budget.
    pub tau_px: Option<f64>,
    /// A triangle budget (constant frame rate by base shifting), or `None` for fixed τ (b = 0).
    pub budget: Option<BudgetConfig>,
    pub zone: ZoneVariant,
    pub block_priority: bool,
    /// Most levels one frame may split below a node taken from the queues; `None`: no limit.
    pub depth_limit: Option<u32>,
    pub cone_culling: bool,
    /// Wheel links per queue (≥ 2).
    pub wheel_links: u32,
    /// How δ nests: Wu's [`NestingRule::Max`], or [`NestingRule::MaxPlusOwn`] (a true bound, to
    /// measure what it costs; 4 more bytes per sample).
    pub nesting: NestingRule,
}

/// The constant-budget settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BudgetConfig {
    /// Rendered triangles per frame to aim at.
    pub triangles: u64,
    /// |n_prev − n| ≤ dead band leaves b alone.
    pub dead_band: u64,
    /// b stays within [−base_limit, base_limit].
    pub base_limit: i64,
    /// The coefficient k of the paper's initial-τ formula (1.5 in the paper).
    pub initial_tau_k: f64,
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
}

const COLUMNS: &[&str] = &[
    columns::BASE_B,
    columns::BASE_CLAMPED,
    columns::SPLITTABLE,
    columns::MERGEABLE,
    columns::LIFE_RECOMPUTATIONS,
    columns::FORCED_SPLITS,
];
const COLUMNS_WITH_CONE: &[&str] = &[
    columns::BASE_B,
    columns::BASE_CLAMPED,
    columns::SPLITTABLE,
    columns::MERGEABLE,
    columns::LIFE_RECOMPUTATIONS,
    columns::FORCED_SPLITS,
    columns::CONE_RENDERED,
];

/// Wu's algorithm over one terrain.
pub struct Wu<'h> {
    hierarchy: &'h Hierarchy,
    lattice: Lattice,
    nodes: Nodes,
    rule: LifeRule,
    config: WuConfig,
    tau_px: f64,
    mesh: VertexSet,
    n_triangles: u64,
    /// Per-block triangle counts for the o(T) cone count; only with cone culling.
    block_counts: Option<BlockTriangleCounts>,
    wheels: Wheels,
    base: i64,
    frame: u64,
    eye: DVec3,
    started: bool,
    previous_count: u64,
    counters: Counters,
    due: Vec<u32>,
    split_work: Vec<(u32, f64, u32)>,
    merge_work: Vec<(u32, f64)>,
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
        let mesh = VertexSet::base_mesh(&lattice);
        let block_counts = config
            .cone_culling
            .then(|| BlockTriangleCounts::new(&lattice, &mesh));
        Wu {
            hierarchy,
            lattice,
            nodes,
            rule: LifeRule {
                radius_per_error: radius_per_error(tau_px * view.pixel_angle()),
                zone: config.zone,
                speed,
                errors,
            },
            config,
            tau_px,
            mesh,
            n_triangles: 2,
            block_counts,
            wheels: Wheels::new(nodes.count(), config.wheel_links.max(2)),
            base: 0,
            frame: 0,
            eye: DVec3::ZERO,
            started: false,
            previous_count: 2,
            counters: Counters::default(),
            due: Vec::new(),
            split_work: Vec::new(),
            merge_work: Vec::new(),
        }
    }

    /// The threshold in use (given, or from the budget formula).
    pub fn tau_px(&self) -> f64 {
        self.tau_px
    }

    /// The current base b.
    pub fn base(&self) -> i64 {
        self.base
    }

    /// Makes a vertex active; returns whether it was not.
    fn insert_vertex(&mut self, p: GridPoint) -> bool {
        let inserted = self.mesh.insert(self.lattice.id(p));
        if inserted && let Some(counts) = &mut self.block_counts {
            counts.vertex_inserted(p);
        }
        inserted
    }

    /// Makes a vertex inactive; returns whether it was active.
    fn remove_vertex(&mut self, p: GridPoint) -> bool {
        let removed = self.mesh.remove(self.lattice.id(p));
        if removed && let Some(counts) = &mut self.block_counts {
            counts.vertex_removed(p);
        }
        removed
    }

    fn is_active(&self, node: u32) -> bool {
        let (centre, _) = self.nodes.centre(node);
        self.mesh.contains_point(&self.lattice, centre)
    }

    fn is_splittable(&self, node: u32) -> bool {
        let parent = self.nodes.parent(node);
        !self.is_active(node) && (parent == NO_NODE || self.is_active(parent))
    }

    fn is_mergeable(&self, node: u32) -> bool {
        if !self.is_active(node) {
            return false;
        }
        let (centre, half) = self.nodes.centre(node);
        self.lattice
            .boundary_vertices(centre, half)
            .iter()
            .all(|m| {
                self.lattice
                    .children(*m)
                    .as_slice()
                    .iter()
                    .all(|c| !self.mesh.contains_point(&self.lattice, *c))
            })
    }

    fn life(&mut self, node: u32) -> f64 {
        self.counters.lives += 1;
        self.rule.life(self.hierarchy, &self.nodes, node, self.eye)
    }

    /// The link a key of `key` frames goes to, or `None` when it is due now.
    fn link_for(&self, key: f64) -> Option<u32> {
        if key <= 0.0 {
            return None;
        }
        if key == f64::INFINITY {
            return Some(self.wheels.parked_link());
        }
        let delay = key.ceil();
        let n_links = self.wheels.n_links();
        if delay >= f64::from(n_links) {
            return Some(self.wheels.overflow_link());
        }
        Some(((self.frame + delay as u64) % u64::from(n_links)) as u32)
    }

    /// The wheel link due `delay` frames from now (1 ≤ delay < W).
    fn link_after(&self, delay: u64) -> u32 {
        ((self.frame + delay) % u64::from(self.wheels.n_links())) as u32
    }

    /// Queues a splittable node by its life; due now goes to the split work list (or to the next
    /// frame when the depth limit forbids splitting it now).
    fn schedule_split(&mut self, node: u32, life: f64, chain_depth: u32) {
        match self.link_for(life - self.base as f64) {
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
                    self.split_work.push((node, life, chain_depth));
                }
            }
        }
    }

    /// Queues a mergeable node by its life; due now goes to the merge work list.
    fn schedule_merge(&mut self, node: u32, life: f64) {
        match self.link_for(self.base as f64 + 1.0 - life) {
            Some(link) => self.wheels.insert(node, Queue::Merge, link),
            None => self.merge_work.push((node, life)),
        }
    }

    /// Recomputes the lives of every node in a link and reschedules them.
    fn recompute_link(&mut self, queue: Queue, link: u32) {
        self.recompute_links(queue, link..link + 1);
    }

    /// Empties the links first, then recomputes each taken node's life once and reschedules it
    /// (a node rescheduled into a later link of the range is not seen twice).
    fn recompute_links(&mut self, queue: Queue, links: std::ops::Range<u32>) {
        let mut due = std::mem::take(&mut self.due);
        due.clear();
        for link in links {
            self.wheels.take_link(queue, link, &mut due);
        }
        for &node in &due {
            let life = self.life(node);
            match queue {
                Queue::Split => self.schedule_split(node, life, 0),
                Queue::Merge => self.schedule_merge(node, life),
            }
        }
        self.due = due;
    }

    /// Moves a due link's nodes to the next frame's link without looking at them.
    fn defer_link(&mut self, queue: Queue, link: u32) {
        let mut due = std::mem::take(&mut self.due);
        due.clear();
        self.wheels.take_link(queue, link, &mut due);
        let next = self.link_after(1);
        for &node in &due {
            self.wheels.insert(node, queue, next);
        }
        self.due = due;
    }

    /// Recomputes every queued life once (first frame, or the speed bounds were broken).
    fn revalidate_all(&mut self) {
        let all_links = 0..self.wheels.n_links() + 2;
        self.recompute_links(Queue::Split, all_links.clone());
        self.recompute_links(Queue::Merge, all_links);
        if !self.started {
            let root = self.nodes.root();
            if self.is_splittable(root) && !self.wheels.is_in(root, Queue::Split) {
                let life = self.life(root);
                self.schedule_split(root, life, 0);
            }
        }
    }

    fn run_split_work(&mut self) {
        while let Some((node, life, chain_depth)) = self.split_work.pop() {
            // A node re-queued since it was listed follows its newer entry.
            if self.is_splittable(node) && !self.wheels.is_in(node, Queue::Split) {
                self.split(node, life, chain_depth);
            }
        }
    }

    fn run_merge_work(&mut self) {
        while let Some((node, life)) = self.merge_work.pop() {
            if self.is_mergeable(node) && !self.wheels.is_in(node, Queue::Merge) {
                self.merge(node, life);
            }
        }
    }
}

impl Wu<'_> {
    /// The current 4-8 mesh (what [`LodAlgorithm::mesh`] hands the runner).
    pub fn vertex_set(&self) -> &VertexSet {
        &self.mesh
    }
}

impl LodAlgorithm for Wu<'_> {
    fn name(&self) -> &'static str {
        NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        if self.config.cone_culling {
            COLUMNS_WITH_CONE
        } else {
            COLUMNS
        }
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        self.frame = input.frame;
        self.eye = input.camera.eye;
        self.counters = Counters::default();
        let n_links = u64::from(self.wheels.n_links());
        let now = (self.frame % n_links) as u32;
        let next = ((self.frame + 1) % n_links) as u32;

        let shift = budget::base_shift(self.config.budget, self.previous_count, self.base);
        self.base = shift.new_base;
        let revalidated = !self.started || input.speed_bound_broken;
        if revalidated {
            self.revalidate_all();
            self.started = true;
        }
        if self.frame.is_multiple_of(n_links) && !revalidated {
            self.recompute_link(Queue::Split, self.wheels.overflow_link());
            self.recompute_link(Queue::Merge, self.wheels.overflow_link());
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
        self.run_split_work();
        self.run_merge_work();

        let cone_rendered = self.block_counts.as_ref().map(|counts| {
            cone_count::cone_rendered_triangles_hierarchical(
                self.hierarchy,
                &self.mesh,
                counts,
                input.camera,
            )
        });
        self.previous_count = cone_rendered.unwrap_or(self.n_triangles);

        let c = self.counters;
        stats.triangles = self.n_triangles;
        stats.splits = c.splits;
        stats.merges = c.merges;
        stats.vertices_inserted = c.inserted;
        stats.vertices_deleted = c.deleted;
        stats.metric_evaluations = c.lives;
        stats.extra.clear();
        stats.extra.extend([
            self.base as f64,
            f64::from(u8::from(shift.clamped)),
            self.wheels.len(Queue::Split) as f64,
            self.wheels.len(Queue::Merge) as f64,
            c.lives as f64,
            c.forced_splits as f64,
        ]);
        if let Some(rendered) = cone_rendered {
            stats.extra.push(rendered as f64);
        }
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::lattice(&self.mesh)
    }

    fn triangle_count(&self) -> u64 {
        self.n_triangles
    }

    fn memory_bytes(&self) -> usize {
        self.rule.errors.memory_bytes()
            + self.mesh.memory_bytes()
            + self.wheels.memory_bytes()
            + self
                .block_counts
                .as_ref()
                .map_or(0, BlockTriangleCounts::memory_bytes)
            + self.due.capacity() * std::mem::size_of::<u32>()
            + self.split_work.capacity() * std::mem::size_of::<(u32, f64, u32)>()
            + self.merge_work.capacity() * std::mem::size_of::<(u32, f64)>()
    }

    fn run_facts(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("tau_px", self.tau_px),
            ("wheel_links", f64::from(self.wheels.n_links())),
        ]
    }
}

impl Wu<'_> {
    /// Checks the queues against the mesh (see `validate.rs`); `check_lives` also checks that
    /// every queued node sits in a link that comes due no later than its key allows (only
    /// meaningful at a fixed base, without block priority and without a depth limit, which both
    /// delay nodes on purpose).
    pub fn validate_queues(&self, check_lives: bool) -> Result<(), String> {
        validate::validate(self, check_lives)
    }
}
