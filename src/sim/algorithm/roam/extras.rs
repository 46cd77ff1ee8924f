//! ROAM's extra columns: which a run writes (the base ones, then those of the effects that are
//! on, fewer for `roam-rebuild`) and their values from a frame's counters, in the same order.
//! The column names themselves are `algorithm/columns.rs`'s.

use super::RoamConfig;
use super::core::Core;
use super::strips;

/// The extra columns of a run: the base ones, then those of the effects that are on.
pub(super) fn columns(config: &RoamConfig, incremental: bool) -> &'static [&'static str] {
    use super::super::columns::roam::{
        DEFERRED, FLAG_TESTS, FORCED_SPLITS, MERGE_QUEUE, OSCILLATION_GUARD_STOPS,
        PRIORITY_RECOMPUTATIONS, REVALIDATIONS, SPLIT_QUEUE, TRIANGLES_PER_STRIP,
    };
    const BASE: &[&str] = &[
        FORCED_SPLITS,
        SPLIT_QUEUE,
        MERGE_QUEUE,
        PRIORITY_RECOMPUTATIONS,
        OSCILLATION_GUARD_STOPS,
    ];
    const TABLE: [&[&str]; 8] = [
        BASE,
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            DEFERRED,
            REVALIDATIONS,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            FLAG_TESTS,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            DEFERRED,
            REVALIDATIONS,
            FLAG_TESTS,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            TRIANGLES_PER_STRIP,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            DEFERRED,
            REVALIDATIONS,
            TRIANGLES_PER_STRIP,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            FLAG_TESTS,
            TRIANGLES_PER_STRIP,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            MERGE_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            OSCILLATION_GUARD_STOPS,
            DEFERRED,
            REVALIDATIONS,
            FLAG_TESTS,
            TRIANGLES_PER_STRIP,
        ],
    ];
    const REBUILD: [&[&str]; 4] = [
        &[FORCED_SPLITS, SPLIT_QUEUE, PRIORITY_RECOMPUTATIONS],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            FLAG_TESTS,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            TRIANGLES_PER_STRIP,
        ],
        &[
            FORCED_SPLITS,
            SPLIT_QUEUE,
            PRIORITY_RECOMPUTATIONS,
            FLAG_TESTS,
            TRIANGLES_PER_STRIP,
        ],
    ];
    let culling = usize::from(config.culling_flags);
    let strips = usize::from(config.strips);
    if incremental {
        TABLE[usize::from(config.deferral) + 2 * culling + 4 * strips]
    } else {
        REBUILD[culling + 2 * strips]
    }
}

impl Core<'_> {
    /// The extra columns' values in the order of `columns`.
    ///
    /// # Panics
    /// On a column this function does not know (a list in `columns` that grew without it):
    /// loudly, never as a silent NaN.
    pub fn extras(&self, columns: &[&str]) -> Vec<f64> {
        use super::super::columns::roam::{
            DEFERRED, FLAG_TESTS, FORCED_SPLITS, MERGE_QUEUE, OSCILLATION_GUARD_STOPS,
            PRIORITY_RECOMPUTATIONS, REVALIDATIONS, SPLIT_QUEUE, TRIANGLES_PER_STRIP,
        };
        let counters = self.counters;
        columns
            .iter()
            .map(|&column| match column {
                FORCED_SPLITS => counters.forced as f64,
                SPLIT_QUEUE => self.queues.split.len() as f64,
                MERGE_QUEUE => self.queues.merge.len() as f64,
                PRIORITY_RECOMPUTATIONS => counters.evaluations as f64,
                OSCILLATION_GUARD_STOPS => counters.guard_stops as f64,
                DEFERRED => counters.deferred as f64,
                REVALIDATIONS => counters.revalidations as f64,
                FLAG_TESTS => counters.flag_tests as f64,
                TRIANGLES_PER_STRIP => strips::triangles_per_strip(&self.bintree),
                other => unreachable!("ROAM fills no column {other:?}"),
            })
            .collect()
    }
}
