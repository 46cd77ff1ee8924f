//! The columns of `frames.csv` and `summary.json`, defined once.
//!
//! Order: `algorithm`, `frame`, the common counters, then every algorithm-specific column in the
//! order first declared by the run's algorithms (empty where an algorithm does not have it),
//! then the audit columns when the audit ran.

use crate::sim::stats::{AuditFrame, ErrorSummary, FrameStats};

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

/// Columns whose values are wall-clock measurements (excluded from determinism comparisons).
pub const TIMING_COLUMNS: &[&str] = &["update_ns"];

/// One algorithm's frames with the names of its extra columns.
pub struct RunColumns<'a> {
    pub label: &'a str,
    pub extra_columns: &'a [&'static str],
    pub frames: &'a [FrameStats],
}

/// The numeric columns of a run (everything but `algorithm` and `frame`).
pub fn numeric_columns(runs: &[RunColumns], audited: bool) -> Vec<&'static str> {
    let mut names: Vec<&'static str> = COMMON_COLUMNS.to_vec();
    for run in runs {
        for name in run.extra_columns {
            if !names.contains(name) {
                names.push(name);
            }
        }
    }
    if audited {
        names.extend_from_slice(AUDIT_COLUMNS);
    }
    names
}

/// The value of `column` in a frame of `run`, or `None` where it does not apply.
pub fn value(run: &RunColumns, frame: &FrameStats, column: &str) -> Option<f64> {
    let count = |n: u64| Some(n as f64);
    match column {
        "triangles" => count(frame.triangles),
        "triangles_rendered" => count(frame.triangles_rendered),
        "splits" => count(frame.splits),
        "merges" => count(frame.merges),
        "vertices_inserted" => count(frame.vertices_inserted),
        "vertices_deleted" => count(frame.vertices_deleted),
        "metric_evaluations" => count(frame.metric_evaluations),
        "update_ns" => count(frame.update_ns),
        _ if column.starts_with("audit_") => audit_value(frame.audit.as_ref()?, column),
        _ => {
            let k = run.extra_columns.iter().position(|c| *c == column)?;
            frame.extra.get(k).copied()
        }
    }
}

fn audit_value(audit: &AuditFrame, column: &str) -> Option<f64> {
    let pick = |summary: Option<ErrorSummary>, field: &str| {
        summary.map(|s| match field {
            "max" => s.max,
            "mean" => s.mean,
            _ => s.p95,
        })
    };
    match column {
        "audit_samples_in_view" => Some(audit.samples_in_view as f64),
        "audit_projected_max_px" => pick(audit.projected, "max"),
        "audit_projected_mean_px" => pick(audit.projected, "mean"),
        "audit_projected_p95_px" => pick(audit.projected, "p95"),
        "audit_view_angle_max_px" => pick(audit.view_angle, "max"),
        "audit_view_angle_mean_px" => pick(audit.view_angle, "mean"),
        "audit_view_angle_p95_px" => pick(audit.view_angle, "p95"),
        _ => None,
    }
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
