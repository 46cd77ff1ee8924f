//! After each frame's selection: mark what it visited as used, then serve its requests for
//! missing children (Lauritsen–Nielsen's listings 3.6–3.7), in visiting order — a source group
//! is loaded (out-of-core loading), a group below the source leaves is synthesised (runtime
//! detail) — within the frame's bandwidth, §3.4.4's limits on creation (chunks requested and
//! not yet finished; optionally the viewpoint's velocity) and the caps, evicting least recently
//! used groups to make room. Policies: `loading.rs`, `detail.rs`.
//!
//! Per frame: O(chunks visited + requests · (held chunks + a chunk's samples)).

use super::cache::GroupCache;
use super::loading::Loading;
use super::select::Selection;
use super::synthesis::RuntimeDetail;
use super::tree::{ChunkId, ChunkTree};
use std::time::Instant;

/// What one frame's requests did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct RequestsFrame {
    /// Chunks synthesised (made now, drawn after the latency).
    pub(super) synthesised: u64,
    /// Synthesised chunks evicted.
    pub(super) evicted: u64,
    /// Synthesis requests not served this frame (creation limit, bandwidth or no room).
    pub(super) refused: u64,
    /// Source chunks whose loading was issued.
    pub(super) loaded: u64,
    /// Source chunks evicted.
    pub(super) unloaded: u64,
    /// Load requests not issued this frame (bandwidth or no room).
    pub(super) waiting: u64,
    /// Time spent synthesising and evicting, nanoseconds (inside the update).
    pub(super) synthesis_ns: u64,
}

/// Serves `selection`'s requests in `frame`, the viewpoint having moved `speed_m` metres since
/// the previous frame (see the module docs).
pub(super) fn serve(
    tree: &ChunkTree,
    selection: &Selection,
    mut detail: Option<&mut RuntimeDetail>,
    mut loading: Option<&mut Loading>,
    frame: u64,
    speed_m: f64,
) -> RequestsFrame {
    let start = Instant::now();
    let leaf_level = tree.leaf_level();
    let visited = selection
        .drawn
        .iter()
        .map(|c| c.id)
        .chain(selection.refined.iter().copied())
        .chain(selection.culled.iter().copied());
    for id in visited {
        if id.level > leaf_level {
            if let Some(detail) = detail.as_deref_mut() {
                detail.cache.touch(id, frame);
            }
        } else if let Some(loading) = loading.as_deref_mut() {
            loading.resident.touch(id, frame);
        }
    }
    let (mut bandwidth, latency) = loading.as_deref().map_or((u64::MAX, 1), |loading| {
        (
            u64::from(loading.config.bandwidth_chunks_per_frame),
            u64::from(loading.config.latency_frames.max(1)),
        )
    });
    // Synthesised chunks requested in earlier frames and not finished yet (still on their way).
    let queued_before = detail
        .as_deref()
        .map_or(0, |detail| detail.cache.in_flight() as u64);
    let mut out = RequestsFrame::default();
    for &parent in &selection.requested {
        let first_child: ChunkId = parent.children()[0];
        if parent.level < leaf_level {
            let loading = loading
                .as_deref_mut()
                .expect("source chunks are requested only when they are loaded");
            let resident = &mut loading.resident;
            if resident.get_any(first_child).is_some() {
                continue; // On its way.
            }
            let cap = loading.config.resident_chunks as usize;
            if bandwidth < 4 || !make_room(resident, cap, frame, &mut out.unloaded) {
                out.waiting += 1;
                continue;
            }
            for child in parent.children() {
                resident.insert(child, (), frame, frame + latency);
            }
            if let Some(disk) = loading.disk.as_mut() {
                disk.forget_evicted(&loading.resident);
                for child in parent.children() {
                    disk.request(child, frame + latency);
                }
            }
            bandwidth -= 4;
            out.loaded += 4;
        } else {
            let detail = detail
                .as_deref_mut()
                .expect("chunks below the source leaves are requested only with detail on");
            if detail.cache.get_any(first_child).is_some() {
                continue; // On its way.
            }
            let cap = detail.cache_cap();
            if bandwidth < 4
                || queued_before + out.synthesised + 4 > detail.queue_limit()
                || detail.too_fast_for_children(parent, speed_m)
                || !make_room(&mut detail.cache, cap, frame, &mut out.evicted)
            {
                out.refused += 1;
                continue;
            }
            detail.synthesise_children(tree, parent, frame, frame + latency);
            bandwidth -= 4;
            out.synthesised += 4;
        }
    }
    out.synthesis_ns = start.elapsed().as_nanos() as u64;
    out
}

/// Evicts groups until four more chunks fit under `cap`; whether they do.
fn make_room<T>(cache: &mut GroupCache<T>, cap: usize, frame: u64, evicted: &mut u64) -> bool {
    while cache.len() + 4 > cap {
        let n = cache.evict_one(frame);
        if n == 0 {
            return false;
        }
        *evicted += n as u64;
    }
    true
}
