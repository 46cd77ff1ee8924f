//! The per-frame selection: which chunks to draw, top-down from the root (listings 3.2–3.6).
//!
//! At each chunk, in order:
//! 1. with culling on, a chunk whose box is outside the view volume is dropped with everything
//!    below it (listing 3.4; `block_lod::cull`);
//! 2. d, the distance from the eye to the chunk's box (or the exact projection's equivalent);
//! 3. if d < δ_c·C and the chunk has children: when all four are available they are visited,
//!    nearest box first with front-to-back ordering on (listing 3.3; ties by their order
//!    south-west, south-east, north-west, north-east, which is also the order without it),
//!    otherwise the chunk is drawn in their place and counted as unavailable (listing 3.6);
//! 4. otherwise the chunk is drawn, with its morph factor (eq. 3.5, against its parent's
//!    δ_c·C; 1 for the root, which has no coarser level, and 1 with morphing off).
//!
//! Drawn chunks come out in visiting order: the draw order. The selection is a pure function
//! of the view, the tolerance and the source's available chunks: nothing is kept from the
//! previous frame. O(chunks visited); the buffers are reused.

use super::super::block_lod::Projection;
use super::super::block_lod::cull::box_outside_view;
use super::super::block_lod::threshold::DetailThreshold;
use super::tree::{ChunkGeometry, ChunkId, ChunkSource};
use crate::sim::view::Camera;

/// How this frame selects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SelectionSettings {
    pub(super) threshold: DetailThreshold,
    pub(super) projection: Projection,
    pub(super) culling: bool,
    pub(super) front_to_back: bool,
    pub(super) morph: bool,
}

/// A chunk chosen for drawing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrawnChunk {
    pub id: ChunkId,
    /// The distance d the detail test used.
    pub distance: f64,
    /// Eq. 3.5's f: 1 at full detail, 0 where the chunk looks like its parent.
    pub morph: f64,
}

/// One selection's result and its buffers.
#[derive(Clone, Debug, Default)]
pub(super) struct Selection {
    /// Chunks to draw, in draw order.
    pub(super) drawn: Vec<DrawnChunk>,
    /// Chunks whose children were visited instead (in visiting order).
    pub(super) refined: Vec<ChunkId>,
    /// Chunks dropped by culling (nothing below them was visited).
    pub(super) culled: Vec<ChunkId>,
    /// Chunks whose distance was measured or box tested.
    pub(super) visited: u64,
    /// Chunks drawn although they wanted refining, because a child was not available.
    pub(super) unavailable: u64,
    /// Those chunks, in visiting order: the requests for their children (listing 3.7).
    pub(super) requested: Vec<ChunkId>,
}

impl Selection {
    fn clear(&mut self) {
        self.drawn.clear();
        self.refined.clear();
        self.culled.clear();
        self.visited = 0;
        self.unavailable = 0;
        self.requested.clear();
    }

    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.drawn.capacity() * std::mem::size_of::<DrawnChunk>()
            + (self.refined.capacity() + self.culled.capacity() + self.requested.capacity())
                * std::mem::size_of::<ChunkId>()
    }
}

/// Selects this frame's chunks from `source` into `out` (cleared first).
pub(super) fn select<S: ChunkSource>(
    source: &S,
    geometry: &ChunkGeometry,
    camera: &Camera,
    settings: &SelectionSettings,
    out: &mut Selection,
) {
    out.clear();
    let visit = Visit {
        source,
        geometry,
        camera,
        settings,
    };
    if source.chunk(ChunkId::ROOT).is_some() {
        visit.chunk(ChunkId::ROOT, None, out);
    }
}

struct Visit<'a, S> {
    source: &'a S,
    geometry: &'a ChunkGeometry,
    camera: &'a Camera,
    settings: &'a SelectionSettings,
}

impl<S: ChunkSource> Visit<'_, S> {
    /// Visits an available chunk whose parent has error `parent_error` (`None` at the root).
    fn chunk(&self, id: ChunkId, parent_error: Option<f32>, out: &mut Selection) {
        let Some(record) = self.source.chunk(id) else {
            return;
        };
        let record = *record;
        out.visited += 1;
        let block = self.geometry.block_box(id, &record);
        if self.settings.culling && box_outside_view(self.camera, &block) {
            out.culled.push(id);
            return;
        }
        let eye = self.camera.eye;
        let d = block.lod_distance(eye, self.settings.projection);
        let threshold = self.settings.threshold;
        if self.source.is_internal(id) && threshold.refines(record.error, d) {
            let children = id.children();
            if children.iter().all(|&c| self.source.chunk(c).is_some()) {
                out.refined.push(id);
                let mut order = [0usize, 1, 2, 3];
                if self.settings.front_to_back {
                    let distance = |k: usize| {
                        self.source.chunk(children[k]).map_or(f64::INFINITY, |r| {
                            self.geometry.block_box(children[k], r).distance(eye)
                        })
                    };
                    let distances = [0, 1, 2, 3].map(distance);
                    order.sort_by(|&a, &b| distances[a].total_cmp(&distances[b]).then(a.cmp(&b)));
                }
                for k in order {
                    self.chunk(children[k], Some(record.error), out);
                }
                return;
            }
            out.unavailable += 1;
            out.requested.push(id);
        }
        let morph = match (self.settings.morph, parent_error) {
            (true, Some(parent_error)) => threshold.morph_factor(record.error, parent_error, d),
            _ => 1.0,
        };
        out.drawn.push(DrawnChunk {
            id,
            distance: d,
            morph,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::super::tree::{ChunkRecord, ChunkTree, SkirtDepth};
    use super::*;
    use crate::sim::hierarchy::Hierarchy;
    use crate::sim::terrain::{Heightfield, Spacing};
    use crate::sim::view::{Pose, ViewSettings};
    use glam::DVec3;

    /// The source tree with some chunks not available (not loaded, not made yet).
    struct Missing<'a> {
        tree: &'a ChunkTree<'a>,
        missing: Vec<ChunkId>,
    }

    impl ChunkSource for Missing<'_> {
        fn chunk(&self, id: ChunkId) -> Option<&ChunkRecord> {
            (!self.missing.contains(&id))
                .then(|| self.tree.chunk(id))
                .flatten()
        }
        fn is_internal(&self, id: ChunkId) -> bool {
            self.tree.is_internal(id)
        }
        fn height(&self, id: ChunkId, a: u32, b: u32) -> f32 {
            self.tree.height(id, a, b)
        }
    }

    #[test]
    fn a_chunk_whose_children_are_not_all_available_is_drawn_in_their_place() {
        let side = 17;
        let heights = (0..side * side).map(|k| ((k * 37) % 11) as f32).collect();
        let hierarchy =
            Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 1.0, dy: 1.0 }).unwrap());
        let tree = ChunkTree::new(&hierarchy, 2, SkirtDepth::ChunkError, false, 0.0);
        let camera = Camera::new(
            &Pose {
                position: DVec3::new(8.0, 8.0, 20.0),
                yaw: 0.0,
                pitch: -1.0,
            },
            ViewSettings {
                width_px: 100,
                height_px: 100,
                fovy: 1.0,
                near: 0.1,
                far: 1000.0,
            },
        );
        // τ = 0: everything with an error is refined down to the leaves.
        let settings = SelectionSettings {
            threshold: DetailThreshold::new(camera.settings.pixels_per_unit(), 0.0),
            projection: Projection::HorizontalView,
            culling: false,
            front_to_back: false,
            morph: false,
        };
        let hidden_leaf = ChunkId {
            level: 2,
            x: 3,
            y: 0,
        };
        let source = Missing {
            tree: &tree,
            missing: vec![hidden_leaf],
        };
        let mut selection = Selection::default();
        select(&source, tree.geometry(), &camera, &settings, &mut selection);
        let level_one = hidden_leaf.parent().unwrap();
        let drawn: Vec<ChunkId> = selection.drawn.iter().map(|c| c.id).collect();
        assert!(drawn.contains(&level_one), "{drawn:?}");
        assert_eq!(selection.unavailable, 1);
        // The other three level-1 chunks are refined to their leaves: 1 + 3 × 4 chunks.
        assert_eq!(drawn.len(), 13);
        assert!(!drawn.contains(&hidden_leaf));
        // With everything available, only leaves.
        select(&tree, tree.geometry(), &camera, &settings, &mut selection);
        assert_eq!(selection.drawn.len(), 16);
        assert_eq!(selection.unavailable, 0);
    }
}
