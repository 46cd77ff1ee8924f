//! The chunks one frame can read: the source tree (with out-of-core loading, its resident
//! chunks only) and, with synthesised detail on, the cache of chunks made below its leaves.
//! The selection, the mesh builder and the frame validator read chunks only through this view
//! ([`ChunkSource`]), so a synthesised chunk and a source chunk look alike to them; a chunk not
//! cached is simply not available.

use super::cache::GroupCache;
use super::detail::DetailCache;
use super::loading::DiskHeights;
use super::tree::{ChunkId, ChunkRecord, ChunkSource, ChunkTree};
use std::collections::BTreeMap;

/// The source tree, and the detail cache with the deepest synthesised level when detail is on.
#[derive(Clone, Copy)]
pub(super) struct Available<'a> {
    pub(super) tree: &'a ChunkTree<'a>,
    pub(super) detail: Option<(&'a DetailCache, u32)>,
    /// With out-of-core loading, the resident source chunks (the root always is).
    pub(super) resident: Option<&'a GroupCache<()>>,
    /// With a source read from disk, the resident chunks' heights as read.
    pub(super) disk: Option<&'a DiskHeights>,
    /// With detail on, the source chunks whose boxes grew to enclose synthesised chunks.
    pub(super) widened: Option<&'a BTreeMap<ChunkId, ChunkRecord>>,
}

impl<'a> Available<'a> {
    /// The chunk `id` if it is available, borrowed for as long as the tree and the cache.
    pub(super) fn get(&self, id: ChunkId) -> Option<&'a ChunkRecord> {
        if id.level <= self.tree.leaf_level() {
            let resident = match self.resident {
                Some(resident) => id == ChunkId::ROOT || resident.get(id).is_some(),
                None => true,
            };
            let widened = self.widened.and_then(|widened| widened.get(&id));
            return self
                .tree
                .chunk(id)
                .filter(|_| resident)
                .map(|r| widened.unwrap_or(r));
        }
        let (cache, _) = self.detail?;
        cache.get(id).map(|chunk| &chunk.record)
    }

    /// The deepest level a chunk can have: the source leaves', or the deepest synthesised one.
    pub(super) fn finest_level(&self) -> u32 {
        self.detail
            .map_or(self.tree.leaf_level(), |(_, finest)| finest)
    }

    /// The record of an available chunk.
    ///
    /// # Panics
    /// When `id` is not available.
    pub(super) fn record(&self, id: ChunkId) -> &ChunkRecord {
        self.chunk(id)
            .unwrap_or_else(|| panic!("chunk {id:?} is not available"))
    }
}

impl ChunkSource for Available<'_> {
    fn chunk(&self, id: ChunkId) -> Option<&ChunkRecord> {
        self.get(id)
    }

    fn is_internal(&self, id: ChunkId) -> bool {
        id.level < self.finest_level()
    }

    fn height(&self, id: ChunkId, a: u32, b: u32) -> f32 {
        if id.level <= self.tree.leaf_level() {
            return match self.disk {
                Some(disk) => disk.height(id, a, b, self.tree.geometry().cells + 1),
                None => self.tree.height(id, a, b),
            };
        }
        let (cache, _) = self
            .detail
            .expect("a chunk below the source leaves needs the detail cache");
        let chunk = cache
            .get(id)
            .unwrap_or_else(|| panic!("chunk {id:?} is not cached"));
        let side = self.tree.geometry().cells + 1;
        chunk.heights[(b * side + a) as usize]
    }
}
