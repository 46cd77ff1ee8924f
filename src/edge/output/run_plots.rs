//! The standard plots of a run: triangles per frame, update time per frame, and the audited
//! error per frame (when the audit ran). One line per algorithm label.

use super::columns::{RunColumns, value};
use super::plots::{LineChart, PlotError, Series, write_line_chart};
use std::path::Path;

/// Writes `triangles`, `update_time` and (when audited) `error` as PNG and SVG into `dir`.
pub fn write_run_plots(dir: &Path, runs: &[RunColumns], audited: bool) -> Result<(), PlotError> {
    let series_of = |column: &str, scale: f64| -> Vec<Series> {
        runs.iter()
            .map(|run| Series {
                label: run.label.to_string(),
                points: run
                    .frames
                    .iter()
                    .filter_map(|f| value(run, f, column).map(|v| (f.frame as f64, v * scale)))
                    .collect(),
            })
            .collect()
    };
    write_line_chart(
        dir,
        "triangles",
        &LineChart {
            title: "Triangles per frame",
            x_label: "frame",
            y_label: "triangles",
            series: &series_of("triangles", 1.0),
            markers: &[],
        },
    )?;
    write_line_chart(
        dir,
        "update_time",
        &LineChart {
            title: "Update time per frame",
            x_label: "frame",
            y_label: "update time (µs)",
            series: &series_of("update_ns", 1e-3),
            markers: &[],
        },
    )?;
    if audited {
        write_line_chart(
            dir,
            "error",
            &LineChart {
                title: "Audited projected screen-space error per frame (p95 over samples in view)",
                x_label: "frame",
                y_label: "error p95 (px)",
                series: &series_of("audit_projected_p95_px", 1.0),
                markers: &[],
            },
        )?;
    }
    Ok(())
}
