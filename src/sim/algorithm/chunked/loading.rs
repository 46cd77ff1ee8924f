//! Out-of-core loading with latency (Lauritsen–Nielsen §3.2.14–3.2.15), an effect of
//! `chunked`: the source chunks below the root are resident only once loaded.
//!
//! The model, in frames (no IO: a simulation of a loader, so that runs are deterministic):
//!
//! - Every chunk's record (its error and box, 16 bytes) is known up front, as the paper's file
//!   directory is; what is loaded is a chunk's vertices ((2^c + 1)² heights), counted as the
//!   resident bytes (`resident_bytes`) while the heights themselves stay in the shared field.
//!   The root is always resident.
//! - When the selection wants a chunk's children and they are not resident, it draws the chunk
//!   and requests them (listing 3.6, the asynchronous scheme); siblings travel together.
//! - Requests are issued in the selection's visiting order (nearest first with front-to-back
//!   on) while the frame's bandwidth (`bandwidth_chunks_per_frame`, four chunks a group)
//!   lasts; a group issued in frame f is drawn from frame f + `latency_frames` on (latency ≥ 1:
//!   the request is made after the frame's selection). Requests not issued are not queued:
//!   the selection asks again next frame if it still wants them (counted as waiting).
//! - Memory: at most `resident_chunks` chunks resident or on their way. Room is made when a
//!   request is issued, by evicting the least recently used group that nothing resident hangs
//!   below and nothing drew this frame (the paper's LRU cache); with no such group the request
//!   waits.
//! - Synthesised chunks (runtime detail, when on) travel the same way: made when issued (within
//!   the creation limit), drawn `latency_frames` later, sharing the bandwidth.
//!
//! "The same flight without latency" is the same entry without this effect: every source
//! chunk resident from the start (synthesised chunks then arrive the frame after their
//! request).

use super::cache::GroupCache;

/// The loading effect as the experiment declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadingConfig {
    /// Frames from a request's issue to the first frame its chunks are drawn (≥ 1).
    pub latency_frames: u32,
    /// Chunks issued per frame (≥ 4: one sibling group).
    pub bandwidth_chunks_per_frame: u32,
    /// Most source chunks resident or on their way, the root not counted (≥ 4).
    pub resident_chunks: u32,
}

/// The resident source chunks.
pub(super) struct Loading {
    pub(super) config: LoadingConfig,
    pub(super) resident: GroupCache<()>,
    /// Bytes of one resident chunk's vertices.
    pub(super) chunk_bytes: usize,
}

impl Loading {
    pub(super) fn new(config: LoadingConfig, cells: u32) -> Loading {
        let side = cells as usize + 1;
        Loading {
            config,
            resident: GroupCache::default(),
            chunk_bytes: side * side * std::mem::size_of::<f32>(),
        }
    }

    /// Bytes the resident (and arriving) chunks hold: their vertices and the cache's entries.
    pub(super) fn memory_bytes(&self) -> usize {
        self.resident.len() * (self.chunk_bytes + GroupCache::<()>::ENTRY_BYTES)
    }
}
