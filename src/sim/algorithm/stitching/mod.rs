//! `stitching-strips`: the multilevel terrain of Zhang, Sun et al. (ISPRS IJGI 2019, §3):
//! quadtree leaves drawn as M-blocks, each tessellated on the GPU at its own continuous factor
//! F, the gaps between them filled every frame by dynamic stitching strips (DSS) and, where four
//! strips meet, P-blocks. With the paper's two comparison methods (§4.1) as options. No GPU is
//! involved: the tessellator is simulated exactly on the CPU (`tessellate.rs`).
//!
//! # The algorithm
//!
//! - **The quadtree** (§3.1, `tree.rs`): built whole before the first frame, down to blocks of
//!   2^`block_level` cells; per node its 32 object-space errors δ_i (the mean vertical error of
//!   the block tessellated at F = 2i) and its height range. A node's M-block is its square less
//!   half a strip on every side inside the domain; when a node splits, its children's blocks
//!   leave a cross of strips `strip_width_cells` wide between them, with a P-block at its
//!   centre.
//! - **Selection** (§3.3.1, `select.rs`), top-down every frame: ρ_i = λ·δ_i·sinθ/d with
//!   λ = y/(2 tan(φ/2)) (the window's height in pixels and its vertical field of view); a node
//!   splits while ρ_32 > ρ_thr and it has children; a leaf's F comes from eq. 4 between the two
//!   levels that bracket ρ_thr (2 when every level is within it, 64 for a finest block that is
//!   not).
//! - **Tessellation** (`tessellate.rs`), simulated exactly: fractional-even spacing on the
//!   block's interior and edges, vertices at fixed-point positions, heights resampled from the
//!   field **bilinearly** (the cell's four samples; exact at samples), so the triangles counted
//!   are the ones a GPU would draw: 2n² per M-block, n = 2⌈F/2⌉.
//! - **Strips and P-blocks** (§3.1.3, §3.2, `strips.rs`): each strip's two rows are the
//!   vertices its neighbouring blocks show along it (the same function, the same factor: bit
//!   for bit the blocks' edge vertices), triangulated by the perpendicular-bisector rule
//!   (Algorithm 1); role `stitch`. P-blocks are surface. Crack policy `stitched`.
//! - **Hierarchical culling** (§3.3.2), an effect (`culling`): a node whose box (region ×
//!   height range) lies outside the view volume is not drawn, nor anything below it, and is
//!   declared culled; of a visible split node, each strip and the P-block is tested by its own
//!   box (rectangle × the node's height range) and left out when outside: the paper's edges
//!   that generate no strip. The selection is made as without culling, so a culled block's
//!   neighbours and strips are unchanged.
//! - **Method I** (`method: power_of_two`, §4.1): the same quadtree and criterion, F rounded up
//!   to a power of two, no strips (the blocks touch). The edges between blocks of different sizes
//!   or factors take one spacing that both sides share: the coarser of the two sides' interior
//!   spacings (for a long side, over every block along it), no coarser than the smallest
//!   block along it; integer spacing (a factor of 1 allowed on an edge).
//! - **Method II** (`method: uniform`, §4.1): every block at the deepest level, F continuous by
//!   the same metric, no strips; a shared edge takes the larger of its two blocks' factors,
//!   fractional-even, so both sides cut it alike.
//!
//! # Decisions where the paper is open
//!
//! - **θ** is the angle between +Z and the direction from the viewpoint to the block's centre
//!   ([`ViewDirection::ToBlock`], the paper's §4.1 figures), so sinθ is the horizontal share of
//!   that direction and a block seen from straight above gets ρ = 0 (its vertical error lies
//!   along the ray). [`ViewDirection::Look`]: the camera's look direction instead.
//! - **d** is to the block's centre ([`BlockDistance::Centre`], the paper's O); the box,
//!   0 inside, is [`BlockDistance::Box`]. d = 0 gives ρ = ∞ (a block with any error splits);
//!   the eye at the centre counts as sinθ = 1.
//! - **λ** = (window height in pixels)/(2 tan(fovy/2)), as eq. 1 writes it.
//! - **What the metric implies.** δ_i is a block's *mean* error, and a block of s ≤ 64 cells
//!   has none at any F = 2i that s divides (every sample is then a vertex): such a block has
//!   δ_32 = 0 and never splits, and δ_i is not monotone in i, so eq. 4's scan from i = 32 down
//!   can make F jump. Both are the paper's metric taken as written.
//! - **Fractional-even rounding**: n = 2⌈F/2⌉ segments, the two short ones in the middle of the
//!   edge (the OpenGL specification leaves their place to the implementation, symmetric).
//!   Every position is rounded once to 1/65 536 of a cell; where a short segment rounds to
//!   nothing the GPU's zero-area triangle is counted with role degenerate.
//! - **F reaches the tessellator as an `f32`**, as a shader writes it: eq. 4's value rounded
//!   once, so the eye moving by a rounding error (a terrain translated by 10^6 m) moves no
//!   vertex.
//! - **The filter** is bilinear over the cell holding the vertex.
//! - **The ring** between a block's interior grid and its edges is triangulated by the same
//!   bisector merge as the strips (implementation-dependent on a GPU; its count is not).
//! - **The P-block** is two triangles over its corners ([`PBlockShape::TwoTriangles`]); the
//!   option [`PBlockShape::Fan`] adds its resampled centre.
//! - **The strip width** is `strip_width_cells` (default 1 cell), the same at every level,
//!   clamped to half the smallest block.
//! - **Counters.** `splits` / `merges`: nodes split this frame and not the previous, and the
//!   reverse; `vertices_inserted` / `vertices_deleted`: the vertices of every block, and of
//!   every node's cross of strips and P-block, that differs from last frame's (positions or
//!   heights; all of the new and all of the old; a block's compared from its patch words,
//!   `changes.rs`); `metric_evaluations`: nodes whose ρ was computed. Columns:
//!   `m_blocks`, `m_blocks_culled`, `p_blocks`, `strips`, `strips_culled`,
//!   `tessellation_factor_mean` (over the M-blocks), the histogram of F
//!   (`tessellation_factor_2_4` … `tessellation_factor_32_64`: blocks with F in [2, 4), …,
//!   [32, 64]) and `strip_construction_ns` (the part of the update spent building strips, a
//!   timing column).
//!
//! # What the GPU is sent (issue #31)
//!
//! What the paper sends each frame, kept by `buffers.rs`: **the blocks** as patches, one per
//! drawn M-block in a per-frame instance buffer (its MBD's Position and Size, §3.1.1, as its
//! rectangle, and its factors: the inner one and its four edges', 36 bytes), drawn by one patch
//! draw and tessellated on the GPU (§3, "terrain block meshes are generated with appropriate
//! levels in the GPU"), so the blocks' triangles are submitted and drawn but never uploaded;
//! **the strips and P-blocks**, whose vertices the CPU computes (§3.2.2) and which the paper
//! rebuilds every frame (§4.2: "the work of DSS generation needs to be done in every frame"),
//! written whole into one vertex and one index buffer each frame and drawn as one list. So a
//! frame uploads 36 bytes a drawn block plus its strips' geometry, whatever the blocks' factors
//! (Methods I and II: the blocks alone). The GPU's tessellator is the CPU simulation
//! (`tessellate.rs`), registered with the buffers.
//!
//! **What the update does, and what it leaves to the GPU.** The update is the paper's CPU work:
//! the selection and factors, each drawn block's patch words, the strips and P-blocks (and
//! roamsim's counters: the vertex changes, compared from the patch words; the histogram). It
//! tessellates no block: the mesh (`MeshOutput`) is made from the frame's patch words by the
//! registered tessellator the first time it is read in the frame (the audit, `--check`,
//! culling's rendered count, PLY export, the preview; `lazy_mesh.rs`), outside the timed spans,
//! so the mesh and what the GPU draws are one code, and the mesh is the list the update made
//! before, bit for bit. So `update_ns` is the paper's CPU work, `frame_ns` adds writing the words
//! and the strips into the buffers, and neither includes the tessellation a GPU does.
//!
//! Memory: the tree (136 bytes a node), a few words of frame state per node, the patch words,
//! the strips' list, the mesh once read, and a few reused buffers. Per frame: O(nodes + the
//! strips' triangles) in the update, O(triangles) when the mesh is read.

mod buffers;
mod changes;
mod lazy_mesh;
mod select;
mod spacing;
mod strips;
mod tessellate;
mod tree;
mod validate;

pub use buffers::{PATCH_BYTES, frame_upload_bytes};
pub use select::{BlockDistance, MetricBox, StitchingMethod, ViewDirection};
pub use strips::PBlockShape;
pub use tessellate::{EdgeSpacing, edge_positions, quad_patch_triangles, resampled_height};
pub use tree::NodeId;
pub use validate::StitchingError;

use super::block_lod::cull::box_outside_view;
use super::block_lod::threshold::BlockBox;
use super::columns::stitching as columns;
use super::{FrameInput, LodAlgorithm};
use crate::sim::draw::{DrawCounts, GpuBuffers};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::{
    CrackPolicy, MeshOutput, SUBGRID_UNITS_PER_CELL, TriangleInfo, TriangleRole,
};
use crate::sim::stats::FrameStats;
use crate::sim::view::Camera;
use buffers::{BlockTessellator, SpacingMode, StitchingBuffers};
use changes::VertexChanges;
use glam::DVec3;
use lazy_mesh::LazyMesh;
use std::sync::Arc;
use std::time::Instant;
use tessellate::Rect;
use tree::Tree;

pub(super) const NAME: &str = "stitching-strips";

const EXTRA_COLUMNS: &[&str] = &[
    columns::M_BLOCKS,
    columns::M_BLOCKS_CULLED,
    columns::P_BLOCKS,
    columns::STRIPS,
    columns::STRIPS_CULLED,
    columns::TESSELLATION_FACTOR_MEAN,
    columns::TESSELLATION_FACTOR_2_4,
    columns::TESSELLATION_FACTOR_4_8,
    columns::TESSELLATION_FACTOR_8_16,
    columns::TESSELLATION_FACTOR_16_32,
    columns::TESSELLATION_FACTOR_32_64,
    columns::STRIP_CONSTRUCTION_NS,
];

/// Parameters of the stitching-strips algorithm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StitchingConfig {
    /// ρ_thr, pixels (finite, ≥ 0).
    pub threshold_px: f64,
    /// The smallest blocks are 2^block_level cells a side (clamped to 1 ..= the terrain's level).
    pub block_level: u32,
    /// Width of the strips in cells (> 0; clamped to half the smallest block). Unused by
    /// Methods I and II.
    pub strip_width_cells: f64,
    pub method: StitchingMethod,
    pub distance: BlockDistance,
    pub view_direction: ViewDirection,
    pub p_block: PBlockShape,
    /// Hierarchical culling of blocks, then strips (an effect).
    pub culling: bool,
}

/// A node's part in this frame's selection.
#[derive(Clone, Copy, Debug, PartialEq)]
enum NodeState {
    /// Below a leaf (or above nothing): not in the selection.
    Unselected,
    /// An M-block at factor F.
    Leaf(f64),
    Split,
}

/// The stitching-strips algorithm. Per frame: O(nodes + triangles); buffers reused.
pub struct Stitching<'h> {
    /// What the GPU draws this frame's mesh from: the blocks' patches, the strips (`buffers.rs`).
    draw: StitchingBuffers,
    /// This frame's blocks (patch words) and strips, and its mesh once read (`lazy_mesh.rs`).
    mesh: LazyMesh,
    tessellator: Arc<BlockTessellator>,
    hierarchy: &'h Hierarchy,
    config: StitchingConfig,
    tree: Tree,
    state: Vec<NodeState>,
    was_split: Vec<bool>,
    leaves: Vec<NodeId>,
    /// Per node: its index in `leaves` when it is a leaf this frame.
    leaf_index: Vec<u32>,
    /// Method I: the leaf (index into `leaves`) owning each finest cell, row by row.
    owners: Vec<u32>,
    strip_scratch: strips::StripScratch,
    frame: FrameCounts,
    /// What each node drew last frame and this frame, for `vertices_inserted` / `_deleted`.
    changes: VertexChanges,
}

/// What a frame drew, for the statistics and the validator.
#[derive(Clone, Debug, Default)]
struct FrameCounts {
    drawn_leaves: Vec<NodeId>,
    drawn_strips: Vec<(NodeId, strips::Arm)>,
    m_blocks_culled: u64,
    p_blocks: u64,
    strips_culled: u64,
    cpu_vertices: u64,
    strip_ns: u64,
}

impl<'h> Stitching<'h> {
    /// Builds the quadtree and its errors (see `tree.rs` for the cost).
    pub fn new(hierarchy: &'h Hierarchy, config: StitchingConfig) -> Stitching<'h> {
        assert!(
            config.threshold_px >= 0.0 && config.threshold_px.is_finite(),
            "stitching-strips needs a finite ρ_thr ≥ 0, not {}",
            config.threshold_px
        );
        assert!(
            config.strip_width_cells > 0.0 && config.strip_width_cells.is_finite(),
            "stitching-strips needs a strip width above 0, not {}",
            config.strip_width_cells
        );
        let field = hierarchy.field();
        let block_level = config.block_level.clamp(1, field.level());
        let half_width = match config.method {
            StitchingMethod::Strips => {
                let smallest = (1i64 << block_level) * SUBGRID_UNITS_PER_CELL;
                let half =
                    (config.strip_width_cells * 0.5 * SUBGRID_UNITS_PER_CELL as f64).round() as i64;
                half.clamp(1, smallest / 4)
            }
            _ => 0,
        };
        let tree = Tree::new(field, block_level, half_width);
        let finest = 1usize << tree.depth_max();
        let n = tree.n_nodes();
        let tessellator = Arc::new(BlockTessellator::new(
            hierarchy,
            match config.method {
                StitchingMethod::PowerOfTwo => SpacingMode::Equal,
                _ => SpacingMode::FractionalEven,
            },
        ));
        let crack_policy = if config.method == StitchingMethod::Strips {
            CrackPolicy::Stitched
        } else {
            CrackPolicy::Closed
        };
        Stitching {
            draw: StitchingBuffers::new(tessellator.clone()),
            mesh: LazyMesh::new(tessellator.clone(), crack_policy),
            tessellator,
            hierarchy,
            config,
            tree,
            state: vec![NodeState::Unselected; n],
            was_split: vec![false; n],
            leaves: Vec::new(),
            leaf_index: vec![0; n],
            owners: if config.method == StitchingMethod::PowerOfTwo {
                vec![0; finest * finest]
            } else {
                Vec::new()
            },
            strip_scratch: strips::StripScratch::default(),
            frame: FrameCounts::default(),
            changes: VertexChanges::new(n),
        }
    }

    /// This frame's M-blocks (quadtree leaves) in traversal order, with their factors.
    pub fn leaves(&self) -> impl Iterator<Item = (NodeId, f64)> + '_ {
        self.leaves
            .iter()
            .map(|&id| (id, self.factor(id).expect("a leaf")))
    }

    /// The deepest depth of the tree (its blocks are 2^block_level cells).
    pub fn depth_max(&self) -> u32 {
        self.tree.depth_max()
    }

    /// The strip width in use, cells (0 for Methods I and II).
    pub fn strip_width_cells(&self) -> f64 {
        2.0 * self.tree.half_width() as f64 / SUBGRID_UNITS_PER_CELL as f64
    }

    /// The factor of node `id` if it is a leaf this frame.
    fn factor(&self, id: NodeId) -> Option<f64> {
        match self.state[self.tree.index(id)] {
            NodeState::Leaf(f) => Some(f),
            _ => None,
        }
    }

    /// Node `id`'s box in terrain-local metres: its region × its height range.
    fn metric_box(&self, id: NodeId) -> MetricBox {
        let region = self.tree.region(id);
        let (low, high) = self.tree.z_range(id);
        let b = self.rect_box(region, (low, high));
        MetricBox {
            low: b.low,
            high: b.high,
        }
    }

    fn rect_box(&self, rect: Rect, (low, high): (f32, f32)) -> BlockBox {
        let spacing = self.hierarchy.field().spacing();
        let unit = 1.0 / SUBGRID_UNITS_PER_CELL as f64;
        BlockBox {
            low: DVec3::new(
                rect.x0 as f64 * unit * spacing.dx,
                rect.y0 as f64 * unit * spacing.dy,
                f64::from(low),
            ),
            high: DVec3::new(
                rect.x1 as f64 * unit * spacing.dx,
                rect.y1 as f64 * unit * spacing.dy,
                f64::from(high),
            ),
        }
    }

    /// Whether node `id` splits, and the factor it would have as a leaf (the criterion alone).
    fn decide(&self, camera: &Camera, id: NodeId) -> (bool, f64) {
        let config = &self.config;
        let scale = select::error_scale(
            camera,
            &self.metric_box(id),
            config.distance,
            config.view_direction,
        );
        let errors = self.tree.errors(id);
        let splittable = id.depth < self.tree.depth_max();
        let split = match config.method {
            StitchingMethod::Uniform => splittable,
            _ => splittable && select::needs_split(scale, errors, config.threshold_px),
        };
        let factor = select::tessellation_factor(scale, errors, config.threshold_px);
        let factor = match config.method {
            StitchingMethod::PowerOfTwo => select::power_of_two_factor(factor),
            _ => factor,
        };
        // Handed to the tessellator as a shader writes it: an f32.
        (split, f64::from(factor as f32))
    }

    /// Selects this frame's leaves top-down. Returns the metric evaluations.
    fn select(&mut self, camera: &Camera) -> u64 {
        self.state.fill(NodeState::Unselected);
        self.leaves.clear();
        let mut evaluations = 0;
        let mut stack = vec![NodeId::ROOT];
        while let Some(id) = stack.pop() {
            let index = self.tree.index(id);
            let uniform_inner =
                self.config.method == StitchingMethod::Uniform && id.depth < self.tree.depth_max();
            let (split, factor) = if uniform_inner {
                (true, 0.0)
            } else {
                evaluations += 1;
                self.decide(camera, id)
            };
            if split {
                self.state[index] = NodeState::Split;
                // Pushed in reverse so that children are visited south-west first.
                stack.extend(id.children().into_iter().rev());
            } else {
                self.state[index] = NodeState::Leaf(factor);
                self.leaf_index[index] = self.leaves.len() as u32;
                self.leaves.push(id);
            }
        }
        self.fill_owners();
        evaluations
    }

    /// The leaves under `id` (itself when a leaf).
    fn leaves_under(&self, id: NodeId) -> u64 {
        match self.state[self.tree.index(id)] {
            NodeState::Leaf(_) => 1,
            NodeState::Split => id.children().iter().map(|&c| self.leaves_under(c)).sum(),
            NodeState::Unselected => 0,
        }
    }

    /// Draws this frame's selection: the blocks' patches, the strips and P-blocks (the mesh is
    /// made from them when read, `lazy_mesh.rs`).
    fn draw(&mut self, camera: Option<&Camera>) {
        self.mesh.begin_frame();
        self.changes.begin_frame();
        self.frame.drawn_leaves.clear();
        self.frame.drawn_strips.clear();
        self.frame.m_blocks_culled = 0;
        self.frame.p_blocks = 0;
        self.frame.strips_culled = 0;
        self.frame.cpu_vertices = 0;
        self.frame.strip_ns = 0;
        self.draw_node(NodeId::ROOT, camera);
    }

    fn outside(&self, camera: Option<&Camera>, rect: Rect, id: NodeId) -> bool {
        camera.is_some_and(|camera| {
            box_outside_view(camera, &self.rect_box(rect, self.tree.z_range(id)))
        })
    }

    fn draw_node(&mut self, id: NodeId, camera: Option<&Camera>) {
        let index = self.tree.index(id);
        let region = self.tree.region(id);
        if self.outside(camera, region, id) {
            self.mesh
                .cpu_mut()
                .add_culled_region(region.low(), region.high());
            self.frame.m_blocks_culled += self.leaves_under(id);
            return;
        }
        match self.state[index] {
            NodeState::Leaf(factor) => {
                let k = self.leaf_index[index] as usize;
                let outer = self.outer_spacings(k);
                let inner = match self.config.method {
                    StitchingMethod::PowerOfTwo => EdgeSpacing::Equal(factor as u32),
                    _ => EdgeSpacing::FractionalEven(factor),
                };
                let patch = self
                    .mesh
                    .push_block(region, inner, outer, index as u32, id.depth);
                self.changes.record_block(index, patch);
                self.frame.drawn_leaves.push(id);
            }
            NodeState::Split => {
                for child in id.children() {
                    self.draw_node(child, camera);
                }
                if self.config.method == StitchingMethod::Strips {
                    self.draw_cross(id, camera);
                }
            }
            NodeState::Unselected => unreachable!("the drawing follows the selection"),
        }
    }

    /// The four strips and the P-block of split node `id`.
    fn draw_cross(&mut self, id: NodeId, camera: Option<&Camera>) {
        let start = Instant::now();
        let first = self.mesh.cpu().vertices().len();
        let first_triangle = self.mesh.cpu().n_triangles();
        let group = self.tree.index(id) as u32;
        let field = self.hierarchy.field();
        let state = &self.state;
        let tree = &self.tree;
        let factor = |n: NodeId| match state[tree.index(n)] {
            NodeState::Leaf(f) => Some(f),
            _ => None,
        };
        for arm in strips::ARMS {
            let rect = arm.rect(tree, id);
            if self.outside(camera, rect, id) {
                self.mesh
                    .cpu_mut()
                    .add_culled_region(rect.low(), rect.high());
                self.frame.strips_culled += 1;
                continue;
            }
            let (vertices, _) = strips::add_strip(
                self.mesh.cpu_mut(),
                field,
                tree,
                &factor,
                id,
                arm,
                group,
                &mut self.strip_scratch,
            );
            self.frame.cpu_vertices += vertices;
            self.frame.drawn_strips.push((id, arm));
        }
        let rect = strips::p_block_rect(tree, id);
        if self.outside(camera, rect, id) {
            self.mesh
                .cpu_mut()
                .add_culled_region(rect.low(), rect.high());
        } else {
            let info = TriangleInfo {
                role: TriangleRole::Surface,
                group,
                level: id.depth,
            };
            let (vertices, _) =
                strips::add_p_block(self.mesh.cpu_mut(), field, rect, self.config.p_block, info);
            self.frame.cpu_vertices += vertices;
            self.frame.p_blocks += 1;
        }
        let end = self.mesh.cpu().vertices().len();
        self.changes.record_cross(group as usize, first, end);
        self.mesh.end_cpu_run(first, first_triangle);
        self.frame.strip_ns += start.elapsed().as_nanos() as u64;
    }

    /// Draws a selection of the caller's, without culling: node `id` splits when `split(id)`
    /// (and it has children; Method II splits down to the deepest level whatever it says), a
    /// leaf gets factor `factor(id)` (clamped to [2, 64]; rounded up to a power of two by
    /// Method I). For exhaustive tests of shapes and factors no eye would give. The next
    /// [`LodAlgorithm::update`] selects again.
    pub fn draw_with(&mut self, split: impl Fn(NodeId) -> bool, factor: impl Fn(NodeId) -> f64) {
        self.state.fill(NodeState::Unselected);
        self.leaves.clear();
        let mut stack = vec![NodeId::ROOT];
        while let Some(id) = stack.pop() {
            let index = self.tree.index(id);
            let deeper = id.depth < self.tree.depth_max();
            let splits = deeper && (self.config.method == StitchingMethod::Uniform || split(id));
            if splits {
                self.state[index] = NodeState::Split;
                stack.extend(id.children().into_iter().rev());
            } else {
                let f = factor(id).clamp(tessellate::MIN_FACTOR, tessellate::MAX_FACTOR);
                // Handed to the tessellator as a shader writes it, as `update` does: an f32.
                let f = f64::from(f as f32);
                let f = match self.config.method {
                    StitchingMethod::PowerOfTwo => select::power_of_two_factor(f),
                    _ => f,
                };
                self.state[index] = NodeState::Leaf(f);
                self.leaf_index[index] = self.leaves.len() as u32;
                self.leaves.push(id);
            }
        }
        self.fill_owners();
        self.draw(None);
    }

    /// Checks the triangle list against this frame's selection (counts, strip vertices on the
    /// blocks' edges; see `validate.rs`), not the selection itself.
    pub fn validate_mesh(&self) -> Result<(), StitchingError> {
        validate::validate_mesh(self)
    }

    /// Checks this frame against the rules (see `validate.rs`): the selection against a
    /// brute-force recomputation, the triangle count, and that every strip vertex is a vertex of
    /// a neighbouring M-block's edge.
    pub fn validate(&self, camera: &Camera) -> Result<(), StitchingError> {
        validate::validate(self, camera)
    }
}

impl LodAlgorithm for Stitching<'_> {
    fn name(&self) -> &'static str {
        NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        EXTRA_COLUMNS
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let camera = input.camera;
        let evaluations = self.select(camera);
        self.draw(self.config.culling.then_some(camera));

        let (mut splits, mut merges) = (0, 0);
        for (state, was) in self.state.iter().zip(self.was_split.iter_mut()) {
            let now = *state == NodeState::Split;
            splits += u64::from(now && !*was);
            merges += u64::from(!now && *was);
            *was = now;
        }
        let factors: Vec<f64> = self.leaves().map(|(_, f)| f).collect();
        let mut histogram = [0u64; 5];
        for &f in &factors {
            let bin = (f.log2().floor() as usize).clamp(1, 5) - 1;
            histogram[bin] += 1;
        }
        stats.triangles = self.mesh.n_triangles();
        stats.splits = splits;
        stats.merges = merges;
        let (inserted, deleted) = self.changes.end_frame(
            &self.tessellator,
            self.mesh.words(),
            self.mesh.cpu().vertices(),
        );
        stats.vertices_inserted = inserted;
        stats.vertices_deleted = deleted;
        stats.metric_evaluations = evaluations;
        let mut extra = vec![
            factors.len() as f64,
            self.frame.m_blocks_culled as f64,
            self.frame.p_blocks as f64,
            self.frame.drawn_strips.len() as f64,
            self.frame.strips_culled as f64,
            factors.iter().sum::<f64>() / factors.len().max(1) as f64,
        ];
        extra.extend(histogram.iter().map(|&n| n as f64));
        extra.push(self.frame.strip_ns as f64);
        stats.extra = extra;
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.draw.prepare(self.mesh.words(), self.mesh.cpu())
    }

    fn buffers(&self) -> &GpuBuffers {
        self.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        MeshOutput::triangles(self.mesh.list())
    }

    fn triangle_count(&self) -> u64 {
        self.mesh.n_triangles()
    }

    fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes()
            + self.state.capacity() * std::mem::size_of::<NodeState>()
            + self.was_split.capacity()
            + self.leaves.capacity() * std::mem::size_of::<NodeId>()
            + self.leaf_index.capacity() * 4
            + self.owners.capacity() * 4
            + self.mesh.memory_bytes()
            + self.strip_scratch.memory_bytes()
            + self.frame.drawn_leaves.capacity() * std::mem::size_of::<NodeId>()
            + self.frame.drawn_strips.capacity() * std::mem::size_of::<(NodeId, strips::Arm)>()
            + self.changes.memory_bytes()
            + self.draw.memory_bytes()
    }

    fn run_facts(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("quadtree_nodes", self.tree.n_nodes() as f64),
            ("quadtree_depth", f64::from(self.tree.depth_max())),
            ("strip_width_cells", self.strip_width_cells()),
        ]
    }
}
