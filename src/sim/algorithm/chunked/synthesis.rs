//! The per-frame work of runtime detail: after the selection, mark what it visited as used,
//! then serve its requests for missing children (synthesis, within the per-frame creation
//! limit), evicting to stay within the cache's cap. The policy is described in `detail.rs`.
//!
//! Per frame: O(chunks visited + requests · (cached chunks + a chunk's samples)).

use super::SkirtDepth;
use super::detail::{DetailCache, DetailConfig, DetailGeometry, Displacement, source_leaf_base};
use super::select::Selection;
use super::tree::{ChunkId, ChunkTree};
use std::time::Instant;

/// The runtime detail's state: its settings, the displacement function and the cache.
pub(super) struct RuntimeDetail {
    config: DetailConfig,
    geometry: DetailGeometry,
    displacement: Displacement,
    skirts: SkirtDepth,
    pub(super) cache: DetailCache,
    /// The deepest synthesised level.
    pub(super) finest_level: u32,
}

/// What one frame's synthesis did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct DetailFrame {
    /// Chunks synthesised.
    pub(super) synthesised: u64,
    /// Chunks evicted.
    pub(super) evicted: u64,
    /// Requests not served this frame (over the creation limit, or no room in the cache).
    pub(super) refused: u64,
    /// Time spent synthesising and evicting, nanoseconds (inside the update).
    pub(super) synthesis_ns: u64,
}

impl RuntimeDetail {
    pub(super) fn new(
        config: DetailConfig,
        geometry: DetailGeometry,
        skirts: SkirtDepth,
    ) -> RuntimeDetail {
        RuntimeDetail {
            config,
            geometry,
            displacement: Displacement::new(&config),
            skirts,
            cache: DetailCache::default(),
            finest_level: geometry.leaf_level + config.levels,
        }
    }

    /// Marks the chunks `selection` visited as used in `frame`, then serves its requests.
    pub(super) fn after_selection(
        &mut self,
        tree: &ChunkTree,
        selection: &Selection,
        frame: u64,
    ) -> DetailFrame {
        let start = Instant::now();
        let leaf_level = self.geometry.leaf_level;
        let visited = selection
            .drawn
            .iter()
            .map(|c| c.id)
            .chain(selection.refined.iter().copied())
            .chain(selection.culled.iter().copied());
        for id in visited {
            if id.level > leaf_level {
                self.cache.touch(id, frame);
            }
        }
        let mut out = DetailFrame::default();
        let limit = u64::from(self.config.max_created_per_frame);
        let cap = self.config.cache_chunks as usize;
        for (k, &parent) in selection.requested.iter().enumerate() {
            let remaining = (selection.requested.len() - k) as u64;
            if out.synthesised + 4 > limit {
                out.refused += remaining;
                break;
            }
            while self.cache.len() + 4 > cap {
                let evicted = self.cache.evict_one(frame);
                if evicted == 0 {
                    break;
                }
                out.evicted += evicted as u64;
            }
            if self.cache.len() + 4 > cap {
                out.refused += remaining;
                break;
            }
            self.synthesise_children(tree, parent, frame);
            out.synthesised += 4;
        }
        out.synthesis_ns = start.elapsed().as_nanos() as u64;
        out
    }

    /// Makes and caches `parent`'s four children.
    fn synthesise_children(&mut self, tree: &ChunkTree, parent: ChunkId, frame: u64) {
        let leaf_level = self.geometry.leaf_level;
        let children = if parent.level == leaf_level {
            let base = source_leaf_base(tree.hierarchy(), parent, self.geometry.cells);
            let error = tree.record(parent).error;
            self.geometry
                .synthesise_children(parent, &base, error, &self.displacement)
        } else {
            let chunk = self
                .cache
                .get(parent)
                .expect("a synthesised chunk requesting children is cached");
            self.geometry.synthesise_children(
                parent,
                &chunk.base,
                chunk.record.error,
                &self.displacement,
            )
        };
        for (id, mut chunk) in children {
            chunk.record.skirt_depth = match self.skirts {
                SkirtDepth::ChunkError => chunk.record.error,
                // The source leaf above: its covering depth bounds every chunk inside it and
                // beside it (synthesised errors halve with each level).
                SkirtDepth::Covering => {
                    let leaf = id.ancestor_at(leaf_level).expect("below the leaves");
                    tree.record(leaf).skirt_depth
                }
            };
            self.cache.insert(id, chunk, frame);
        }
    }

    /// Heap bytes held by the cache.
    pub(super) fn memory_bytes(&self) -> usize {
        self.cache.memory_bytes()
    }
}
