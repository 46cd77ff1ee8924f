//! `geomipmap`: de Boer's geometrical mipmapping (2000; not in `papers/`), as Lauritsen and
//! Nielsen survey it (§2.5, eq. 3.3): fixed patches of (2^k + 1)² samples, each drawn at the
//! level its distance allows, borders between levels stitched, optional geomorphing, and with
//! `box_culling` the patches outside the view left out through a quadtree over them.
//!
//! # The algorithm
//!
//! - **Patches and levels** (`patches.rs`): patch level ℓ keeps every 2^ℓ-th sample; its error
//!   D_ℓ is the largest vertical distance of a left-out sample from the level's surface.
//! - **Selection** (`levels.rs`): the coarsest level whose d_ℓ = D_ℓ·C (eq. 3.3, C =
//!   S/(2τ·tan(fov/2))) is not above the patch's distance d; neighbouring patches at most one
//!   level apart by default.
//! - **Stitching** (`stitch.rs`): a patch whose neighbour is coarser leaves out the border
//!   vertices the neighbour lacks and fans its border strip to the ones it keeps (role stitch);
//!   the surface is closed (crack policy `stitched`).
//! - **Culling** (`block_lod/quadtree.rs`, option `box_culling`): a quadtree over the patches, each node
//!   with its patches' height range; a node outside the view is left with everything below it
//!   and declared to the mesh as a culled region. Levels, stitching and factors are then chosen
//!   over the drawn patches only (a culled neighbour is no neighbour: nothing to stitch to), so
//!   a frame costs O(patches in view), whatever the terrain's size. Without it every patch is
//!   drawn, as before.
//! - **GPU side** (`buffers.rs`, issue #31): per patch a static vertex buffer of its
//!   full-resolution samples, index buffers shared per (level, stitched sides), one draw per
//!   patch; a level change picks another index buffer and writes no vertex; geomorphing writes
//!   the morphing patches' heights from the CPU, as de Boer does (decision and reasons there).
//! - **Geomorphing**, an effect: odd vertices move towards the coarser level by de Boer's
//!   factor (eq. 3.5), patch borders by the coarser-looking side's factor, so the surface stays
//!   closed while it morphs.
//!
//! # Decisions where the paper is open
//!
//! - **Level errors nest** (D_ℓ = max over levels 0..=ℓ), so the level is a function of the
//!   distance; with de Boer's usual increasing errors this changes nothing.
//! - **Distance** from the eye to the patch's box (square × sample height range); the
//!   projection is the horizontal-view one by default ([`Projection::Exact`] as an option,
//!   shared with `chunked`).
//! - **Neighbour levels.** The survey's figure skips every other border vertex: one level of
//!   difference, [`LevelDifference::AtMostOne`], kept by refining coarser patches (never
//!   coarsening finer ones); [`LevelDifference::Any`] stitches across any difference.
//! - **Morphing at borders**: a border is drawn at the level and factor of the patch that
//!   looks coarser (higher level; equal levels: smaller factor), by both patches alike.
//! - **Triangle target**: as `chunked` (`block_lod/budget.rs`): the finest τ whose mesh,
//!   stitches included, fits.
//! - **Counters.** `splits` / `merges`: patches drawn finer / coarser than last frame;
//!   `vertices_inserted` / `vertices_deleted`: the vertices of patches whose level or stitching
//!   changed (all of the new and of the old triangulation); `metric_evaluations`: level
//!   tests (δ·C against d), over every pass of the frame. Columns:
//!   `patches_refined_for_neighbours` (patches drawn finer than their criterion for the level
//!   limit), `stitched_sides`, `patch_level_mean` (0 = full resolution), `tau_px`,
//!   `target_unreachable`; with `box_culling` also `patches_culled` and
//!   `quadtree_nodes_visited`. One draw per drawn patch.
//!
//! Memory: the patch grid (about 0.1 B per sample for 17² patches), per patch a few words of
//! frame state, the quadtree, the triangle list, the vertex buffers of the patches drawn so
//! far. Per frame: O(drawn patches · levels + drawn triangles + quadtree nodes visited).

mod brute_force;
mod buffers;
mod levels;
mod patches;
mod stitch;
mod validate;

pub use brute_force::levels_from_scratch;
pub use levels::LevelDifference;
pub use validate::GeomipmapError;

use super::block_lod::budget::finest_tau_within;
use super::block_lod::quadtree::PatchQuadtree;
use super::block_lod::threshold::DetailThreshold;
use super::block_lod::{BlockGoal, Projection};
use super::columns::geomipmap as columns;
use super::{FrameInput, LodAlgorithm};
use crate::sim::draw::{DrawCounts, GpuBuffers};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::{CrackPolicy, MeshOutput, SubgridPoint, TriangleList};
use crate::sim::stats::FrameStats;
use crate::sim::view::{Camera, ViewSettings};
use buffers::{MorphKey, PatchBuffers};
use levels::{PatchLevels, choose_levels, measure, set_morph_factors};
use patches::PatchGrid;
use stitch::{PatchDraw, PatchScratch, add_patch};

pub(super) const NAME: &str = "geomipmap";

const EXTRA_COLUMNS: &[&str] = &[
    columns::PATCHES_REFINED_FOR_NEIGHBOURS,
    columns::STITCHED_SIDES,
    columns::PATCH_LEVEL_MEAN,
    columns::TAU,
    columns::TARGET_UNREACHABLE,
];

/// With box culling, also what the quadtree culled and visited.
const CULLING_COLUMNS: &[&str] = &[
    columns::PATCHES_REFINED_FOR_NEIGHBOURS,
    columns::STITCHED_SIDES,
    columns::PATCH_LEVEL_MEAN,
    columns::TAU,
    columns::TARGET_UNREACHABLE,
    columns::PATCHES_CULLED,
    columns::QUADTREE_NODES_VISITED,
];

/// Parameters of geometrical mipmapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeomipmapConfig {
    /// k: patches of (2^k + 1)² samples (1..=15; clamped to the terrain's level).
    pub patch_level: u32,
    pub goal: BlockGoal,
    pub level_difference: LevelDifference,
    /// Geomorphing by de Boer's factor.
    pub morph: bool,
    pub projection: Projection,
    /// Patches whose box is outside the view are not drawn, found through the quadtree over
    /// the patches (de Boer's; default false: every patch drawn, as before).
    pub box_culling: bool,
}

/// What a patch drew last frame: its triangulation, its morph state, its vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PatchState {
    /// The patch's level and its sides' levels.
    shape: [u32; 5],
    /// The bits of its factor and its sides' factors.
    morph: [u64; 5],
    vertices: u64,
    morphing_vertices: u64,
}

/// The stitch step of each side (WEST, EAST, SOUTH, NORTH) of `patch` at the current levels:
/// `None` where the neighbour is not coarser (or there is none).
fn stitch_steps(grid: &PatchGrid, levels: &PatchLevels, patch: usize) -> [Option<u32>; 4] {
    let own = levels.level[patch];
    levels.neighbours(grid, patch).map(|neighbour| {
        neighbour
            .map(|q| levels.level[q])
            .filter(|&side| side > own)
            .map(|side| 1 << (side - own))
    })
}

/// Geometrical mipmapping. Per frame: O(drawn patches · levels + drawn triangles); buffers
/// reused.
pub struct Geomipmap<'h> {
    /// The buffers a GPU draws this frame's mesh from (`buffers.rs`).
    draw: PatchBuffers,
    quadtree: PatchQuadtree,
    /// This frame's patches not culled, and the squares of the quadtree nodes culled (reused).
    visible: Vec<u32>,
    culled_squares: Vec<((u32, u32), u32)>,
    /// This frame's drawn patches as drawn, for `prepare_draw` (reused).
    patch_draws: Vec<(usize, PatchDraw, Option<MorphKey>)>,
    /// Quadtree nodes visited this frame.
    nodes_visited: u64,
    hierarchy: &'h Hierarchy,
    config: GeomipmapConfig,
    lambda: f64,
    grid: PatchGrid,
    levels: PatchLevels,
    list: TriangleList,
    scratch: PatchScratch,
    tau_px: f64,
    target_unreachable: bool,
    /// Per patch, the frame it was last drawn in and what it drew.
    states: Vec<Option<(u32, PatchState)>>,
    /// Last frame's drawn patches, ascending.
    previous_drawn: Vec<u32>,
}

impl<'h> Geomipmap<'h> {
    /// Cuts the terrain into patches and computes their level errors (O(samples · k)). The
    /// goal's τ must be finite and ≥ 0 (the experiment validation guarantees it).
    pub fn new(
        hierarchy: &'h Hierarchy,
        config: GeomipmapConfig,
        view: &ViewSettings,
    ) -> Geomipmap<'h> {
        let tau_px = match config.goal {
            BlockGoal::TolerancePx(tau) => {
                assert!(
                    tau.is_finite() && tau >= 0.0,
                    "geomipmap's τ must be finite and at least 0, not {tau}"
                );
                tau
            }
            BlockGoal::TargetTriangles(_) => 1.0,
        };
        let grid = PatchGrid::new(hierarchy, config.patch_level);
        let n = grid.n_patches();
        Geomipmap {
            draw: PatchBuffers::new(n),
            quadtree: PatchQuadtree::new(
                grid.per_side(),
                grid.cells(),
                hierarchy.field().spacing(),
                |patch| grid.z_range(patch),
            ),
            visible: Vec::new(),
            culled_squares: Vec::new(),
            patch_draws: Vec::new(),
            nodes_visited: 0,
            hierarchy,
            config,
            lambda: view.pixels_per_unit(),
            levels: PatchLevels::new(&grid),
            grid,
            list: TriangleList::new(hierarchy.lattice(), CrackPolicy::Stitched),
            scratch: PatchScratch::default(),
            tau_px,
            target_unreachable: false,
            states: vec![None; n],
            previous_drawn: Vec::new(),
        }
    }

    /// The effective k (patches of (2^k + 1)² samples).
    pub fn patch_level(&self) -> u32 {
        self.grid.patch_level()
    }

    /// Patches per side.
    pub fn patches_per_side(&self) -> u32 {
        self.grid.per_side()
    }

    /// This frame's level of every patch, row by row from the south-west (0 = full
    /// resolution, k = the corners only).
    pub fn levels(&self) -> &[u32] {
        &self.levels.level
    }

    /// This frame's morph factor of every patch, row by row.
    pub fn morph_factors(&self) -> &[f64] {
        &self.levels.morph
    }

    /// The τ this frame was drawn with.
    pub fn tau_px(&self) -> f64 {
        self.tau_px
    }

    /// Checks the patch grid against the height field and this frame's levels, factors and
    /// triangles against the rules (see `validate.rs`). O(samples · k).
    pub fn validate(&self, camera: &Camera) -> Result<(), GeomipmapError> {
        validate::validate(&validate::FrameView {
            hierarchy: self.hierarchy,
            config: self.config,
            grid: &self.grid,
            levels: &self.levels,
            threshold: &DetailThreshold::new(self.lambda, self.tau_px),
            list: &self.list,
            camera,
        })
    }

    /// Triangles the current levels draw (without building them): per drawn patch of n cells a side,
    /// 2n² less, per side stitched at step 2^Δ, the n − n/2^Δ triangles its zipped strip saves
    /// (the sum of [`stitch::patch_triangles`] over the patches, in closed form: the target search
    /// runs this about ten times a frame). O(patches), no allocation.
    fn count_triangles(grid: &PatchGrid, levels: &PatchLevels) -> u64 {
        let cells = u64::from(grid.cells());
        let mut total = 0;
        for &patch in &levels.drawn {
            let own = levels.level[patch as usize];
            let n = cells >> own;
            let mut triangles = 2 * n * n;
            for neighbour in levels
                .neighbours(grid, patch as usize)
                .into_iter()
                .flatten()
            {
                let side = levels.level[neighbour];
                if side > own {
                    triangles -= n - (n >> (side - own));
                }
            }
            total += triangles;
        }
        total
    }

    /// This frame's τ; returns the level tests made choosing it.
    fn choose_tau(&mut self) -> u64 {
        let BlockGoal::TargetTriangles(target) = self.config.goal else {
            return 0;
        };
        let mut tests = 0;
        let (grid, levels) = (&self.grid, &mut self.levels);
        let (lambda, difference) = (self.lambda, self.config.level_difference);
        let choice = finest_tau_within(target, self.tau_px, |tau_px| {
            let threshold = DetailThreshold::new(lambda, tau_px);
            tests += choose_levels(grid, &threshold, difference, levels);
            Geomipmap::count_triangles(grid, levels)
        });
        self.tau_px = choice.tau_px;
        self.target_unreachable = choice.unreachable;
        tests
    }
}

impl LodAlgorithm for Geomipmap<'_> {
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
        let eye = input.camera.eye;
        let (grid, projection) = (&self.grid, self.config.projection);
        self.nodes_visited = self.quadtree.visible_patches(
            self.config.box_culling.then_some(input.camera),
            &mut self.visible,
            &mut self.culled_squares,
        );
        measure(
            &self.visible,
            |patch| grid.block_box(patch).lod_distance(eye, projection),
            &mut self.levels,
        );
        let search_tests = self.choose_tau();
        let threshold = DetailThreshold::new(self.lambda, self.tau_px);
        let tests = choose_levels(
            &self.grid,
            &threshold,
            self.config.level_difference,
            &mut self.levels,
        );
        set_morph_factors(&self.grid, &threshold, self.config.morph, &mut self.levels);

        self.list.clear();
        for &((x0, y0), cells) in &self.culled_squares {
            self.list.add_culled_region(
                SubgridPoint::grid(x0, y0),
                SubgridPoint::grid(x0 + cells, y0 + cells),
            );
        }
        self.patch_draws.clear();
        let k = self.grid.patch_level();
        let per_side = self.grid.per_side();
        let mut stitched_sides = 0;
        let (mut finer, mut coarser, mut inserted, mut deleted) = (0, 0, 0, 0);
        for &patch in &self.levels.drawn {
            let patch = patch as usize;
            let (px, py) = (patch as u32 % per_side, patch as u32 / per_side);
            let level = self.levels.level[patch];
            let sides = self.levels.sides(&self.grid, patch);
            stitched_sides += sides.iter().filter(|s| s.0 > level).count() as u64;
            let draw = PatchDraw {
                origin: self.grid.origin(px, py),
                patch_cells: self.grid.cells(),
                level,
                morph: self.levels.morph[patch],
                sides,
                group: patch as u32,
                list_level: k - level,
            };
            let added = add_patch(&mut self.list, self.hierarchy, &draw, &mut self.scratch);
            let now = PatchState {
                shape: [level, sides[0].0, sides[1].0, sides[2].0, sides[3].0],
                morph: [
                    draw.morph.to_bits(),
                    sides[0].1.to_bits(),
                    sides[1].1.to_bits(),
                    sides[2].1.to_bits(),
                    sides[3].1.to_bits(),
                ],
                vertices: added.vertices,
                morphing_vertices: added.morphing_vertices,
            };
            let frame = self.levels.frame();
            let before = self.states[patch]
                .filter(|&(drawn_in, _)| drawn_in + 1 == frame)
                .map(|(_, state)| state);
            match before {
                None => inserted += now.vertices,
                Some(before) if before.shape != now.shape => {
                    inserted += now.vertices;
                    deleted += before.vertices;
                    finer += u64::from(now.shape[0] < before.shape[0]);
                    coarser += u64::from(now.shape[0] > before.shape[0]);
                }
                Some(_) => {}
            }
            self.states[patch] = Some((frame, now));
            let morphing = draw.morph < 1.0 || sides.iter().any(|side| side.1 < 1.0);
            self.patch_draws
                .push((patch, draw, morphing.then_some((now.shape, now.morph))));
        }
        for &patch in &self.previous_drawn {
            if !self.levels.is_drawn(patch as usize) {
                deleted += self.states[patch as usize].map_or(0, |(_, state)| state.vertices);
            }
        }
        self.previous_drawn.clone_from(&self.levels.drawn);

        let n_drawn = self.levels.drawn.len();
        let refined_for_neighbours = self
            .levels
            .drawn
            .iter()
            .filter(|&&p| self.levels.level[p as usize] < self.levels.own[p as usize])
            .count();
        let level_mean = self
            .levels
            .drawn
            .iter()
            .map(|&p| f64::from(self.levels.level[p as usize]))
            .sum::<f64>()
            / n_drawn.max(1) as f64;
        stats.triangles = self.list.n_triangles();
        stats.splits = finer;
        stats.merges = coarser;
        stats.vertices_inserted = inserted;
        stats.vertices_deleted = deleted;
        stats.metric_evaluations = search_tests + tests;
        stats.extra = vec![
            refined_for_neighbours as f64,
            stitched_sides as f64,
            level_mean,
            self.tau_px,
            f64::from(u8::from(self.target_unreachable)),
        ];
        if self.config.box_culling {
            stats.extra.push((self.grid.n_patches() - n_drawn) as f64);
            stats.extra.push(self.nodes_visited as f64);
        }
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.draw.begin_frame();
        for (patch, draw, morph) in &self.patch_draws {
            self.draw.draw_patch(self.hierarchy, *patch, draw, *morph);
        }
        self.draw.end_frame()
    }

    fn buffers(&self) -> &GpuBuffers {
        self.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::triangles(&self.list)
    }

    fn triangle_count(&self) -> u64 {
        self.list.n_triangles()
    }

    fn memory_bytes(&self) -> usize {
        self.grid.memory_bytes()
            + self.levels.memory_bytes()
            + self.list.memory_bytes()
            + self.scratch.memory_bytes()
            + self.states.capacity() * std::mem::size_of::<Option<(u32, PatchState)>>()
            + self.previous_drawn.capacity() * std::mem::size_of::<u32>()
            + self.quadtree.memory_bytes()
            + self.visible.capacity() * std::mem::size_of::<u32>()
            + self.culled_squares.capacity() * std::mem::size_of::<((u32, u32), u32)>()
            + self.patch_draws.capacity()
                * std::mem::size_of::<(usize, PatchDraw, Option<MorphKey>)>()
            + self.draw.memory_bytes()
    }

    fn run_facts(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("patches", self.grid.n_patches() as f64),
            ("patch_level", f64::from(self.grid.patch_level())),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::stitch::patch_triangles;
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};

    #[test]
    fn the_closed_form_count_is_the_sum_of_every_patchs_triangles() {
        let side = 65;
        let heights = (0..side * side).map(|k| (k % 7) as f32).collect();
        let hierarchy =
            Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 1.0, dy: 1.0 }).unwrap());
        let grid = PatchGrid::new(&hierarchy, 3);
        let mut state = 12345u64;
        for _ in 0..50 {
            let level = (0..grid.n_patches())
                .map(|_| {
                    state = state
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    ((state >> 33) % 4) as u32
                })
                .collect();
            let mut levels = PatchLevels::new(&grid);
            let every: Vec<u32> = (0..grid.n_patches() as u32).collect();
            measure(&every, |_| 0.0, &mut levels);
            levels.level = level;
            let summed: u64 = (0..grid.n_patches())
                .map(|patch| {
                    patch_triangles(
                        grid.cells() >> levels.level[patch],
                        stitch_steps(&grid, &levels, patch),
                    )
                })
                .sum();
            assert_eq!(Geomipmap::count_triangles(&grid, &levels), summed);
        }
    }
}
