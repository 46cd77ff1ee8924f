//! Assembling a run's outputs (SPEC §8): each point's `frames.csv`, `summary.json`, `report.md`,
//! exported meshes and plots written into the staged folder as the point is added, the sweep's
//! own files at the top at the end, then the commit. Not the formats themselves (`edge::output`
//! writes each), nor the running of a point (`point.rs`).
//!
//! **One assembly for a run and a merge.** A whole run and `roamsim merge` feed the same
//! [`RunAssembly`] point by point, a merge with the results read back from the shard files, so
//! a merged output cannot differ from a whole run's but in timings.
//!
//! **A folder per sweep point.** A sweep point's files go into its own sub-folder of the staging
//! folder (`edge::output::atomic_dir`), named from its choice (`parameter=value` pairs joined by
//! `_`); the point of an experiment without a sweep writes at the top.
//!
//! **Goals judged over the summarised frames.** Whether an entry held its budget or target is
//! judged over the frames after the warm-up, as report.md and summary.json judge it; the entries
//! that did not, and the tuned entries whose search did not reach its target, are the run's goal
//! flags.

use super::point::{AlgorithmResult, PointRun};
use super::run::{RunFailure, RunOutcome, io_error};
use crate::edge::experiment::{self, Experiment, Plan, SweepChoice, tuned_spec};
use crate::edge::output::atomic_dir::StagedDir;
use crate::edge::output::columns::RunColumns;
use crate::edge::output::end_of_run::PointFigures;
use crate::edge::output::frames_csv::frames_csv;
use crate::edge::output::goal_check::{GoalCheck, check_goal};
use crate::edge::output::report_md::{ReportInputs, report_markdown, row};
use crate::edge::output::run_plots::{RunPlotInputs, write_run_plots};
use crate::edge::output::summary_json::{Preprocessing, RunRecord, summary_json};
use crate::edge::output::sweep_outputs::{
    EntryFigures, SweepPoint, SweepRun, sweep_report_markdown, sweep_summary_json,
    write_sweep_plots,
};
use crate::edge::output::tuning::TuningRecord;
use crate::edge::output::warm_up::summarised_runs;
use std::path::{Path, PathBuf};

/// The outputs of a run (or of merged shards) being assembled point by point: each point's
/// files are written as it is added, the sweep's own files and the commit at the end.
pub(super) struct RunAssembly {
    outcome: RunOutcome,
    sweep_points: Vec<SweepPoint>,
    record: RunRecord,
}

impl RunAssembly {
    pub(super) fn new(
        plan: &Plan,
        out_dir: PathBuf,
        threads: usize,
        record: RunRecord,
    ) -> RunAssembly {
        RunAssembly {
            outcome: RunOutcome::nothing_yet(plan, out_dir, threads, record.check_meshes),
            sweep_points: Vec::new(),
            record,
        }
    }

    /// Writes point `k`'s outputs into its folder under `top` and keeps its figures.
    pub(super) fn add_point(
        &mut self,
        (k, plan_choice): (usize, Option<&SweepChoice>),
        experiment: &Experiment,
        point: PointRun,
        top: &Path,
    ) -> Result<(), RunFailure> {
        let choice_label = plan_choice.map(|c| experiment::choice_label(c));
        let context = OutputContext {
            experiment,
            preprocessing: &point.preprocessing,
            hierarchy_bytes: point.hierarchy_bytes,
            frames_resident_bytes: point.frames_resident_bytes,
            record: &self.record,
        };
        let folder = plan_choice.map(|c| point_folder(c)).unwrap_or_default();
        let point_dir = top.join(&folder);
        let figures = write_outputs(&context, &point.results, &point_dir)?;
        let outcome = &mut self.outcome;
        outcome.frames += experiment.flight.n_frames();
        outcome.meshes += experiment.flight.n_frames() * experiment.algorithms.len() as u64;
        outcome.goal_flags.extend(goal_flags(
            experiment,
            &point.results,
            choice_label.as_deref(),
        ));
        outcome.preprocessing_seconds += point.preprocessing.seconds;
        if k == 0 {
            outcome.speed_violation_frames = point.violation_frames;
        }
        outcome.points.push(PointFigures {
            choice: choice_label.clone(),
            folder: folder.clone(),
            entries: figures.clone(),
            below_ground_frames: experiment.below_ground_frames.clone(),
        });
        if let Some(choice) = plan_choice {
            self.sweep_points.push(SweepPoint {
                choice: choice.clone(),
                folder,
                side: experiment.field.side(),
                n_samples: experiment.field.n_samples(),
                frames: experiment.flight.n_frames(),
                preprocessing_seconds: point.preprocessing.seconds,
                hierarchy_bytes_per_sample: point.preprocessing.bytes_per_sample,
                entries: figures,
            });
        }
        Ok(())
    }

    /// Writes the sweep's own files (for a sweep) and moves the folder into place.
    pub(super) fn finish(
        self,
        plan: &Plan,
        path: &Path,
        staging: StagedDir,
    ) -> Result<RunOutcome, RunFailure> {
        if plan.is_sweep() {
            let top = staging.path();
            let sweep = SweepRun {
                name: plan.name(),
                description: plan.description(),
                file: path,
                content_sha256: plan.content_sha256(),
                record: &self.record,
                points: &self.sweep_points,
            };
            let summary_path = top.join("summary.json");
            let text =
                serde_json::to_string_pretty(&sweep_summary_json(&sweep)).unwrap_or_default();
            std::fs::write(&summary_path, text + "\n").map_err(io_error(&summary_path))?;
            let report_path = top.join("report.md");
            std::fs::write(&report_path, sweep_report_markdown(&sweep))
                .map_err(io_error(&report_path))?;
            let plots = top.join("plots");
            std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
            write_sweep_plots(&plots, &sweep)?;
        }
        staging.commit()?;
        Ok(self.outcome)
    }
}

/// The point's entries that did not hold their budget or target over the summarised frames, or
/// whose search did not reach its target, as `label: why` (prefixed with `(choice) ` for a
/// sweep point).
fn goal_flags(
    experiment: &Experiment,
    results: &[AlgorithmResult],
    choice_label: Option<&str>,
) -> Vec<String> {
    let point = choice_label.map_or(String::new(), |c| format!("({c}) "));
    let mut flags = Vec::new();
    for (spec, result) in experiment.algorithms.iter().zip(results) {
        // Over the summarised frames, as report.md and summary.json judge it.
        let all = RunColumns {
            label: &spec.label,
            extra_columns: &result.extra_columns,
            frames: &result.frames,
        };
        let run = summarised_runs(&[all], experiment.warm_up_frames).remove(0);
        if let Some(goal) = spec.config.count_goal()
            && let Some(GoalCheck {
                flag: Some(reason), ..
            }) = check_goal(&run, goal)
        {
            flags.push(format!("{point}{}: {reason}", spec.label));
        }
        if let Some(tuning) = &result.tuning
            && !tuning.reached
        {
            flags.push(format!(
                "{point}{}: tune did not reach {} {} within {}: the closest probe gave {} at {} = {}",
                spec.label,
                tuning.target.value(),
                tuning.target.unit(),
                tuning.tolerance,
                tuning.probe_mean,
                tuning.parameter,
                tuning.value,
            ));
        }
    }
    flags
}

/// What the writers need besides the results.
struct OutputContext<'a> {
    experiment: &'a Experiment,
    preprocessing: &'a Preprocessing,
    /// Bytes of the shared preprocessed terrain (heights and Wu's node table).
    hierarchy_bytes: f64,
    /// The process's resident set measured during the point's frames (`None` for a merge).
    frames_resident_bytes: Option<u64>,
    record: &'a RunRecord,
}

/// One point's results as the writers take them, entry by entry in the experiment's order.
struct PointTables<'r> {
    runs: Vec<RunColumns<'r>>,
    /// Each entry's algorithm name.
    names: Vec<&'r str>,
    tunings: Vec<Option<&'r TuningRecord>>,
    entry_preprocessing: Vec<Preprocessing>,
    /// The shared terrain's bytes and the entry's own, per sample of the terrain.
    bytes_per_sample: Vec<f64>,
}

impl<'r> PointTables<'r> {
    fn new(context: &OutputContext<'r>, results: &'r [AlgorithmResult]) -> PointTables<'r> {
        let experiment = context.experiment;
        let n_samples = experiment.field.n_samples() as f64;
        PointTables {
            runs: experiment
                .algorithms
                .iter()
                .zip(results)
                .map(|(spec, result)| RunColumns {
                    label: &spec.label,
                    extra_columns: &result.extra_columns,
                    frames: &result.frames,
                })
                .collect(),
            names: experiment
                .algorithms
                .iter()
                .map(|s| s.config.name())
                .collect(),
            tunings: results.iter().map(|r| r.tuning.as_ref()).collect(),
            entry_preprocessing: results.iter().map(|r| r.preprocessing).collect(),
            bytes_per_sample: results
                .iter()
                .map(|r| (context.hierarchy_bytes + r.memory_bytes as f64) / n_samples)
                .collect(),
        }
    }
}

/// Writes one point's `frames.csv`, `summary.json`, `report.md` and plots into `dir` (inside the
/// staged output folder); returns each entry's report figures.
fn write_outputs(
    context: &OutputContext,
    results: &[AlgorithmResult],
    dir: &Path,
) -> Result<Vec<EntryFigures>, RunFailure> {
    let experiment = context.experiment;
    let tables = PointTables::new(context, results);
    let audited = experiment.effects.audit.is_some();
    std::fs::create_dir_all(dir).map_err(io_error(dir))?;
    let csv_path = dir.join("frames.csv");
    std::fs::write(&csv_path, frames_csv(&tables.runs, audited)).map_err(io_error(&csv_path))?;
    write_summary(context, results, &tables, dir)?;
    write_report(context, &tables, dir)?;
    write_meshes(experiment, results, dir)?;
    if experiment.plots {
        let plots = dir.join("plots");
        std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
        let violation_frames: Vec<u64> = experiment.violations.iter().map(|v| v.frame).collect();
        write_run_plots(
            &plots,
            &RunPlotInputs {
                runs: &tables.runs,
                names: &tables.names,
                audited,
                speed_violation_frames: &violation_frames,
                horizontal_m_per_frame: experiment.speed.horizontal,
                warm_up_frames: experiment.warm_up_frames,
            },
        )?;
    }
    Ok(summarised_runs(&tables.runs, experiment.warm_up_frames)
        .iter()
        .zip(&tables.names)
        .zip(&tables.bytes_per_sample)
        .map(|((run, name), bytes)| EntryFigures {
            label: run.label.to_string(),
            name: name.to_string(),
            row: row(run),
            bytes_per_sample: *bytes,
        })
        .collect())
}

/// Writes the point's `summary.json`. A tuned entry's parameters are listed with the value its
/// search found.
fn write_summary(
    context: &OutputContext,
    results: &[AlgorithmResult],
    tables: &PointTables,
    dir: &Path,
) -> Result<(), RunFailure> {
    let experiment = context.experiment;
    let parameters: Vec<_> = experiment
        .algorithms
        .iter()
        .zip(results)
        .map(|(spec, result)| {
            spec.tune
                .as_ref()
                .zip(result.tuning.as_ref())
                .and_then(|(tune, record)| tuned_spec(spec, tune, record.value).ok())
                .map_or_else(|| spec.parameters.clone(), |tuned| tuned.parameters)
        })
        .collect();
    let facts: Vec<_> = results.iter().map(|r| r.facts.clone()).collect();
    let summary = summary_json(
        context.record,
        experiment,
        context.preprocessing,
        &tables.runs,
        &parameters,
        &tables.names,
        &facts,
        &tables.entry_preprocessing,
        &tables.tunings,
        context.frames_resident_bytes,
    );
    let summary_path = dir.join("summary.json");
    let text = serde_json::to_string_pretty(&summary).unwrap_or_default() + "\n";
    std::fs::write(&summary_path, text).map_err(io_error(&summary_path))
}

/// Writes the point's `report.md`.
fn write_report(
    context: &OutputContext,
    tables: &PointTables,
    dir: &Path,
) -> Result<(), RunFailure> {
    let report = report_markdown(&ReportInputs {
        experiment: context.experiment,
        runs: &tables.runs,
        names: &tables.names,
        bytes_per_sample: &tables.bytes_per_sample,
        threads: context.record.threads,
        terrain_preprocessing: context.preprocessing,
        entry_preprocessing: &tables.entry_preprocessing,
        tunings: &tables.tunings,
    });
    let report_path = dir.join("report.md");
    std::fs::write(&report_path, report).map_err(io_error(&report_path))
}

/// Writes the entries' exported meshes, one PLY file per frame under
/// `meshes/<k>-<label>/`.
fn write_meshes(
    experiment: &Experiment,
    results: &[AlgorithmResult],
    dir: &Path,
) -> Result<(), RunFailure> {
    for (k, (spec, result)) in experiment.algorithms.iter().zip(results).enumerate() {
        if result.meshes.is_empty() {
            continue;
        }
        let folder = dir.join("meshes").join(mesh_folder(k, &spec.label));
        std::fs::create_dir_all(&folder).map_err(io_error(&folder))?;
        for (frame, text) in &result.meshes {
            let path = folder.join(format!("frame-{frame:06}.ply"));
            std::fs::write(&path, text).map_err(io_error(&path))?;
        }
    }
    Ok(())
}

/// A folder name for a sweep point: `parameter=value` pairs joined by `_`, anything but letters,
/// digits and `._=-+` replaced by `-` (field names keep their `_`: `view.fovy_deg=60`).
fn point_folder(choice: &[(String, serde_json::Value)]) -> String {
    choice
        .iter()
        .map(|(parameter, value)| {
            let value = match value {
                serde_json::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            file_name_part(&format!("{parameter}={value}"))
        })
        .collect::<Vec<_>>()
        .join("_")
}

/// `text` with anything but ASCII letters, digits and `._=-+` replaced by `-`.
fn file_name_part(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._=-+".contains(c) {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// The folder of entry `k`'s exported meshes, under `meshes/`: its position and its label.
fn mesh_folder(k: usize, label: &str) -> String {
    format!("{k}-{}", file_name_part(label))
}
