//! `frames.csv`: one row per algorithm per frame, long format, with a header row
//! (`docs/output-formats.md`, "frames.csv"). The columns, their order and the writing of numbers
//! are `columns.rs`'s; this file only lays out the rows, quoting labels as RFC 4180 asks.

use super::columns::{RunColumns, format_number, numeric_columns, value};
use std::fmt::Write;

/// The whole file as text.
pub fn frames_csv(runs: &[RunColumns], audited: bool) -> String {
    let columns = numeric_columns(runs, audited);
    let mut out = String::from("algorithm,frame");
    for name in &columns {
        out.push(',');
        out.push_str(name);
    }
    out.push('\n');
    for run in runs {
        let label = csv_field(run.label);
        for frame in run.frames {
            out.push_str(&label);
            let _ = write!(out, ",{}", frame.frame);
            for name in &columns {
                out.push(',');
                if let Some(v) = value(run, frame, name) {
                    out.push_str(&format_number(v));
                }
            }
            out.push('\n');
        }
    }
    out
}

/// Quotes a field when it holds a comma, a quote or a line break (RFC 4180).
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::stats::FrameStats;

    #[test]
    fn extra_columns_are_empty_where_an_algorithm_lacks_them() {
        let frames_a = vec![FrameStats {
            frame: 0,
            triangles: 10,
            extra: vec![-3.0],
            ..FrameStats::default()
        }];
        let frames_b = vec![FrameStats {
            frame: 0,
            triangles: 12,
            ..FrameStats::default()
        }];
        let runs = [
            RunColumns {
                label: "wu, budget 6000",
                extra_columns: &["base_b"],
                frames: &frames_a,
            },
            RunColumns {
                label: "reference",
                extra_columns: &[],
                frames: &frames_b,
            },
        ];
        let text = frames_csv(&runs, false);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "algorithm,frame,triangles,triangles_rendered,splits,merges,vertices_inserted,\
             vertices_deleted,metric_evaluations,update_ns,frame_ns,upload_bytes,draw_calls,\
             triangles_submitted,base_b"
        );
        assert_eq!(
            lines[1],
            "\"wu, budget 6000\",0,10,0,0,0,0,0,0,0,0,0,0,0,-3"
        );
        assert_eq!(lines[2], "reference,0,12,0,0,0,0,0,0,0,0,0,0,0,");
    }
}
