//! The chunk tree from records computed before the run (a chunk pyramid's, which `roamsim
//! prepare` computes with the same functions, [`ChunkRecord::leaf`] and
//! [`ChunkRecord::internal`]), instead of from the height field's samples: O(chunks), reading
//! no height, so a terrain read on demand is never read whole. Skirt depths follow from the
//! records as in [`ChunkTree::new`]. Not here: synthesised detail's leaf error ε (the records'
//! leaves have error 0; an entry with detail builds its tree from the samples).

use super::{ChunkRecord, ChunkSource, ChunkTree, SkirtDepth};
use crate::sim::hierarchy::Hierarchy;

impl<'h> ChunkTree<'h> {
    /// The tree over `hierarchy`'s terrain for chunks of (2^`chunk_level` + 1)² vertices from
    /// `records`, every chunk's in breadth-first order (`ChunkId::breadth_first_index`), leaves
    /// of error 0. Refused (a sentence) when the chunk level is not one the terrain can have or
    /// the number of records is not the tree's.
    pub(in crate::sim::algorithm::chunked) fn from_records(
        hierarchy: &'h Hierarchy,
        chunk_level: u32,
        skirts: SkirtDepth,
        morph: bool,
        records: &[ChunkRecord],
    ) -> Result<ChunkTree<'h>, String> {
        let terrain_level = hierarchy.lattice().level();
        if !(1..=terrain_level).contains(&chunk_level) {
            return Err(format!(
                "chunk level {chunk_level}: expected 1 to the terrain's level {terrain_level}"
            ));
        }
        let leaf_level = terrain_level - chunk_level;
        let expected = ((1usize << (2 * (leaf_level + 1))) - 1) / 3;
        if records.len() != expected {
            return Err(format!(
                "{} chunk records: a terrain of level {terrain_level} in chunks of level \
                 {chunk_level} has {expected}",
                records.len()
            ));
        }
        let mut tree = ChunkTree::new_empty(hierarchy, chunk_level, 0.0);
        let mut rest = records;
        tree.levels = (0..=leaf_level)
            .map(|level| {
                let (these, after) = rest.split_at(1usize << (2 * level));
                rest = after;
                these.to_vec()
            })
            .collect();
        tree.set_skirt_depths(skirts, morph);
        debug_assert!(tree.chunk(super::ChunkId::ROOT).is_some());
        Ok(tree)
    }
}

#[cfg(test)]
mod tests {
    use super::super::ChunkId;
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};

    fn bumpy(level: u32) -> Hierarchy {
        let side = (1usize << level) + 1;
        let heights = (0..side * side)
            .map(|k| {
                let (i, j) = ((k % side) as f32, (k / side) as f32);
                (i * 0.37).sin() * 20.0 + (j * 0.23).cos() * 15.0 + (i * j * 0.01).sin() * 3.0
            })
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 5.0, dy: 5.0 }).unwrap())
    }

    fn breadth_first(tree: &ChunkTree) -> Vec<ChunkRecord> {
        let mut records = Vec::new();
        for level in 0..=tree.leaf_level() {
            for y in 0..1u32 << level {
                for x in 0..1u32 << level {
                    let mut record = *tree.record(ChunkId { level, x, y });
                    record.skirt_depth = 0.0;
                    records.push(record);
                }
            }
        }
        records
    }

    #[test]
    fn a_tree_from_its_own_records_is_the_tree_from_the_samples() {
        let hierarchy = bumpy(6);
        for skirts in [SkirtDepth::ChunkError, SkirtDepth::Covering] {
            for morph in [false, true] {
                let built = ChunkTree::new(&hierarchy, 3, skirts, morph, 0.0);
                let records = breadth_first(&built);
                let read = ChunkTree::from_records(&hierarchy, 3, skirts, morph, &records)
                    .expect("the records fit the terrain");
                assert_eq!(read.levels, built.levels, "{skirts:?}, morph {morph}");
            }
        }
    }

    #[test]
    fn records_of_another_tree_are_refused() {
        let hierarchy = bumpy(5);
        let records = breadth_first(&ChunkTree::new(
            &hierarchy,
            2,
            SkirtDepth::Covering,
            false,
            0.0,
        ));
        let error = ChunkTree::from_records(&hierarchy, 3, SkirtDepth::Covering, false, &records)
            .unwrap_err();
        assert!(error.contains("chunk records"), "{error}");
        let error = ChunkTree::from_records(&hierarchy, 6, SkirtDepth::Covering, false, &records)
            .unwrap_err();
        assert!(
            error.contains("expected 1 to the terrain's level 5"),
            "{error}"
        );
    }
}
