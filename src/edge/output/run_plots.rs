//! The standard plots of a run (`docs/output-formats.md`, "plots/"): triangles per frame
//! (rendered ones too, when culling made them differ), time to a drawn frame per frame, the audited error
//! per frame and the accuracy-versus-time Pareto plot (SPEC §7, when the audit ran), popping per
//! frame (when it was measured), Wu's b (when a `wu` entry has a budget) and Röttger's c per
//! frame (when such an entry ran), and the rendered triangles each entry tuned to an audited
//! error target needed for it (`triangles_for_error_target`).
//! Per-frame plots draw one line per algorithm label. This file chooses what is plotted;
//! `plots` draws it. Every series and point carries its entry's algorithm and its variant
//! counted over the whole run, so that an entry has the same colour in every plot, also in one
//! that leaves other entries out (`base_b`, `desired_resolution_c`).
//!
//! Every per-frame plot but Röttger's c marks the frames that broke the speed or rotation
//! bounds. Triangles and frame times always take a logarithmic y axis (entries differ by orders
//! of magnitude), error and popping only when the entries' means differ by more than ten times
//! (`LOG_AXIS_ABOVE_RATIO`). The Pareto plot, a summary, leaves out the warm-up frames; the
//! per-frame plots keep them.

use super::columns::{RunColumns, value};
use super::plots::{
    LineChart, Marker, PlotError, ScatterChart, ScatterPoint, Series, variants_in_order,
    write_line_chart, write_scatter_chart,
};
use super::warm_up::summarised_runs;
use crate::sim::algorithm::columns::rottger::DESIRED_RESOLUTION_C;
use crate::sim::algorithm::columns::wu::BASE_B;
use crate::sim::stats::{pareto_front, summarise};
use std::path::Path;

/// What the standard plots of a run are drawn from.
pub struct RunPlotInputs<'a> {
    pub runs: &'a [RunColumns<'a>],
    /// Each run's algorithm name (`wu`, `roam`, …): the colour of its series and points.
    pub names: &'a [&'a str],
    pub audited: bool,
    /// Frames that broke the speed or rotation bounds: marked on every per-frame plot.
    pub speed_violation_frames: &'a [u64],
    /// Whether each run shifts Wu's base b (a `wu` entry with a budget): `base_b` is drawn for
    /// those only, and not at all when none does (b stays 0 without a budget).
    pub shifts_base: &'a [bool],
    /// Each run tuned to an audited error target, with that target and its line
    /// (`triangles_for_error_target`); `None` for the others.
    pub error_targets: &'a [Option<ErrorTarget>],
    /// The horizontal speed bound (m/frame), the unit of Wu's b.
    pub horizontal_m_per_frame: f64,
    /// The first frames the summaries leave out (`outputs.warm_up_frames`): the accuracy plot,
    /// a summary, leaves them out too; per-frame plots keep them.
    pub warm_up_frames: u64,
}

/// An entry tuned to an audited error target (`"tune": {"audit_p95_px": …}`), as
/// `triangles_for_error_target` draws it.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorTarget {
    /// The target, px of audited p95.
    pub target_px: f64,
    /// Whether its search reached the target.
    pub reached: bool,
    /// Which line it is a point of: entries of one algorithm with the same parameters but the
    /// tuned one share a line; the line's legend label.
    pub line: String,
}

/// The legend text of the frames marked on per-frame plots.
const VIOLATION_LABEL: &str = "frames breaking the speed bounds";

/// Series whose positive means differ by more than this factor get a logarithmic y axis.
const LOG_AXIS_ABOVE_RATIO: f64 = 10.0;

/// Writes `triangles` and `frame_time` (logarithmic y: entries differ by orders of magnitude),
/// `triangles_rendered` (when culling made some frame's rendered count differ from its mesh),
/// `error` and `accuracy_vs_time` (when audited), `popping` (when some frame measured it),
/// `base_b` (when a `wu` entry has a budget) and `desired_resolution_c` (when one reports
/// Röttger's c) as PNG and SVG into `dir`. Every per-frame plot marks the frames that broke the
/// speed bounds; `error` and `popping` use a logarithmic y axis when their entries' means differ
/// by more than ten times.
pub fn write_run_plots(dir: &Path, inputs: &RunPlotInputs) -> Result<(), PlotError> {
    let runs = inputs.runs;
    let looks = Looks::new(inputs.names);
    let marked: Vec<f64> = inputs
        .speed_violation_frames
        .iter()
        .map(|&f| f as f64)
        .collect();
    let series_of = |column: &str, scale: f64| -> Vec<Series> {
        runs.iter()
            .enumerate()
            .map(|(run_idx, run)| {
                looks.series(
                    run_idx,
                    run.label.to_string(),
                    run.frames
                        .iter()
                        .filter_map(|f| value(run, f, column).map(|v| (f.frame as f64, v * scale)))
                        .collect(),
                )
            })
            .collect()
    };
    let line = |stem: &str, title: &str, y_label: &str, series: &[Series], log_y: bool| {
        write_line_chart(
            dir,
            stem,
            &LineChart {
                title,
                x_label: "frame",
                y_label,
                series,
                markers: &[],
                log_y,
                marked_x: &marked,
                marked_x_label: VIOLATION_LABEL,
            },
        )
    };
    line(
        "triangles",
        "Triangles per frame (whole mesh)",
        "triangles (log scale)",
        &series_of("triangles", 1.0),
        true,
    )?;
    let culled = runs
        .iter()
        .any(|r| r.frames.iter().any(|f| f.triangles_rendered != f.triangles));
    if culled {
        line(
            "triangles_rendered",
            "Rendered triangles per frame (meeting the view volume)",
            "rendered triangles (log scale)",
            &series_of("triangles_rendered", 1.0),
            true,
        )?;
    }
    line(
        "frame_time",
        "Time to a drawn frame (update and buffer upkeep) per frame",
        "frame time (µs, log scale)",
        &series_of("frame_ns", 1e-3),
        true,
    )?;
    write_base_plot(dir, inputs, &looks, &marked)?;
    write_error_target_plot(dir, inputs)?;
    write_desired_resolution_plot(dir, runs, &looks)?;
    if inputs.audited {
        let summarised = summarised_runs(runs, inputs.warm_up_frames);
        write_accuracy_vs_time(dir, &summarised, inputs.names)?;
        let error = series_of("audit_projected_p95_px", 1.0);
        let log_error = differ_by_orders(&error);
        line(
            "error",
            "Audited projected screen-space error per frame (p95 over samples in view)",
            if log_error {
                "error p95 (px, log scale)"
            } else {
                "error p95 (px)"
            },
            &error,
            log_error,
        )?;
        let popped = runs.iter().any(|r| {
            r.frames
                .iter()
                .any(|f| f.audit.is_some_and(|a| a.popping.is_some()))
        });
        if popped {
            let popping = series_of("popping_rmse_px", 1.0);
            let log_popping = differ_by_orders(&popping);
            line(
                "popping",
                "Popping: RMSE of the drawn surface's change since the previous frame",
                if log_popping {
                    "popping RMSE (projected px, log scale)"
                } else {
                    "popping RMSE (projected px)"
                },
                &popping,
                log_popping,
            )?;
        }
    }
    Ok(())
}

/// Each run's algorithm and variant (its place among the run's entries of that algorithm), which
/// fix its colour in every plot.
struct Looks<'a> {
    names: &'a [&'a str],
    variants: Vec<usize>,
}

impl<'a> Looks<'a> {
    fn new(names: &'a [&'a str]) -> Looks<'a> {
        Looks {
            names,
            variants: variants_in_order(names),
        }
    }

    /// The series of the run at `run_idx`.
    fn series(&self, run_idx: usize, label: String, points: Vec<(f64, f64)>) -> Series {
        Series {
            label,
            points,
            algorithm: self.names.get(run_idx).copied().unwrap_or("").to_string(),
            variant: self.variants.get(run_idx).copied().unwrap_or(0),
        }
    }
}

/// Whether the series' means over their positive values differ by more than
/// [`LOG_AXIS_ABOVE_RATIO`].
fn differ_by_orders(series: &[Series]) -> bool {
    let means: Vec<f64> = series
        .iter()
        .filter_map(|s| {
            let positive: Vec<f64> = s.points.iter().map(|p| p.1).filter(|y| *y > 0.0).collect();
            summarise(&positive).map(|summary| summary.mean)
        })
        .collect();
    let lo = means.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = means.iter().copied().fold(0.0, f64::max);
    means.len() > 1 && hi > LOG_AXIS_ABOVE_RATIO * lo
}

/// `triangles_for_error_target`: for the entries tuned to an audited error target, the mean
/// rendered triangles per frame (warm-up left out, as the report's) against the target, a line
/// per group of entries that differ only in the target (`ErrorTarget::line`), coloured by
/// algorithm. A line whose search missed a target says so in its legend label. Not drawn when
/// no entry is tuned to an error.
fn write_error_target_plot(dir: &Path, inputs: &RunPlotInputs) -> Result<(), PlotError> {
    let summarised = summarised_runs(inputs.runs, inputs.warm_up_frames);
    let mut lines: Vec<TargetLine> = Vec::new();
    for ((target, run), name) in inputs
        .error_targets
        .iter()
        .zip(&summarised)
        .zip(inputs.names)
    {
        let Some(target) = target else { continue };
        let rendered: Vec<f64> = run
            .frames
            .iter()
            .filter_map(|f| value(run, f, "triangles_rendered"))
            .collect();
        let Some(mean) = summarise(&rendered).map(|s| s.mean) else {
            continue;
        };
        let at = match lines.iter().position(|line| line.name == target.line) {
            Some(at) => at,
            None => {
                lines.push(TargetLine {
                    name: target.line.clone(),
                    algorithm: name,
                    points: Vec::new(),
                    missed: Vec::new(),
                });
                lines.len() - 1
            }
        };
        lines[at].points.push((target.target_px, mean));
        if !target.reached {
            lines[at].missed.push(target.target_px);
        }
    }
    if lines.is_empty() {
        return Ok(());
    }
    let algorithms: Vec<&str> = lines.iter().map(|line| line.algorithm).collect();
    let series: Vec<Series> = lines
        .iter()
        .zip(variants_in_order(&algorithms))
        .map(|(line, variant)| {
            let TargetLine {
                name: line,
                algorithm: name,
                points,
                missed,
            } = line;
            let mut points = points.clone();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            let missed: Vec<String> = missed.iter().map(|t| format!("{t}")).collect();
            Series {
                label: if missed.is_empty() {
                    line.clone()
                } else {
                    format!("{line} (target not reached at {} px)", missed.join(", "))
                },
                points,
                algorithm: name.to_string(),
                variant,
            }
        })
        .collect();
    write_line_chart(
        dir,
        "triangles_for_error_target",
        &LineChart {
            title: "Rendered triangles each entry needed for its audited error target",
            x_label: "audited p95 error target (px)",
            y_label: "mean rendered triangles per frame (log scale)",
            series: &series,
            markers: &[],
            log_y: true,
            marked_x: &[],
            marked_x_label: "",
        },
    )
}

/// One line of `triangles_for_error_target`: its legend name, its algorithm, its (target, mean
/// rendered triangles) points, and the targets its searches missed.
struct TargetLine<'a> {
    name: String,
    algorithm: &'a str,
    points: Vec<(f64, f64)>,
    missed: Vec<f64>,
}

/// b per frame for every run that has it. One run: its min, max and mean as marked lines.
/// Several: the same figures in each legend label.
fn write_base_plot(
    dir: &Path,
    inputs: &RunPlotInputs,
    looks: &Looks,
    marked: &[f64],
) -> Result<(), PlotError> {
    let (runs, horizontal_m_per_frame) = (inputs.runs, inputs.horizontal_m_per_frame);
    let metres = |b: f64| b * horizontal_m_per_frame;
    let mut series = Vec::new();
    let mut figures = Vec::new();
    for (run_idx, run) in runs
        .iter()
        .enumerate()
        .filter(|(k, r)| inputs.shifts_base[*k] && r.extra_columns.contains(&BASE_B))
    {
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
        series.push(looks.series(run_idx, run.label.to_string(), points));
    }
    if series.is_empty() {
        return Ok(());
    }
    let markers: Vec<Marker> = if series.len() == 1 {
        let (min, max, mean) = figures[0];
        vec![
            Marker {
                label: format!("max {max} ({:.0}\u{a0}m)", metres(max)),
                y: max,
            },
            Marker {
                label: format!("mean {mean:.2} ({:.0}\u{a0}m)", metres(mean)),
                y: mean,
            },
            Marker {
                label: format!("min {min} ({:.0}\u{a0}m)", metres(min)),
                y: min,
            },
        ]
    } else {
        for (s, (min, max, mean)) in series.iter_mut().zip(&figures) {
            s.label = format!(
                "{} (min {min}, max {max}, mean {mean:.2}; mean {:.0}\u{a0}m)",
                s.label,
                metres(*mean)
            );
        }
        Vec::new()
    };
    write_line_chart(
        dir,
        "base_b",
        &LineChart {
            title: "Base b of the life axis per frame",
            x_label: "frame",
            y_label: &format!(
                "b (frames of travel at {horizontal_m_per_frame} m/frame; × {horizontal_m_per_frame} = metres)"
            ),
            series: &series,
            markers: &markers,
            log_y: false,
            marked_x: marked,
            marked_x_label: VIOLATION_LABEL,
        },
    )
}

/// Röttger's c per frame for every run that reports it (log scale: the controller moves it by
/// factors).
fn write_desired_resolution_plot(
    dir: &Path,
    runs: &[RunColumns],
    looks: &Looks,
) -> Result<(), PlotError> {
    let series: Vec<Series> = runs
        .iter()
        .enumerate()
        .filter(|(_, r)| r.extra_columns.contains(&DESIRED_RESOLUTION_C))
        .map(|(run_idx, run)| {
            looks.series(
                run_idx,
                run.label.to_string(),
                run.frames
                    .iter()
                    .filter_map(|f| {
                        value(run, f, DESIRED_RESOLUTION_C)
                            .filter(|c| *c > 0.0)
                            .map(|c| (f.frame as f64, c.log10()))
                    })
                    .collect(),
            )
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
            log_y: false,
            marked_x: &[],
            marked_x_label: "",
        },
    )
}

/// Audited p95 error (mean over frames) against median update time, one point per entry, the
/// Pareto front joined.
fn write_accuracy_vs_time(
    dir: &Path,
    runs: &[RunColumns],
    names: &[&str],
) -> Result<(), PlotError> {
    let points: Vec<ScatterPoint> = runs
        .iter()
        .zip(names)
        .map(|(run, name)| {
            let column = |name: &str| -> Vec<f64> {
                run.frames
                    .iter()
                    .filter_map(|f| value(run, f, name))
                    .collect()
            };
            ScatterPoint {
                label: run.label.to_string(),
                x: summarise(&column("frame_ns")).map_or(f64::NAN, |s| s.p50 / 1e3),
                y: summarise(&column("audit_projected_p95_px")).map_or(f64::NAN, |s| s.mean),
                group: name.to_string(),
            }
        })
        .collect();
    let front = pareto_front(&points.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>());
    write_scatter_chart(
        dir,
        "accuracy_vs_time",
        &ScatterChart {
            title: "What accuracy costs in time (Pareto front in black, labelled)",
            x_label: "median time to a drawn frame (µs, log scale)",
            y_label: "audited projected error, p95 (px)",
            points: &points,
            front: &front,
            log_x: true,
        },
    )
}
