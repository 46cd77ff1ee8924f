//! `vanek`: the distance-driven patches of Vaněk and Ježek (WSCG 2004, §3 "Large height-map",
//! drawn with §2's strip): the terrain cut into overlapping patches of (2^n + 1)² samples, each
//! drawn every frame at the level of detail its distance gives, as one triangle strip with
//! degenerate triangles; cracks removed by moving the finer patch's border vertices onto the
//! coarser neighbour's. Distance alone chooses a patch's level: no roughness enters it.
//!
//! # The algorithm
//!
//! - **Patches** (§3): patch (px, py) covers 2^n cells a side from sample (px·2^n, py·2^n);
//!   level k (0 ..= n) keeps every 2^(n−k)-th sample, (2^k + 1)² vertices (k = n: every sample,
//!   k = 0: the four corners). The terrain's own grid is 2^N + 1 samples a side, so the patches
//!   form a 2^(N−n) square; n is clamped to [1, N].
//! - **Selection** (§3, `select.rs`): k = n nearer than `mindist`, 0 beyond `maxdist`, else
//!   n·(1 − ((dist − mindist)/(maxdist − mindist))^exp), rounded. The audit shows what
//!   distance-only selection costs on rough terrain (`docs/reproductions/vanek.md`).
//! - **Drawing** (§2, `strip.rs`): each patch's vertex buffer is its level's (2^k + 1)²
//!   vertices, row by row; its index buffer is the paper's single strip with degenerate
//!   triangles, the same for every patch of a level. Every three consecutive indices are a
//!   triangle (every other one reversed, as a GPU reads a strip); those with a repeated index
//!   are the strip's joins (role degenerate).
//! - **Cracks** (§3, crack policy `collapsed`, `mesh.rs`): where a side's neighbour is at a coarser
//!   level k′ < k, the side's vertices that the neighbour lacks are moved (in the vertex buffer,
//!   the index buffer unchanged) onto one the neighbour has; the triangles this flattens are
//!   degenerate too, and the rest of the patch meets the neighbour edge for edge.
//! - **GPU side** (issue #31, §2–3, `buffers.rs`): the paper keeps "one index buffer for all
//!   patches of the same level" (the strip, built once per level on first use) and per patch a
//!   vertex buffer holding its level's vertices, border ones already moved onto the coarser
//!   neighbour's, so a patch's vertex buffer is rewritten only when its level or a neighbour's
//!   collapsing level changes (its shape: k and the four side levels, a culled neighbour's side at
//!   k), never otherwise; a culled patch keeps its buffer. One strip draw per drawn patch. The
//!   index buffer starts with its first index repeated, which makes a GPU read the paper's strip
//!   with the parity roamsim draws it with (counter-clockwise; see Winding below): one more
//!   degenerate triangle per draw, counted in `triangles_submitted`, not in the mesh.
//! - **Box culling** (§3), an effect (`box_culling`): a patch whose box (square × its samples'
//!   height range) lies entirely outside the view volume is not drawn and is declared to the
//!   mesh as a culled region. The paper projects each patch's box to the screen and tests it
//!   against the viewport; roamsim tests it against the frustum's planes (`block_lod/cull.rs`)
//!   and, as issue #31 asks ("patches culled hierarchically"; the paper is silent on how it
//!   finds the patches to test), through the quadtree over the patches that geomipmapping uses
//!   (`block_lod/quadtree.rs`, de Boer's): a node outside the view is left with every patch
//!   below it, and culls exactly the patches the per-patch test would. Distances and levels are
//!   then chosen for the patches not culled only, so a frame costs O(patches in view + nodes
//!   visited), whatever the terrain's size: a culled patch is given no level. A culled
//!   neighbour is no neighbour: a drawn patch's side beside it is not collapsed (nothing is
//!   drawn there to meet). Where every patch is in view the mesh is therefore the one drawn
//!   without culling, triangle for triangle; where culling drops a coarser neighbour, the drawn
//!   patch keeps that side's vertices (its triangle count, and so the target's μ, unchanged),
//!   on a border at or beyond the edge of the view.
//! - **Triangle target** (`target_triangles`, roamsim's: the paper's user sets `mindist`,
//!   `maxdist` and `exp` by hand): every frame, the distances are multiplied by a factor μ (the
//!   same as dividing `mindist` and `maxdist` by μ; `exp` kept), μ the smallest on the grid of
//!   `block_lod/budget.rs` whose mesh has at most the target's triangles: the finest mesh the
//!   target allows. The count never rises as μ grows, so that μ is found whatever the search
//!   starts from. The count is every triangle drawn, joins and collapsed ones included (what
//!   the GPU is sent), over the patches not culled.
//!
//! # Decisions where the paper is open
//!
//! - **dist** is measured from the eye to the patch's box, 0 inside it
//!   ([`PatchDistance::Box`]): the nearest point of the patch decides, so a patch the eye stands
//!   on is at k = n. The paper says only "the patch distance from the camera position" (§3).
//!   The alternative, to the box's centre, is [`PatchDistance::Centre`].
//! - **k is rounded down** ([`LodRounding::Down`]), roamsim's choice: the paper gives k as a
//!   real expression and does not say how it becomes a level. Rounding down, as a C integer
//!   conversion would, keeps k = n exactly where dist ≤ mindist, as the formula's first case
//!   says. [`LodRounding::Nearest`] and [`LodRounding::Up`] are the alternatives.
//! - **Which vertex a collapsed one moves to**: on the south and west sides the neighbour's
//!   vertex at or before it (towards the south-west corner), on the north and east sides the
//!   one at or after it (towards the north-east corner). Moving along the side in order keeps
//!   the triangles from folding; the directions matter at the two corners the strip's
//!   north-west–south-east diagonals do not reach (south-west, north-east): there the corner
//!   cell has a triangle with a vertex on each side, and moving both towards the corner
//!   flattens it, where moving them away would leave a T-junction on its diagonal (tested on
//!   every combination of neighbouring levels, `tests/vanek.rs`).
//! - **Winding**: the paper's strip, read as a GPU reads a strip, is clockwise seen from above
//!   in roamsim's frame (rows run north); roamsim keeps its indices and reads it with the
//!   opposite parity, so every triangle with area is counter-clockwise like every other
//!   algorithm's (`strip.rs`, `sim::mesh::winding`). Which triangles are drawn and their count
//!   are the paper's.
//! - **The strip's last two indices** (after the last row) are kept, as the paper's code emits
//!   them: a patch at level k draws (2·(2^k + 1) + 2)·2^k − 2 triangles, 2·4^k of them surface
//!   (less the collapsed ones).
//! - **Counters.** `splits` / `merges`: patches at a higher / lower k than last frame;
//!   `vertices_inserted` / `vertices_deleted`: the vertex buffers of patches whose level,
//!   collapsed sides or culling changed (all of the new and of the old);
//!   `metric_evaluations`: level computations (one per patch not culled), over every pass of
//!   the frame. Columns: `strip_indices` (indices sent, drawn patches),
//!   `degenerate_triangles` (joins and collapsed), `collapsed_triangles`, `patches_culled`,
//!   `patch_lod_mean` (the paper's k, n = full resolution, over the drawn patches),
//!   `distance_multiplier` (μ), `target_unreachable`; with `box_culling` also
//!   `quadtree_nodes_visited`. One draw batch per drawn patch.
//!
//! Memory: per patch its height range, its vertex buffer once drawn, and a few words of frame
//! state; the quadtree (a third more height ranges), the triangle list, one index buffer per
//! level. Per frame: O(patches in view + quadtree nodes visited + drawn indices) with culling,
//! O(patches + drawn indices) without.

mod buffers;
mod mesh;
mod select;
pub mod strip;
mod validate;

pub use select::{LodCurve, LodRounding, PatchDistance, patch_distance};
pub use validate::{VanekError, lods_from_scratch};

use super::block_lod::budget::finest_tau_within;
use super::block_lod::quadtree::PatchQuadtree;
use super::block_lod::threshold::BlockBox;
use super::columns::vanek as columns;
use super::{FrameInput, LodAlgorithm};
use crate::sim::draw::{BufferId, DrawCounts, GpuBuffers};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::{CrackPolicy, MeshOutput, TriangleList, TriangleRole};
use crate::sim::stats::FrameStats;
use crate::sim::view::Camera;
use glam::DVec3;

pub(super) const NAME: &str = "vanek";

/// The extra columns; with box culling, also the last one, the quadtree nodes visited.
const CULLING_COLUMNS: &[&str] = &[
    columns::STRIP_INDICES,
    columns::DEGENERATE_TRIANGLES,
    columns::COLLAPSED_TRIANGLES,
    columns::PATCHES_CULLED,
    columns::PATCH_LOD_MEAN,
    columns::DISTANCE_MULTIPLIER,
    columns::TARGET_UNREACHABLE,
    columns::QUADTREE_NODES_VISITED,
];
const EXTRA_COLUMNS: &[&str] = CULLING_COLUMNS.split_at(CULLING_COLUMNS.len() - 1).0;

// Sides of a patch, in the order of the per-side arrays.
const WEST: usize = 0;
const EAST: usize = 1;
const SOUTH: usize = 2;
const NORTH: usize = 3;

/// Parameters of the Vaněk–Ježek patches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VanekConfig {
    /// n: patches of (2^n + 1)² samples (1..=15; clamped to the terrain's level).
    pub patch_level: u32,
    /// mindist, maxdist, exp and the rounding of k.
    pub curve: LodCurve,
    pub distance: PatchDistance,
    /// Holds this many triangles every frame by scaling the distances (see the module docs).
    pub target_triangles: Option<u64>,
    /// Patch-box culling (an effect).
    pub box_culling: bool,
}

/// What a drawn patch drew: its level and the level each side is collapsed to.
type Shape = [u32; 5];

/// The Vaněk–Ježek patches. Per frame: O(patches in view + quadtree nodes visited + drawn
/// indices) with box culling, O(patches + drawn indices) without; buffers reused.
pub struct Vanek<'h> {
    /// The buffers a GPU draws this frame's mesh from (see the module docs, "GPU side").
    gpu: GpuBuffers,
    /// Per level k, the paper's strip as one shared index buffer and its index count.
    level_strips: Vec<Option<(BufferId, u32)>>,
    /// Per patch, its vertex buffer and the shape (level, side levels) it holds.
    patch_vertices: Vec<Option<(BufferId, [u32; 5])>>,
    /// This frame's drawn patches: patch, first vertex in the list, shape.
    drawn: Vec<(usize, u32, [u32; 5])>,
    /// Vertex buffers written this frame (made or rewritten).
    patches_rewritten: u64,
    hierarchy: &'h Hierarchy,
    config: VanekConfig,
    /// n, clamped.
    patch_level: u32,
    per_side: u32,
    /// Per patch: lowest and highest sample.
    z_range: Vec<(f32, f32)>,
    /// The quadtree over the patches that culls them (`block_lod/quadtree.rs`).
    quadtree: PatchQuadtree,
    /// This frame's patches not culled (ascending), and the squares of the quadtree nodes
    /// culled (reused).
    visible: Vec<u32>,
    culled_squares: Vec<((u32, u32), u32)>,
    nodes_visited: u64,
    /// This frame's number (from 1), and per patch the number of the last frame that drew it.
    frame: u32,
    drawn_in: Vec<u32>,
    /// Per patch; only the entries of this frame's drawn patches are this frame's.
    lods: Vec<u32>,
    distances: Vec<f64>,
    multiplier: f64,
    target_unreachable: bool,
    list: TriangleList,
    /// One patch's strip and its vertices' (column, row) after collapsing.
    strip: Vec<u32>,
    moved: Vec<(u32, u32)>,
    strip_indices: u64,
    collapsed: u64,
    /// Per patch, the frame it was last drawn in and the shape it drew.
    states: Vec<Option<(u32, Shape)>>,
    /// Last frame's drawn patches, ascending.
    previous_drawn: Vec<u32>,
}

impl<'h> Vanek<'h> {
    /// Cuts the terrain into patches and measures their height ranges (O(samples)).
    pub fn new(hierarchy: &'h Hierarchy, config: VanekConfig) -> Vanek<'h> {
        let curve = config.curve;
        assert!(
            curve.min_dist_m >= 0.0
                && curve.min_dist_m < curve.max_dist_m
                && curve.max_dist_m.is_finite()
                && curve.exponent > 0.0
                && curve.exponent.is_finite(),
            "vanek needs 0 ≤ mindist < maxdist < ∞ and 0 < exp < ∞, not {curve:?}"
        );
        let terrain_level = hierarchy.lattice().level();
        let patch_level = config.patch_level.clamp(1, terrain_level);
        let per_side = 1u32 << (terrain_level - patch_level);
        let cells = 1u32 << patch_level;
        let mut z_range = Vec::with_capacity((per_side * per_side) as usize);
        for py in 0..per_side {
            for px in 0..per_side {
                let (x0, y0) = (px * cells, py * cells);
                let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
                for j in y0..=y0 + cells {
                    for i in x0..=x0 + cells {
                        let z = hierarchy.height(GridPoint::new(i, j));
                        low = low.min(z);
                        high = high.max(z);
                    }
                }
                z_range.push((low, high));
            }
        }
        let n = z_range.len();
        let quadtree = PatchQuadtree::new(per_side, cells, hierarchy.field().spacing(), |patch| {
            z_range[patch]
        });
        Vanek {
            gpu: GpuBuffers::new(),
            level_strips: vec![None; patch_level as usize + 1],
            patch_vertices: vec![None; n],
            drawn: Vec::new(),
            patches_rewritten: 0,
            hierarchy,
            config,
            patch_level,
            per_side,
            z_range,
            quadtree,
            visible: Vec::new(),
            culled_squares: Vec::new(),
            nodes_visited: 0,
            frame: 0,
            drawn_in: vec![0; n],
            lods: vec![patch_level; n],
            distances: vec![0.0; n],
            multiplier: 1.0,
            target_unreachable: false,
            list: TriangleList::new(hierarchy.lattice(), CrackPolicy::Collapsed),
            strip: Vec::new(),
            moved: Vec::new(),
            strip_indices: 0,
            collapsed: 0,
            states: vec![None; n],
            previous_drawn: Vec::new(),
        }
    }

    /// The effective n (patches of (2^n + 1)² samples).
    pub fn patch_level(&self) -> u32 {
        self.patch_level
    }

    /// Patches per side.
    pub fn patches_per_side(&self) -> u32 {
        self.per_side
    }

    /// This frame's level of every patch, row by row from the south-west (the paper's k:
    /// n = full resolution, 0 = the corners only); `None` for a patch culled, whose level is
    /// not chosen. O(patches): for tests and audits, not for the frame.
    pub fn lods(&self) -> Vec<Option<u32>> {
        (0..self.lods.len())
            .map(|patch| self.is_drawn(patch).then_some(self.lods[patch]))
            .collect()
    }

    /// This frame's drawn patches (row by row from the south-west), ascending.
    pub fn drawn_patches(&self) -> &[u32] {
        &self.visible
    }

    /// Whether `patch` is drawn this frame.
    fn is_drawn(&self, patch: usize) -> bool {
        self.frame > 0 && self.drawn_in[patch] == self.frame
    }

    /// The distance multiplier μ this frame was drawn with (1 without a target).
    pub fn distance_multiplier(&self) -> f64 {
        self.multiplier
    }

    fn cells(&self) -> u32 {
        1 << self.patch_level
    }

    /// Patch `patch`'s box in terrain-local metres.
    fn patch_box(&self, patch: usize) -> BlockBox {
        let spacing = self.hierarchy.field().spacing();
        let (x0, y0) = self.origin(patch);
        let cells = f64::from(self.cells());
        let (low, high) = self.z_range[patch];
        BlockBox {
            low: DVec3::new(
                f64::from(x0) * spacing.dx,
                f64::from(y0) * spacing.dy,
                f64::from(low),
            ),
            high: DVec3::new(
                (f64::from(x0) + cells) * spacing.dx,
                (f64::from(y0) + cells) * spacing.dy,
                f64::from(high),
            ),
        }
    }

    /// The grid sample at the patch's south-west corner.
    fn origin(&self, patch: usize) -> (u32, u32) {
        let (px, py) = (patch as u32 % self.per_side, patch as u32 / self.per_side);
        (px * self.cells(), py * self.cells())
    }

    /// The neighbour of `patch` across `side`, if any.
    fn neighbour(&self, patch: usize, side: usize) -> Option<usize> {
        let per_side = self.per_side as usize;
        let (px, py) = (patch % per_side, patch / per_side);
        match side {
            WEST => (px > 0).then(|| patch - 1),
            EAST => (px + 1 < per_side).then(|| patch + 1),
            SOUTH => (py > 0).then(|| patch - per_side),
            _ => (py + 1 < per_side).then(|| patch + per_side),
        }
    }

    /// Chooses the level of every patch not culled with distances multiplied by `multiplier`;
    /// returns the triangles they draw.
    fn choose_lods(&mut self, multiplier: f64) -> u64 {
        let n = self.patch_level;
        let mut triangles = 0;
        for &patch in &self.visible {
            let patch = patch as usize;
            let k = self.config.curve.lod(n, self.distances[patch] * multiplier);
            self.lods[patch] = k;
            let m = (1 << k) + 1;
            triangles += strip::degenerate_strip_triangles(m, m);
        }
        triangles
    }

    /// Starts a frame that draws the patches in `self.visible`.
    fn begin_frame(&mut self) {
        self.frame += 1;
        for &patch in &self.visible {
            self.drawn_in[patch as usize] = self.frame;
        }
    }

    /// Checks the triangle list against this frame's levels (counts, collapsed borders lining
    /// up; see `validate.rs`), not the levels themselves.
    pub fn validate_mesh(&self) -> Result<(), VanekError> {
        validate::validate_mesh(self)
    }

    /// Checks this frame against the rules (see `validate.rs`): the levels and culling against a
    /// brute-force recomputation, the counts, and that collapsed borders line up.
    pub fn validate(&self, camera: &Camera) -> Result<(), VanekError> {
        validate::validate(self, camera)
    }
}

impl LodAlgorithm for Vanek<'_> {
    fn name(&self) -> &'static str {
        NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        if self.config.box_culling {
            CULLING_COLUMNS
        } else {
            EXTRA_COLUMNS
        }
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let camera = input.camera;
        let eye = camera.eye;
        self.nodes_visited = self.quadtree.visible_patches(
            self.config.box_culling.then_some(camera),
            &mut self.visible,
            &mut self.culled_squares,
        );
        self.begin_frame();
        for index in 0..self.visible.len() {
            let patch = self.visible[index] as usize;
            let block = self.patch_box(patch);
            self.distances[patch] =
                patch_distance(eye, block.low, block.high, self.config.distance);
        }
        let in_view = self.visible.len() as u64;
        let mut evaluations = 0;
        if let Some(target) = self.config.target_triangles {
            let start = self.multiplier;
            let choice = finest_tau_within(target, start, |mu| {
                evaluations += in_view;
                self.choose_lods(mu)
            });
            self.multiplier = choice.tau_px;
            self.target_unreachable = choice.unreachable;
        }
        evaluations += in_view;
        self.choose_lods(self.multiplier);

        let [finer, coarser, inserted, deleted] = self.draw();

        let level_sum: f64 = self
            .visible
            .iter()
            .map(|&p| f64::from(self.lods[p as usize]))
            .sum();
        stats.triangles = self.list.n_triangles();
        stats.splits = finer;
        stats.merges = coarser;
        stats.vertices_inserted = inserted;
        stats.vertices_deleted = deleted;
        stats.metric_evaluations = evaluations;
        stats.extra = vec![
            self.strip_indices as f64,
            self.list.role_count(TriangleRole::Degenerate) as f64,
            self.collapsed as f64,
            (self.lods.len() - self.visible.len()) as f64,
            level_sum / self.visible.len().max(1) as f64,
            self.multiplier,
            f64::from(u8::from(self.target_unreachable)),
        ];
        if self.config.box_culling {
            stats.extra.push(self.nodes_visited as f64);
        }
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.write_buffers()
    }

    fn buffers(&self) -> &GpuBuffers {
        &self.gpu
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::triangles(&self.list)
    }

    fn triangle_count(&self) -> u64 {
        self.list.n_triangles()
    }

    fn memory_bytes(&self) -> usize {
        self.z_range.capacity() * std::mem::size_of::<(f32, f32)>()
            + self.quadtree.memory_bytes()
            + (self.visible.capacity() + self.drawn_in.capacity() + self.previous_drawn.capacity())
                * std::mem::size_of::<u32>()
            + self.culled_squares.capacity() * std::mem::size_of::<((u32, u32), u32)>()
            + self.lods.capacity() * std::mem::size_of::<u32>()
            + self.distances.capacity() * std::mem::size_of::<f64>()
            + self.list.memory_bytes()
            + self.strip.capacity() * std::mem::size_of::<u32>()
            + self.moved.capacity() * std::mem::size_of::<(u32, u32)>()
            + self.states.capacity() * std::mem::size_of::<Option<(u32, Shape)>>()
            + self.gpu.memory_bytes()
            + self.patch_vertices.capacity() * std::mem::size_of::<Option<(BufferId, [u32; 5])>>()
            + self.drawn.capacity() * std::mem::size_of::<(usize, u32, [u32; 5])>()
    }

    fn run_facts(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("patches", self.lods.len() as f64),
            ("patch_level", f64::from(self.patch_level)),
        ]
    }
}
