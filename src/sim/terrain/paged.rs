//! A height field read on demand: [`PagedSamples`], the samples of a terrain that is never held
//! whole (a chunk pyramid on disk, `edge::pyramid`), read a point or a row at a time through a
//! cache the source bounds. A [`Heightfield`](super::Heightfield) built with
//! `Heightfield::paged` answers `height`, `row`, `height_range` and `ground_height` through it,
//! so the flight, the audit and the mesh visitors read the same terrain either way.
//!
//! **Not here**: the IO (the edge implements the trait), and anything that needs every sample at
//! once (Wu's node table, the in-memory hierarchies of the other algorithms): a run over a paged
//! terrain is refused for them before it starts (`edge::experiment`). A source also gives the
//! chunk records it was prepared with and a reader of whole chunks, so chunked LOD builds its
//! tree from the records instead of from the samples.
//!
//! **Failures.** A read that fails during a run (a file changed or damaged after it was
//! checked) cannot stop the core mid-frame: the source answers the lowest height of the
//! terrain for it, remembers the first failure, and the session reports it and fails the run
//! after the frames ([`PagedSamples::failure`]).

use crate::sim::algorithm::chunked::{ChunkHeightSource, ChunkRecord};
use std::fmt::Debug;

/// The samples of a (2^n + 1)² terrain read on demand. Shared by the run's threads.
pub trait PagedSamples: Send + Sync + Debug {
    /// The height of sample (i, j), 0 ≤ i, j < side.
    fn height(&self, i: usize, j: usize) -> f32;
    /// Row `j`'s heights, west to east, into `row` (cleared first).
    fn row(&self, j: usize, row: &mut Vec<f32>);
    /// The lowest and highest height of the whole terrain (known without reading it).
    fn height_range(&self) -> (f32, f32);
    /// Bytes held: the cache at its bound plus the records.
    fn memory_bytes(&self) -> usize;
    /// The first read that failed, a sentence naming the file and the chunk; `None` while none.
    fn failure(&self) -> Option<String>;
    /// c: the chunks the source was prepared with have (2^c + 1)² vertices.
    fn chunk_level(&self) -> u32;
    /// Every chunk's record in breadth-first order (`ChunkId::breadth_first_index`), skirt
    /// depth 0, as the chunked tree computes them for leaves of error 0.
    fn chunk_records(&self) -> &[ChunkRecord];
    /// A reader of whole chunks' heights (a loader thread), for chunked LOD's `loading` effect.
    fn chunk_reader(&self) -> Result<Box<dyn ChunkHeightSource>, String>;
}
