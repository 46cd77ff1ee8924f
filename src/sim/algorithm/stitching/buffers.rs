//! What the stitching-strips algorithm sends to the GPU each frame (§3, §3.1.1, §3.2, §4.2 of
//! the 2019 paper), and the tessellation stage that expands it:
//!
//! - **The blocks**: one patch per drawn M-block in a per-frame instance buffer, its MBD's
//!   Position and Size (the block's rectangle, four words) and its tessellation factors (the
//!   inner factor and the four edges', five words): [`PATCH_WORDS`] words, 36 bytes a block,
//!   rewritten whole every frame (the paper recomputes every F each frame, §3.3.1) and drawn by
//!   one [`Topology::Patches`] call. The blocks' interiors are the GPU's work: the registered
//!   [`BlockTessellator`] makes them from the words and the resident height map, so they are
//!   submitted and drawn, never uploaded.
//! - **The strips and P-blocks**: built on the CPU (§3.2: "the vertices of a DSS are obtained
//!   by tessellating edges of adjacent M-blocks in CPU"), rebuilt every frame (§4.2: "the work
//!   of DSS generation needs to be done in every frame"), so their vertex and index buffers are
//!   rewritten whole every frame and drawn by one triangle-list call. The P-blocks go with them:
//!   their few vertices are the CPU's too (§3.1.2).
//!
//! What it is not: the tessellator itself (`tessellate.rs`), the frame's record of blocks and
//! strips (`lazy_mesh.rs`, which keeps the patch words and the strips' list that `prepare`
//! writes, and makes the mesh from them through the same [`BlockTessellator`], so the buffers
//! draw the mesh bit for bit) or the selection.

use super::tessellate::{self, EdgeSpacing, PatchScratch, Rect};
use crate::sim::draw::patches::Tessellator;
use crate::sim::draw::{BufferId, DrawCall, DrawCounts, DrawVertex, GpuBuffers, Topology};
use crate::sim::draw::{INDEX_BYTES, VERTEX_BYTES};
use crate::sim::hierarchy::{Hierarchy, Lattice};
use crate::sim::mesh::{CrackPolicy, SurfacePoint, TriangleInfo, TriangleList, TriangleRole};
use crate::sim::terrain::Heightfield;
use std::sync::Arc;

/// Words of one block's patch: x0, y0, x1, y1 (raw units), then the inner factor and the south,
/// east, north and west edges' (each an `f32`'s bits for fractional-even spacing, a segment
/// count for equal spacing).
pub const PATCH_WORDS: usize = 9;

/// Bytes of one block's patch data.
pub const PATCH_BYTES: u64 = PATCH_WORDS as u64 * INDEX_BYTES;

/// How a method's tessellator spaces its edges (one pipeline state per method).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpacingMode {
    /// Fractional-even spacing (the strips method, Method II).
    FractionalEven,
    /// Integer spacing (Method I's power-of-two factors).
    Equal,
}

impl SpacingMode {
    fn encode(self, spacing: EdgeSpacing) -> u32 {
        match (self, spacing) {
            (SpacingMode::FractionalEven, EdgeSpacing::FractionalEven(f)) => {
                let word = f as f32;
                debug_assert_eq!(
                    f64::from(word),
                    f,
                    "a factor reaches the tessellator as an f32"
                );
                word.to_bits()
            }
            (SpacingMode::Equal, EdgeSpacing::Equal(m)) => m,
            (mode, spacing) => panic!("a {mode:?} tessellator was given {spacing:?}"),
        }
    }

    fn decode(self, word: u32) -> EdgeSpacing {
        match self {
            SpacingMode::FractionalEven => {
                EdgeSpacing::FractionalEven(f64::from(f32::from_bits(word)))
            }
            SpacingMode::Equal => EdgeSpacing::Equal(word),
        }
    }
}

/// The patch words of a block: its rectangle and spacings. Raw units fit 32 bits: a terrain
/// has at most 2^15 cells a side (`terrain::MAX_LEVEL`), 2^31 raw units.
pub fn patch_words(
    mode: SpacingMode,
    rect: Rect,
    inner: EdgeSpacing,
    outer: [EdgeSpacing; 4],
) -> [u32; PATCH_WORDS] {
    let raw = |v: i64| u32::try_from(v).expect("a block's corner fits 32 bits of raw units");
    let mut words = [0; PATCH_WORDS];
    words[..4].copy_from_slice(&[raw(rect.x0), raw(rect.y0), raw(rect.x1), raw(rect.y1)]);
    words[4] = mode.encode(inner);
    for (word, &spacing) in words[5..].iter_mut().zip(&outer) {
        *word = mode.encode(spacing);
    }
    words
}

/// The GPU's tessellation stage for the blocks: a patch's words and the height map (resident as
/// a texture) give its triangles ([`tessellate::add_quad_patch`]). The mesh the runner reads is
/// made by it too (`lazy_mesh.rs`), so what the GPU draws and the mesh are one code.
#[derive(Debug)]
pub struct BlockTessellator {
    field: Arc<Heightfield>,
    lattice: Lattice,
    mode: SpacingMode,
}

impl BlockTessellator {
    /// The tessellator of a method spacing its edges by `mode`, over `hierarchy`'s height map.
    pub fn new(hierarchy: &Hierarchy, mode: SpacingMode) -> BlockTessellator {
        BlockTessellator {
            field: hierarchy.shared_field(),
            lattice: *hierarchy.lattice(),
            mode,
        }
    }

    /// The words of the patch of block `rect` at spacings `inner` and `outer`.
    pub fn words(
        &self,
        rect: Rect,
        inner: EdgeSpacing,
        outer: [EdgeSpacing; 4],
    ) -> [u32; PATCH_WORDS] {
        patch_words(self.mode, rect, inner, outer)
    }

    /// What a patch's words say: its rectangle, inner spacing and four outer spacings.
    pub fn patch(&self, patch: &[u32]) -> (Rect, EdgeSpacing, [EdgeSpacing; 4]) {
        let rect = Rect {
            x0: i64::from(patch[0]),
            y0: i64::from(patch[1]),
            x1: i64::from(patch[2]),
            y1: i64::from(patch[3]),
        };
        let inner = self.mode.decode(patch[4]);
        let outer = [5, 6, 7, 8].map(|k| self.mode.decode(patch[k]));
        (rect, inner, outer)
    }

    /// Adds the triangles of `patch` (its words) to `list` with `info`, as the GPU makes them.
    /// Returns (vertices added, triangles added).
    pub fn add_patch(
        &self,
        patch: &[u32],
        list: &mut TriangleList,
        info: TriangleInfo,
        scratch: &mut PatchScratch,
    ) -> (u64, u64) {
        let (rect, inner, outer) = self.patch(patch);
        tessellate::add_quad_patch(list, &self.field, rect, inner, outer, info, scratch)
    }

    /// An empty list over the terrain's domain with `crack_policy`.
    pub fn empty_list(&self, crack_policy: CrackPolicy) -> TriangleList {
        TriangleList::new(&self.lattice, crack_policy)
    }
}

impl Tessellator for BlockTessellator {
    fn words_per_patch(&self) -> usize {
        PATCH_WORDS
    }

    fn triangles(&self, patch: &[u32]) -> u64 {
        let (_, inner, outer) = self.patch(patch);
        tessellate::quad_patch_triangles(inner, outer)
    }

    fn for_each_triangle(&self, patch: &[u32], visit: &mut dyn FnMut([SurfacePoint; 3])) {
        let mut list = self.empty_list(CrackPolicy::Stitched);
        let info = TriangleInfo {
            role: TriangleRole::Surface,
            group: 0,
            level: 0,
        };
        self.add_patch(patch, &mut list, info, &mut PatchScratch::default());
        let vertices = list.vertices();
        for corners in list.triangles() {
            visit(corners.map(|k| vertices[k as usize]));
        }
    }
}

/// The GPU-side state of one stitching-strips entry: the blocks' instance buffer and the strips'
/// vertex and index buffers.
#[derive(Debug)]
pub struct StitchingBuffers {
    gpu: GpuBuffers,
    /// The blocks' patch words (an instance buffer; the draw's index buffer).
    blocks: BufferId,
    /// The patch draw's vertex buffer, never read (patches carry their data in `blocks`).
    no_vertices: BufferId,
    strip_vertices: BufferId,
    strip_indices: BufferId,
}

impl StitchingBuffers {
    /// Empty buffers, `tessellator` registered with them as their tessellation stage.
    pub fn new(tessellator: Arc<BlockTessellator>) -> StitchingBuffers {
        let mut gpu = GpuBuffers::new();
        gpu.set_tessellator(tessellator);
        StitchingBuffers {
            blocks: gpu.create_indices(Vec::new()),
            no_vertices: gpu.create_vertices(Vec::new(), VERTEX_BYTES),
            strip_vertices: gpu.create_vertices(Vec::new(), VERTEX_BYTES),
            strip_indices: gpu.create_indices(Vec::new()),
            gpu,
        }
    }

    /// Writes this frame's blocks (`words`, their patches) and strips and P-blocks (`cpu`, the
    /// list the CPU built, nothing else in it), issues the frame's draws (the patches, then the
    /// strips) and ends the frame. O(words + the strips' vertices and triangles).
    pub fn prepare(&mut self, words: &[u32], cpu: &TriangleList) -> DrawCounts {
        self.gpu
            .replace_indices(self.blocks, |out| out.extend_from_slice(words));
        self.gpu.replace_vertices(self.strip_vertices, |out| {
            out.extend(cpu.vertices().iter().map(|&v| DrawVertex::of(v)))
        });
        self.gpu.replace_indices(self.strip_indices, |out| {
            out.extend(cpu.triangles().iter().flatten())
        });
        let strip_indices = u32::try_from(cpu.n_triangles() * 3).expect("fewer than 2^32 indices");
        self.gpu.clear_draws();
        if !words.is_empty() {
            self.gpu.draw(DrawCall {
                vertices: self.no_vertices,
                indices: self.blocks,
                first_index: 0,
                index_count: u32::try_from(words.len()).expect("fewer than 2^32 words"),
                topology: Topology::Patches,
                blend: 0.0,
            });
        }
        if strip_indices > 0 {
            self.gpu.draw(DrawCall {
                vertices: self.strip_vertices,
                indices: self.strip_indices,
                first_index: 0,
                index_count: strip_indices,
                topology: Topology::TriangleList,
                blend: 0.0,
            });
        }
        self.gpu.end_frame()
    }

    pub fn gpu(&self) -> &GpuBuffers {
        &self.gpu
    }

    /// Heap bytes on the CPU side: the buffers' model.
    pub fn memory_bytes(&self) -> usize {
        self.gpu.memory_bytes()
    }
}

/// Bytes a frame uploads for `blocks` blocks and strips of `vertices` vertices and `triangles`
/// triangles: what `StitchingBuffers::prepare` writes.
pub fn frame_upload_bytes(blocks: u64, vertices: u64, triangles: u64) -> u64 {
    blocks * PATCH_BYTES + vertices * u64::from(VERTEX_BYTES) + triangles * 3 * INDEX_BYTES
}
