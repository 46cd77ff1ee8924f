//! The columns of `frames.csv` and `summary.json`, defined once (each documented in
//! `docs/output-formats.md`, "frames.csv").
//!
//! Order: `algorithm`, `frame`, the common counters, then the mesh columns when some run's mesh
//! has them (triangle lists and morphed 4-8 meshes), then every algorithm-specific column in the
//! order first declared by the run's algorithms (empty where an algorithm does not have it),
//! then the audit columns when the audit ran, its coverage columns when some run drew a
//! triangle list, and the popping columns when popping was measured.
//!
//! Columns are looked up by name ([`value`]); a name that is no column at all is a bug and
//! panics, so a misspelling can never read as an empty column. Algorithm-specific names are the
//! constants of [`crate::sim::algorithm::columns`].

use crate::sim::algorithm::columns::extra_value;
use crate::sim::stats::{AuditFrame, ErrorSummary, FrameStats, PoppingFrame, SurfaceCoverage};

/// The common counters, in order.
pub const COMMON_COLUMNS: &[&str] = &[
    "triangles",
    "triangles_rendered",
    "splits",
    "merges",
    "vertices_inserted",
    "vertices_deleted",
    "metric_evaluations",
    "update_ns",
    "frame_ns",
    "upload_bytes",
    "draw_calls",
    "triangles_submitted",
];

/// What the families beyond plain 4-8 meshes are counted by, in order (present when some run's
/// frames have them).
pub const MESH_COLUMNS: &[&str] = &[
    "triangles_surface",
    "triangles_skirt",
    "triangles_degenerate",
    "triangles_stitch",
    "morphing_vertices",
];

/// Audit columns, in order.
pub const AUDIT_COLUMNS: &[&str] = &[
    "audit_samples_in_view",
    "audit_projected_max_px",
    "audit_projected_mean_px",
    "audit_projected_p95_px",
    "audit_view_angle_max_px",
    "audit_view_angle_mean_px",
    "audit_view_angle_p95_px",
];

/// Holes and cracks of triangle-list meshes, in order (present when some run drew one).
pub const COVERAGE_COLUMNS: &[&str] = &[
    "audit_holes",
    "audit_crack_samples",
    "audit_crack_gap_max_m",
    "audit_crack_gap_max_px",
    "audit_cracks_uncovered",
    "audit_crack_uncovered_max_m",
    "audit_crack_uncovered_max_px",
];

/// The audit against the detail-extended surface, in order (present when some entry
/// synthesised detail under the audit): the `audit_*` columns measure against the source.
pub const DETAIL_AUDIT_COLUMNS: &[&str] = &[
    "audit_detail_samples_in_view",
    "audit_detail_projected_max_px",
    "audit_detail_projected_mean_px",
    "audit_detail_projected_p95_px",
    "audit_detail_view_angle_max_px",
    "audit_detail_view_angle_mean_px",
    "audit_detail_view_angle_p95_px",
    "audit_detail_holes",
];

/// Popping columns, in order (present when popping was measured).
pub const POPPING_COLUMNS: &[&str] = &[
    "popping_rmse_m",
    "popping_max_m",
    "popping_rmse_px",
    "popping_max_px",
];

/// Columns whose values are wall-clock measurements (excluded from determinism comparisons).
pub const TIMING_COLUMNS: &[&str] = &[
    "update_ns",
    "frame_ns",
    "strip_construction_ns",
    "detail_synthesis_ms",
    "read_latency_max_us",
    "read_latency_mean_us",
    "read_wait_us",
];

/// The timing columns measured once, in the pass that reads from disk, never replaced by a
/// timing pass's: a timing pass rereads chunks the page cache now holds, so its reads would
/// say nothing of the disk.
pub const MEASURED_PASS_TIMING_COLUMNS: &[&str] = &[
    "read_latency_max_us",
    "read_latency_mean_us",
    "read_wait_us",
];

/// One algorithm's frames with the names of its extra columns.
pub struct RunColumns<'a> {
    pub label: &'a str,
    pub extra_columns: &'a [&'a str],
    pub frames: &'a [FrameStats],
}

/// The numeric columns of a run (everything but `algorithm` and `frame`).
pub fn numeric_columns<'a>(runs: &[RunColumns<'a>], audited: bool) -> Vec<&'a str> {
    let any_frame =
        |has: &dyn Fn(&FrameStats) -> bool| runs.iter().any(|r| r.frames.iter().any(has));
    let mut names: Vec<&'a str> = COMMON_COLUMNS.to_vec();
    if any_frame(&|f| f.mesh.is_some()) {
        names.extend_from_slice(MESH_COLUMNS);
    }
    for run in runs {
        for name in run.extra_columns {
            if !names.contains(name) {
                names.push(name);
            }
        }
    }
    if audited {
        names.extend_from_slice(AUDIT_COLUMNS);
        if any_frame(&|f| f.audit.is_some_and(|a| a.coverage.is_some())) {
            names.extend_from_slice(COVERAGE_COLUMNS);
        }
        if any_frame(&|f| f.audit.is_some_and(|a| a.popping.is_some())) {
            names.extend_from_slice(POPPING_COLUMNS);
        }
        if any_frame(&|f| f.audit_detail.is_some()) {
            names.extend_from_slice(DETAIL_AUDIT_COLUMNS);
        }
    }
    names
}

/// The value of `column` in a frame of `run`, or `None` where it does not apply.
///
/// # Panics
/// When `column` is no column of `frames.csv` (a misspelt name).
pub fn value(run: &RunColumns, frame: &FrameStats, column: &str) -> Option<f64> {
    let count = |n: u64| Some(n as f64);
    let mesh = frame.mesh.as_ref();
    let audit = frame.audit.as_ref();
    match column {
        "triangles" => count(frame.triangles),
        "triangles_rendered" => count(frame.triangles_rendered),
        "splits" => count(frame.splits),
        "merges" => count(frame.merges),
        "vertices_inserted" => count(frame.vertices_inserted),
        "vertices_deleted" => count(frame.vertices_deleted),
        "metric_evaluations" => count(frame.metric_evaluations),
        "update_ns" => count(frame.update_ns),
        "frame_ns" => count(frame.frame_ns),
        "upload_bytes" => count(frame.upload_bytes),
        "draw_calls" => count(frame.draw_calls),
        "triangles_submitted" => count(frame.triangles_submitted),
        "triangles_surface" => mesh.map(|m| m.triangles_by_role[0] as f64),
        "triangles_skirt" => mesh.map(|m| m.triangles_by_role[1] as f64),
        "triangles_degenerate" => mesh.map(|m| m.triangles_by_role[2] as f64),
        "triangles_stitch" => mesh.map(|m| m.triangles_by_role[3] as f64),
        "morphing_vertices" => mesh.map(|m| m.morphing_vertices as f64),
        _ if column.starts_with("audit_detail_") => audit_value(
            frame.audit_detail.as_ref(),
            &column.replacen("audit_detail_", "audit_", 1),
        ),
        _ if column.starts_with("audit_") => audit_value(audit, column),
        _ if column.starts_with("popping_") => {
            popping_value(audit.and_then(|a| a.popping.as_ref()), column)
        }
        _ => extra_value(run.extra_columns, frame, column),
    }
}

/// An `audit_*` column; panics on a name that is none.
fn audit_value(audit: Option<&AuditFrame>, column: &str) -> Option<f64> {
    let pick = |summary: Option<ErrorSummary>, field: fn(ErrorSummary) -> f64| summary.map(field);
    let projected = audit.and_then(|a| a.projected);
    let view_angle = audit.and_then(|a| a.view_angle);
    let coverage =
        |field: fn(&SurfaceCoverage) -> f64| audit.and_then(|a| a.coverage.as_ref()).map(field);
    match column {
        "audit_samples_in_view" => audit.map(|a| a.samples_in_view as f64),
        "audit_projected_max_px" => pick(projected, |s| s.max),
        "audit_projected_mean_px" => pick(projected, |s| s.mean),
        "audit_projected_p95_px" => pick(projected, |s| s.p95),
        "audit_view_angle_max_px" => pick(view_angle, |s| s.max),
        "audit_view_angle_mean_px" => pick(view_angle, |s| s.mean),
        "audit_view_angle_p95_px" => pick(view_angle, |s| s.p95),
        "audit_holes" => coverage(|c| c.holes as f64),
        "audit_crack_samples" => coverage(|c| c.crack_samples as f64),
        "audit_crack_gap_max_m" => coverage(|c| c.crack_gap_max_m),
        "audit_crack_gap_max_px" => coverage(|c| c.crack_gap_max_px),
        "audit_cracks_uncovered" => coverage(|c| c.cracks_uncovered as f64),
        "audit_crack_uncovered_max_m" => coverage(|c| c.crack_uncovered_max_m),
        "audit_crack_uncovered_max_px" => coverage(|c| c.crack_uncovered_max_px),
        _ => panic!("{column:?} is no audit column"),
    }
}

/// A `popping_*` column; panics on a name that is none.
fn popping_value(popping: Option<&PoppingFrame>, column: &str) -> Option<f64> {
    let field: fn(&PoppingFrame) -> f64 = match column {
        "popping_rmse_m" => |p| p.rmse_m,
        "popping_max_m" => |p| p.max_m,
        "popping_rmse_px" => |p| p.rmse_px,
        "popping_max_px" => |p| p.max_px,
        _ => panic!("{column:?} is no popping column"),
    };
    popping.map(field)
}

/// A number as CSV text: whole numbers without a decimal point, others in Rust's shortest
/// round-trip form (deterministic across platforms).
pub fn format_number(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 9.0e15 {
        format!("{}", value as i64)
    } else {
        format!("{value}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::stats::MeshCounts;

    fn run<'a>(frames: &'a [FrameStats]) -> RunColumns<'a> {
        RunColumns {
            label: "a",
            extra_columns: &[],
            frames,
        }
    }

    #[test]
    fn the_new_families_columns_appear_only_where_some_run_has_them() {
        let plain = [FrameStats::default()];
        assert_eq!(numeric_columns(&[run(&plain)], false), COMMON_COLUMNS);
        let listed = [FrameStats {
            mesh: Some(MeshCounts {
                triangles_by_role: [10, 4, 2, 0],
                morphing_vertices: 1,
            }),
            ..FrameStats::default()
        }];
        let names = numeric_columns(&[run(&plain), run(&listed)], false);
        assert_eq!(names[COMMON_COLUMNS.len()..], *MESH_COLUMNS);
        assert_eq!(
            value(&run(&listed), &listed[0], "triangles_skirt"),
            Some(4.0)
        );
        assert_eq!(value(&run(&plain), &plain[0], "triangles_skirt"), None);
    }

    #[test]
    fn every_listed_column_has_a_value_rule_and_a_misspelt_one_panics() {
        let frames = [FrameStats::default()];
        for name in COMMON_COLUMNS
            .iter()
            .chain(MESH_COLUMNS)
            .chain(AUDIT_COLUMNS)
            .chain(COVERAGE_COLUMNS)
            .chain(POPPING_COLUMNS)
        {
            // No panic: each name is known (its value may not apply to this frame).
            let _ = value(&run(&frames), &frames[0], name);
        }
        for misspelt in ["triangle", "audit_holess", "popping_rms_m", "base_bb"] {
            let result = std::panic::catch_unwind(|| value(&run(&frames), &frames[0], misspelt));
            let message = result.expect_err(misspelt);
            let message = message
                .downcast_ref::<String>()
                .cloned()
                .unwrap_or_default();
            assert!(message.contains(misspelt), "{message}");
        }
    }
}
