//! Runtime detail's state between frames: the displacement function, the cache of synthesised
//! chunks, and how a sibling group is made (Lauritsen–Nielsen §3.4.3: four children from their
//! parent's bordered base grid). The policy is described in `detail.rs`; requests are served in
//! `requests.rs`.

use super::SkirtDepth;
use super::detail::{DetailCache, DetailConfig, DetailGeometry, Displacement, source_leaf_base};
use super::tree::{ChunkId, ChunkTree};

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

    /// The most chunks made per frame.
    pub(super) fn creation_limit(&self) -> u64 {
        u64::from(self.config.max_created_per_frame)
    }

    /// The most chunks held.
    pub(super) fn cache_cap(&self) -> usize {
        self.config.cache_chunks as usize
    }

    /// Makes `parent`'s four children in `frame` and holds them, drawn from `available_from` on.
    pub(super) fn synthesise_children(
        &mut self,
        tree: &ChunkTree,
        parent: ChunkId,
        frame: u64,
        available_from: u64,
    ) {
        let leaf_level = self.geometry.leaf_level;
        let children = if parent.level == leaf_level {
            let base = source_leaf_base(tree.hierarchy(), parent, self.geometry.cells);
            let error = tree.record(parent).error;
            self.geometry
                .synthesise_children(parent, &base, error, &self.displacement)
        } else {
            let chunk = self
                .cache
                .get_any(parent)
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
            self.cache.insert(id, chunk, frame, available_from);
        }
    }

    /// Heap bytes held by the cache.
    pub(super) fn memory_bytes(&self) -> usize {
        self.cache.memory_bytes()
    }
}
