//! The top of a swept experiment's output folder: what the points of its top-level sweep show
//! side by side (`docs/output-formats.md`, "Swept experiments").
//!
//! Each point has written its own folder (frames.csv, summary.json, report.md, plots); this
//! module makes, from the figures of those reports, the sweep's `summary.json` (every point's
//! entries with their figures and operation counters), `report.md` (the points, then each
//! entry's median time to a drawn frame and memory across the points as ratios to the first
//! point, its triangles, rendered triangles, audited error, and a table of its operation
//! counters, each a mean per frame) and the plots
//! `sweep_frame_time` and `sweep_bytes_per_sample` (one line per entry label against the swept
//! value, or against the terrain size when the points' terrains differ). Pure: text and values
//! out; the session writes them.

use super::columns::{RunColumns, TIMING_COLUMNS, value};
use super::plots::{LineChart, PlotError, Series, variants_in_order, write_line_chart};
use super::report_md::Row;
use crate::edge::experiment::{SweepChoice, choice_label};
use serde_json::{Map, Value, json};
use std::fmt::Write;
use std::path::Path;

/// One entry of one point, as its report showed it.
#[derive(Clone, Debug)]
pub struct EntryFigures {
    pub label: String,
    /// The algorithm's name (`wu`, `roam`, …).
    pub name: String,
    pub row: Row,
    pub bytes_per_sample: f64,
    /// The algorithm's operation counters, each one's mean per frame ([`counter_means`]).
    pub counters: Vec<(String, f64)>,
}

/// The counters of the common columns that count operations, in `frames.csv`'s order.
const COMMON_OPERATION_COUNTERS: &[&str] = &[
    "splits",
    "merges",
    "vertices_inserted",
    "vertices_deleted",
    "metric_evaluations",
];

/// Each operation counter of `run` with its mean per frame: the common ones (splits, merges,
/// vertices inserted and deleted, metric evaluations), then the algorithm's own columns, its
/// timing columns left out (they are no counts).
pub fn counter_means(run: &RunColumns) -> Vec<(String, f64)> {
    COMMON_OPERATION_COUNTERS
        .iter()
        .chain(run.extra_columns.iter())
        .filter(|name| !TIMING_COLUMNS.contains(name))
        .filter_map(|&name| {
            let values: Vec<f64> = run
                .frames
                .iter()
                .filter_map(|f| value(run, f, name))
                .collect();
            (!values.is_empty()).then(|| {
                (
                    name.to_string(),
                    values.iter().sum::<f64>() / values.len() as f64,
                )
            })
        })
        .collect()
}

/// One point of the sweep.
#[derive(Clone, Debug)]
pub struct SweepPoint {
    pub choice: SweepChoice,
    /// Its short label (the sweep's `"labels"`), if given: its folder and its name in tables.
    pub label: Option<String>,
    /// Its sub-folder of the output folder.
    pub folder: String,
    pub side: usize,
    pub n_samples: usize,
    pub frames: u64,
    pub preprocessing_seconds: f64,
    /// Heights and Wu's node table, per sample.
    pub hierarchy_bytes_per_sample: f64,
    pub entries: Vec<EntryFigures>,
}

/// The whole sweep.
#[derive(Clone, Copy, Debug)]
pub struct SweepRun<'a> {
    pub name: &'a str,
    pub description: Option<&'a str>,
    pub file: &'a Path,
    pub content_sha256: &'a str,
    pub record: &'a super::summary_json::RunRecord,
    pub points: &'a [SweepPoint],
}

/// The sweep's `summary.json` (format version 1, `"kind": "sweep"`; see docs/output-formats.md).
pub fn sweep_summary_json(run: &SweepRun) -> Value {
    let points: Vec<Value> = run
        .points
        .iter()
        .map(|point| {
            let choice: Map<String, Value> = point.choice.iter().cloned().collect();
            let entries: Vec<Value> = point
                .entries
                .iter()
                .map(|e| {
                    let r = &e.row;
                    json!({
                        "label": e.label,
                        "name": e.name,
                        "triangles_mean": finite(r.triangles),
                        "triangles_rendered_mean": finite(r.rendered),
                        "frame_p50_us": finite(r.frame_p50_us),
                        "frame_p95_us": finite(r.frame_p95_us),
                        "update_p50_us": finite(r.update_p50_us),
                        "update_p95_us": finite(r.update_p95_us),
                        "operations_per_frame": finite(r.operations_per_frame),
                        "evaluations_per_operation": r.evaluations_per_operation.and_then(finite),
                        "bytes_per_sample": finite(e.bytes_per_sample),
                        "audited_error_px": r.error.map(|(max, mean, p95)| json!({
                            "max": max, "mean": mean, "p95_mean": p95
                        })),
                        "counters_per_frame": e.counters.iter()
                            .map(|(name, mean)| (name.clone(), json!(finite(*mean))))
                            .collect::<Map<String, Value>>(),
                    })
                })
                .collect();
            json!({
                "choice": choice,
                "label": point.label,
                "folder": point.folder,
                "terrain": {
                    "side": point.side,
                    "samples": point.n_samples,
                    "preprocessing_seconds": point.preprocessing_seconds,
                    "preprocessing_ns_per_sample":
                        point.preprocessing_seconds * 1e9 / point.n_samples as f64,
                    "bytes_per_sample": point.hierarchy_bytes_per_sample,
                },
                "frames": point.frames,
                "algorithms": entries,
            })
        })
        .collect();
    json!({
        "format_version": super::summary_json::SUMMARY_FORMAT_VERSION,
        "kind": "sweep",
        "roamsim_version": env!("CARGO_PKG_VERSION"),
        "experiment": {
            "name": run.name,
            "description": run.description,
            "file": run.file.display().to_string(),
            "content_sha256": run.content_sha256,
        },
        "run": run.record.to_json(run.points.iter().map(|p| p.frames * p.entries.len() as u64).sum()),
        "points": points,
    })
}

/// JSON has no NaN: a figure that could not be measured is `null`.
fn finite(value: f64) -> Option<f64> {
    value.is_finite().then_some(value)
}

/// Entry labels in first-seen order over the points.
fn labels(run: &SweepRun) -> Vec<String> {
    labelled_entries(run)
        .into_iter()
        .map(|(label, _)| label)
        .collect()
}

/// Entry labels in first-seen order over the points, each with its algorithm.
fn labelled_entries(run: &SweepRun) -> Vec<(String, String)> {
    let mut entries: Vec<(String, String)> = Vec::new();
    for entry in run.points.iter().flat_map(|p| &p.entries) {
        if !entries.iter().any(|(label, _)| *label == entry.label) {
            entries.push((entry.label.clone(), entry.name.clone()));
        }
    }
    entries
}

/// A point's name in the tables' headers: its label, or its swept values.
fn point_name(point: &SweepPoint) -> String {
    point
        .label
        .clone()
        .unwrap_or_else(|| choice_label(&point.choice))
        .replace('|', "\\|")
}

fn entry<'a>(point: &'a SweepPoint, label: &str) -> Option<&'a EntryFigures> {
    point.entries.iter().find(|e| e.label == label)
}

/// The sweep's `report.md`.
pub fn sweep_report_markdown(run: &SweepRun) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# {}: sweep of {} points\n",
        run.name,
        run.points.len()
    );
    if let Some(description) = run.description {
        let _ = writeln!(out, "{description}\n");
    }
    let _ = writeln!(
        out,
        "Points ran one after another, each from its own preprocessed terrain; entries within a \
         point ran side by side on {} thread(s){}. Each point's own report, frames and plots are \
         in its folder.\n",
        run.record.threads,
        if run.record.threads > 1 {
            " (for timing comparisons run with --threads 1)"
        } else {
            ""
        }
    );
    let _ = writeln!(
        out,
        "| point | folder | terrain | preprocessing (ns/sample) | shared bytes per sample |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|");
    for point in run.points {
        let title = match &point.label {
            Some(label) => format!("{label} ({})", choice_label(&point.choice)),
            None => choice_label(&point.choice),
        };
        let _ = writeln!(
            out,
            "| {} | `{}` | {}² ({} samples) | {:.1} | {:.2} |",
            title.replace('|', "\\|"),
            point.folder,
            point.side,
            point.n_samples,
            point.preprocessing_seconds * 1e9 / point.n_samples as f64,
            point.hierarchy_bytes_per_sample,
        );
    }
    let first = &run.points[0];
    let _ = writeln!(
        out,
        "\n## Median time to a drawn frame (µs), and its ratio to the first point\n"
    );
    table_across_points(&mut out, run, |e| e.row.frame_p50_us, |_| true);
    let _ = writeln!(
        out,
        "\n## Memory (bytes per sample), and its ratio to the first point\n"
    );
    table_across_points(&mut out, run, |e| e.bytes_per_sample, |_| true);
    let _ = writeln!(out, "\n## Mean triangles per frame\n");
    table_across_points(&mut out, run, |e| e.row.triangles, |_| false);
    let _ = writeln!(
        out,
        "\n## Mean rendered triangles per frame (meeting the view volume)\n"
    );
    table_across_points(&mut out, run, |e| e.row.rendered, |_| false);
    if run
        .points
        .iter()
        .any(|p| p.entries.iter().any(|e| e.row.error.is_some()))
    {
        let _ = writeln!(
            out,
            "\n## Audited projected error, mean of per-frame p95 (px)\n"
        );
        table_across_points(
            &mut out,
            run,
            |e| e.row.error.map_or(f64::NAN, |(_, _, p95)| p95),
            |_| false,
        );
        let _ = writeln!(out, "\n## Audited projected error, largest (px)\n");
        table_across_points(
            &mut out,
            run,
            |e| e.row.error.map_or(f64::NAN, |(max, _, _)| max),
            |_| false,
        );
    }
    let _ = writeln!(
        out,
        "\nRatios divide each point's figure by the same entry's figure at the first point ({}).",
        point_name(first)
    );
    write_counters(&mut out, run);
    out
}

/// Each entry's operation counters across the points: a table per entry, a row per counter.
fn write_counters(out: &mut String, run: &SweepRun) {
    let _ = writeln!(
        out,
        "\n## Operation counters (means per frame)\n\nEach entry's counters from `frames.csv` \
         (the common ones, then its algorithm's own; docs/output-formats.md), warm-up frames left \
         out.\n"
    );
    let header: Vec<String> = run.points.iter().map(point_name).collect();
    for (label, algorithm) in labelled_entries(run) {
        let mut names: Vec<&str> = Vec::new();
        for figures in run.points.iter().filter_map(|p| entry(p, &label)) {
            for (name, _) in &figures.counters {
                if !names.contains(&name.as_str()) {
                    names.push(name);
                }
            }
        }
        let _ = writeln!(
            out,
            "### {} ({algorithm})\n\n| counter | {} |\n|---|{}",
            label.replace('|', "\\|"),
            header.join(" | "),
            "---|".repeat(run.points.len())
        );
        for name in names {
            let cells: Vec<String> = run
                .points
                .iter()
                .map(|point| {
                    entry(point, &label)
                        .and_then(|e| e.counters.iter().find(|(n, _)| n == name))
                        .filter(|(_, mean)| mean.is_finite())
                        .map_or("—".to_string(), |(_, mean)| figure_text(*mean))
                })
                .collect();
            let _ = writeln!(out, "| `{name}` | {} |", cells.join(" | "));
        }
        let _ = writeln!(out);
    }
}

/// One row per entry label, one column per point: the figure, with its ratio to the first point
/// when `ratios` says so.
fn table_across_points(
    out: &mut String,
    run: &SweepRun,
    figure: impl Fn(&EntryFigures) -> f64,
    ratios: impl Fn(&str) -> bool,
) {
    let header: Vec<String> = run.points.iter().map(point_name).collect();
    let _ = writeln!(out, "| entry | {} |", header.join(" | "));
    let _ = writeln!(out, "|---|{}", "---|".repeat(run.points.len()));
    for label in labels(run) {
        let base = entry(&run.points[0], &label).map(&figure);
        let cells: Vec<String> = run
            .points
            .iter()
            .map(|point| match entry(point, &label).map(&figure) {
                Some(value) if value.is_finite() => match base {
                    Some(base) if ratios(&label) && base > 0.0 => {
                        format!("{} (×{:.2})", figure_text(value), value / base)
                    }
                    _ => figure_text(value),
                },
                _ => "—".to_string(),
            })
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} |",
            label.replace('|', "\\|"),
            cells.join(" | ")
        );
    }
}

fn figure_text(value: f64) -> String {
    if value.abs() >= 100.0 {
        format!("{value:.0}")
    } else {
        format!("{value:.2}")
    }
}

/// Writes `sweep_frame_time` and `sweep_bytes_per_sample` (PNG and SVG) into `dir`.
pub fn write_sweep_plots(dir: &Path, run: &SweepRun) -> Result<(), PlotError> {
    let (x_label, xs) = x_axis(run);
    let entries = labelled_entries(run);
    let algorithms: Vec<&str> = entries.iter().map(|(_, name)| name.as_str()).collect();
    let variants = variants_in_order(&algorithms);
    let series_of = |figure: &dyn Fn(&EntryFigures) -> f64| -> Vec<Series> {
        entries
            .iter()
            .zip(&variants)
            .map(|((label, algorithm), &variant)| Series {
                points: run
                    .points
                    .iter()
                    .zip(&xs)
                    .filter_map(|(point, &x)| {
                        let y = figure(entry(point, label)?);
                        y.is_finite().then_some((x, y))
                    })
                    .collect(),
                label: label.clone(),
                algorithm: algorithm.clone(),
                variant,
            })
            .collect()
    };
    write_line_chart(
        dir,
        "sweep_frame_time",
        &LineChart {
            title: "Median time to a drawn frame across the sweep",
            x_label: &x_label,
            y_label: "median frame time (µs, log scale)",
            series: &series_of(&|e| e.row.frame_p50_us),
            markers: &[],
            log_y: true,
            marked_x: &[],
            marked_x_label: "",
        },
    )?;
    write_line_chart(
        dir,
        "sweep_bytes_per_sample",
        &LineChart {
            title: "Memory per height sample across the sweep (shared terrain + algorithm state)",
            x_label: &x_label,
            y_label: "bytes per sample",
            series: &series_of(&|e| e.bytes_per_sample),
            markers: &[],
            log_y: false,
            marked_x: &[],
            marked_x_label: "",
        },
    )
}

/// The x of each point: the terrain's level n (side 2^n + 1) when the terrains differ, else the
/// first swept value when every point's is a number, else the point's index.
fn x_axis(run: &SweepRun) -> (String, Vec<f64>) {
    let sides_differ = run.points.iter().any(|p| p.side != run.points[0].side);
    if sides_differ {
        let levels = run
            .points
            .iter()
            .map(|p| ((p.side - 1).max(1) as f64).log2())
            .collect();
        return ("terrain level n (side 2^n + 1 samples)".to_string(), levels);
    }
    let numbers: Option<Vec<f64>> = run
        .points
        .iter()
        .map(|p| p.choice.first().and_then(|(_, v)| v.as_f64()))
        .collect();
    match (numbers, run.points[0].choice.first()) {
        (Some(numbers), Some((parameter, _))) => (parameter.clone(), numbers),
        _ => (
            "sweep point".to_string(),
            (0..run.points.len()).map(|k| k as f64).collect(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn figures(label: &str, frame_p50_us: f64, bytes_per_sample: f64) -> EntryFigures {
        EntryFigures {
            label: label.to_string(),
            name: "wu".to_string(),
            row: Row {
                triangles: 6000.0,
                rendered: 6000.0,
                error: None,
                frame_p50_us,
                frame_p95_us: frame_p50_us * 2.0,
                update_p50_us: frame_p50_us / 2.0,
                update_p95_us: frame_p50_us,
                upload_bytes: 0.0,
                draw_calls: 1.0,
                triangles_submitted: 6000.0,
                operations_per_frame: 30.0,
                evaluations_per_operation: Some(12.0),
            },
            bytes_per_sample,
            counters: vec![("splits".to_string(), 4.0), ("base_b".to_string(), 0.5)],
        }
    }

    fn point(level: u32, entries: Vec<EntryFigures>) -> SweepPoint {
        let side = (1usize << level) + 1;
        SweepPoint {
            choice: vec![("terrain.synthetic.level".to_string(), json!(level))],
            label: None,
            folder: format!("terrain.synthetic.level={level}"),
            side,
            n_samples: side * side,
            frames: 10,
            preprocessing_seconds: 0.01,
            hierarchy_bytes_per_sample: 8.0,
            entries,
        }
    }

    const ONE_THREAD: crate::edge::output::summary_json::RunRecord =
        crate::edge::output::summary_json::RunRecord {
            threads: 1,
            check_meshes: false,
            command_line: None,
        };

    fn run(points: &[SweepPoint]) -> SweepRun<'_> {
        SweepRun {
            name: "scaling",
            description: None,
            file: Path::new("scaling.json"),
            content_sha256: "00",
            record: &ONE_THREAD,
            points,
        }
    }

    #[test]
    fn the_report_gives_each_entrys_ratio_to_the_first_point() {
        let points = [
            point(4, vec![figures("wu", 10.0, 12.0)]),
            point(6, vec![figures("wu", 15.0, 12.5)]),
        ];
        let report = sweep_report_markdown(&run(&points));
        assert!(
            report.contains("| wu | 10.00 (×1.00) | 15.00 (×1.50) |"),
            "{report}"
        );
        assert!(
            report.contains("| wu | 12.00 (×1.00) | 12.50 (×1.04) |"),
            "{report}"
        );
        assert!(report.contains("17² (289 samples)"), "{report}");
        assert!(
            report.contains(
                "### wu (wu)\n\n| counter | terrain.synthetic.level=4 | terrain.synthetic.level=6 |"
            ),
            "{report}"
        );
        assert!(report.contains("| `splits` | 4.00 | 4.00 |"), "{report}");
    }

    #[test]
    fn an_entry_missing_from_a_point_shows_a_dash_and_no_measurement_is_null() {
        let points = [
            point(
                4,
                vec![figures("wu", 10.0, 12.0), figures("roam", 20.0, 9.0)],
            ),
            point(6, vec![figures("wu", f64::NAN, 12.5)]),
        ];
        let run = run(&points);
        let report = sweep_report_markdown(&run);
        assert!(report.contains("| roam | 20.00 (×1.00) | — |"), "{report}");
        assert!(report.contains("| wu | 10.00 (×1.00) | — |"), "{report}");
        let summary = sweep_summary_json(&run);
        assert_eq!(summary["kind"], "sweep");
        assert_eq!(
            summary["points"][1]["algorithms"][0]["frame_p50_us"],
            Value::Null
        );
        assert_eq!(summary["points"][1]["choice"]["terrain.synthetic.level"], 6);
    }

    #[test]
    fn terrains_of_different_sizes_are_plotted_against_their_level() {
        let points = [point(4, vec![]), point(6, vec![])];
        let (label, xs) = x_axis(&run(&points));
        assert!(label.starts_with("terrain level"));
        assert_eq!(xs, [4.0, 6.0]);
    }
}
