//! `report.md`: the run's comparison table, readable as it is and on a code host
//! (`docs/output-formats.md`, "report.md").
//!
//! One row per algorithm entry (sweep points included): triangles, the audited error, update
//! time, operations per frame and per split or merge, and memory per sample; then the entries on
//! the accuracy-versus-time Pareto front; then, where they apply, popping and the triangle-list
//! figures (holes, cracks, triangles by role); last, the preprocessing: the shared terrain's and
//! each entry's own. Every figure comes from `frames.csv`'s columns or the run's measurements;
//! the definitions are under the tables.

use super::columns::{RunColumns, value};
use super::goal_check::{
    FRAME_TOLERANCE, GoalCheck, MEAN_TOLERANCE, STRAY_SHARE, STRAY_STRETCH, check_goal,
};
use super::summary_json::Preprocessing;
use super::tuning::{TuningRecord, write_tuned_entries};
use super::warm_up::{Settling, settling, summarised_runs, warm_up_paragraph};
use crate::edge::experiment::{BoundOrigin, Experiment};
use crate::sim::stats::{pareto_front, summarise};
use std::fmt::Write;

/// The report's file name, as messages name it.
pub const REPORT_FILE: &str = "report.md";

/// The headings of `report.md`'s sections that a message elsewhere points to (the end-of-run
/// warnings, `docs/output-formats.md`): written here and named there from these constants, so a
/// pointer cannot name a section the report does not have.
pub mod section {
    /// How every budget or target entry held its count (written when some entry has one).
    pub const BUDGETS_AND_TARGETS: &str = "Budgets and targets";
    /// What each tuned entry's search found (written when some entry is tuned).
    pub const TUNED_ENTRIES: &str = "Tuned entries";
}

/// Algorithms whose `splits` count every node their from-scratch rebuild activates (merges 0),
/// marked † in the report's table.
pub const FROM_SCRATCH_ACTIVATIONS: &[&str] = &["reference", "roam-rebuild"];

/// What the report is made from.
pub struct ReportInputs<'a> {
    pub experiment: &'a Experiment,
    pub runs: &'a [RunColumns<'a>],
    pub names: &'a [&'a str],
    pub bytes_per_sample: &'a [f64],
    pub threads: usize,
    /// The shared terrain's preprocessing.
    pub terrain_preprocessing: &'a Preprocessing,
    /// Each entry's own preprocessing, in the order of `runs`.
    pub entry_preprocessing: &'a [Preprocessing],
    /// Each tuned entry's search, in the order of `runs` (`None`: not tuned).
    pub tunings: &'a [Option<&'a TuningRecord>],
}

/// One entry's figures, as its report row shows them.
#[derive(Clone, Copy, Debug)]
pub struct Row {
    /// Mean triangles per frame: whole mesh, and meeting the view volume.
    pub triangles: f64,
    pub rendered: f64,
    /// Audited projected error: largest max, mean of means, mean of p95s (px).
    pub error: Option<(f64, f64, f64)>,
    /// Time to a drawn frame (`frame_ns`: the update and the buffer upkeep), µs: the time axis.
    pub frame_p50_us: f64,
    pub frame_p95_us: f64,
    /// The update alone (`update_ns`), µs.
    pub update_p50_us: f64,
    pub update_p95_us: f64,
    /// Means per frame of what the frame sent a GPU.
    pub upload_bytes: f64,
    pub draw_calls: f64,
    pub triangles_submitted: f64,
    pub operations_per_frame: f64,
    pub evaluations_per_operation: Option<f64>,
}

/// The figures of one entry's run.
pub fn row(run: &RunColumns) -> Row {
    let column = |name: &str| -> Vec<f64> {
        run.frames
            .iter()
            .filter_map(|f| value(run, f, name))
            .collect()
    };
    let mean = |name: &str| summarise(&column(name)).map_or(f64::NAN, |s| s.mean);
    let update = summarise(&column("update_ns"));
    let frame = summarise(&column("frame_ns"));
    let error = summarise(&column("audit_projected_max_px")).and_then(|max| {
        let mean = summarise(&column("audit_projected_mean_px"))?;
        let p95 = summarise(&column("audit_projected_p95_px"))?;
        Some((max.max, mean.mean, p95.mean))
    });
    let operations: f64 = run
        .frames
        .iter()
        .map(|f| (f.splits + f.merges) as f64)
        .sum();
    let evaluations: f64 = run.frames.iter().map(|f| f.metric_evaluations as f64).sum();
    Row {
        triangles: mean("triangles"),
        rendered: mean("triangles_rendered"),
        error,
        frame_p50_us: frame.map_or(f64::NAN, |s| s.p50 / 1e3),
        frame_p95_us: frame.map_or(f64::NAN, |s| s.p95 / 1e3),
        update_p50_us: update.map_or(f64::NAN, |s| s.p50 / 1e3),
        update_p95_us: update.map_or(f64::NAN, |s| s.p95 / 1e3),
        upload_bytes: mean("upload_bytes"),
        draw_calls: mean("draw_calls"),
        triangles_submitted: mean("triangles_submitted"),
        operations_per_frame: operations / run.frames.len().max(1) as f64,
        evaluations_per_operation: (operations > 0.0).then(|| evaluations / operations),
    }
}

/// The report's text.
pub fn report_markdown(inputs: &ReportInputs) -> String {
    let experiment = inputs.experiment;
    let terrain = &experiment.terrain;
    let mut out = String::new();
    let _ = writeln!(out, "# {}: comparison\n", experiment.name);
    if let Some(description) = &experiment.description {
        let _ = writeln!(out, "{description}\n");
    }
    let _ = writeln!(
        out,
        "Terrain {} ({}², dx {:.2} m, dy {:.2} m); {} flight of {} frames; window {}×{}, fovy {:.1}°; {}; culling {}. \
         Timings measured with {} thread(s) running entries side by side{}.\n",
        terrain.source,
        terrain.side,
        terrain.spacing.dx,
        terrain.spacing.dy,
        experiment.flight_kind,
        experiment.flight.n_frames(),
        experiment.view.width_px,
        experiment.view.height_px,
        experiment.view.fovy.to_degrees(),
        match experiment.effects.audit {
            Some(a) => format!("audited every {} samples", a.stride),
            None => "not audited".to_string(),
        },
        if experiment.effects.culling {
            "on"
        } else {
            "off"
        },
        inputs.threads,
        if inputs.threads > 1 {
            " (for timing comparisons run with --threads 1)"
        } else {
            ""
        },
    );
    if let Some(paged) = experiment.field.paged_samples() {
        let _ = writeln!(
            out,
            "The terrain was read on demand from its chunk pyramid ({}), never held whole: the \
             chunked entries' loaded chunks by a loader thread, the flight's terrain following, \
             the audit's true heights and the map through a cache of full-resolution chunks; \
             cache at its bound and chunk records {:.1} MB.\n",
            terrain.format,
            paged.memory_bytes() as f64 / 1e6
        );
    }
    if experiment.rotation_bound == BoundOrigin::Derived {
        let _ = writeln!(
            out,
            "The rotation bound was not declared: the flight's largest turn, {} rad a frame, was \
             used.\n",
            experiment.speed.rotation
        );
    }
    if let Some(first) = experiment.below_ground_frames.first() {
        let _ = writeln!(
            out,
            "**Eye below the ground** in {} frame(s) (first: frame {first}); the meshes of those \
             frames are seen from under the surface. summary.json lists them \
             (`flight.eye_below_ground_frames`).\n",
            experiment.below_ground_frames.len()
        );
    }
    let _ = writeln!(
        out,
        "| entry | algorithm | triangles | rendered | error max / mean / mean of p95 (px) | frame p50 / p95 (µs) | update p50 (µs) | upload per frame (kB) | draw calls | splits + merges per frame | evaluations per split or merge | bytes per sample |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|---|---|---|");
    let summarised = summarised_runs(inputs.runs, experiment.warm_up_frames);
    let rows: Vec<Row> = summarised.iter().map(row).collect();
    for (k, (run, r)) in inputs.runs.iter().zip(&rows).enumerate() {
        let error = r.error.map_or("—".to_string(), |(max, mean, p95)| {
            format!("{max:.2} / {mean:.3} / {p95:.2}")
        });
        // A from-scratch rebuild's "splits" are every activation of the frame's rebuild.
        let mark = if FROM_SCRATCH_ACTIVATIONS.contains(&inputs.names[k]) {
            " †"
        } else {
            ""
        };
        let per_operation = r
            .evaluations_per_operation
            .map_or("—".to_string(), |e| format!("{e:.1}{mark}"));
        let _ = writeln!(
            out,
            "| {} | {} | {:.0} | {:.0} | {} | {:.1} / {:.1} | {:.1} | {:.1} | {:.0} | {:.1}{mark} | {} | {:.2} |",
            run.label.replace('|', "\\|"),
            inputs.names[k],
            r.triangles,
            r.rendered,
            error,
            r.frame_p50_us,
            r.frame_p95_us,
            r.update_p50_us,
            r.upload_bytes / 1e3,
            r.draw_calls,
            r.operations_per_frame,
            per_operation,
            inputs.bytes_per_sample[k],
        );
    }
    let points: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.frame_p50_us, r.error.map_or(f64::NAN, |e| e.2)))
        .collect();
    let front = pareto_front(&points);
    if !front.is_empty() {
        let labels: Vec<&str> = front.iter().map(|&k| inputs.runs[k].label).collect();
        let _ = writeln!(
            out,
            "\nOn the accuracy-versus-time Pareto front (no other entry is both faster and more \
             accurate; median time to a drawn frame against audited p95 error): {}.",
            labels.join(", ")
        );
    }
    let labels: Vec<&str> = inputs.runs.iter().map(|r| r.label).collect();
    write_tuned_entries(&mut out, &labels, inputs.tunings);
    let _ = writeln!(
        out,
        "\n**Columns.** *triangles*, *rendered*: means per frame of the whole mesh and of the \
         triangles meeting the view volume. *error*: the audited projected screen-space error — the \
         largest of any frame, the mean over frames of each frame's mean, and the mean over frames of \
         each frame's 95th percentile over its samples (not a 95th percentile over frames). \
         *frame*: median and 95th percentile of the time to a drawn frame (`frame_ns`), the time \
         axis of this report and its plots: the CPU work from the new camera to buffers a GPU can \
         draw, that is the algorithm's update and then the upkeep of the buffers it keeps. \
         *update*: the median of the update alone (`update_ns`). *upload per frame*: the mean \
         bytes written into GPU buffers per frame (vertices, indices, per-draw data); *draw \
         calls*: their mean per frame. *splits + merges*: the \
         algorithm's operations per frame; † marks an algorithm that rebuilds its mesh from scratch \
         every frame (`reference`, `roam-rebuild`), whose splits count every activation of the \
         rebuild (merges 0): not comparable with an incremental algorithm's splits and merges, and \
         neither are its evaluations per split or merge. *evaluations per split or merge*: metric (or valid-life) \
         evaluations over the flight divided by its splits and merges. *bytes per sample*: the \
         shared preprocessed terrain (heights, 4 B/sample, and Wu's node table above the finest level, 1 B/sample, \
         when an entry reads it) plus the algorithm's own state at the end of the run, per height sample."
    );
    let settled: Vec<Option<Settling>> = inputs
        .runs
        .iter()
        .zip(inputs.names)
        .zip(&experiment.algorithms)
        .map(|((run, _), spec)| settling(spec.config.count_goal(), run))
        .collect();
    let warm_up = warm_up_paragraph(
        &labels,
        &settled,
        experiment.warm_up_frames,
        experiment.flight.n_frames(),
    );
    if !warm_up.is_empty() {
        let _ = writeln!(out, "\n{warm_up}");
    }
    write_goals(&mut out, experiment, &summarised);
    write_popping(&mut out, &summarised);
    write_triangle_lists(&mut out, &summarised);
    write_preprocessing(&mut out, inputs);
    out
}

/// The mean over frames of `column` in `run`, when it has values.
fn mean_of(run: &RunColumns, column: &str) -> Option<f64> {
    let values: Vec<f64> = run
        .frames
        .iter()
        .filter_map(|f| value(run, f, column))
        .collect();
    summarise(&values).map(|s| s.mean)
}

/// The largest value of `column` in `run`, when it has values.
fn max_of(run: &RunColumns, column: &str) -> Option<f64> {
    run.frames
        .iter()
        .filter_map(|f| value(run, f, column))
        .reduce(f64::max)
}

/// A figure with `digits` decimals, or a dash where there is none.
fn cell(value: Option<f64>, digits: usize) -> String {
    value.map_or("—".to_string(), |v| format!("{v:.digits$}"))
}

/// How every budget or target entry held its count over the summarised frames (the warm-up
/// left out), with the flags of `goal_check`.
fn write_goals(out: &mut String, experiment: &Experiment, runs: &[RunColumns]) {
    let checks: Vec<(&str, GoalCheck)> = experiment
        .algorithms
        .iter()
        .zip(runs)
        .filter_map(|(spec, run)| {
            let goal = spec.config.count_goal()?;
            Some((run.label, check_goal(run, goal)?))
        })
        .collect();
    if checks.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\n## {}\n\n| entry | counted | goal | mean | mean off by | approach (frames) | later frames > {:.0} % off | longest stretch | held? |\n|---|---|---|---|---|---|---|---|---|",
        section::BUDGETS_AND_TARGETS,
        FRAME_TOLERANCE * 100.0
    );
    for (label, check) in &checks {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.0} | {:+.1} % | {} | {} of {} | {} | {} |",
            label.replace('|', "\\|"),
            check.goal.column,
            check.goal.target,
            check.mean,
            check.mean_deviation * 100.0,
            check.approach_frames,
            check.frames_straying,
            check.frames - check.approach_frames,
            check.longest_stretch,
            match &check.flag {
                Some(reason) => format!("**no**: {reason}"),
                None => "yes".to_string(),
            }
        );
    }
    let _ = writeln!(
        out,
        "\nAn entry holds its goal when its mean is within {:.0} % of it, and, after its approach \
         (the frames before the first one within {3:.0} % of it), no more than {:.0} % of its \
         frames, and fewer than {} consecutive ones, are more than {:.0} % off it \
         (docs/output-formats.md).",
        MEAN_TOLERANCE * 100.0,
        STRAY_SHARE * 100.0,
        STRAY_STRETCH,
        FRAME_TOLERANCE * 100.0
    );
}

/// Popping per entry, when it was measured.
fn write_popping(out: &mut String, runs: &[RunColumns]) {
    if !runs.iter().any(|r| mean_of(r, "popping_rmse_m").is_some()) {
        return;
    }
    let _ = writeln!(
        out,
        "\n## Popping\n\n| entry | RMSE (m) | max (m) | RMSE (px) | max (px) |\n|---|---|---|---|---|"
    );
    for run in runs {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} |",
            run.label.replace('|', "\\|"),
            cell(mean_of(run, "popping_rmse_m"), 4),
            cell(max_of(run, "popping_max_m"), 3),
            cell(mean_of(run, "popping_rmse_px"), 3),
            cell(max_of(run, "popping_max_px"), 2),
        );
    }
    let _ = writeln!(
        out,
        "\nThe change of the drawn surface's height at the audited samples in view since the \
         previous frame: RMSE (mean over frames) and largest change (over the flight), in metres \
         and in projected pixels from the current eye."
    );
}

/// Triangles by role, morphing vertices, holes and cracks, for entries that draw triangle lists or
/// morph.
fn write_triangle_lists(out: &mut String, runs: &[RunColumns]) {
    let listed: Vec<&RunColumns> = runs
        .iter()
        .filter(|r| mean_of(r, "triangles_surface").is_some())
        .collect();
    if listed.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\n## Meshes beyond the 4-8 family\n\n| entry | surface | skirt | degenerate | stitch | morphing vertices | holes | crack samples | crack gap max (m) | left open by skirts max (m) |\n|---|---|---|---|---|---|---|---|---|---|"
    );
    for run in listed {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            run.label.replace('|', "\\|"),
            cell(mean_of(run, "triangles_surface"), 0),
            cell(mean_of(run, "triangles_skirt"), 0),
            cell(mean_of(run, "triangles_degenerate"), 0),
            cell(mean_of(run, "triangles_stitch"), 0),
            cell(mean_of(run, "morphing_vertices"), 0),
            cell(max_of(run, "audit_holes"), 0),
            cell(mean_of(run, "audit_crack_samples"), 1),
            cell(max_of(run, "audit_crack_gap_max_m"), 3),
            cell(max_of(run, "audit_crack_uncovered_max_m"), 3),
        );
    }
    let _ = writeln!(
        out,
        "\nMeans per frame, except *holes* (the most audited samples in view that no surface \
         triangle covered, in any frame), *crack gap* (the largest height disagreement \
         between surface triangles meeting at a sample, over the flight) and *left open by \
         skirts* (the largest part of a crack gap that no skirt hung there spans: a crack a \
         viewer can see through)."
    );
}

/// The shared terrain's preprocessing and each entry's own.
fn write_preprocessing(out: &mut String, inputs: &ReportInputs) {
    let terrain = inputs.terrain_preprocessing;
    let _ = writeln!(
        out,
        "\n## Preprocessing\n\nShared terrain (heights, and Wu's node table when an entry reads it): {:.3} s, {:.2} B/sample.\n\n| entry | algorithm | own preprocessing (s) | own bytes per sample after it |\n|---|---|---|---|",
        terrain.seconds, terrain.bytes_per_sample
    );
    for (k, (run, own)) in inputs
        .runs
        .iter()
        .zip(inputs.entry_preprocessing)
        .enumerate()
    {
        let _ = writeln!(
            out,
            "| {} | {} | {:.4} | {:.3} |",
            run.label.replace('|', "\\|"),
            inputs.names[k],
            own.seconds,
            own.bytes_per_sample
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::stats::{AuditFrame, FrameStats, MeshCounts, SurfaceCoverage};

    fn frame(frame: u64, holes: u64, gap: f64) -> FrameStats {
        FrameStats {
            frame,
            triangles: 16,
            mesh: Some(MeshCounts {
                triangles_by_role: [10, 4, 2, 0],
                morphing_vertices: 5,
            }),
            audit: Some(AuditFrame {
                samples_in_view: 100,
                projected: None,
                view_angle: None,
                coverage: Some(SurfaceCoverage {
                    holes,
                    crack_samples: 4,
                    crack_gap_max_m: gap,
                    crack_gap_max_px: 1.0,
                    cracks_uncovered: 1,
                    crack_uncovered_max_m: gap / 2.0,
                    crack_uncovered_max_px: 0.5,
                }),
                popping: None,
            }),
            ..FrameStats::default()
        }
    }

    #[test]
    fn triangle_list_entries_get_their_roles_holes_and_cracks_and_4_8_entries_no_row() {
        let listed = [frame(0, 2, 0.5), frame(1, 7, 1.25)];
        let plain = [FrameStats::default()];
        let runs = [
            RunColumns {
                label: "patches",
                extra_columns: &[],
                frames: &listed,
            },
            RunColumns {
                label: "wu",
                extra_columns: &[],
                frames: &plain,
            },
        ];
        let mut out = String::new();
        write_triangle_lists(&mut out, &runs);
        let rows: Vec<&str> = out.lines().filter(|l| l.starts_with("| ")).collect();
        assert_eq!(
            rows[1..],
            ["| patches | 10 | 4 | 2 | 0 | 5 | 7 | 4.0 | 1.250 | 0.625 |"]
        );
        let mut none = String::new();
        write_triangle_lists(&mut none, &runs[1..]);
        assert!(none.is_empty());
    }
}
