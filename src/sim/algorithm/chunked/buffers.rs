//! What chunked LOD keeps on the GPU side, as Ulrich's chunked LOD keeps it (Lauritsen–Nielsen
//! §3.2.3 and §3.2.14: a chunk is a static mesh, preprocessed and loaded as a unit): one vertex
//! buffer per chunk, made once, and one index buffer shared by every chunk; per frame only the
//! draw list, one draw per drawn chunk with its morph blend as a per-draw constant (§3.2.8: the
//! morph is done by the vertex shader from a per-chunk factor, each vertex carrying its morph
//! target). Not the selection and not the mesh: which chunks are drawn and their morph factors
//! are `select.rs`'s, the vertices and triangles `mesh.rs`'s.
//!
//! - **Vertex buffers**: a chunk's (2^c + 1)² grid vertices and its 4·2^c skirt bottoms
//!   (`mesh::chunk_vertices`), 16 bytes a vertex with morphing (the target height), 12 without.
//!   Made the first time the chunk is drawn after it became available (from the in-memory tree,
//!   or once loaded or synthesised: such a chunk is wanted when it arrives), never written
//!   again; released when the chunk stops being available (evicted by the loading or detail
//!   cache, which never evicts a chunk drawn this frame).
//! - **Chunks of the in-memory tree** (no loading) are never evicted by a cache, and keeping a
//!   buffer for every chunk ever drawn would grow towards the whole tree on a long flight (16
//!   bytes a sample at every level). So their buffers follow the paper's LRU idea on their own
//!   clock: a buffer not drawn for [`IDLE_FRAMES`] frames is released, and made again if the
//!   chunk is drawn later. The chunks a flight draws within that window stay resident, so a
//!   camera that turns back within it uploads nothing new; memory is the chunks drawn within
//!   the window, counted in `memory_bytes` like every other buffer.
//! - **Index buffer**: every chunk has the same grid and skirts, so one triangle list
//!   (`mesh::chunk_indices`) serves all, made with the algorithm. Culling is per chunk, so no
//!   clipped variant is needed.
//! - **Per frame**: the draw list, and [`CONSTANT_BYTES`] of per-draw constants per drawn chunk
//!   (its blend); a still camera uploads nothing else.
//!
//! Per frame: O(drawn chunks + resident buffers) besides the buffers made.

use super::mesh;
use super::select::DrawnChunk;
use super::source::Available;
use super::tree::{ChunkGeometry, ChunkId};
use crate::sim::draw::emit::vertex_bytes;
use crate::sim::draw::{BufferId, DrawCall, DrawCounts, DrawVertex, GpuBuffers, Topology};
use std::collections::BTreeMap;
use std::collections::btree_map::Entry;

/// Frames an in-memory tree chunk's buffer stays resident without being drawn (two seconds at
/// 60 frames a second).
pub(super) const IDLE_FRAMES: u64 = 120;

/// Bytes of per-draw constants a drawn chunk uploads each frame: its blend, one `f32`.
pub(super) const CONSTANT_BYTES: u64 = 4;

/// A chunk's vertex buffer and the last frame it was drawn.
#[derive(Clone, Copy, Debug)]
struct Resident {
    vertices: BufferId,
    last_drawn: u64,
}

/// The chunks' buffers on the GPU side (see the module docs).
#[derive(Clone, Debug)]
pub(super) struct ChunkBuffers {
    gpu: GpuBuffers,
    indices: BufferId,
    index_count: u32,
    bytes_per_vertex: u32,
    resident: BTreeMap<ChunkId, Resident>,
    /// Chunks whose buffer was made this frame (for the tests' counters).
    made: u64,
    scratch: Vec<DrawVertex>,
    released: Vec<ChunkId>,
}

impl ChunkBuffers {
    /// The shared index buffer for chunks of `cells` cells (uploaded with the first frame);
    /// vertices of `morph`ing chunks carry their target.
    pub(super) fn new(cells: u32, morph: bool) -> ChunkBuffers {
        let mut gpu = GpuBuffers::new();
        let indices = mesh::chunk_indices(cells);
        let index_count =
            u32::try_from(indices.len()).expect("a chunk has fewer than 2^32 indices");
        ChunkBuffers {
            indices: gpu.create_indices(indices),
            gpu,
            index_count,
            bytes_per_vertex: vertex_bytes(morph),
            resident: BTreeMap::new(),
            made: 0,
            scratch: Vec::new(),
            released: Vec::new(),
        }
    }

    /// Frame `frame`'s buffers, made during its update (before the mesh, which reads them):
    /// releases the buffers of chunks no longer available, then makes the buffer of every chunk
    /// of `drawn` that has none. [`ChunkBuffers::prepare`] then issues the draws.
    pub(super) fn make_drawn(
        &mut self,
        source: &Available,
        geometry: &ChunkGeometry,
        drawn: &[DrawnChunk],
        frame: u64,
    ) {
        // Evicted chunks first: an id made again later is a new chunk.
        self.release(|id, _| source.get(id).is_none());
        self.made = 0;
        for chunk in drawn {
            self.resident_for(source, geometry, chunk.id, frame);
        }
    }

    /// Frame `frame`'s upkeep: releases the buffers of chunks no longer available (and of
    /// in-memory tree chunks idle for [`IDLE_FRAMES`]), makes the buffers of drawn chunks that
    /// have none (all were made by [`ChunkBuffers::make_drawn`] unless something was evicted
    /// since), and issues one draw per chunk of `drawn`, in order. `evictable_by_idle`: whether
    /// chunks at or above `source`'s tree leaves have no cache of their own (no loading).
    pub(super) fn prepare(
        &mut self,
        source: &Available,
        geometry: &ChunkGeometry,
        drawn: &[DrawnChunk],
        frame: u64,
        evictable_by_idle: bool,
    ) -> DrawCounts {
        self.release(|id, _| source.get(id).is_none());
        self.gpu.clear_draws();
        for chunk in drawn {
            let resident = self.resident_for(source, geometry, chunk.id, frame);
            resident.last_drawn = frame;
            let vertices = resident.vertices;
            self.gpu.upload_constants(CONSTANT_BYTES);
            self.gpu.draw(DrawCall {
                vertices,
                indices: self.indices,
                first_index: 0,
                index_count: self.index_count,
                topology: Topology::TriangleList,
                blend: mesh::blend(chunk.morph),
            });
        }
        // Then in-memory tree chunks idle too long (never one drawn this frame).
        if evictable_by_idle {
            let leaf_level = source.tree.leaf_level();
            self.release(|id, resident| {
                id.level <= leaf_level && frame.saturating_sub(resident.last_drawn) > IDLE_FRAMES
            });
        }
        self.gpu.end_frame()
    }

    /// Chunk `id`'s residency, its buffer made now (at `frame`) when it has none.
    fn resident_for(
        &mut self,
        source: &Available,
        geometry: &ChunkGeometry,
        id: ChunkId,
        frame: u64,
    ) -> &mut Resident {
        match self.resident.entry(id) {
            Entry::Occupied(resident) => resident.into_mut(),
            Entry::Vacant(slot) => {
                let morph = self.bytes_per_vertex == vertex_bytes(true);
                let record = source.record(id);
                mesh::chunk_vertices(source, geometry, id, record, morph, &mut self.scratch);
                let vertices = self
                    .gpu
                    .create_vertices(self.scratch.clone(), self.bytes_per_vertex);
                self.made += 1;
                slot.insert(Resident {
                    vertices,
                    last_drawn: frame,
                })
            }
        }
    }

    /// The vertex buffer of resident chunk `id` ([`mesh::chunk_vertices`]).
    ///
    /// # Panics
    /// When `id` has no buffer (not made by [`ChunkBuffers::make_drawn`] this frame).
    pub(super) fn vertices(&self, id: ChunkId) -> &[DrawVertex] {
        let resident = self
            .resident
            .get(&id)
            .expect("a drawn chunk's buffer is resident");
        self.gpu.vertices(resident.vertices)
    }

    /// The index buffer every chunk shares ([`mesh::chunk_indices`]).
    pub(super) fn indices(&self) -> &[u32] {
        self.gpu.indices(self.indices)
    }

    /// Releases the vertex buffers of the chunks `release` names.
    fn release(&mut self, release: impl Fn(ChunkId, &Resident) -> bool) {
        self.released.clear();
        self.released.extend(
            self.resident
                .iter()
                .filter(|&(&id, resident)| release(id, resident))
                .map(|(&id, _)| id),
        );
        for id in &self.released {
            let resident = self.resident.remove(id).expect("a resident chunk");
            self.gpu.release_vertices(resident.vertices);
        }
    }

    pub(super) fn gpu(&self) -> &GpuBuffers {
        &self.gpu
    }

    /// The chunks holding a vertex buffer, in id order.
    pub(super) fn resident(&self) -> impl Iterator<Item = ChunkId> + '_ {
        self.resident.keys().copied()
    }

    /// Vertex buffers made this frame (by its update, or its draw when something was evicted
    /// in between).
    pub(super) fn made(&self) -> u64 {
        self.made
    }

    /// Bytes of one chunk's vertex buffer.
    pub(super) fn chunk_vertex_bytes(&self, cells: u32) -> u64 {
        mesh::vertices_per_chunk(cells) * u64::from(self.bytes_per_vertex)
    }

    /// Heap bytes: the buffers' model and the residency map.
    pub(super) fn memory_bytes(&self) -> usize {
        self.gpu.memory_bytes()
            + self.resident.len() * std::mem::size_of::<(ChunkId, Resident)>()
            + self.scratch.capacity() * std::mem::size_of::<DrawVertex>()
            + self.released.capacity() * std::mem::size_of::<ChunkId>()
    }
}
