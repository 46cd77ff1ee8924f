//! `chunked`: the chunked quadtree of Lauritsen and Nielsen 2005 (§3.2), after Ulrich's chunked
//! LOD: chunks of (2^c + 1)² vertices at every level of a quadtree, selected top-down each
//! frame, skirts hung from every chunk border, morphing, box culling and front-to-back order as
//! effects; runtime detail (§3.3–3.4) and out-of-core loading (§3.2.14) as two more. Loading is
//! a model counted in frames (`loading.rs`); the loaded chunks' heights can also be read from a
//! prepared pyramid on disk (see "Heights read from disk" below).
//!
//! # The algorithm as the paper gives it
//!
//! - **Chunks** (§3.2.1–3.2.3): the root holds the whole terrain every 2^D-th sample, each
//!   level halves the stride, the leaves (level D) hold the samples themselves; every chunk is a
//!   grid of (2^c + 1)² vertices (65² by default, the paper's), simplified by dropping every
//!   other row and column (geomipmapping's scheme). See `tree.rs`.
//! - **Errors** (eq. 3.1): δ_c = 0 at a leaf, max(children's δ_c) + δ_m above, δ_m the largest
//!   vertical distance of a dropped vertex from the line between its two neighbours.
//! - **Selection** (listing 3.2): from the root, refine while d < δ_c·C (eq. 3.3,
//!   C = S/(2τ·tan(fov/2))), draw otherwise. See `select.rs`.
//! - **Skirts** (§3.2.6): a vertical curtain of depth δ_c below every chunk border. See
//!   `mesh.rs`.
//! - **Morphing** (§3.2.8, eq. 3.4–3.5), an effect: per chunk, f = 1 − (d − d_m)/(d_mp − d_m).
//! - **Culling and order** (§3.2.11–12), effects: chunks whose box is outside the view volume
//!   are not drawn and not descended; children are visited nearest first.
//!
//! # Decisions where the paper is open
//!
//! - **The distance d** is from the eye to the chunk's box (its square × the height range of
//!   its samples), 0 inside it; the paper says "the distance from the viewpoint to the chunk".
//!   The same d drives the morph factor.
//! - **The projection.** The paper assumes a horizontal view direction (eq. 3.2), which we keep
//!   as the default; [`Projection::Exact`] uses the exact vertical projection of its reference
//!   \[13\] (Lindstrom'96) over the box instead, so that the audit can show what the assumption
//!   costs.
//! - **Skirt depth.** The paper's δ_c is zero at the leaves, so a leaf's skirt covers nothing;
//!   [`SkirtDepth::Covering`] is the option whose skirts provably cover every crack (see
//!   there). The audit's `audit_cracks_uncovered` measures both.
//! - **Morph heights at borders**: every odd vertex of the chunk morphs, its border vertices
//!   included, so neighbours with different factors disagree along their border; the skirts
//!   hide that too (as the paper intends), and the audit measures the gap.
//! - **Culled chunks** are left out of the mesh and declared to it as culled regions, so
//!   `--check` knows the surface may leave them uncovered; the audit counts any sample of them
//!   in view as a hole (none, since the culling test is conservative).
//! - **Triangle target** ([`BlockGoal::TargetTriangles`]): τ is chosen every frame as the
//!   smallest (to 1/64 of an octave) whose mesh fits the target, skirts included (see
//!   `block_lod/budget.rs`).
//! - **Counters.** `splits`: chunks drawn last frame that are refined now; `merges`: chunks
//!   drawn now that were refined last frame; `vertices_inserted`/`vertices_deleted`: the
//!   vertices (grid and skirt bottoms) of chunks that started or stopped being drawn;
//!   `metric_evaluations`: chunks visited, over every selection pass of the frame (the target
//!   search runs several). Columns: `chunks_drawn`, `chunks_culled`, `skirt_depth_max_m` (the
//!   deepest skirt drawn), `order_inversions` (consecutive drawn chunks the second of which is
//!   nearer: what front-to-back order removes), `tau_px`, `target_unreachable`.
//!
//! # Runtime detail and out-of-core loading (§3.2.14, §3.3–3.4), two effects
//!
//! Chunks are named by [`ChunkId`] (level, x, y), never by an index into an array built up
//! front, and the selection, the mesh builder and the validator read them through the
//! `ChunkSource` trait (`tree.rs`) as one view, `source.rs`'s `Available`: the source tree (with
//! loading on, only its resident chunks) and the cache of synthesised chunks. A chunk whose
//! children are not available is drawn in their place and its children are requested
//! (listing 3.6 / 3.7); `requests.rs` serves the requests after the frame's selection.
//!
//! - **`detail`** (`detail.rs`, `synthesis.rs`): the source leaves get the estimated error ε
//!   (the largest δ_m of sampled one-level detail additions, §3.4.1) and the tree's errors nest
//!   over it; below them, chunks down to `levels` more levels are synthesised from their parent
//!   by the four-point subdivision (Kobbelt's scheme on a regular grid) with a two-sample border,
//!   plus a seeded gradient-noise fractal displacement kept apart from the base (§3.3.1), each
//!   with half its parent's error. At most `max_queued_chunks` chunks requested and not yet
//!   finished (§3.4.4's request limit, 4–8 in the thesis), and optionally §3.4.4's limit by the
//!   viewpoint's velocity (`max_speed_per_spacing`); at most `cache_chunks` held, least
//!   recently used sibling groups evicted.
//! - **`loading`** (`loading.rs`): source chunks are resident only after a request, a latency in
//!   frames and a bandwidth in chunks per frame, under a cap of resident chunks (LRU, the
//!   paper's cache); synthesised chunks travel the same way.
//! - **Decisions.** Requests are made after the frame's selection, so a chunk is drawn at the
//!   earliest the frame after it was wanted (the asynchronous scheme; latency ≥ 1). Requests
//!   not served are not queued: the selection asks again while it still wants them. A group
//!   used in the current frame, or still on its way, is never evicted; with nothing evictable a
//!   request waits, so the caps hold in every frame. A synthesised chunk's box is its own
//!   samples' range, and when children are made their parent's box and its ancestors' (source
//!   chunks' included) grow to enclose theirs, so that box culling, which skips a subtree with
//!   its root's box, never hides detail in view (`synthesis.rs`; boxes never shrink). With both effects off every count is
//!   what it was before they existed.
//! - **A terrain too large for memory** is flown as a small source extended by synthesised
//!   levels (a 1025² source with six levels is a 65 537² surface,
//!   `experiments/lauritsen-65537.json`): the surface is evaluated per chunk on demand and held
//!   only in the cache, never built whole (the detail audit builds it only up to
//!   [`detail::DETAIL_TRUTH_MAX_SAMPLES`]).
//! - **Heights read from disk** ([`Chunked::with_disk_heights`], `loading.rs`): under the
//!   `loading` effect, the source chunks' heights can come from a [`ChunkHeightSource`] (the
//!   edge's loader thread over a pyramid that `roamsim prepare` writes, `src/edge/pyramid`)
//!   rather than the shared field; the loading model still decides when a chunk is available
//!   and a frame waits for a read not done by then, so the meshes are the in-memory ones
//!   (`tests/pyramid_format.rs`). An experiment whose terrain is a pyramid runs over a paged
//!   height field (`sim::terrain::paged`): the tree comes from the pyramid's records
//!   (`tree/from_records.rs`) and the heights from the loader, so no sample is held but the
//!   resident chunks and the field's bounded cache (`tests/pyramid_run.rs`).
//!
//! # What the GPU keeps (issue #31), `buffers.rs`
//!
//! Ulrich's chunked LOD's own representation (§3.2.3, §3.2.8, §3.2.14): each chunk a static
//! vertex buffer (grid and skirts, 16-byte vertices carrying the morph target), made once when
//! the chunk is first drawn after it became available and released when it is evicted (in-memory
//! tree chunks: after `IDLE_FRAMES`, 120 frames, undrawn); one index buffer shared by every
//! chunk (all have the same topology); per frame only the draw list, one draw per drawn chunk
//! with its blend 1 − f as a 4-byte per-draw constant, the vertex shader morphing by
//! `draw::morph_height`, which the mesh's heights are computed with too. The update makes the
//! drawn chunks' missing buffers and builds the mesh from the buffers' vertices and the shared
//! indices: a chunk's heights are read once, when its buffer is made, not every frame.
//!
//! Memory: 16 bytes per chunk for the tree (about 0.005 B per sample with 65² chunks), the
//! triangle list (O(drawn triangles)), the selection's buffers; with runtime detail the cached
//! chunks (`detail.rs`), with loading the resident chunks' heights (`loading.rs`); the chunks'
//! vertex buffers (those drawn within the idle window or resident), counted in `memory_bytes`. Per frame:
//! O(chunks visited + drawn triangles), several selection passes with a target.

mod brute_force;
mod buffers;
mod cache;
pub mod detail;
mod loading;
mod mesh;
mod requests;
mod select;
mod source;
mod synthesis;
mod tree;
mod validate;

pub use brute_force::chunks_from_scratch;
pub use detail::DetailConfig;
pub use loading::{ChunkHeightSource, ChunkRead, DiskFrame, LoadingConfig};
pub use select::DrawnChunk;
pub use tree::{ChunkId, ChunkRecord, SkirtDepth, chunk_own_error};
pub use validate::ChunkedError;

use super::block_lod::budget::finest_tau_within;
use super::block_lod::threshold::DetailThreshold;
use super::block_lod::{BlockGoal, Projection};
use super::columns::chunked as columns;
use super::{FrameInput, LodAlgorithm};
use crate::sim::draw::{DrawCounts, GpuBuffers};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::{CrackPolicy, MeshOutput, TriangleList};
use crate::sim::stats::FrameStats;
use crate::sim::view::{Camera, ViewSettings};
use buffers::ChunkBuffers;
use detail::DetailGeometry;
use loading::{DiskHeights, Loading};
use select::{Selection, SelectionSettings, select};
use source::Available;
use synthesis::RuntimeDetail;
use tree::{ChunkSource, ChunkTree};

pub(super) const NAME: &str = "chunked";

// The extra columns come in groups, always in this order; an entry writes the groups its
// configuration uses (`extra_columns`), and `update` pushes their values in the same order.

/// Every entry's columns.
const SELECTION_COLUMNS: &[&str] = &[
    columns::CHUNKS_DRAWN,
    columns::CHUNKS_CULLED,
    columns::SKIRT_DEPTH_MAX,
    columns::ORDER_INVERSIONS,
    columns::TAU,
    columns::TARGET_UNREACHABLE,
];

/// With detail or loading: the chunks drawn coarser than chosen and the requests under way.
const REQUEST_COLUMNS: &[&str] = &[columns::CHUNKS_COARSER, columns::REQUESTS_IN_FLIGHT];

/// With synthesised detail.
const DETAIL_COLUMNS: &[&str] = &[
    columns::DETAIL_SYNTHESISED,
    columns::DETAIL_EVICTED,
    columns::DETAIL_CACHED,
    columns::DETAIL_REFUSED,
    columns::DETAIL_SYNTHESIS_MS,
    columns::DETAIL_BYTES,
    columns::DETAIL_DEEPEST_DRAWN,
];

/// With out-of-core loading.
const LOADING_COLUMNS: &[&str] = &[
    columns::REQUESTS_WAITING,
    columns::CHUNKS_LOADED,
    columns::CHUNKS_UNLOADED,
    columns::RESIDENT_CHUNKS,
    columns::RESIDENT_BYTES,
];

/// With loading whose heights are read from disk: the reads.
const DISK_COLUMNS: &[&str] = &[
    columns::CHUNKS_READ,
    columns::READ_LATENCY_MAX_US,
    columns::READ_LATENCY_MEAN_US,
    columns::READ_WAIT_US,
];

/// `groups`' columns one after another, as an array of exactly `N` names (checked when the
/// constants below are evaluated, at compile time).
const fn joined<const N: usize>(groups: &[&[&'static str]]) -> [&'static str; N] {
    let mut out = [""; N];
    let (mut g, mut k) = (0, 0);
    while g < groups.len() {
        let mut i = 0;
        while i < groups[g].len() {
            out[k] = groups[g][i];
            (i, k) = (i + 1, k + 1);
        }
        g += 1;
    }
    assert!(
        k == N,
        "the joined column groups do not have the declared length"
    );
    out
}

const EXTRA_COLUMNS: &[&str] = SELECTION_COLUMNS;
const EXTRA_COLUMNS_WITH_DETAIL: &[&str] =
    &joined::<15>(&[SELECTION_COLUMNS, REQUEST_COLUMNS, DETAIL_COLUMNS]);
const EXTRA_COLUMNS_WITH_LOADING: &[&str] =
    &joined::<13>(&[SELECTION_COLUMNS, REQUEST_COLUMNS, LOADING_COLUMNS]);
const EXTRA_COLUMNS_WITH_DETAIL_AND_LOADING: &[&str] = &joined::<20>(&[
    SELECTION_COLUMNS,
    REQUEST_COLUMNS,
    DETAIL_COLUMNS,
    LOADING_COLUMNS,
]);
const EXTRA_COLUMNS_WITH_LOADING_FROM_DISK: &[&str] = &joined::<17>(&[
    SELECTION_COLUMNS,
    REQUEST_COLUMNS,
    LOADING_COLUMNS,
    DISK_COLUMNS,
]);
const EXTRA_COLUMNS_WITH_DETAIL_AND_LOADING_FROM_DISK: &[&str] = &joined::<24>(&[
    SELECTION_COLUMNS,
    REQUEST_COLUMNS,
    DETAIL_COLUMNS,
    LOADING_COLUMNS,
    DISK_COLUMNS,
]);

/// Parameters of the chunked quadtree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChunkedConfig {
    /// c: chunks of (2^c + 1)² vertices (1..=15; clamped to the terrain's level). The paper's
    /// is 6 (65²).
    pub chunk_level: u32,
    pub goal: BlockGoal,
    pub projection: Projection,
    pub skirts: SkirtDepth,
    /// Geomorphing by eq. 3.5.
    pub morph: bool,
    /// Box culling against the view volume.
    pub culling: bool,
    /// Children visited nearest first.
    pub front_to_back: bool,
    /// Detail synthesised below the finest source level at run time (§3.3–3.4); `None`: off.
    pub detail: Option<DetailConfig>,
    /// Out-of-core loading with a latency and a bandwidth (§3.2.14); `None`: off, every source
    /// chunk resident.
    pub loading: Option<LoadingConfig>,
}

/// The chunked quadtree. Per frame: O(chunks visited + drawn triangles); buffers are reused.
pub struct Chunked<'h> {
    /// The chunks' vertex buffers, the shared index buffer and the frame's draw list.
    draw: ChunkBuffers,
    /// The frame being drawn.
    frame: u64,
    /// The previous frame's eye (the viewpoint's velocity, for §3.4.4's limit).
    previous_eye: Option<glam::DVec3>,
    config: ChunkedConfig,
    lambda: f64,
    tree: ChunkTree<'h>,
    /// Runtime detail, when on (boxed: an entry without it stays small).
    detail: Option<Box<RuntimeDetail>>,
    /// Out-of-core loading, when on.
    loading: Option<Box<Loading>>,
    list: TriangleList,
    selection: Selection,
    /// Scratch selection for the target search's counting passes (boxed: only a target uses it).
    counting: Box<Selection>,
    /// τ of the current frame (the last one drawn), pixels.
    tau_px: f64,
    target_unreachable: bool,
    /// Last frame's drawn chunks (sorted by id) with their morph factors' bits, and refined
    /// chunks (sorted).
    previous_drawn: Vec<(ChunkId, u64)>,
    previous_refined: Vec<ChunkId>,
    drawn_sorted: Vec<(ChunkId, u64)>,
    refined_sorted: Vec<ChunkId>,
}

impl<'h> Chunked<'h> {
    /// Builds the chunk tree (O(samples)). The goal's τ must be finite and ≥ 0 (the experiment
    /// validation guarantees it). Over a terrain read on demand (`terrain::paged`) whose chunk
    /// level is the entry's, without detail: the tree from the source's records (O(chunks), no
    /// height read) and, with `loading` on, the chunks' heights from its reader.
    pub fn new(
        hierarchy: &'h Hierarchy,
        config: ChunkedConfig,
        view: &ViewSettings,
    ) -> Chunked<'h> {
        let tau_px = match config.goal {
            BlockGoal::TolerancePx(tau) => {
                assert!(
                    tau.is_finite() && tau >= 0.0,
                    "chunked's τ must be finite and at least 0, not {tau}"
                );
                tau
            }
            BlockGoal::TargetTriangles(_) => 1.0,
        };
        let terrain_level = hierarchy.lattice().level();
        let cells = 1u32 << config.chunk_level.clamp(1, terrain_level);
        let leaf_level = terrain_level - config.chunk_level.clamp(1, terrain_level);
        let geometry = DetailGeometry { cells, leaf_level };
        let detail_config = effective_detail(hierarchy, &config);
        let leaf_error = detail_config.map_or(0.0, |detail| {
            geometry.estimate_leaf_error(hierarchy, &detail)
        });
        // A terrain read on demand gives the tree's records and the chunks' heights itself.
        let paged = hierarchy.field().paged_samples().filter(|paged| {
            detail_config.is_none() && paged.chunk_level() == terrain_level - leaf_level
        });
        let from_records = paged.and_then(|paged| {
            let records = paged.chunk_records();
            ChunkTree::from_records(
                hierarchy,
                paged.chunk_level(),
                config.skirts,
                config.morph,
                records,
            )
            .ok()
        });
        let tree = from_records.unwrap_or_else(|| {
            ChunkTree::new(
                hierarchy,
                config.chunk_level,
                config.skirts,
                config.morph,
                leaf_error,
            )
        });
        let mut loading = config
            .loading
            .map(|loading| Box::new(Loading::new(loading, cells)));
        if let (Some(loading), Some(paged)) = (loading.as_mut(), paged) {
            // Without a reader the heights come through the field (the same file, the same
            // values); a file that cannot be read says so through the field's failure.
            loading.disk = paged.chunk_reader().and_then(DiskHeights::new).ok();
        }
        Chunked {
            draw: ChunkBuffers::new(cells, config.morph),
            frame: 0,
            config,
            lambda: view.pixels_per_unit(),
            detail: detail_config.map(|detail| {
                let spacing = hierarchy.field().spacing();
                Box::new(RuntimeDetail::new(
                    detail,
                    geometry,
                    config.skirts,
                    spacing.dx.max(spacing.dy),
                ))
            }),
            previous_eye: None,
            loading,
            tree,
            list: TriangleList::new(hierarchy.lattice(), CrackPolicy::Skirted),
            selection: Selection::default(),
            counting: Box::default(),
            tau_px,
            target_unreachable: false,
            previous_drawn: Vec::new(),
            previous_refined: Vec::new(),
            drawn_sorted: Vec::new(),
            refined_sorted: Vec::new(),
        }
    }

    /// Reads the source chunks' heights from `source` (a file, on a loader thread) instead of
    /// the shared field, under the entry's out-of-core loading, which still decides when each
    /// chunk is available (`loading.rs`); the root is read now. The records stay the tree's
    /// (a pyramid holds the same). Refused without loading on, or when the root cannot be read.
    pub fn with_disk_heights(
        mut self,
        source: Box<dyn ChunkHeightSource>,
    ) -> Result<Chunked<'h>, String> {
        let Some(loading) = self.loading.as_mut() else {
            return Err(
                "heights read from disk need the entry's `loading` effect, which decides when \
                 each chunk is available"
                    .into(),
            );
        };
        loading.disk = Some(DiskHeights::new(source)?);
        Ok(self)
    }

    /// What the reads from disk did this frame; `None` without a source read from disk.
    pub fn disk_frame(&self) -> Option<DiskFrame> {
        let disk = self.loading.as_ref()?.disk.as_ref()?;
        Some(disk.frame)
    }

    /// The first read from disk that failed during the flight, a sentence naming the file and the
    /// chunk (the chunk was drawn flat, so the run's figures are not the terrain's); `None` while
    /// none failed or without a source read from disk.
    pub fn disk_failure(&self) -> Option<&str> {
        self.loading.as_ref()?.disk.as_ref()?.failure()
    }

    /// This frame's drawn chunks, in draw order.
    pub fn drawn(&self) -> &[DrawnChunk] {
        &self.selection.drawn
    }

    /// The chunks this frame drew in place of children that were not available, in visiting
    /// order: the requests for those children (listing 3.6).
    pub fn requested(&self) -> &[ChunkId] {
        &self.selection.requested
    }

    /// This frame's culled chunks.
    pub fn culled(&self) -> &[ChunkId] {
        &self.selection.culled
    }

    /// The chunks holding a vertex buffer after the last prepared frame, in id order.
    pub fn buffered_chunks(&self) -> Vec<ChunkId> {
        self.draw.resident().collect()
    }

    /// Chunk vertex buffers the last prepared frame made.
    pub fn chunk_buffers_made(&self) -> u64 {
        self.draw.made()
    }

    /// Bytes of one chunk's vertex buffer (grid and skirt bottoms).
    pub fn chunk_buffer_bytes(&self) -> u64 {
        self.draw.chunk_vertex_bytes(self.tree.geometry().cells)
    }

    /// The τ this frame was drawn with (the fixed one, or the one the target search chose).
    pub fn tau_px(&self) -> f64 {
        self.tau_px
    }

    /// The record of chunk `id`, from the source tree or the detail cache; `None` when it is
    /// not available.
    pub fn chunk(&self, id: ChunkId) -> Option<&ChunkRecord> {
        available(&self.tree, &self.detail, &self.loading).get(id)
    }

    /// The height of vertex (a, b) of the available chunk `id`'s grid.
    ///
    /// # Panics
    /// When `id` is not available.
    pub fn chunk_height(&self, id: ChunkId, a: u32, b: u32) -> f32 {
        available(&self.tree, &self.detail, &self.loading).height(id, a, b)
    }

    /// The synthesised chunks held, in id order, with their drawn heights ((2^c + 1)², row by
    /// row); empty with detail off.
    pub fn synthesised_chunks(&self) -> Vec<(ChunkId, &[f32])> {
        self.detail.as_ref().map_or_else(Vec::new, |detail| {
            detail
                .cache
                .iter()
                .map(|(id, chunk)| (id, chunk.heights.as_slice()))
                .collect()
        })
    }

    /// The deepest level a chunk can have (the source leaves', or the deepest synthesised).
    pub fn finest_level(&self) -> u32 {
        available(&self.tree, &self.detail, &self.loading).finest_level()
    }

    /// The level of the full-resolution leaves.
    pub fn leaf_level(&self) -> u32 {
        self.tree.leaf_level()
    }

    /// Chunks in the tree.
    pub fn n_chunks(&self) -> usize {
        self.tree.n_chunks()
    }

    /// Checks the chunk tree against the height field: errors (eq. 3.1 recomputed), boxes,
    /// skirt depths. O(samples · levels + chunks²); the tree does not change between frames.
    pub fn validate_tree(&self) -> Result<(), ChunkedError> {
        validate::validate_tree(&self.tree, self.config)
    }

    /// Checks this frame's selection, seen from `camera`: drawn and culled chunks tile the
    /// terrain, every decision is the criterion's, morph factors are eq. 3.5's, the order is
    /// front-to-back when asked, the mesh has the counts the selection implies.
    pub fn validate_frame(&self, camera: &Camera) -> Result<(), ChunkedError> {
        let settings = self.settings(self.tau_px);
        validate::validate_frame(&validate::FrameView {
            source: available(&self.tree, &self.detail, &self.loading),
            config: self.config,
            settings: &settings,
            selection: &self.selection,
            list: &self.list,
            camera,
        })
    }

    fn settings(&self, tau_px: f64) -> SelectionSettings {
        SelectionSettings {
            threshold: DetailThreshold::new(self.lambda, tau_px),
            projection: self.config.projection,
            culling: self.config.culling,
            front_to_back: self.config.front_to_back,
            morph: self.config.morph,
        }
    }

    /// This frame's τ, and the chunks visited choosing it.
    fn choose_tau(&mut self, camera: &Camera) -> u64 {
        let BlockGoal::TargetTriangles(target) = self.config.goal else {
            return 0;
        };
        let per_chunk = mesh::triangles_per_chunk(self.tree.geometry().cells);
        let mut visited = 0;
        let source = available(&self.tree, &self.detail, &self.loading);
        let (tree, counting) = (&self.tree, &mut *self.counting);
        let (lambda, config) = (self.lambda, self.config);
        let choice = finest_tau_within(target, self.tau_px, |tau_px| {
            let settings = SelectionSettings {
                threshold: DetailThreshold::new(lambda, tau_px),
                projection: config.projection,
                culling: config.culling,
                front_to_back: false,
                morph: false,
            };
            select(&source, tree.geometry(), camera, &settings, counting);
            visited += counting.visited;
            counting.drawn.len() as u64 * per_chunk
        });
        self.tau_px = choice.tau_px;
        self.target_unreachable = choice.unreachable;
        visited
    }

    /// Fills the triangle list from the selection.
    fn build_mesh(&mut self) {
        self.list.clear();
        let geometry = *self.tree.geometry();
        for &id in &self.selection.culled {
            let (low, high) = geometry.square(id);
            self.list.add_culled_region(low, high);
        }
        // The drawn chunks' buffers first: the mesh is read from them (a chunk's vertices are
        // computed once, when its buffer is made).
        let source = available(&self.tree, &self.detail, &self.loading);
        self.draw
            .make_drawn(&source, &geometry, &self.selection.drawn, self.frame);
        let indices = self.draw.indices();
        for chunk in &self.selection.drawn {
            mesh::add_chunk(
                &mut self.list,
                &geometry,
                chunk,
                self.draw.vertices(chunk.id),
                indices,
            );
        }
    }

    /// Consecutive drawn chunks whose second is nearer (Euclidean distance to the box).
    fn order_inversions(&self, camera: &Camera) -> u64 {
        let geometry = self.tree.geometry();
        let source = available(&self.tree, &self.detail, &self.loading);
        let distances: Vec<f64> = self
            .selection
            .drawn
            .iter()
            .map(|c| {
                geometry
                    .block_box(c.id, source.record(c.id))
                    .distance(camera.eye)
            })
            .collect();
        distances.windows(2).filter(|w| w[1] < w[0]).count() as u64
    }
}

impl LodAlgorithm for Chunked<'_> {
    fn name(&self) -> &'static str {
        NAME
    }

    fn extra_columns(&self) -> &'static [&'static str] {
        let from_disk = self.disk_frame().is_some();
        match (self.detail.is_some(), self.loading.is_some(), from_disk) {
            (false, false, _) => EXTRA_COLUMNS,
            (true, false, _) => EXTRA_COLUMNS_WITH_DETAIL,
            (false, true, false) => EXTRA_COLUMNS_WITH_LOADING,
            (true, true, false) => EXTRA_COLUMNS_WITH_DETAIL_AND_LOADING,
            (false, true, true) => EXTRA_COLUMNS_WITH_LOADING_FROM_DISK,
            (true, true, true) => EXTRA_COLUMNS_WITH_DETAIL_AND_LOADING_FROM_DISK,
        }
    }

    fn update(&mut self, input: &FrameInput, stats: &mut FrameStats) {
        let camera = input.camera;
        self.frame = input.frame;
        // Chunks due by this frame arrive.
        if let Some(detail) = self.detail.as_mut() {
            detail.cache.set_frame(input.frame);
            detail.enclose_pending(&self.tree);
        }
        if let Some(loading) = self.loading.as_mut() {
            loading.resident.set_frame(input.frame);
            if let Some(disk) = loading.disk.as_mut() {
                disk.arrive(input.frame, &self.tree);
            }
        }
        let search_visits = self.choose_tau(camera);
        let settings = self.settings(self.tau_px);
        select(
            &available(&self.tree, &self.detail, &self.loading),
            self.tree.geometry(),
            camera,
            &settings,
            &mut self.selection,
        );
        self.build_mesh();
        let skirt_depth_max = {
            let source = available(&self.tree, &self.detail, &self.loading);
            self.selection
                .drawn
                .iter()
                .map(|c| f64::from(source.record(c.id).skirt_depth))
                .fold(0.0, f64::max)
        };
        let order_inversions = self.order_inversions(camera);
        let deepest_drawn = self.selection.drawn.iter().map(|c| c.id.level).max();
        // The children this frame asked for: made or loaded now, drawn after the latency.
        let requests = requests::serve(
            &self.tree,
            &self.selection,
            self.detail.as_deref_mut(),
            self.loading.as_deref_mut(),
            input.frame,
            self.previous_eye
                .map_or(0.0, |previous| previous.distance(camera.eye)),
        );
        self.previous_eye = Some(camera.eye);

        // What changed since the previous frame.
        let cells = self.tree.geometry().cells;
        self.drawn_sorted.clear();
        self.drawn_sorted.extend(
            self.selection
                .drawn
                .iter()
                .map(|c| (c.id, c.morph.to_bits())),
        );
        self.drawn_sorted.sort_unstable();
        self.refined_sorted.clear();
        self.refined_sorted
            .extend_from_slice(&self.selection.refined);
        self.refined_sorted.sort_unstable();
        let was_drawn = |id: ChunkId, list: &[(ChunkId, u64)]| {
            list.binary_search_by(|(other, _)| other.cmp(&id)).ok()
        };
        let (mut entered, mut left, mut splits, mut merges) = (0, 0, 0, 0);
        for &(id, _) in &self.drawn_sorted {
            match was_drawn(id, &self.previous_drawn) {
                Some(_) => {}
                None => {
                    entered += 1;
                    merges += u64::from(self.previous_refined.binary_search(&id).is_ok());
                }
            }
        }
        for &(id, _) in &self.previous_drawn {
            if was_drawn(id, &self.drawn_sorted).is_none() {
                left += 1;
                splits += u64::from(self.refined_sorted.binary_search(&id).is_ok());
            }
        }
        std::mem::swap(&mut self.previous_drawn, &mut self.drawn_sorted);
        std::mem::swap(&mut self.previous_refined, &mut self.refined_sorted);

        let per_chunk = mesh::vertices_per_chunk(cells);
        stats.triangles = self.list.n_triangles();
        stats.splits = splits;
        stats.merges = merges;
        stats.vertices_inserted = entered * per_chunk;
        stats.vertices_deleted = left * per_chunk;
        stats.metric_evaluations = search_visits + self.selection.visited;
        stats.extra = vec![
            self.selection.drawn.len() as f64,
            self.selection.culled.len() as f64,
            skirt_depth_max,
            order_inversions as f64,
            self.tau_px,
            f64::from(u8::from(self.target_unreachable)),
        ];
        if self.detail.is_some() || self.loading.is_some() {
            let in_flight = self.detail.as_ref().map_or(0, |d| d.cache.in_flight())
                + self.loading.as_ref().map_or(0, |l| l.resident.in_flight());
            stats
                .extra
                .extend([self.selection.unavailable as f64, in_flight as f64]);
        }
        if let Some(detail) = self.detail.as_ref() {
            stats.extra.extend([
                requests.synthesised as f64,
                requests.evicted as f64,
                detail.cache.len() as f64,
                requests.refused as f64,
                requests.synthesis_ns as f64 * 1e-6,
                detail.memory_bytes() as f64,
                f64::from(deepest_drawn.unwrap_or(0)),
            ]);
        }
        if let Some(loading) = self.loading.as_ref() {
            stats.extra.extend([
                requests.waiting as f64,
                requests.loaded as f64,
                requests.unloaded as f64,
                loading.resident.len() as f64,
                loading.memory_bytes() as f64,
            ]);
        }
        if let Some(disk) = self.disk_frame() {
            let us = |ns: u64| ns as f64 * 1e-3;
            stats.extra.extend([
                disk.chunks_arrived as f64,
                us(disk.read_latency_max_ns),
                us(disk
                    .read_latency_sum_ns
                    .checked_div(disk.chunks_arrived)
                    .unwrap_or(0)),
                us(disk.wait_ns),
            ]);
        }
    }

    fn prepare_draw(&mut self) -> DrawCounts {
        let source = available(&self.tree, &self.detail, &self.loading);
        self.draw.prepare(
            &source,
            self.tree.geometry(),
            &self.selection.drawn,
            self.frame,
            self.loading.is_none(),
        )
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
        self.tree.memory_bytes()
            + self.list.memory_bytes()
            + self.selection.memory_bytes()
            + self.counting.memory_bytes()
            + (self.previous_drawn.capacity() + self.drawn_sorted.capacity())
                * std::mem::size_of::<(ChunkId, u64)>()
            + (self.previous_refined.capacity() + self.refined_sorted.capacity())
                * std::mem::size_of::<ChunkId>()
            + self.draw.memory_bytes()
            + self
                .detail
                .as_deref()
                .map_or(0, RuntimeDetail::memory_bytes)
            + self.loading.as_deref().map_or(0, Loading::memory_bytes)
    }

    fn run_facts(&self) -> Vec<(&'static str, f64)> {
        let mut facts = vec![
            ("chunks", self.tree.n_chunks() as f64),
            ("leaf_level", f64::from(self.tree.leaf_level())),
            (
                "triangles_per_chunk",
                mesh::triangles_per_chunk(self.tree.geometry().cells) as f64,
            ),
        ];
        if let Some(detail) = &self.detail {
            facts.extend([
                ("detail_finest_level", f64::from(detail.finest_level)),
                ("detail_leaf_error_m", f64::from(self.tree.leaf_error())),
            ]);
        }
        let reads = self
            .loading
            .as_ref()
            .and_then(|l| l.disk.as_ref()?.reads_summary());
        if let Some(reads) = reads {
            facts.extend([
                ("chunks_read", reads.reads as f64),
                ("read_latency_p50_us", reads.latency_p50_ns * 1e-3),
                ("read_latency_p95_us", reads.latency_p95_ns * 1e-3),
                ("read_latency_max_us", reads.latency_max_ns * 1e-3),
                ("read_wait_total_ms", reads.wait_total_ns as f64 * 1e-6),
            ]);
        }
        facts
    }
}

/// The detail `config` asks for on `hierarchy`, as a run can have it: the deepest level is at
/// most 15 (chunk numbers fit a `u32`), so deeper levels are dropped (the run fact
/// `detail_finest_level` says how deep the run could go); `None` when off or when no level is
/// left.
pub fn effective_detail(hierarchy: &Hierarchy, config: &ChunkedConfig) -> Option<DetailConfig> {
    let terrain_level = hierarchy.lattice().level();
    let leaf_level = terrain_level - config.chunk_level.clamp(1, terrain_level);
    let detail = config.detail?;
    let levels = detail
        .levels
        .clamp(1, detail::MAX_DETAIL_LEVELS)
        .min(15u32.saturating_sub(leaf_level));
    (levels > 0).then_some(DetailConfig { levels, ..detail })
}

/// The synthesised surface at the deepest level `config`'s detail reaches on `hierarchy`, the
/// truth the detail audit measures against; `None` with detail off. O(4^levels · samples).
/// `None` too when that surface has more than [`detail::DETAIL_TRUTH_MAX_SAMPLES`] samples (a
/// run that flies a terrain too large for memory is not audited against it).
pub fn detail_truth(hierarchy: &Hierarchy, config: &ChunkedConfig) -> Option<detail::DetailField> {
    let detail = effective_detail(hierarchy, config)?;
    let side = (u64::from(hierarchy.lattice().cells()) << detail.levels) + 1;
    (side * side <= detail::DETAIL_TRUTH_MAX_SAMPLES)
        .then(|| detail::DetailField::new(hierarchy, &detail, detail.levels))
}

/// The chunks available now: the tree, and the detail cache when detail is on.
fn available<'a>(
    tree: &'a ChunkTree<'a>,
    detail: &'a Option<Box<RuntimeDetail>>,
    loading: &'a Option<Box<Loading>>,
) -> Available<'a> {
    Available {
        tree,
        resident: loading.as_ref().map(|loading| &loading.resident),
        disk: loading.as_ref().and_then(|loading| loading.disk.as_ref()),
        widened: detail.as_ref().map(|detail| &detail.widened),
        detail: detail
            .as_ref()
            .map(|detail| (&detail.cache, detail.finest_level)),
    }
}
