//! `rottger`: Röttger, Heidrich, Slusallek and Seidel 1998, "Real-Time Generation of Continuous
//! Levels of Detail for Height Fields" (§2: the quadtree, the criterion, geomorphing, clipping),
//! on the shared 4-8 lattice. It is not incremental: every frame's mesh is generated from
//! scratch, and only the previous frame's is kept, to count what changed.
//!
//! Every frame is generated top-down from the root (`refine.rs`): a block subdivides when
//! f = l / (d · C · max(c · d2, 1)) < 1 (eq. 3, `criterion.rs`), with d2 the block's roughness,
//! precomputed and propagated bottom-up (`roughness.rs`) and stored with the frame's blend values
//! in one byte per grid point (`matrix.rs`). Subdivided blocks draw triangle fans (`fans.rs`);
//! blocks out of view can be left coarse (`clip.rs`); with geomorphing on, the blend values give
//! every drawn vertex a morphed height, which the mesh output carries, so the audit, popping and
//! culling measure the morphed surface (`geomorph.rs`); c can be chosen every frame to hold a
//! load (`control.rs`). `brute_force.rs` evaluates the same criterion on every block with no
//! traversal; `validate.rs` checks the matrix and the frame.
//!
//! **What a GPU draws** (`draw.rs`, issue #31): the fans, as the paper sends them (§2.1, §3):
//! every frame each fan's vertices (centre, then the ring) at their drawn heights, morphed on the
//! CPU when geomorphing is on (equal to the mesh output's bit for bit), one `TriangleFan` draw per
//! fan as a 1998 renderer issued one `glBegin(GL_TRIANGLE_FAN)` per fan. Upload is O(mesh) per
//! frame by design: the paper rebuilds its fans every frame.
//!
//! # The paper on the 4-8 lattice
//!
//! The paper's quadtree blocks are the lattice's square diamonds: a block is its centre vertex
//! with a half-size. Its fans are a restricted quadtree triangulation, which is a 4-8 mesh:
//!
//! - **A block is subdivided** (its matrix entry is not 0) **iff its centre is in the mesh.** The
//!   paper draws a fan around the centre of every subdivided block, over the quadrants whose child
//!   is not subdivided (§2.1's "full or partial triangle fan"; §2.3: with f in [½, 1) "a single
//!   triangle fan is generated for the complete node"). The finest blocks (3 × 3 samples) can be
//!   subdivided too: their children are single cells, and their fan is then the full resolution
//!   of the block, as in the paper's figure 1 (entries at (7, 5) and (7, 7)).
//! - **An edge midpoint is drawn iff every block of the edge's size beside it is subdivided**:
//!   the paper skips it when "the neighbouring node is not subdivided to the same level"; on the
//!   border the block is alone beside its edge, so its midpoint is drawn when the block is
//!   subdivided. These are exactly the midpoints whose 4-8 parents are all in the mesh.
//! - **The level-difference rule is 4-8 closure.** A block centre's 4-8 parents are two edge
//!   midpoints of its parent block; a midpoint's parents are the centres of the blocks beside
//!   it. So a subdivided block needs its parent and the blocks of its parent's size that it
//!   touches subdivided: "all adjacent blocks of twice the edge length have to be subdivided,
//!   too" (§2.2). When the criterion leaves such a block undivided, the frame subdivides it
//!   anyway (a **forced split**, counted), so every frame's mesh is closed and crack-free.
//! - When the root is not subdivided the mesh is the two base triangles (one fan).
//!
//! # The 2D guarantee, and 3D
//!
//! The paper proves (§2.2, eq. 4–5) that propagating d2 with K = C/(2(C − 1)) makes every block
//! adjacent to a subdivided half-size block subdivide too, so no forcing is ever needed, for C ≥ 2
//! and distances measured in the plane. The proof uses two facts: the centres of a block and an
//! adjacent half-size block are at most d apart, and both blocks see the eye's height the same
//! way. The first holds for our blocks in both norms (d is the longer edge). The second holds in
//! 3D only when the two blocks have the same average elevation, since l measures the eye's height
//! against each block's own average elevation: l₁ ≤ l₂ + d + |z̄₁ − z̄₂|. So the guarantee holds
//! exactly where the blocks' average elevations agree (flat terrain, or any terrain whose
//! blocks all average alike — tested on every eye of such a terrain, with no forced split), and
//! elsewhere the forced splits count the places where it failed. Frustum clipping can also
//! leave a block undivided beside a subdivided one; those are forced and counted too.
//!
//! # Decisions the paper leaves open
//!
//! - **Distance.** l = |Δx| + |Δy| + |Δz| (the paper's L¹ norm, §2.2, the default), Δx, Δy
//!   from the block's centre and Δz from the block's **average elevation**, the mean of its nine
//!   samples at its own level (corners, edge midpoints, centre): the paper's approximation for
//!   3D (§2.2). The mean over all the block's samples would need 4 more bytes per block; the
//!   nine are read in O(1). [`DistanceNorm::Euclidean`] is the option: the Euclidean distance
//!   from the same point, as Röttger's own library (libMini) measures it.
//! - **d** is the block's edge length in metres, the longer edge where dx ≠ dy.
//! - **d2** (eq. 2) is the largest of the block's six elevation differences (four edge
//!   midpoints, the centre against both diagonals) over d. It is propagated bottom-up: each
//!   block's d2 is at least K times the d2 of every adjacent block one level finer — its own
//!   four children and the children of its edge neighbours that touch it (the blocks condition
//!   (4) relates it to; "adjacent blocks at the next lower level"). `d2_propagation: false`
//!   stores the local values instead, to measure what propagation buys.
//! - **One byte per grid point** (§3): the matrix keeps each block's blend byte at its centre
//!   and its d2 code at its north edge midpoint, a vertex no other block uses (`matrix.rs`).
//!   d2 is coded logarithmically, relative to the terrain's largest local d2, in 255 steps of
//!   2^(1/8) (9 %), rounded up; propagation runs on the coded values, so the inequality it
//!   guarantees holds on what the criterion reads. `matrix_bytes_per_sample` (= 1) is reported.
//! - **Blend** b = 2(1 − f) clamped to [0, 1], stored as ⌈255·b⌉ (at least 1: 0 means "not
//!   subdivided"). A forced block stores 1: it is drawn as flat as a subdivided block can be.
//!   A shared midpoint takes the smaller byte of its two blocks; see `geomorph.rs` for the
//!   morphed heights and the diagonal a centre morphs along.
//! - **Forced blocks' children** are not tested: the criterion declined the block, so the
//!   traversal, as in the paper, does not descend into it.
//! - **Clipping** (an option): mesh generation does not subdivide a block whose box (footprint ×
//!   height range), three times as large, is outside the frustum; fans are counted only when their
//!   block's own box may be seen. The mesh (and its `triangles`) covers the whole terrain; the fan
//!   counts are what would be drawn.
//! - **Constant load** (an option): c is set every frame by `control.rs` to hold a target of
//!   fan triangles or fan vertices, starting from the configured c.
//!
//! # Counters
//!
//! `triangles` = the mesh's (2 + Σ parents). `splits` / `merges` = vertices entering / leaving
//! the mesh since the previous frame (as for `lindstrom`, what an incremental renderer would
//! apply). `metric_evaluations` = evaluations of f. Extra columns: `desired_resolution_c` (c this
//! frame), `c_clamped` (the controller hit a bound), `fans`, `fan_vertices`, `fan_triangles`
//! (what the fans draw, clipped when clipping is on), `mesh_vertices`, `nodes_visited` (blocks the
//! traversal reached, clipped ones included), `subdivided` (blocks subdivided by the criterion),
//! `forced_splits` (blocks subdivided only to keep the mesh conforming), `clipped_nodes`,
//! `morphing_vertices` (vertices drawn below full blend with a non-zero error: those the mesh
//! output gives a morphed height; 0 when geomorphing is off).
//!
//! Memory: the matrix (1 byte per grid point, reported as the run fact
//! `matrix_bytes_per_sample`), two bits per grid point for the double-buffered mesh, the lists
//! of active vertices and subdivided blocks, and with geomorphing two maps of the morphing
//! vertices' heights (this frame's and the previous). It reads the shared hierarchy's heights
//! and block height ranges (for clipping) and stores nothing else. Per frame:
//! O(blocks visited + mesh).

mod brute_force;
mod clip;
mod control;
mod criterion;
mod draw;
mod fans;
mod geomorph;
mod matrix;
mod refine;
mod roughness;
mod validate;

pub use brute_force::{FromScratchFrame, FromScratchView, frame_from_scratch};
pub use clip::{GENERATION_BOX_SCALE, ViewFrustum, block_box, box_may_be_seen};
pub use control::{
    ControlStep, DESIRED_RESOLUTION_MAX, DESIRED_RESOLUTION_MIN, LoadCount, LoadTarget,
    next_desired_resolution,
};
pub use criterion::{
    Criterion, DistanceNorm, SMALLEST_BLEND_BYTE, average_elevation, blend, blend_byte,
    block_distance, block_edge_m, morph_factor, propagation_factor, subdivides,
};
pub use fans::FanCounts;
pub use matrix::{D2Scale, QuadtreeMatrix};
pub use roughness::{adjacent_finer_blocks, local_d2};
pub use validate::RottgerStateError;

use super::columns::rottger as columns;
use super::{FrameInput, LodAlgorithm};
use crate::sim::draw::{DrawCounts, GpuBuffers};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::rebuilt::RebuiltMesh;
use crate::sim::mesh::{MeshOutput, MorphedHeights, VertexSet};
use crate::sim::stats::FrameStats;
use refine::{GenerationInput, GenerationState, add_drawn_midpoints, subdivide_top_down};

pub(super) const NAME: &str = "rottger";

const EXTRA_COLUMNS: &[&str] = &[
    columns::DESIRED_RESOLUTION_C,
    columns::C_CLAMPED,
    columns::FANS,
    columns::FAN_VERTICES,
    columns::FAN_TRIANGLES,
    columns::MESH_VERTICES,
    columns::NODES_VISITED,
    columns::SUBDIVIDED,
    columns::FORCED_SPLITS,
    columns::CLIPPED_NODES,
    columns::MORPHING_VERTICES,
];

/// Parameters of Röttger's algorithm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RottgerConfig {
    /// C, the minimum global resolution (finite, ≥ 2: the paper's bound needs K ≤ 1).
    pub minimum_resolution: f64,
    /// c, the desired global resolution (finite, ≥ 0); with a load target, the starting value
    /// (> 0).
    pub desired_resolution: f64,
    /// Hold a load by choosing c every frame; `None`: c stays fixed.
    pub load: Option<LoadTarget>,
    pub distance: DistanceNorm,
    /// Propagate d2 bottom-up (the paper); `false` keeps each block's local d2.
    pub d2_propagation: bool,
    /// Frustum clipping (§2.4).
    pub clipping: bool,
    /// Geomorphing (§2.3): count the morphing vertices and draw morphed heights.
    pub geomorphing: bool,
}

/// Röttger's algorithm. Per frame: O(blocks visited + mesh); buffers are reused.
pub struct Rottger<'h> {
    /// The fans a GPU draws this frame's mesh from (`draw.rs`).
    draw: draw::FanBuffers,
    hierarchy: &'h Hierarchy,
    config: RottgerConfig,
    matrix: QuadtreeMatrix,
    mesh: RebuiltMesh,
    n_triangles: u64,
    /// c for the current frame.
    desired_resolution: f64,
    /// What the previous frame drew, in the load target's count.
    previous_load: Option<u64>,
    /// Centres of the blocks subdivided this frame, in the order they entered the mesh.
    subdivided: Vec<u32>,
    /// With geomorphing: the heights of this frame's morphing vertices (the mesh output's).
    /// Empty without.
    morphed: MorphedHeights,
    stack: Vec<(GridPoint, u32)>,
}

impl<'h> Rottger<'h> {
    /// Preprocesses the quadtree matrix (O(samples)); the mesh starts as the base mesh. The
    /// parameters must satisfy [`RottgerConfig`]'s bounds (the experiment validation does it).
    pub fn new(hierarchy: &'h Hierarchy, config: RottgerConfig) -> Rottger<'h> {
        let c_ok = if config.load.is_some() {
            config.desired_resolution > 0.0
        } else {
            config.desired_resolution >= 0.0
        };
        assert!(
            config.minimum_resolution >= 2.0
                && config.minimum_resolution.is_finite()
                && c_ok
                && config.desired_resolution.is_finite()
                && config.load.is_none_or(|load| load.target >= 1),
            "Röttger's parameters out of range: {config:?}"
        );
        let lattice = hierarchy.lattice();
        Rottger {
            draw: draw::FanBuffers::new(),
            hierarchy,
            config,
            matrix: roughness::build_matrix(
                hierarchy,
                config.minimum_resolution,
                config.d2_propagation,
            ),
            mesh: RebuiltMesh::new(lattice),
            n_triangles: 2,
            desired_resolution: config.desired_resolution,
            previous_load: None,
            subdivided: Vec::new(),
            morphed: MorphedHeights::new(),
            stack: Vec::new(),
        }
    }

    pub fn config(&self) -> &RottgerConfig {
        &self.config
    }

    /// This frame's mesh: the vertices of its fans.
    pub fn vertex_set(&self) -> &VertexSet {
        self.mesh.mesh()
    }

    /// The quadtree matrix (d2 codes, this frame's blend bytes).
    pub fn matrix(&self) -> &QuadtreeMatrix {
        &self.matrix
    }

    /// c as used by the last frame (the configured c before the first).
    pub fn desired_resolution(&self) -> f64 {
        self.desired_resolution
    }

    /// The blend b (0..=1) the vertex `p` is drawn with, or `None` when it is not in the mesh.
    /// Corners and vertices drawn at their own height give 1.
    pub fn vertex_blend(&self, p: GridPoint) -> Option<f64> {
        let lattice = self.hierarchy.lattice();
        self.mesh
            .mesh()
            .contains_point(lattice, p)
            .then(|| morph_factor(geomorph::vertex_blend_byte(lattice, &self.matrix, p)))
    }

    /// The height the mesh draws vertex `p` at: with geomorphing, z − (1 − b)·ε (see
    /// `geomorph.rs`); without it, or for a vertex not in the mesh, the sample's height. The
    /// mesh output hands it on (rounded to `f32`) for every morphing vertex.
    pub fn drawn_height(&self, p: GridPoint) -> f64 {
        let lattice = self.hierarchy.lattice();
        if !self.config.geomorphing || !self.mesh.mesh().contains_point(lattice, p) {
            return f64::from(self.hierarchy.height(p));
        }
        let byte = geomorph::vertex_blend_byte(lattice, &self.matrix, p);
        geomorph::morphed_height(self.hierarchy, p, byte)
    }

    /// Checks this frame's matrix entries and mesh against each other (`validate.rs`).
    /// O(samples).
    pub fn validate_frame(&self) -> Result<(), RottgerStateError> {
        validate::validate_frame(
            self.hierarchy,
            &self.matrix,
            self.mesh.mesh(),
            &self.subdivided,
            self.config.geomorphing.then_some(&self.morphed),
        )
    }

    /// Checks the stored d2 codes against a recomputation and the propagation inequality.
    /// O(samples).
    pub fn validate_roughness(&self) -> Result<(), RottgerStateError> {
        validate::validate_roughness(
            self.hierarchy,
            &self.matrix,
            self.config.minimum_resolution,
            self.config.d2_propagation,
        )
    }
}

impl LodAlgorithm for Rottger<'_> {
    fn name(&self) -> &'static str {
        NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        EXTRA_COLUMNS
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let hierarchy = self.hierarchy;
        let mut clamped = false;
        if let (Some(load), Some(drawn)) = (self.config.load, self.previous_load) {
            let step = next_desired_resolution(self.desired_resolution, drawn, load.target);
            self.desired_resolution = step.desired_resolution;
            clamped = step.clamped;
        }
        let frustum = self
            .config
            .clipping
            .then(|| clip::ViewFrustum::new(input.camera));
        let generation = GenerationInput {
            hierarchy,
            criterion: Criterion {
                minimum_resolution: self.config.minimum_resolution,
                desired_resolution: self.desired_resolution,
                norm: self.config.distance,
            },
            camera: input.camera,
            clipping: frustum.as_ref(),
        };
        let mut state = GenerationState {
            mesh: &mut self.mesh,
            matrix: &mut self.matrix,
            subdivided: &mut self.subdivided,
            stack: &mut self.stack,
            triangles: 2,
        };
        state.start_frame(hierarchy);
        let counts = subdivide_top_down(&generation, &mut state);
        add_drawn_midpoints(hierarchy, &mut state);
        self.n_triangles = state.triangles;

        let fans = fans::count_fans(
            hierarchy,
            self.mesh.mesh(),
            &self.subdivided,
            frustum.as_ref(),
        );
        if self.config.geomorphing {
            geomorph::rebuild_morphed(
                hierarchy,
                &self.matrix,
                self.mesh.active(),
                &mut self.morphed,
            );
        }
        let morphing = self.morphed.len();
        if let Some(load) = self.config.load {
            self.previous_load = Some(match load.count {
                LoadCount::Triangles => fans.triangles,
                LoadCount::FanVertices => fans.vertices,
            });
        }
        let forced = self.subdivided.len() as u64 - counts.by_criterion;

        stats.triangles = self.n_triangles;
        stats.vertices_inserted = self.mesh.inserted_since_previous();
        stats.vertices_deleted = self.mesh.deleted_since_previous();
        stats.splits = stats.vertices_inserted;
        stats.merges = stats.vertices_deleted;
        stats.metric_evaluations = counts.evaluated;
        stats.extra = vec![
            self.desired_resolution,
            f64::from(u8::from(clamped)),
            fans.fans as f64,
            fans.vertices as f64,
            fans.triangles as f64,
            self.mesh.active().len() as f64,
            counts.visited as f64,
            counts.by_criterion as f64,
            forced as f64,
            counts.clipped as f64,
            morphing as f64,
        ];
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        self.draw.prepare(
            self.hierarchy,
            self.mesh.mesh(),
            &self.subdivided,
            self.config.geomorphing.then_some(&self.morphed),
        )
    }

    fn buffers(&self) -> &GpuBuffers {
        self.draw.gpu()
    }

    fn mesh(&self) -> MeshOutput<'_> {
        if self.config.geomorphing {
            MeshOutput::morphed_lattice(self.mesh.mesh(), &self.morphed)
        } else {
            MeshOutput::lattice(self.mesh.mesh())
        }
    }

    fn triangle_count(&self) -> u64 {
        self.n_triangles
    }

    fn memory_bytes(&self) -> usize {
        self.matrix.memory_bytes()
            + self.draw.memory_bytes()
            + self.mesh.memory_bytes()
            + self.subdivided.capacity() * std::mem::size_of::<u32>()
            + self.morphed.memory_bytes()
            + self.stack.capacity() * std::mem::size_of::<(GridPoint, u32)>()
    }

    fn run_facts(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("matrix_bytes_per_sample", self.matrix.bytes_per_sample()),
            (
                "propagation_k",
                propagation_factor(self.config.minimum_resolution),
            ),
            ("d2_max", self.matrix.scale().largest()),
        ]
    }
}

#[cfg(test)]
mod tests;
