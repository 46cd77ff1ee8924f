//! The standard plots of a run: triangles per frame, update time per frame, the audited error
//! per frame (when the audit ran), popping per frame (when it was measured). One line per
//! algorithm label.

use super::columns::{RunColumns, value};
use super::plots::{
    LineChart, Marker, PlotError, ScatterChart, ScatterPoint, Series, write_line_chart,
    write_scatter_chart,
};
use crate::sim::algorithm::columns::rottger::DESIRED_RESOLUTION_C;
use crate::sim::algorithm::columns::wu::BASE_B;
use crate::sim::stats::{pareto_front, summarise};
use std::path::Path;

/// Writes `triangles`, `update_time`, `error` and `accuracy_vs_time` (when audited), `popping`
/// (when some frame measured it), `base_b` (when an algorithm reports Wu's base) and
/// `desired_resolution_c` (when one reports Röttger's c) as PNG and SVG into `dir`.
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
    write_base_plot(dir, runs)?;
    write_desired_resolution_plot(dir, runs)?;
    if audited {
        write_accuracy_vs_time(dir, runs)?;
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
        let popped = runs.iter().any(|r| {
            r.frames
                .iter()
                .any(|f| f.audit.is_some_and(|a| a.popping.is_some()))
        });
        if popped {
            write_line_chart(
                dir,
                "popping",
                &LineChart {
                    title: "Popping: RMSE of the drawn surface's change since the previous frame",
                    x_label: "frame",
                    y_label: "popping RMSE (projected px)",
                    series: &series_of("popping_rmse_px", 1.0),
                    markers: &[],
                },
            )?;
        }
    }
    Ok(())
}

/// b per frame for every run that has it. One run: its min, max and mean as marked lines.
/// Several: the same figures in each legend label.
fn write_base_plot(dir: &Path, runs: &[RunColumns]) -> Result<(), PlotError> {
    let mut series = Vec::new();
    let mut figures = Vec::new();
    for run in runs.iter().filter(|r| r.extra_columns.contains(&BASE_B)) {
        let points: Vec<(f64, f64)> = run
            .frames
            .iter()
            .filter_map(|f| value(run, f, BASE_B).map(|b| (f.frame as f64, b)))
            .collect();
        let values: Vec<f64> = points.iter().map(|p| p.1).collect();
        let Some(summary) = summarise(&values) else {
            continue;
        };
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        figures.push((min, summary.max, summary.mean));
        series.push(Series {
            label: run.label.to_string(),
            points,
        });
    }
    if series.is_empty() {
        return Ok(());
    }
    let markers: Vec<Marker> = if series.len() == 1 {
        let (min, max, mean) = figures[0];
        vec![
            Marker {
                label: format!("max {max}"),
                y: max,
            },
            Marker {
                label: format!("mean {mean:.2}"),
                y: mean,
            },
            Marker {
                label: format!("min {min}"),
                y: min,
            },
        ]
    } else {
        for (s, (min, max, mean)) in series.iter_mut().zip(&figures) {
            s.label = format!("{} (min {min}, max {max}, mean {mean:.2})", s.label);
        }
        Vec::new()
    };
    write_line_chart(
        dir,
        "base_b",
        &LineChart {
            title: "Base b of the life axis per frame",
            x_label: "frame",
            y_label: "b (frames)",
            series: &series,
            markers: &markers,
        },
    )
}

/// Röttger's c per frame for every run that reports it (log scale: the controller moves it by
/// factors).
fn write_desired_resolution_plot(dir: &Path, runs: &[RunColumns]) -> Result<(), PlotError> {
    let series: Vec<Series> = runs
        .iter()
        .filter(|r| r.extra_columns.contains(&DESIRED_RESOLUTION_C))
        .map(|run| Series {
            label: run.label.to_string(),
            points: run
                .frames
                .iter()
                .filter_map(|f| {
                    value(run, f, DESIRED_RESOLUTION_C)
                        .filter(|c| *c > 0.0)
                        .map(|c| (f.frame as f64, c.log10()))
                })
                .collect(),
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    if series.is_empty() {
        return Ok(());
    }
    write_line_chart(
        dir,
        DESIRED_RESOLUTION_C,
        &LineChart {
            title: "Röttger's desired resolution c per frame",
            x_label: "frame",
            y_label: "log10 c",
            series: &series,
            markers: &[],
        },
    )
}

/// Audited p95 error (mean over frames) against median update time, one point per entry, the
/// Pareto front joined.
fn write_accuracy_vs_time(dir: &Path, runs: &[RunColumns]) -> Result<(), PlotError> {
    let points: Vec<ScatterPoint> = runs
        .iter()
        .map(|run| {
            let column = |name: &str| -> Vec<f64> {
                run.frames
                    .iter()
                    .filter_map(|f| value(run, f, name))
                    .collect()
            };
            ScatterPoint {
                label: run.label.to_string(),
                x: summarise(&column("update_ns")).map_or(f64::NAN, |s| s.p50 / 1e3),
                y: summarise(&column("audit_projected_p95_px")).map_or(f64::NAN, |s| s.mean),
            }
        })
        .collect();
    let front = pareto_front(&points.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>());
    write_scatter_chart(
        dir,
        "accuracy_vs_time",
        &ScatterChart {
            title: "What accuracy costs in time (Pareto front in red)",
            x_label: "median update time per frame (µs, log scale)",
            y_label: "audited projected error, p95 (px)",
            points: &points,
            front: &front,
            log_x: true,
        },
    )
}
