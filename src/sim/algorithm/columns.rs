//! Every algorithm-specific column of `frames.csv`, named once.
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
    pub const MERGEABLE: &str = "mergeable";
    pub const LIFE_RECOMPUTATIONS: &str = "life_recomputations";
    pub const FORCED_SPLITS: &str = "forced_splits";
    pub const CONE_RENDERED: &str = "cone_rendered";
}

/// `lindstrom` (Lindstrom et al. 1996).
pub mod lindstrom {
    pub const BLOCKS_COARSEST: &str = "blocks_coarsest";
    pub const BLOCKS_FINEST: &str = "blocks_finest";
    pub const BLOCKS_PARTIAL: &str = "blocks_partial";
    pub const VERTICES_EVALUATED: &str = "vertices_evaluated";
    pub const VERTICES_BY_INTERVAL: &str = "vertices_by_interval";
    pub const FORCED_ACTIVATIONS: &str = "forced_activations";
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
    pub const TRIANGLES_PER_STRIP: &str = "triangles_per_strip";
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

/// Every algorithm-specific column name (some are shared: `forced_splits`).
pub const ALL: &[&str] = &[
    wu::BASE_B,
    wu::BASE_CLAMPED,
    wu::SPLITTABLE,
    wu::MERGEABLE,
    wu::LIFE_RECOMPUTATIONS,
    wu::FORCED_SPLITS,
    wu::CONE_RENDERED,
    lindstrom::BLOCKS_COARSEST,
    lindstrom::BLOCKS_FINEST,
    lindstrom::BLOCKS_PARTIAL,
    lindstrom::VERTICES_EVALUATED,
    lindstrom::VERTICES_BY_INTERVAL,
    lindstrom::FORCED_ACTIVATIONS,
    roam::FORCED_SPLITS,
    roam::SPLIT_QUEUE,
    roam::MERGE_QUEUE,
    roam::PRIORITY_RECOMPUTATIONS,
    roam::OSCILLATION_GUARD_STOPS,
    roam::DEFERRED,
    roam::REVALIDATIONS,
    roam::TRIANGLES_PER_STRIP,
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
