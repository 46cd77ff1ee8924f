//! A pyramid's finest level as a terrain read on demand ([`PagedSamples`]): point and row reads
//! of the full-resolution leaves through a least-recently-used cache of whole leaf chunks, the
//! records kept for chunked LOD's tree, and a loader thread per chunked entry for its chunks.
//!
//! **Memory.** The cache holds at most [`PyramidSamples::cache_chunks`] leaves: two rows of
//! leaves plus 16 (a row read, the audit's, touches one row of leaves; the flight's point reads
//! touch a few), so (2·2^D + 16)·(2^c + 1)²·4 bytes, plus 16 bytes per chunk of records: about
//! 17 MB of cache for a 32 769² pyramid of 65² chunks, whatever the samples. Not here: read-ahead,
//! and the chunked entries' own resident chunks (their loading effect's cap bounds those).
//!
//! **Failures** (a file changed or damaged after it was checked at open): the lowest height of
//! the terrain is answered and the first failure kept for [`PagedSamples::failure`]. The chunk
//! readers it hands out keep theirs in the same place (a failed read on a loader thread is
//! drawn flat by chunked LOD), so the session fails the run after the frames either way.

use super::{PyramidFile, PyramidLoader};
use crate::sim::algorithm::chunked::{ChunkHeightSource, ChunkId, ChunkRead, ChunkRecord};
use crate::sim::terrain::paged::PagedSamples;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};

/// A pyramid's samples, read on demand.
#[derive(Debug)]
pub struct PyramidSamples {
    pyramid: PyramidFile,
    cache: Mutex<LeafCache>,
    /// The first failed read, of the cache or of a chunk reader handed out.
    failure: Arc<Mutex<Option<String>>>,
}

/// Leaves by their breadth-first number, with the tick of their last use.
#[derive(Debug, Default)]
struct LeafCache {
    leaves: HashMap<u32, (Vec<f32>, u64)>,
    tick: u64,
}

impl PyramidSamples {
    /// The samples of the open `pyramid`; nothing is read yet.
    pub fn new(pyramid: PyramidFile) -> PyramidSamples {
        PyramidSamples {
            pyramid,
            cache: Mutex::new(LeafCache::default()),
            failure: Arc::default(),
        }
    }

    /// The most leaves the cache holds: two rows of leaves plus 16.
    pub fn cache_chunks(&self) -> usize {
        2 * (1usize << self.pyramid.header().leaf_level()) + 16
    }

    /// Bytes of the cache's heights when full (`f32`, whatever the file stores).
    pub fn cache_bytes(&self) -> usize {
        let side = self.pyramid.header().cells() as usize + 1;
        self.cache_chunks() * side * side * std::mem::size_of::<f32>()
    }

    pub fn pyramid(&self) -> &PyramidFile {
        &self.pyramid
    }

    /// The leaf holding sample (i, j), and the sample's vertex in it.
    fn leaf_of(&self, i: usize, j: usize) -> (ChunkId, u32, u32) {
        let header = self.pyramid.header();
        let (cells, level) = (header.cells() as usize, header.leaf_level());
        let last = (1usize << level) - 1;
        let (x, y) = ((i / cells).min(last), (j / cells).min(last));
        let id = ChunkId {
            level,
            x: x as u32,
            y: y as u32,
        };
        (id, (i - x * cells) as u32, (j - y * cells) as u32)
    }

    /// Leaf `id`'s heights from the cache, read (evicting the least recently used) when absent.
    fn leaf<'c>(&self, cache: &'c mut LeafCache, id: ChunkId) -> Option<&'c [f32]> {
        let key = id.breadth_first_index();
        cache.tick += 1;
        let tick = cache.tick;
        if !cache.leaves.contains_key(&key) {
            if cache.leaves.len() >= self.cache_chunks()
                && let Some(&oldest) = cache
                    .leaves
                    .iter()
                    .min_by_key(|(_, (_, used))| *used)
                    .map(|(k, _)| k)
            {
                cache.leaves.remove(&oldest);
            }
            let mut heights = Vec::new();
            if let Err(error) = self.pyramid.read_heights(id, &mut heights) {
                let mut failure = lock(&self.failure);
                failure.get_or_insert_with(|| error.to_string());
                return None;
            }
            cache.leaves.insert(key, (heights, tick));
        }
        let (heights, used) = cache.leaves.get_mut(&key)?;
        *used = tick;
        Some(heights)
    }

    fn lowest(&self) -> f32 {
        self.pyramid.records()[0].z_min
    }
}

impl PagedSamples for PyramidSamples {
    fn height(&self, i: usize, j: usize) -> f32 {
        let (id, a, b) = self.leaf_of(i, j);
        let side = self.pyramid.header().cells() + 1;
        let mut cache = lock(&self.cache);
        self.leaf(&mut cache, id)
            .map_or_else(|| self.lowest(), |heights| heights[(b * side + a) as usize])
    }

    fn row(&self, j: usize, row: &mut Vec<f32>) {
        let header = *self.pyramid.header();
        let (cells, side) = (header.cells(), header.cells() + 1);
        let (first, _, b) = self.leaf_of(0, j);
        let per_side = 1u32 << header.leaf_level();
        row.clear();
        let mut cache = lock(&self.cache);
        for x in 0..per_side {
            let id = ChunkId { x, ..first };
            // Each leaf's row but its last sample, which is the next leaf's first.
            let width = if x + 1 == per_side { cells + 1 } else { cells };
            match self.leaf(&mut cache, id) {
                Some(heights) => {
                    let start = (b * side) as usize;
                    row.extend_from_slice(&heights[start..start + width as usize]);
                }
                None => row.extend(std::iter::repeat_n(self.lowest(), width as usize)),
            }
        }
    }

    fn height_range(&self) -> (f32, f32) {
        let root = self.pyramid.records()[0];
        (root.z_min, root.z_max)
    }

    fn memory_bytes(&self) -> usize {
        self.cache_bytes() + std::mem::size_of_val(self.pyramid.records())
    }

    fn failure(&self) -> Option<String> {
        lock(&self.failure).clone()
    }

    fn chunk_level(&self) -> u32 {
        self.pyramid.header().chunk_level
    }

    fn chunk_records(&self) -> &[ChunkRecord] {
        self.pyramid.records()
    }

    fn chunk_reader(&self) -> Result<Box<dyn ChunkHeightSource>, String> {
        let file = PyramidFile::open(self.pyramid.path()).map_err(|error| error.to_string())?;
        Ok(Box::new(ReportingReader {
            loader: PyramidLoader::start(file),
            failure: Arc::clone(&self.failure),
        }))
    }
}

/// A loader whose failed reads are also kept as the samples' failure, which the session reports.
struct ReportingReader {
    loader: PyramidLoader,
    failure: Arc<Mutex<Option<String>>>,
}

impl ChunkHeightSource for ReportingReader {
    fn request(&mut self, id: ChunkId) {
        self.loader.request(id);
    }

    fn take(&mut self, id: ChunkId) -> Result<ChunkRead, String> {
        self.loader.take(id).inspect_err(|error| {
            lock(&self.failure).get_or_insert_with(|| error.clone());
        })
    }
}

/// The mutex's data; a panic elsewhere while it was held leaves it usable (a cache and a
/// message: nothing half-written matters).
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}
