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
//! - **Read from disk** ([`ChunkHeightSource`], attached by `Chunked::with_disk_heights`): the
//!   same model decides when a chunk is available; the real read starts when its load is
//!   issued, and a frame that reaches a chunk's arrival before its read is done waits for it
//!   (measured per frame, [`DiskFrame`]), so the meshes are those of the modelled loading
//!   whatever the disk's speed. The heights drawn are the ones read. The measured reads are
//!   reported beside the model's counts: per frame the reads taken, their latency (largest,
//!   mean) and the wait (frames.csv's `chunks_read`, `read_latency_max_us`,
//!   `read_latency_mean_us`, `read_wait_us`, timing columns), and per run their p50, p95 and
//!   largest latency (summary.json's facts).
//!
//! "The same flight without latency" is the same entry without this effect: every source
//! chunk resident from the start (synthesised chunks then arrive the frame after their
//! request).

use super::cache::GroupCache;
use super::tree::ChunkId;
use crate::sim::stats::nearest_rank;
use std::collections::BTreeMap;

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
    /// With a source read from disk, the resident chunks' heights (`None`: the modelled
    /// loading reads them from the shared field).
    pub(super) disk: Option<DiskHeights>,
}

impl Loading {
    pub(super) fn new(config: LoadingConfig, cells: u32) -> Loading {
        let side = cells as usize + 1;
        Loading {
            config,
            resident: GroupCache::default(),
            chunk_bytes: side * side * std::mem::size_of::<f32>(),
            disk: None,
        }
    }

    /// Bytes the resident (and arriving) chunks hold: their vertices and the cache's entries.
    pub(super) fn memory_bytes(&self) -> usize {
        self.resident.len() * (self.chunk_bytes + GroupCache::<()>::ENTRY_BYTES)
            + self.disk.as_ref().map_or(0, DiskHeights::memory_bytes)
    }
}

/// Where the heights of a source read from disk come from: the core asks for a chunk when its
/// load is issued and takes its heights when the model makes it available. The edge implements
/// it with the file and a loader thread (`src/edge/pyramid/loader.rs`); the core does no IO.
pub trait ChunkHeightSource: Send {
    /// Starts reading chunk `id`'s heights; returns at once.
    fn request(&mut self, id: ChunkId);
    /// Requested chunk `id`'s (2^c + 1)² heights, row by row from the south, waiting for its
    /// read to finish; the read's own latency from the request. An error (the read failed) is a
    /// sentence naming the file.
    fn take(&mut self, id: ChunkId) -> Result<ChunkRead, String>;
}

/// One chunk's heights as read, with the read's latency from its request.
#[derive(Clone, Debug, PartialEq)]
pub struct ChunkRead {
    pub heights: Vec<f32>,
    pub latency_ns: u64,
}

/// What the reads did in one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DiskFrame {
    /// Chunks whose heights arrived this frame (the model made them available).
    pub chunks_arrived: u64,
    /// The longest read latency among them, from request to read done, nanoseconds.
    pub read_latency_max_ns: u64,
    /// The sum of their read latencies, nanoseconds (their mean is this over `chunks_arrived`).
    pub read_latency_sum_ns: u64,
    /// How long the frame waited for reads not finished when the model made them available.
    pub wait_ns: u64,
}

/// The reads of a whole flight: what summary.json's facts say of them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ReadsSummary {
    pub(super) reads: u64,
    pub(super) latency_p50_ns: f64,
    pub(super) latency_p95_ns: f64,
    pub(super) latency_max_ns: f64,
    pub(super) wait_total_ns: u64,
}

/// The heights of the resident source chunks, read on demand through a [`ChunkHeightSource`].
/// The modelled loading alone decides when a chunk is available, so meshes do not depend on IO
/// timing: a read not done by then is waited for. Memory: the arrived chunks' heights, which
/// are the resident bytes `Loading::memory_bytes` counts.
pub(super) struct DiskHeights {
    source: Box<dyn ChunkHeightSource>,
    /// Arrived chunks' heights (the root always).
    held: BTreeMap<ChunkId, Vec<f32>>,
    /// Requested chunks not yet arrived, with the frame they become available.
    pending: Vec<(ChunkId, u64)>,
    pub(super) frame: DiskFrame,
    /// Every read taken in a frame so far (the root's, read before the flight, not counted),
    /// its latency in nanoseconds: 8 bytes a read, for the run's percentiles.
    latencies_ns: Vec<u64>,
    /// The frames' waits added up, nanoseconds.
    wait_total_ns: u64,
}

impl DiskHeights {
    /// Reads the root now (it is always resident); the error of a failed read.
    pub(super) fn new(mut source: Box<dyn ChunkHeightSource>) -> Result<DiskHeights, String> {
        source.request(ChunkId::ROOT);
        let root = source.take(ChunkId::ROOT)?;
        Ok(DiskHeights {
            source,
            held: BTreeMap::from([(ChunkId::ROOT, root.heights)]),
            pending: Vec::new(),
            frame: DiskFrame::default(),
            latencies_ns: Vec::new(),
            wait_total_ns: 0,
        })
    }

    /// Starts reading `id`, available from `available_from`.
    pub(super) fn request(&mut self, id: ChunkId, available_from: u64) {
        self.source.request(id);
        self.pending.push((id, available_from));
    }

    /// Takes the heights of every chunk available by `frame`, waiting for unfinished reads.
    ///
    /// # Panics
    /// When a read failed (the file was checked at open; this is the disk failing mid-run).
    pub(super) fn arrive(&mut self, frame: u64) {
        self.frame = DiskFrame::default();
        let mut k = 0;
        while k < self.pending.len() {
            let (id, available_from) = self.pending[k];
            if available_from > frame {
                k += 1;
                continue;
            }
            self.pending.swap_remove(k);
            let start = std::time::Instant::now();
            let read = self
                .source
                .take(id)
                .unwrap_or_else(|error| panic!("chunk {id:?} could not be read: {error}"));
            self.frame.wait_ns += start.elapsed().as_nanos() as u64;
            self.frame.chunks_arrived += 1;
            self.frame.read_latency_max_ns = self.frame.read_latency_max_ns.max(read.latency_ns);
            self.frame.read_latency_sum_ns += read.latency_ns;
            self.latencies_ns.push(read.latency_ns);
            self.held.insert(id, read.heights);
        }
        self.wait_total_ns += self.frame.wait_ns;
    }

    /// The reads taken so far, summarised: their number, the p50, p95 and largest latency
    /// (nearest rank) and the frames' total wait; `None` before the first.
    pub(super) fn reads_summary(&self) -> Option<ReadsSummary> {
        let mut sorted: Vec<f64> = self.latencies_ns.iter().map(|&ns| ns as f64).collect();
        sorted.sort_unstable_by(f64::total_cmp);
        let last = *sorted.last()?;
        Some(ReadsSummary {
            reads: sorted.len() as u64,
            latency_p50_ns: nearest_rank(&sorted, 0.50),
            latency_p95_ns: nearest_rank(&sorted, 0.95),
            latency_max_ns: last,
            wait_total_ns: self.wait_total_ns,
        })
    }

    /// Bytes of the reads' record (the latencies kept for the percentiles).
    pub(super) fn memory_bytes(&self) -> usize {
        self.latencies_ns.capacity() * std::mem::size_of::<u64>()
    }

    /// Drops the heights of chunks no longer resident.
    pub(super) fn forget_evicted(&mut self, resident: &GroupCache<()>) {
        self.held
            .retain(|&id, _| id == ChunkId::ROOT || resident.get_any(id).is_some());
    }

    /// The height of vertex (a, b) of arrived chunk `id`, `side` vertices a row.
    ///
    /// # Panics
    /// When `id` has not arrived.
    pub(super) fn height(&self, id: ChunkId, a: u32, b: u32, side: u32) -> f32 {
        let heights = self
            .held
            .get(&id)
            .unwrap_or_else(|| panic!("chunk {id:?}'s heights have not arrived"));
        heights[(b * side + a) as usize]
    }
}
