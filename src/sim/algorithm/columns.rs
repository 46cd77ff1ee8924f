//! Every algorithm-specific column of `frames.csv`, named once. What a column means is in the
//! module doc of the algorithm that fills it (its "Counters" list); the common columns are
//! `FrameStats`'s, not here.
//!
//! An algorithm declares its columns ([`super::LodAlgorithm::extra_columns`]) with these
//! constants, and whoever reads a column by name (the plots, the report, the tests) uses them
//! too, so a misspelt name is a compile error. A name that is not here at all (a string typed
//! by hand) is refused loudly by [`extra_value`] and by the edge's column lookup: a panic, never
//! a silent empty column. A new algorithm adds its module here and its names to [`ALL`].

use crate::sim::stats::FrameStats;

/// `wu` (Wu et al. 2001).
pub mod wu {
    pub const BASE_B: &str = "base_b";
    pub const BASE_CLAMPED: &str = "base_clamped";
    pub const SPLITTABLE: &str = "splittable";
    pub const SPLIT_QUEUE: &str = "split_queue";
    pub const MERGEABLE: &str = "mergeable";
    pub const LIFE_RECOMPUTATIONS: &str = "life_recomputations";
    pub const FORCED_SPLITS: &str = "forced_splits";
    pub const CONE_TESTS: &str = "cone_tests";
    pub const TRIANGLES_IN_VIEW_BLOCKS: &str = "triangles_in_view_blocks";
    pub const TAU_PX: &str = "tau_px";
}

/// `lindstrom` (Lindstrom et al. 1996).
pub mod lindstrom {
    pub const BLOCKS_COARSEST: &str = "blocks_coarsest";
    pub const BLOCKS_FINEST: &str = "blocks_finest";
    pub const BLOCKS_PARTIAL: &str = "blocks_partial";
    pub const VERTICES_EVALUATED: &str = "vertices_evaluated";
    pub const VERTICES_BY_INTERVAL: &str = "vertices_by_interval";
    pub const FORCED_ACTIVATIONS: &str = "forced_activations";
    pub const BLOCKS_CHANGED: &str = "blocks_changed";
    pub const INTERVAL_PROBES: &str = "interval_probes";
}

/// `roam` and `roam-rebuild` (Duchaineau et al. 1997).
pub mod roam {
    pub const FORCED_SPLITS: &str = "forced_splits";
    pub const SPLIT_QUEUE: &str = "split_queue";
    pub const MERGE_QUEUE: &str = "merge_queue";
    pub const PRIORITY_RECOMPUTATIONS: &str = "priority_recomputations";
    pub const OSCILLATION_GUARD_STOPS: &str = "oscillation_guard_stops";
    pub const DEFERRED: &str = "deferred";
    pub const REVALIDATIONS: &str = "revalidations";
    pub const FLAG_TESTS: &str = "flag_tests";
    pub const TRIANGLES_PER_STRIP: &str = "triangles_per_strip";
}

/// `geomipmap` (de Boer 2000).
pub mod geomipmap {
    pub const PATCHES_REFINED_FOR_NEIGHBOURS: &str = "patches_refined_for_neighbours";
    pub const STITCHED_SIDES: &str = "stitched_sides";
    pub const PATCH_LEVEL_MEAN: &str = "patch_level_mean";
    pub const TAU: &str = "tau_px";
    pub const TARGET_UNREACHABLE: &str = "target_unreachable";
    pub const PATCHES_CULLED: &str = "patches_culled";
    pub const QUADTREE_NODES_VISITED: &str = "quadtree_nodes_visited";
}

/// `chunked` (Lauritsen and Nielsen 2005).
pub mod chunked {
    pub const CHUNKS_DRAWN: &str = "chunks_drawn";
    pub const CHUNKS_CULLED: &str = "chunks_culled";
    pub const SKIRT_DEPTH_MAX: &str = "skirt_depth_max_m";
    pub const ORDER_INVERSIONS: &str = "order_inversions";
    pub const TAU: &str = "tau_px";
    pub const TARGET_UNREACHABLE: &str = "target_unreachable";
    /// Chunks drawn coarser than the criterion wants: their children were not available.
    pub const CHUNKS_COARSER: &str = "chunks_coarser";
    pub const DETAIL_SYNTHESISED: &str = "detail_synthesised";
    pub const DETAIL_EVICTED: &str = "detail_evicted";
    pub const DETAIL_CACHED: &str = "detail_cached";
    /// Requests for children not served this frame (creation limit or cache cap).
    pub const DETAIL_REFUSED: &str = "detail_refused";
    /// Time spent synthesising and evicting inside the update, milliseconds.
    pub const DETAIL_SYNTHESIS_MS: &str = "detail_synthesis_ms";
    /// Bytes held by the synthesised chunks.
    pub const DETAIL_BYTES: &str = "detail_bytes";
    /// The deepest level drawn this frame.
    pub const DETAIL_DEEPEST_DRAWN: &str = "detail_deepest_level_drawn";
    /// Chunks requested and on their way (issued, not yet arrived), source and synthesised.
    pub const REQUESTS_IN_FLIGHT: &str = "requests_in_flight";
    /// Load requests the selection made this frame that were not issued (bandwidth, room).
    pub const REQUESTS_WAITING: &str = "requests_waiting";
    pub const CHUNKS_LOADED: &str = "chunks_loaded";
    pub const CHUNKS_UNLOADED: &str = "chunks_unloaded";
    /// Source chunks resident or on their way, the root not counted.
    pub const RESIDENT_CHUNKS: &str = "resident_chunks";
    /// Bytes the resident source chunks hold.
    pub const RESIDENT_BYTES: &str = "resident_bytes";
    /// With heights read from disk: chunks whose read was taken this frame (they arrived).
    pub const CHUNKS_READ: &str = "chunks_read";
    /// With heights read from disk: the longest request-to-read-end latency among this frame's
    /// reads, microseconds (0 without a read; a timing column).
    pub const READ_LATENCY_MAX_US: &str = "read_latency_max_us";
    /// With heights read from disk: their mean latency, microseconds (0 without a read; a
    /// timing column).
    pub const READ_LATENCY_MEAN_US: &str = "read_latency_mean_us";
    /// With heights read from disk: how long the update waited for reads not done when the
    /// model made their chunks available, microseconds (inside `update_ns`; a timing column).
    pub const READ_WAIT_US: &str = "read_wait_us";
}

/// `vanek` (Vaněk and Ježek 2004).
pub mod vanek {
    pub const STRIP_INDICES: &str = "strip_indices";
    pub const DEGENERATE_TRIANGLES: &str = "degenerate_triangles";
    pub const COLLAPSED_TRIANGLES: &str = "collapsed_triangles";
    pub const PATCHES_CULLED: &str = "patches_culled";
    pub const PATCH_LOD_MEAN: &str = "patch_lod_mean";
    pub const DISTANCE_MULTIPLIER: &str = "distance_multiplier";
    pub const TARGET_UNREACHABLE: &str = "target_unreachable";
    pub const QUADTREE_NODES_VISITED: &str = "quadtree_nodes_visited";
}

/// `stitching-strips` (the 2019 dynamic stitching strips).
pub mod stitching {
    pub const M_BLOCKS: &str = "m_blocks";
    pub const M_BLOCKS_CULLED: &str = "m_blocks_culled";
    pub const P_BLOCKS: &str = "p_blocks";
    pub const STRIPS: &str = "strips";
    pub const STRIPS_CULLED: &str = "strips_culled";
    pub const TESSELLATION_FACTOR_MEAN: &str = "tessellation_factor_mean";
    pub const TESSELLATION_FACTOR_2_4: &str = "tessellation_factor_2_4";
    pub const TESSELLATION_FACTOR_4_8: &str = "tessellation_factor_4_8";
    pub const TESSELLATION_FACTOR_8_16: &str = "tessellation_factor_8_16";
    pub const TESSELLATION_FACTOR_16_32: &str = "tessellation_factor_16_32";
    pub const TESSELLATION_FACTOR_32_64: &str = "tessellation_factor_32_64";
    /// The part of the update spent building strips and P-blocks (a timing column).
    pub const STRIP_CONSTRUCTION_NS: &str = "strip_construction_ns";
}

/// `rottger` (Röttger et al. 1998).
pub mod rottger {
    pub const DESIRED_RESOLUTION_C: &str = "desired_resolution_c";
    pub const C_CLAMPED: &str = "c_clamped";
    pub const FANS: &str = "fans";
    pub const FAN_VERTICES: &str = "fan_vertices";
    pub const FAN_TRIANGLES: &str = "fan_triangles";
    pub const MESH_VERTICES: &str = "mesh_vertices";
    pub const NODES_VISITED: &str = "nodes_visited";
    pub const SUBDIVIDED: &str = "subdivided";
    pub const FORCED_SPLITS: &str = "forced_splits";
    pub const CLIPPED_NODES: &str = "clipped_nodes";
    pub const MORPHING_VERTICES: &str = "morphing_vertices";
}

/// Every algorithm-specific column name (some are shared: `forced_splits`, `split_queue`,
/// `tau_px`, `target_unreachable`).
pub const ALL: &[&str] = &[
    wu::BASE_B,
    wu::BASE_CLAMPED,
    wu::SPLITTABLE,
    wu::SPLIT_QUEUE,
    wu::MERGEABLE,
    wu::LIFE_RECOMPUTATIONS,
    wu::FORCED_SPLITS,
    wu::CONE_TESTS,
    wu::TRIANGLES_IN_VIEW_BLOCKS,
    wu::TAU_PX,
    lindstrom::BLOCKS_COARSEST,
    lindstrom::BLOCKS_FINEST,
    lindstrom::BLOCKS_PARTIAL,
    lindstrom::VERTICES_EVALUATED,
    lindstrom::VERTICES_BY_INTERVAL,
    lindstrom::FORCED_ACTIVATIONS,
    lindstrom::BLOCKS_CHANGED,
    lindstrom::INTERVAL_PROBES,
    roam::FORCED_SPLITS,
    roam::SPLIT_QUEUE,
    roam::MERGE_QUEUE,
    roam::PRIORITY_RECOMPUTATIONS,
    roam::OSCILLATION_GUARD_STOPS,
    roam::DEFERRED,
    roam::REVALIDATIONS,
    roam::FLAG_TESTS,
    roam::TRIANGLES_PER_STRIP,
    geomipmap::PATCHES_REFINED_FOR_NEIGHBOURS,
    geomipmap::STITCHED_SIDES,
    geomipmap::PATCH_LEVEL_MEAN,
    geomipmap::TAU,
    geomipmap::TARGET_UNREACHABLE,
    geomipmap::PATCHES_CULLED,
    geomipmap::QUADTREE_NODES_VISITED,
    chunked::CHUNKS_DRAWN,
    chunked::CHUNKS_CULLED,
    chunked::SKIRT_DEPTH_MAX,
    chunked::ORDER_INVERSIONS,
    chunked::TAU,
    chunked::TARGET_UNREACHABLE,
    chunked::CHUNKS_COARSER,
    chunked::DETAIL_SYNTHESISED,
    chunked::DETAIL_EVICTED,
    chunked::DETAIL_CACHED,
    chunked::DETAIL_REFUSED,
    chunked::DETAIL_SYNTHESIS_MS,
    chunked::DETAIL_BYTES,
    chunked::DETAIL_DEEPEST_DRAWN,
    chunked::REQUESTS_IN_FLIGHT,
    chunked::REQUESTS_WAITING,
    chunked::CHUNKS_LOADED,
    chunked::CHUNKS_UNLOADED,
    chunked::RESIDENT_CHUNKS,
    chunked::RESIDENT_BYTES,
    chunked::CHUNKS_READ,
    chunked::READ_LATENCY_MAX_US,
    chunked::READ_LATENCY_MEAN_US,
    chunked::READ_WAIT_US,
    vanek::STRIP_INDICES,
    vanek::DEGENERATE_TRIANGLES,
    vanek::COLLAPSED_TRIANGLES,
    vanek::PATCHES_CULLED,
    vanek::PATCH_LOD_MEAN,
    vanek::DISTANCE_MULTIPLIER,
    vanek::TARGET_UNREACHABLE,
    vanek::QUADTREE_NODES_VISITED,
    stitching::M_BLOCKS,
    stitching::M_BLOCKS_CULLED,
    stitching::P_BLOCKS,
    stitching::STRIPS,
    stitching::STRIPS_CULLED,
    stitching::TESSELLATION_FACTOR_MEAN,
    stitching::TESSELLATION_FACTOR_2_4,
    stitching::TESSELLATION_FACTOR_4_8,
    stitching::TESSELLATION_FACTOR_8_16,
    stitching::TESSELLATION_FACTOR_16_32,
    stitching::TESSELLATION_FACTOR_32_64,
    stitching::STRIP_CONSTRUCTION_NS,
    rottger::DESIRED_RESOLUTION_C,
    rottger::C_CLAMPED,
    rottger::FANS,
    rottger::FAN_VERTICES,
    rottger::FAN_TRIANGLES,
    rottger::MESH_VERTICES,
    rottger::NODES_VISITED,
    rottger::SUBDIVIDED,
    rottger::FORCED_SPLITS,
    rottger::CLIPPED_NODES,
    rottger::MORPHING_VERTICES,
];

/// Whether `name` is an algorithm-specific column of some algorithm.
pub fn is_known(name: &str) -> bool {
    ALL.contains(&name)
}

/// The value of column `name` in `stats` of an algorithm that declares the columns `declared`:
/// `None` when it does not declare `name`.
///
/// # Panics
/// When `name` is no algorithm's column (a misspelt name must not read as "not applicable").
pub fn extra_value(declared: &[&str], stats: &FrameStats, name: &str) -> Option<f64> {
    assert!(
        is_known(name),
        "{name:?} is no algorithm's column (see sim::algorithm::columns)"
    );
    let k = declared.iter().position(|c| *c == name)?;
    stats.extra.get(k).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_declared_column_is_read_and_an_undeclared_one_does_not_apply() {
        let stats = FrameStats {
            extra: vec![-3.0, 1.0],
            ..FrameStats::default()
        };
        let declared = [wu::BASE_B, wu::BASE_CLAMPED];
        assert_eq!(extra_value(&declared, &stats, wu::BASE_CLAMPED), Some(1.0));
        assert_eq!(extra_value(&declared, &stats, roam::SPLIT_QUEUE), None);
    }

    #[test]
    fn a_misspelt_column_is_refused_loudly() {
        let result = std::panic::catch_unwind(|| {
            extra_value(&[wu::BASE_B], &FrameStats::default(), "base_bb")
        });
        let message = result.expect_err("a misspelt column must panic");
        let message = message.downcast_ref::<String>().map(String::as_str);
        assert_eq!(
            message,
            Some("\"base_bb\" is no algorithm's column (see sim::algorithm::columns)")
        );
    }
}
