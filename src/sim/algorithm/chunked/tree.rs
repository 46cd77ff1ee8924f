//! The chunk quadtree (Lauritsen–Nielsen §3.2.1–3.2.3, errors by eq. 3.1): chunk identity, the
//! chunks built from the height field before the first frame, and what the selection and the
//! mesh read them through.
//!
//! **Identity.** A chunk is named by its place in the quadtree, [`ChunkId`] (level, x, y), not
//! by an index into an array built up front: level 0 is the root (the whole terrain), and at
//! level L the terrain is 2^L × 2^L chunks. Its square, its stride and its parent and children
//! follow from the id alone, at any level, finer than the source included.
//!
//! **Availability.** The selection and the mesh builder read chunks through [`ChunkSource`]:
//! "is this chunk available now, and what are its vertices' heights?". [`ChunkTree`] is the
//! source tree built completely before the first frame, in which every chunk down to the
//! full-resolution leaves exists; `source.rs`'s view adds what the two effects change: with
//! out-of-core loading only the resident source chunks are available, and with runtime detail
//! the synthesised chunks below the leaves are (chunks that exist only once made or loaded, and
//! are evicted again). The selection never assumes a chunk is there; when it wants a chunk's
//! children and they are not available it draws the chunk itself (listing 3.6).
//!
//! **What the tree holds per chunk** ([`ChunkRecord`], 16 bytes): its nested error δ_c
//! (eq. 3.1: 0 at a leaf, max(children's δ_c) + δ_m above, δ_m the largest vertex error of the
//! vertices its children have and it has not), the height range of its samples (its box: the
//! children's boxes are inside it, §3.2.12), and the depth of the skirt hung from its borders
//! (see [`SkirtDepth`]). Heights are not copied: a source chunk's vertices are read from the
//! shared height field, every 2^(leaf level − L)-th sample.
//!
//! Build: O(samples) (each level's vertex errors once, the height ranges bottom-up). Memory:
//! 16 bytes per chunk, (4^(D+1) − 1)/3 chunks for leaves at level D.

use super::super::block_lod::grid::{coarser_neighbours, round_up_f32};
use super::super::block_lod::threshold::BlockBox;
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::{SUBGRID_UNITS_PER_CELL, SubgridPoint};
use glam::DVec3;

mod from_records;

/// A chunk's place in the quadtree: level 0 is the root; at level L the terrain is 2^L × 2^L
/// chunks, x to the east and y to the north.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ChunkId {
    pub level: u32,
    pub x: u32,
    pub y: u32,
}

impl ChunkId {
    /// The root: the whole terrain.
    pub const ROOT: ChunkId = ChunkId {
        level: 0,
        x: 0,
        y: 0,
    };

    /// The chunk one level up; `None` for the root.
    pub fn parent(self) -> Option<ChunkId> {
        (self.level > 0).then(|| ChunkId {
            level: self.level - 1,
            x: self.x / 2,
            y: self.y / 2,
        })
    }

    /// The four chunks one level down: south-west, south-east, north-west, north-east.
    pub fn children(self) -> [ChunkId; 4] {
        let child = |dx: u32, dy: u32| ChunkId {
            level: self.level + 1,
            x: 2 * self.x + dx,
            y: 2 * self.y + dy,
        };
        [child(0, 0), child(1, 0), child(0, 1), child(1, 1)]
    }

    /// The chunk's ancestor at `level` (itself at its own level); `None` below it.
    pub fn ancestor_at(self, level: u32) -> Option<ChunkId> {
        (level <= self.level).then(|| {
            let shift = self.level - level;
            ChunkId {
                level,
                x: self.x >> shift,
                y: self.y >> shift,
            }
        })
    }

    /// Whether `self` is `other` or one of its ancestors.
    pub fn contains(self, other: ChunkId) -> bool {
        other.ancestor_at(self.level) == Some(self)
    }

    /// The chunk's number in a breadth-first numbering of the quadtree (root 0, then each level
    /// row by row): the triangle list's group. Fits a `u32` down to level 15.
    pub fn breadth_first_index(self) -> u32 {
        let above = ((1u64 << (2 * self.level)) - 1) / 3;
        let index = above + u64::from(self.y) * (1u64 << self.level) + u64::from(self.x);
        u32::try_from(index).expect("chunk levels up to 15 number within u32")
    }
}

/// What the tree knows of one chunk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChunkRecord {
    /// δ_c of eq. 3.1, metres, rounded up to `f32`.
    pub error: f32,
    /// The lowest and highest sample in the chunk's closed square.
    pub z_min: f32,
    pub z_max: f32,
    /// How far the skirt hangs below the chunk's borders, metres.
    pub skirt_depth: f32,
}

impl ChunkRecord {
    /// A leaf's record: the range of its samples `heights` (all (2^c + 1)² of them, in any
    /// order), δ_c = `leaf_error`, no skirt yet. What the tree and a prepared pyramid compute.
    pub fn leaf(heights: impl IntoIterator<Item = f32>, leaf_error: f32) -> ChunkRecord {
        let (mut z_min, mut z_max) = (f32::INFINITY, f32::NEG_INFINITY);
        for z in heights {
            z_min = z_min.min(z);
            z_max = z_max.max(z);
        }
        ChunkRecord {
            error: leaf_error,
            z_min,
            z_max,
            skirt_depth: 0.0,
        }
    }

    /// An internal chunk's record from its four children's (any order) and its own δ_m
    /// ([`chunk_own_error`]): δ_c = max(children's δ_c) + δ_m rounded up to `f32` (eq. 3.1),
    /// the height range the children's union, no skirt yet.
    pub fn internal(children: &[ChunkRecord; 4], own_error: f64) -> ChunkRecord {
        let children_error = children
            .iter()
            .map(|c| f64::from(c.error))
            .fold(0.0, f64::max);
        ChunkRecord {
            error: round_up_f32(children_error + own_error),
            z_min: children
                .iter()
                .map(|c| c.z_min)
                .fold(f32::INFINITY, f32::min),
            z_max: children
                .iter()
                .map(|c| c.z_max)
                .fold(f32::NEG_INFINITY, f32::max),
            skirt_depth: 0.0,
        }
    }
}

/// δ_m of an internal chunk of 2^c = `cells` cells a side, from `height(a, b)`, 0 ≤ a, b ≤
/// 2·`cells`: the vertices of its children's union grid (half its stride). The largest
/// vertical distance of a vertex that grid has and the chunk's own lacks from the line between
/// its two neighbours (Lauritsen–Nielsen fig. 3.4). O(cells²).
pub fn chunk_own_error(cells: u32, height: impl Fn(u32, u32) -> f32) -> f64 {
    let fine_cells = 2 * cells;
    let mut largest: f64 = 0.0;
    for b in 0..=fine_cells {
        for a in 0..=fine_cells {
            if let Some([p, q]) = coarser_neighbours(a, b) {
                let line = 0.5 * (f64::from(height(p.0, p.1)) + f64::from(height(q.0, q.1)));
                largest = largest.max((f64::from(height(a, b)) - line).abs());
            }
        }
    }
    largest
}

/// How deep a chunk's skirt hangs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SkirtDepth {
    /// The paper's choice (§3.2.6): the chunk's own error δ_c. Zero at the leaves (eq. 3.1),
    /// so a leaf beside a coarser chunk whose border runs below the leaf's leaves that crack
    /// open; the audit's `audit_cracks_uncovered` counts such cracks.
    ChunkError,
    /// Deep enough for every crack whatever the selection: the chunk's deviation bound e plus
    /// the largest e of any chunk that can be drawn beside it (any chunk touching its square
    /// that is neither an ancestor nor a descendant). e is δ_c, or, with morphing, the parent's
    /// δ_c (a morphed chunk lies between its own surface and its parent's). Two drawn chunks
    /// differ at a shared sample by at most e₁ + e₂, so the higher one's skirt reaches the
    /// lower one. Costs no triangle, only fill (longer curtains).
    Covering,
}

/// Where the selection and the mesh read chunks from. [`ChunkTree`] is the source tree built
/// up front; sources whose chunks are created, loaded and evicted at run time implement the
/// same three questions.
pub(super) trait ChunkSource {
    /// The chunk `id` if it is available now (`None`: outside the tree, or not made or loaded
    /// yet).
    fn chunk(&self, id: ChunkId) -> Option<&ChunkRecord>;
    /// Whether `id` has children in the tree (which may or may not be available).
    fn is_internal(&self, id: ChunkId) -> bool;
    /// The height of vertex (a, b), 0 ≤ a, b ≤ cells, of chunk `id`'s grid.
    fn height(&self, id: ChunkId, a: u32, b: u32) -> f32;
}

/// Where a chunk lies and how its vertices are spaced, from its id.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ChunkGeometry {
    /// Grid cells per chunk side: 2^c.
    pub(super) cells: u32,
    /// log2 of the terrain's cells per side.
    terrain_level: u32,
    /// Grid spacing, metres.
    dx: f64,
    dy: f64,
}

impl ChunkGeometry {
    /// The stride of `id`'s vertices in fixed-point units (1/65 536 of a cell).
    pub(super) fn stride_units(&self, id: ChunkId) -> i64 {
        self.side_units(id) / i64::from(self.cells)
    }

    /// The side of `id`'s square in fixed-point units.
    pub(super) fn side_units(&self, id: ChunkId) -> i64 {
        (SUBGRID_UNITS_PER_CELL << self.terrain_level) >> id.level
    }

    /// Vertex (a, b) of `id`'s grid.
    pub(super) fn vertex(&self, id: ChunkId, a: u32, b: u32) -> SubgridPoint {
        let (side, stride) = (self.side_units(id), self.stride_units(id));
        let x = i64::from(id.x) * side + i64::from(a) * stride;
        let y = i64::from(id.y) * side + i64::from(b) * stride;
        SubgridPoint::from_raw(x, y).expect("a chunk's vertices lie in the terrain")
    }

    /// The chunk's square, low and high corners.
    pub(super) fn square(&self, id: ChunkId) -> (SubgridPoint, SubgridPoint) {
        (
            self.vertex(id, 0, 0),
            self.vertex(id, self.cells, self.cells),
        )
    }

    /// The chunk's box: its square times the height range of `record`.
    pub(super) fn block_box(&self, id: ChunkId, record: &ChunkRecord) -> BlockBox {
        let (low, high) = self.square(id);
        let metres = |p: SubgridPoint| {
            let (x, y) = p.grid_units();
            (x * self.dx, y * self.dy)
        };
        let ((x0, y0), (x1, y1)) = (metres(low), metres(high));
        BlockBox {
            low: DVec3::new(x0, y0, f64::from(record.z_min)),
            high: DVec3::new(x1, y1, f64::from(record.z_max)),
        }
    }
}

/// The source tree: every chunk from the root down to the full-resolution leaves, built from
/// the height field before the first frame.
#[derive(Clone, Debug)]
pub(super) struct ChunkTree<'h> {
    hierarchy: &'h Hierarchy,
    geometry: ChunkGeometry,
    /// The level of the leaves, D = n − c.
    leaf_level: u32,
    /// δ_c of every leaf: 0, or with synthesised detail the estimated ε (§3.4.1).
    leaf_error: f32,
    /// Per level, its 4^L chunks row by row.
    levels: Vec<Vec<ChunkRecord>>,
}

impl<'h> ChunkTree<'h> {
    /// Builds the tree for chunks of (2^`chunk_level` + 1)² vertices (clamped to the terrain:
    /// a chunk level at or above the terrain's gives one chunk, the whole terrain at full
    /// resolution), with skirts as `skirts` says for a run that morphs or not, and `leaf_error`
    /// as every leaf's δ_c (0 without synthesised detail).
    pub(super) fn new(
        hierarchy: &'h Hierarchy,
        chunk_level: u32,
        skirts: SkirtDepth,
        morph: bool,
        leaf_error: f32,
    ) -> ChunkTree<'h> {
        let mut tree = ChunkTree::new_empty(hierarchy, chunk_level, leaf_error);
        let leaf_level = tree.leaf_level;
        // Bottom-up: errors and height ranges, finest level first.
        let mut levels: Vec<Vec<ChunkRecord>> = Vec::with_capacity(leaf_level as usize + 1);
        for level in (0..=leaf_level).rev() {
            let per_side = 1u32 << level;
            let finer = levels.last();
            let mut records = Vec::with_capacity((per_side * per_side) as usize);
            for y in 0..per_side {
                for x in 0..per_side {
                    let id = ChunkId { level, x, y };
                    let record = match finer {
                        None => tree.leaf_record(id),
                        Some(finer) => tree.internal_record(id, finer),
                    };
                    records.push(record);
                }
            }
            levels.push(records);
        }
        levels.reverse();
        tree.levels = levels;
        tree.set_skirt_depths(skirts, morph);
        tree
    }

    /// The tree's geometry with no chunk yet (the chunk level clamped to the terrain's).
    fn new_empty(hierarchy: &'h Hierarchy, chunk_level: u32, leaf_error: f32) -> ChunkTree<'h> {
        let terrain_level = hierarchy.lattice().level();
        let chunk_level = chunk_level.clamp(1, terrain_level);
        let spacing = hierarchy.field().spacing();
        let geometry = ChunkGeometry {
            cells: 1 << chunk_level,
            terrain_level,
            dx: spacing.dx,
            dy: spacing.dy,
        };
        ChunkTree {
            hierarchy,
            geometry,
            leaf_level: terrain_level - chunk_level,
            leaf_error,
            levels: Vec::new(),
        }
    }

    pub(super) fn geometry(&self) -> &ChunkGeometry {
        &self.geometry
    }

    /// The level of the full-resolution leaves.
    pub(super) fn leaf_level(&self) -> u32 {
        self.leaf_level
    }

    /// Every leaf's δ_c.
    pub(super) fn leaf_error(&self) -> f32 {
        self.leaf_error
    }

    /// The shared height field.
    pub(super) fn hierarchy(&self) -> &'h Hierarchy {
        self.hierarchy
    }

    /// Chunks in the tree.
    pub(super) fn n_chunks(&self) -> usize {
        self.levels.iter().map(Vec::len).sum()
    }

    /// Heap bytes held.
    pub(super) fn memory_bytes(&self) -> usize {
        self.levels.capacity() * std::mem::size_of::<Vec<ChunkRecord>>()
            + self
                .levels
                .iter()
                .map(|level| level.capacity() * std::mem::size_of::<ChunkRecord>())
                .sum::<usize>()
    }

    /// The grid point of vertex (a, b) of a source chunk (every chunk of this tree is one).
    fn grid_point(&self, id: ChunkId, a: u32, b: u32) -> GridPoint {
        let stride = 1u32 << (self.leaf_level - id.level);
        let side = self.geometry.cells * stride;
        GridPoint::new(id.x * side + a * stride, id.y * side + b * stride)
    }

    /// A chunk's square in grid cells: its south-west corner and its side.
    pub(super) fn grid_square(&self, id: ChunkId) -> (u32, u32, u32) {
        let side = self.geometry.cells << (self.leaf_level - id.level);
        (id.x * side, id.y * side, side)
    }

    /// The height field's sample (i, j).
    pub(super) fn sample(&self, i: u32, j: u32) -> f32 {
        self.hierarchy.height(GridPoint::new(i, j))
    }

    fn leaf_record(&self, id: ChunkId) -> ChunkRecord {
        let cells = self.geometry.cells;
        let heights = (0..=cells).flat_map(|b| {
            (0..=cells).map(move |a| self.hierarchy.height(self.grid_point(id, a, b)))
        });
        ChunkRecord::leaf(heights, self.leaf_error)
    }

    /// δ_c = max(children's δ_c) + δ_m (eq. 3.1); the height range is the children's.
    fn internal_record(&self, id: ChunkId, finer: &[ChunkRecord]) -> ChunkRecord {
        let children = id.children().map(|c| finer[self.index_in_level(c)]);
        ChunkRecord::internal(&children, self.own_error(id))
    }

    /// δ_m of an internal chunk: the largest vertical distance of a vertex its children's
    /// grids have (stride half its own) and its own grid lacks from the line between its two
    /// neighbours (Lauritsen–Nielsen fig. 3.4), i.e. from the chunk's own surface.
    pub(super) fn own_error(&self, id: ChunkId) -> f64 {
        let half_stride = 1u32 << (self.leaf_level - id.level - 1);
        let side = self.geometry.cells * 2 * half_stride;
        let (x0, y0) = (id.x * side, id.y * side);
        chunk_own_error(self.geometry.cells, |a, b| {
            self.hierarchy
                .height(GridPoint::new(x0 + a * half_stride, y0 + b * half_stride))
        })
    }

    fn index_in_level(&self, id: ChunkId) -> usize {
        (id.y as usize) * (1usize << id.level) + id.x as usize
    }

    fn record_mut(&mut self, id: ChunkId) -> &mut ChunkRecord {
        let index = self.index_in_level(id);
        &mut self.levels[id.level as usize][index]
    }

    /// Sets every chunk's skirt depth (see [`SkirtDepth`]).
    fn set_skirt_depths(&mut self, skirts: SkirtDepth, morph: bool) {
        let ids: Vec<ChunkId> = (0..=self.leaf_level)
            .flat_map(|level| {
                let per_side = 1u32 << level;
                (0..per_side * per_side).map(move |k| ChunkId {
                    level,
                    x: k % per_side,
                    y: k / per_side,
                })
            })
            .collect();
        let depths: Vec<f32> = ids
            .iter()
            .map(|&id| match skirts {
                SkirtDepth::ChunkError => self.record(id).error,
                SkirtDepth::Covering => {
                    let bound = |chunk: ChunkId| self.deviation_bound(chunk, morph);
                    let beside = self
                        .neighbours_beside(id)
                        .into_iter()
                        .map(|n| f64::from(bound(n)))
                        .fold(0.0, f64::max);
                    round_up_f32(f64::from(bound(id)) + beside)
                }
            })
            .collect();
        for (id, depth) in ids.into_iter().zip(depths) {
            self.record_mut(id).skirt_depth = depth;
        }
    }

    /// e: a bound of how far the chunk's drawn surface lies from the samples (δ_c, or its
    /// parent's δ_c when morphing moves it towards the parent's surface).
    fn deviation_bound(&self, id: ChunkId, morph: bool) -> f32 {
        match (morph, id.parent()) {
            (true, Some(parent)) => self.record(parent).error,
            _ => self.record(id).error,
        }
    }

    /// Every chunk that touches `id`'s closed square and is neither an ancestor nor a
    /// descendant of it, up to nesting: at each level from the root to `id`'s, the neighbours
    /// of `id`'s ancestor there that touch `id`. (Finer chunks beside `id` lie inside its
    /// same-level neighbours, whose δ_c bound theirs.)
    fn neighbours_beside(&self, id: ChunkId) -> Vec<ChunkId> {
        let mut beside = Vec::new();
        let (ix, iy) = (i64::from(id.x), i64::from(id.y));
        for level in 0..=id.level {
            let ancestor = id.ancestor_at(level).unwrap_or(ChunkId::ROOT);
            let per_side = 1i64 << level;
            let shift = id.level - level;
            // A level-L chunk's extent in units of `id`'s level.
            let span = |v: i64| (v << shift, (v + 1) << shift);
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (nx, ny) = (i64::from(ancestor.x) + dx, i64::from(ancestor.y) + dy);
                    let inside = (0..per_side).contains(&nx) && (0..per_side).contains(&ny);
                    if (dx, dy) == (0, 0) || !inside {
                        continue;
                    }
                    let ((x0, x1), (y0, y1)) = (span(nx), span(ny));
                    if x0 <= ix + 1 && ix <= x1 && y0 <= iy + 1 && iy <= y1 {
                        beside.push(ChunkId {
                            level,
                            x: nx as u32,
                            y: ny as u32,
                        });
                    }
                }
            }
        }
        beside
    }

    /// The record of a chunk of the tree.
    ///
    /// # Panics
    /// When `id` is not in the tree.
    pub(super) fn record(&self, id: ChunkId) -> &ChunkRecord {
        self.chunk(id)
            .unwrap_or_else(|| panic!("chunk {id:?} is not in the tree"))
    }
}

impl ChunkSource for ChunkTree<'_> {
    fn chunk(&self, id: ChunkId) -> Option<&ChunkRecord> {
        let per_side = 1u32 << id.level.min(31);
        (id.level <= self.leaf_level && id.x < per_side && id.y < per_side)
            .then(|| &self.levels[id.level as usize][self.index_in_level(id)])
    }

    fn is_internal(&self, id: ChunkId) -> bool {
        id.level < self.leaf_level
    }

    fn height(&self, id: ChunkId, a: u32, b: u32) -> f32 {
        self.hierarchy.height(self.grid_point(id, a, b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};

    fn ramp_with_bump(level: u32) -> Hierarchy {
        let side = (1usize << level) + 1;
        let heights = (0..side * side)
            .map(|k| {
                let (i, j) = (k % side, k / side);
                (i as f32) * 0.5 + if (i, j) == (3, 5) { 8.0 } else { 0.0 }
            })
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 2.0, dy: 3.0 }).unwrap())
    }

    #[test]
    fn ids_know_their_parents_children_and_numbering() {
        let id = ChunkId {
            level: 2,
            x: 3,
            y: 1,
        };
        assert_eq!(
            id.parent(),
            Some(ChunkId {
                level: 1,
                x: 1,
                y: 0
            })
        );
        assert!(id.children().iter().all(|c| c.parent() == Some(id)));
        assert!(ChunkId::ROOT.contains(id) && id.contains(id));
        assert!(!id.contains(ChunkId::ROOT));
        assert_eq!(ChunkId::ROOT.breadth_first_index(), 0);
        assert_eq!(id.breadth_first_index(), 5 + 4 + 3);
    }

    #[test]
    fn a_ramp_has_no_error_and_a_bump_is_counted_where_it_is_removed() {
        // 17×17, chunks of 5×5: leaves at level 2 (stride 1), level 1 (stride 2), root
        // (stride 4). The bump at (3, 5) is odd, so the level-1 chunk holding it drops it.
        let hierarchy = ramp_with_bump(4);
        let tree = ChunkTree::new(&hierarchy, 2, SkirtDepth::ChunkError, false, 0.0);
        assert_eq!((tree.leaf_level(), tree.n_chunks()), (2, 21));
        let bump_leaf = ChunkId {
            level: 2,
            x: 0,
            y: 1,
        };
        assert_eq!(tree.record(bump_leaf).error, 0.0);
        let level_one = ChunkId {
            level: 1,
            x: 0,
            y: 0,
        };
        // (3, 5) is odd in both: its line is the cell's diagonal from (2, 4) to (4, 6), on the
        // ramp.
        assert_eq!(tree.record(level_one).error, 8.0);
        assert_eq!(tree.record(ChunkId::ROOT).error, 8.0);
        let other = ChunkId {
            level: 1,
            x: 1,
            y: 1,
        };
        assert_eq!(tree.record(other).error, 0.0);
        assert_eq!(
            (
                tree.record(ChunkId::ROOT).z_min,
                tree.record(ChunkId::ROOT).z_max
            ),
            (0.0, 9.5)
        );
        assert_eq!(tree.record(bump_leaf).z_max, 9.5);
    }

    #[test]
    fn the_papers_skirts_are_the_chunk_errors_and_covering_ones_add_the_neighbours() {
        let hierarchy = ramp_with_bump(4);
        let paper = ChunkTree::new(&hierarchy, 2, SkirtDepth::ChunkError, false, 0.0);
        let covering = ChunkTree::new(&hierarchy, 2, SkirtDepth::Covering, false, 0.0);
        let leaf = ChunkId {
            level: 2,
            x: 2,
            y: 0,
        };
        assert_eq!(paper.record(leaf).skirt_depth, 0.0);
        // The leaf touches the level-1 chunk (0, 0), whose error is the bump's 8 m.
        assert_eq!(covering.record(leaf).skirt_depth, 8.0);
        // The root touches nothing beside itself.
        assert_eq!(covering.record(ChunkId::ROOT).skirt_depth, 8.0);
        let far_leaf = ChunkId {
            level: 2,
            x: 3,
            y: 3,
        };
        assert_eq!(covering.record(far_leaf).skirt_depth, 0.0);
    }

    #[test]
    fn geometry_follows_from_the_id() {
        let hierarchy = ramp_with_bump(4);
        let tree = ChunkTree::new(&hierarchy, 2, SkirtDepth::ChunkError, false, 0.0);
        let geometry = tree.geometry();
        let id = ChunkId {
            level: 1,
            x: 1,
            y: 0,
        };
        assert_eq!(geometry.vertex(id, 0, 0), SubgridPoint::grid(8, 0));
        assert_eq!(geometry.vertex(id, 4, 4), SubgridPoint::grid(16, 8));
        assert_eq!(
            tree.height(id, 1, 0),
            hierarchy.height(GridPoint::new(10, 0))
        );
        let b = geometry.block_box(id, tree.record(id));
        assert_eq!((b.low.x, b.high.x, b.high.y), (16.0, 32.0, 24.0));
        assert!(
            tree.chunk(ChunkId {
                level: 3,
                x: 0,
                y: 0
            })
            .is_none()
        );
        assert!(!tree.is_internal(ChunkId {
            level: 2,
            x: 0,
            y: 0
        }));
    }
}
