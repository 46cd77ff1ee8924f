//! The chunk pyramid file: a terrain's chunked-LOD quadtree written once by `roamsim prepare`
//! (`prepare.rs`, in bounded memory, bottom-up from bands of rows, from a raw file streamed or
//! any terrain read whole, `source.rs`) and read chunk by chunk
//! (`open.rs`), the way Ulrich's chunker preprocesses a terrain into a `.chu` file of chunks with
//! their errors. The format is documented in `docs/output-formats.md` ("Chunk pyramid").
//!
//! **What it holds.** Exactly the source tree `chunked` builds in memory
//! (`src/sim/algorithm/chunked/tree.rs`) for a terrain of (2^n + 1)² samples and chunks of
//! (2^c + 1)² vertices: every chunk from the root to the full-resolution leaves, each with its
//! nested error δ_c (eq. 3.1, computed by the same functions, [`ChunkRecord::leaf`],
//! [`ChunkRecord::internal`] and [`chunk_own_error`]), its height range and its vertices'
//! heights, stored losslessly (`i16` for a 16-bit integer source, `f32` otherwise). Skirt depths
//! are not stored: they depend on the entry's `skirt_depth` and `morph`, and follow from the
//! records alone.
//!
//! **What it is not.** Not a tiled copy of the samples (a chunk at level L holds every
//! 2^(D − L)-th sample of its square, so the file is about 4/3 of the samples), not
//! georeferenced (only the spacing is kept; the terrain's origin is at (0, 0)), and it holds no
//! synthesised detail (leaf errors are 0).
//!
//! [`ChunkRecord::leaf`]: crate::sim::algorithm::chunked::ChunkRecord::leaf
//! [`ChunkRecord::internal`]: crate::sim::algorithm::chunked::ChunkRecord::internal
//! [`chunk_own_error`]: crate::sim::algorithm::chunked::chunk_own_error

mod command;
mod loader;
mod open;
mod prepare;
mod samples;
mod source;

pub use command::{PrepareSource, prepare_command};
pub use loader::PyramidLoader;
pub use open::PyramidFile;
pub use prepare::{PrepareSummary, RawSource, prepare_from_field, prepare_from_raw};
pub use samples::PyramidSamples;
pub use source::{TerrainInMemory, read_experiment_terrain, read_terrain_file};

use crate::sim::algorithm::chunked::ChunkId;
use std::path::{Path, PathBuf};

/// The first eight bytes of every pyramid file.
pub const MAGIC: [u8; 8] = *b"ROAMPYRD";
/// The format version this build writes and reads.
pub const VERSION: u32 = 1;
/// Bytes of the header; the chunk records start here.
pub const HEADER_BYTES: u64 = 48;
/// Bytes of one chunk record: δ_c, lowest and highest sample, three little-endian `f32`.
pub const RECORD_BYTES: u64 = 12;
/// The largest terrain level a pyramid holds: 65 537² samples.
pub const MAX_TERRAIN_LEVEL: u32 = 16;
/// The deepest leaf level: chunk numbers fit a `u32` down to level 15.
pub const MAX_LEAF_LEVEL: u32 = 15;

/// How the heights are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StoredSample {
    /// Little-endian `i16`: every height an integer in −32 768..=32 767 (SRTM's).
    I16,
    /// Little-endian `f32`.
    F32,
}

impl StoredSample {
    pub fn bytes(self) -> u64 {
        match self {
            StoredSample::I16 => 2,
            StoredSample::F32 => 4,
        }
    }

    fn code(self) -> u32 {
        match self {
            StoredSample::I16 => 1,
            StoredSample::F32 => 2,
        }
    }

    fn from_code(code: u32) -> Option<StoredSample> {
        match code {
            1 => Some(StoredSample::I16),
            2 => Some(StoredSample::F32),
            _ => None,
        }
    }
}

/// What the header says, validated: the terrain and chunk levels, the spacing, the samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PyramidHeader {
    pub sample: StoredSample,
    /// n: the terrain has (2^n + 1)² samples.
    pub terrain_level: u32,
    /// c: chunks of (2^c + 1)² vertices, 1 ≤ c ≤ n.
    pub chunk_level: u32,
    /// Metres between samples, east and north.
    pub dx: f64,
    pub dy: f64,
}

impl PyramidHeader {
    /// Samples per side.
    pub fn side(&self) -> u64 {
        (1u64 << self.terrain_level) + 1
    }

    /// Cells per chunk side, 2^c.
    pub fn cells(&self) -> u32 {
        1 << self.chunk_level
    }

    /// D = n − c, the level of the full-resolution leaves.
    pub fn leaf_level(&self) -> u32 {
        self.terrain_level - self.chunk_level
    }

    /// Chunks in the tree: (4^(D+1) − 1)/3.
    pub fn n_chunks(&self) -> u64 {
        ((1u64 << (2 * (self.leaf_level() + 1))) - 1) / 3
    }

    /// Bytes of one chunk's heights.
    pub fn chunk_bytes(&self) -> u64 {
        let side = u64::from(self.cells()) + 1;
        side * side * self.sample.bytes()
    }

    /// Where chunk `id`'s record starts.
    pub fn record_offset(&self, id: ChunkId) -> u64 {
        HEADER_BYTES + u64::from(id.breadth_first_index()) * RECORD_BYTES
    }

    /// Where chunk `id`'s heights start.
    pub fn heights_offset(&self, id: ChunkId) -> u64 {
        HEADER_BYTES
            + self.n_chunks() * RECORD_BYTES
            + u64::from(id.breadth_first_index()) * self.chunk_bytes()
    }

    /// The file's length.
    pub fn file_bytes(&self) -> u64 {
        HEADER_BYTES + self.n_chunks() * (RECORD_BYTES + self.chunk_bytes())
    }

    /// The header's bytes.
    fn encode(&self) -> [u8; HEADER_BYTES as usize] {
        let mut bytes = [0u8; HEADER_BYTES as usize];
        bytes[0..8].copy_from_slice(&MAGIC);
        bytes[8..12].copy_from_slice(&VERSION.to_le_bytes());
        bytes[12..16].copy_from_slice(&self.sample.code().to_le_bytes());
        bytes[16..20].copy_from_slice(&self.terrain_level.to_le_bytes());
        bytes[20..24].copy_from_slice(&self.chunk_level.to_le_bytes());
        bytes[24..32].copy_from_slice(&self.dx.to_le_bytes());
        bytes[32..40].copy_from_slice(&self.dy.to_le_bytes());
        bytes[40..48].copy_from_slice(&self.n_chunks().to_le_bytes());
        bytes
    }

    /// The header `bytes` hold, or what is wrong with it (a sentence).
    fn decode(bytes: &[u8; HEADER_BYTES as usize]) -> Result<PyramidHeader, String> {
        let u32_at = |k: usize| u32::from_le_bytes(bytes[k..k + 4].try_into().expect("4 bytes"));
        let f64_at = |k: usize| f64::from_le_bytes(bytes[k..k + 8].try_into().expect("8 bytes"));
        if bytes[0..8] != MAGIC {
            return Err(
                "not a roamsim chunk pyramid (its first bytes are not \"ROAMPYRD\"; \
                 make one with `roamsim prepare`)"
                    .into(),
            );
        }
        let version = u32_at(8);
        if version != VERSION {
            return Err(format!(
                "field `version` is {version}; this roamsim reads version {VERSION} \
                 (prepare the terrain again)"
            ));
        }
        let sample = StoredSample::from_code(u32_at(12)).ok_or_else(|| {
            format!(
                "field `sample` is {}; expected 1 (i16) or 2 (f32)",
                u32_at(12)
            )
        })?;
        let terrain_level = u32_at(16);
        if !(1..=MAX_TERRAIN_LEVEL).contains(&terrain_level) {
            return Err(format!(
                "field `terrain_level` is {terrain_level}; expected 1 to {MAX_TERRAIN_LEVEL}"
            ));
        }
        let chunk_level = u32_at(20);
        if !(1..=terrain_level).contains(&chunk_level)
            || terrain_level - chunk_level > MAX_LEAF_LEVEL
        {
            return Err(format!(
                "field `chunk_level` is {chunk_level}; expected 1 to {terrain_level} (the terrain \
                 level), leaving at most {MAX_LEAF_LEVEL} levels of chunks below the root"
            ));
        }
        let (dx, dy) = (f64_at(24), f64_at(32));
        if !(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0) {
            return Err(format!(
                "fields `dx`, `dy` are {dx}, {dy}; expected finite spacings above 0 m"
            ));
        }
        let header = PyramidHeader {
            sample,
            terrain_level,
            chunk_level,
            dx,
            dy,
        };
        let n_chunks = u64::from_le_bytes(bytes[40..48].try_into().expect("8 bytes"));
        if n_chunks != header.n_chunks() {
            return Err(format!(
                "field `n_chunks` is {n_chunks}; a terrain level {terrain_level} with chunk level \
                 {chunk_level} has {}",
                header.n_chunks()
            ));
        }
        Ok(header)
    }
}

/// A pyramid could not be written or read: the file and what went wrong.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", path.display())]
pub struct PyramidError {
    pub path: PathBuf,
    pub problem: String,
}

impl PyramidError {
    fn new(path: &Path, problem: impl Into<String>) -> PyramidError {
        PyramidError {
            path: path.to_path_buf(),
            problem: problem.into(),
        }
    }
}

/// Every chunk of a tree with leaves at `leaf_level`, in breadth-first order (the file's).
pub fn chunk_ids(leaf_level: u32) -> impl Iterator<Item = ChunkId> {
    (0..=leaf_level).flat_map(|level| {
        let per_side = 1u32 << level;
        (0..per_side).flat_map(move |y| (0..per_side).map(move |x| ChunkId { level, x, y }))
    })
}
