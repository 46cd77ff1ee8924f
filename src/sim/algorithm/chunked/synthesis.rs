//! Runtime detail's state between frames: the displacement function, the cache of synthesised
//! chunks, and how a sibling group is made (Lauritsen–Nielsen §3.4.3: four children from their
//! parent's bordered base grid). The policy is described in `detail.rs`; requests are served in
//! `requests.rs`.

use super::SkirtDepth;
use super::detail::{DetailCache, DetailConfig, DetailGeometry, Displacement, source_leaf_base};
use super::tree::{ChunkId, ChunkRecord, ChunkTree};
use std::collections::BTreeMap;

/// The runtime detail's state: its settings, the displacement function and the cache.
pub(super) struct RuntimeDetail {
    config: DetailConfig,
    geometry: DetailGeometry,
    displacement: Displacement,
    skirts: SkirtDepth,
    /// The source's sample spacing, metres (the larger of dx and dy).
    spacing_m: f64,
    pub(super) cache: DetailCache,
    /// The deepest synthesised level.
    pub(super) finest_level: u32,
    /// Source chunks whose box grew to enclose chunks synthesised below them: the tree's record
    /// with the widened height range (see [`RuntimeDetail::enclose`]).
    pub(super) widened: BTreeMap<ChunkId, ChunkRecord>,
    /// Parents whose children were made this frame, with the children's height range: their
    /// boxes grow at the start of the next frame ([`RuntimeDetail::enclose_pending`]), before
    /// any selection can reach the children, so that a frame's selection sees one box per chunk.
    pending: Vec<(ChunkId, f32, f32)>,
}

impl RuntimeDetail {
    pub(super) fn new(
        config: DetailConfig,
        geometry: DetailGeometry,
        skirts: SkirtDepth,
        spacing_m: f64,
    ) -> RuntimeDetail {
        RuntimeDetail {
            config,
            geometry,
            displacement: Displacement::new(&config),
            skirts,
            spacing_m,
            cache: DetailCache::default(),
            finest_level: geometry.leaf_level + config.levels,
            widened: BTreeMap::new(),
            pending: Vec::new(),
        }
    }

    /// §3.4.4's creation limit: the most chunks requested and not yet finished.
    pub(super) fn queue_limit(&self) -> u64 {
        u64::from(self.config.max_queued_chunks)
    }

    /// Whether §3.4.4's velocity-based limit refuses `parent`'s children to a viewpoint moving
    /// `speed_m` metres this frame: faster than `max_speed_per_spacing` of the children's sample
    /// spacings (the source's halved at every level below the source leaves).
    pub(super) fn too_fast_for_children(&self, parent: ChunkId, speed_m: f64) -> bool {
        self.config.max_speed_per_spacing.is_some_and(|k| {
            let depth = parent.level + 1 - self.geometry.leaf_level;
            let spacing = self.spacing_m / f64::from(1u32 << depth);
            speed_m > k * spacing
        })
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
        let z_min = children
            .iter()
            .map(|(_, c)| c.record.z_min)
            .fold(f32::INFINITY, f32::min);
        let z_max = children
            .iter()
            .map(|(_, c)| c.record.z_max)
            .fold(f32::NEG_INFINITY, f32::max);
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
        self.pending.push((parent, z_min, z_max));
    }

    /// Widens the boxes above the children made last frame ([`RuntimeDetail::enclose`]). Called
    /// at the start of a frame: children are available at the earliest the frame after their
    /// request, so no selection reaches them through a box that does not enclose them.
    pub(super) fn enclose_pending(&mut self, tree: &ChunkTree) {
        let pending = std::mem::take(&mut self.pending);
        for &(parent, z_min, z_max) in &pending {
            self.enclose(tree, parent, z_min, z_max);
        }
        self.pending = pending;
        self.pending.clear();
    }

    /// Widens the box of `id` and of its ancestors until each encloses heights `z_min..=z_max`
    /// (new children's). Box culling (§3.2.11) skips a chunk's whole subtree when its box is
    /// outside the view, so a box that did not enclose its descendants' could hide detail in
    /// view: with every box enclosing its children's, culling never opens a hole. Stops at the
    /// first box that already encloses them (its ancestors' do too). Boxes never shrink, not
    /// even when the chunks below are evicted: conservative, and the same whatever the cache.
    fn enclose(&mut self, tree: &ChunkTree, mut id: ChunkId, z_min: f32, z_max: f32) {
        let leaf_level = self.geometry.leaf_level;
        loop {
            let current = if id.level > leaf_level {
                match self.cache.get_any(id) {
                    Some(chunk) => chunk.record,
                    None => return, // Evicted, and its children with it.
                }
            } else {
                self.widened.get(&id).copied().unwrap_or(*tree.record(id))
            };
            if current.z_min <= z_min && current.z_max >= z_max {
                return;
            }
            let widened = ChunkRecord {
                z_min: current.z_min.min(z_min),
                z_max: current.z_max.max(z_max),
                ..current
            };
            if id.level > leaf_level {
                self.cache
                    .get_any_mut(id)
                    .expect("a synthesised parent is cached")
                    .record = widened;
            } else {
                self.widened.insert(id, widened);
            }
            match id.parent() {
                Some(parent) => id = parent,
                None => return,
            }
        }
    }

    /// Heap bytes held by the cache and the widened boxes.
    pub(super) fn memory_bytes(&self) -> usize {
        self.cache.memory_bytes()
            + self.widened.len() * std::mem::size_of::<(ChunkId, ChunkRecord)>()
            + self.pending.capacity() * std::mem::size_of::<(ChunkId, f32, f32)>()
    }
}
