//! A stitching-strips frame as the update leaves it, and its mesh made only when someone reads
//! it. The update records what the paper's CPU makes (§3, §3.2, §4.2): each drawn M-block's
//! patch words (its rectangle and factors, what the GPU is sent) and the strips and P-blocks
//! (their vertices and triangles, a [`TriangleList`] of their own), in drawing order. The
//! blocks' interiors are the GPU's work, so the update does not make them: the first read of
//! the mesh (the audit, `--check`, culling's count, PLY export, the preview, tests) tessellates
//! every block from its words with the [`BlockTessellator`] the buffers register, outside the
//! timed `update` and `prepare_draw`, and keeps the result for the rest of the frame.
//!
//! The mesh is the list the update made before issue #31's last step, bit for bit: the blocks'
//! and the crosses' triangles in drawing order (a block, or a node's strips and P-block, at a
//! time), then the culled rectangles in the order they were declared.
//!
//! Costs: recording is O(blocks + the strips' vertices and triangles) a frame; the first read
//! O(triangles); buffers are reused across frames (the made list goes back to a spare when the
//! next frame begins).
//!
//! What it is not: the tessellator (`tessellate.rs`, `buffers.rs`), the GPU's buffers
//! (`buffers.rs`, which `prepare` fills from this record) or the selection.

use super::buffers::{BlockTessellator, PATCH_WORDS};
use super::tessellate::{EdgeSpacing, PatchScratch, Rect, quad_patch_triangles};
use crate::sim::mesh::{CrackPolicy, TriangleInfo, TriangleList, TriangleRole};
use std::sync::{Arc, Mutex, OnceLock};

/// One drawn piece of the frame, in drawing order.
#[derive(Clone, Copy, Debug)]
enum Piece {
    /// The next block's patch (blocks take the patches in order), drawn with `group` and
    /// `level`.
    Block { group: u32, level: u32 },
    /// A run of the CPU's list (a node's strips and P-block): its vertices, and its triangles,
    /// which refer only to those vertices.
    Cpu {
        first_vertex: u32,
        vertices: u32,
        first_triangle: u32,
        triangles: u32,
    },
}

/// Buffers the made mesh reuses from frame to frame.
#[derive(Debug, Default)]
struct Spare {
    list: Option<TriangleList>,
    scratch: PatchScratch,
}

/// A frame's blocks (patch words), strips and P-blocks (the CPU's list), and its mesh once read.
#[derive(Debug)]
pub struct LazyMesh {
    tessellator: Arc<BlockTessellator>,
    crack_policy: CrackPolicy,
    /// The drawn blocks' patches, [`PATCH_WORDS`] words each, in drawing order.
    words: Vec<u32>,
    /// The triangles the drawn blocks' patches make (counted from their factors).
    block_triangles: u64,
    /// The strips and P-blocks, and every culled rectangle, in drawing order.
    cpu: TriangleList,
    pieces: Vec<Piece>,
    /// The frame's mesh, once read.
    made: OnceLock<TriangleList>,
    spare: Mutex<Spare>,
}

impl LazyMesh {
    /// An empty frame whose blocks `tessellator` makes, its mesh closed by `crack_policy`.
    pub fn new(tessellator: Arc<BlockTessellator>, crack_policy: CrackPolicy) -> LazyMesh {
        LazyMesh {
            cpu: tessellator.empty_list(crack_policy),
            tessellator,
            crack_policy,
            words: Vec::new(),
            block_triangles: 0,
            pieces: Vec::new(),
            made: OnceLock::new(),
            spare: Mutex::new(Spare::default()),
        }
    }

    /// Forgets the last frame (its made mesh becomes the spare the next one is made in).
    pub fn begin_frame(&mut self) {
        self.words.clear();
        self.block_triangles = 0;
        self.cpu.clear();
        self.pieces.clear();
        if let Some(list) = self.made.take() {
            self.spare_mut().list = Some(list);
        }
    }

    fn spare_mut(&mut self) -> &mut Spare {
        self.spare
            .get_mut()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Records a drawn M-block: its patch, drawn with `group` and `level` (role surface).
    /// Returns the patch's index in [`LazyMesh::words`] (in patches). O(1).
    pub fn push_block(
        &mut self,
        rect: Rect,
        inner: EdgeSpacing,
        outer: [EdgeSpacing; 4],
        group: u32,
        level: u32,
    ) -> usize {
        let patch = self.words.len() / PATCH_WORDS;
        self.words
            .extend_from_slice(&self.tessellator.words(rect, inner, outer));
        self.block_triangles += quad_patch_triangles(inner, outer);
        self.pieces.push(Piece::Block { group, level });
        patch
    }

    /// The CPU's list, for a node's strips and P-block and for culled rectangles; what is added
    /// to it is drawn once [`LazyMesh::end_cpu_run`] says where it begins.
    pub fn cpu_mut(&mut self) -> &mut TriangleList {
        &mut self.cpu
    }

    /// Records that the CPU's vertices from `first_vertex` and triangles from `first_triangle`
    /// on are drawn here in the drawing order (a node's strips and P-block).
    pub fn end_cpu_run(&mut self, first_vertex: usize, first_triangle: u64) {
        let count = |n: usize| u32::try_from(n).expect("fewer than 2^32 vertices and triangles");
        let vertices = count(self.cpu.vertices().len() - first_vertex);
        let triangles = count((self.cpu.n_triangles() - first_triangle) as usize);
        if vertices > 0 || triangles > 0 {
            self.pieces.push(Piece::Cpu {
                first_vertex: count(first_vertex),
                vertices,
                first_triangle: count(first_triangle as usize),
                triangles,
            });
        }
    }

    /// The drawn blocks' patch words, [`PATCH_WORDS`] a block, in drawing order.
    pub fn words(&self) -> &[u32] {
        &self.words
    }

    /// The strips and P-blocks (and the culled rectangles): what the CPU built.
    pub fn cpu(&self) -> &TriangleList {
        &self.cpu
    }

    /// The frame's triangles, the blocks' counted from their factors, without making them.
    pub fn n_triangles(&self) -> u64 {
        self.block_triangles + self.cpu.n_triangles()
    }

    /// The frame's mesh: made on the first call of the frame (every block tessellated from its
    /// words, the CPU's runs copied in drawing order), kept until the next frame begins.
    pub fn list(&self) -> &TriangleList {
        self.made.get_or_init(|| self.make())
    }

    fn make(&self) -> TriangleList {
        let mut spare = self
            .spare
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        let Spare { list, scratch } = &mut *spare;
        let mut list = list
            .take()
            .unwrap_or_else(|| self.tessellator.empty_list(self.crack_policy));
        list.clear();
        let mut patches = self.words.chunks_exact(PATCH_WORDS);
        let (vertices, triangles, info) =
            (self.cpu.vertices(), self.cpu.triangles(), self.cpu.info());
        for &piece in &self.pieces {
            match piece {
                Piece::Block { group, level } => {
                    let patch = patches.next().expect("a patch for every block");
                    let info = TriangleInfo {
                        role: TriangleRole::Surface,
                        group,
                        level,
                    };
                    self.tessellator.add_patch(patch, &mut list, info, scratch);
                }
                Piece::Cpu {
                    first_vertex,
                    vertices: n_vertices,
                    first_triangle,
                    triangles: n_triangles,
                } => {
                    let base = list.vertices().len() as u32;
                    let range = first_vertex as usize..(first_vertex + n_vertices) as usize;
                    for v in &vertices[range] {
                        list.add_vertex(v.position, v.z);
                    }
                    let range = first_triangle as usize..(first_triangle + n_triangles) as usize;
                    for (corners, &info) in triangles[range.clone()].iter().zip(&info[range]) {
                        list.add_triangle(corners.map(|k| k - first_vertex + base), info);
                    }
                }
            }
        }
        for &(low, high) in self.cpu.culled_regions() {
            list.add_culled_region(low, high);
        }
        list
    }

    /// Heap bytes held: the record, the made mesh and the spare.
    pub fn memory_bytes(&self) -> usize {
        let spare = self
            .spare
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        self.words.capacity() * size_of::<u32>()
            + self.cpu.memory_bytes()
            + self.pieces.capacity() * size_of::<Piece>()
            + self.made.get().map_or(0, TriangleList::memory_bytes)
            + spare.list.as_ref().map_or(0, TriangleList::memory_bytes)
            + spare.scratch.memory_bytes()
    }
}
