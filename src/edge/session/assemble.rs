//! Assembling a run's outputs (SPEC §8): each point's `frames.csv`, `flight.csv`, `summary.json`,
//! `report.md`, exported meshes and plots written into the staged folder as the point is added,
//! the sweep's own files at the top at the end, then the commit. Not the formats themselves (`edge::output`
//! writes each), nor the running of a point (`point.rs`).
//!
//! **One assembly for a run and a merge.** A whole run and `roamsim merge` feed the same
//! [`RunAssembly`] point by point, a merge with the results read back from the shard files, so
//! a merged output cannot differ from a whole run's but in timings.
//!
//! **A folder per sweep point.** A sweep point's files go into its own sub-folder of the staging
//! folder (`edge::output::atomic_dir`), named by its label (the sweep's `"labels"`, checked to
//! be unique, safe folder names) or else from its choice (`parameter=value` pairs joined by
//! `_`); the point of an experiment without a sweep writes at the top.
//!
//! **Goals judged over the summarised frames.** Whether an entry held its budget or target is
//! judged over the frames after the warm-up, as report.md and summary.json judge it; the entries
//! that did not, and the tuned entries whose search did not reach its target, are the run's goal
//! flags.

use super::point::{AlgorithmResult, PointRun};
use super::run::{RunFailure, RunOutcome, io_error};
use crate::edge::experiment::{self, Experiment, Plan, TuneTarget, tuned_spec};
use crate::edge::output::atomic_dir::StagedDir;
use crate::edge::output::columns::RunColumns;
use crate::edge::output::end_of_run::PointFigures;
use crate::edge::output::flight_csv::flight_csv;
use crate::edge::output::flight_map::{FlightOnMap, write_flight_map};
use crate::edge::output::frames_csv::frames_csv;
use crate::edge::output::goal_check::{GoalCheck, check_goal};
use crate::edge::output::report_md::{REPORT_FILE, ReportInputs, report_markdown, row, section};
use crate::edge::output::run_plots::{ErrorTarget, RunPlotInputs, write_run_plots};
use crate::edge::output::summary_json::{Preprocessing, RunRecord, summary_json};
use crate::edge::output::sweep_outputs::{
    EntryFigures, SweepPoint, SweepRun, counter_means, sweep_report_markdown, sweep_summary_json,
    write_sweep_plots,
};
use crate::edge::output::tuned_experiment::{
    FrozenRun, TUNED_EXPERIMENT_FILE, entry_as_run, relative_path, tuned_experiment,
};
use crate::edge::output::tuning::{TuningRecord, significant};
use crate::edge::output::warm_up::summarised_runs;
use crate::sim::algorithm::AlgorithmConfig;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// The outputs of a run (or of merged shards) being assembled point by point: each point's
/// files are written as it is added, the sweep's own files and the commit at the end.
pub(super) struct RunAssembly {
    outcome: RunOutcome,
    sweep_points: Vec<SweepPoint>,
    record: RunRecord,
    /// Whether some point drew its plots (`outputs.plots`): the sweep's own plots follow it.
    plots: bool,
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
            plots: false,
        }
    }

    /// Writes point `k`'s outputs into its folder under `top` and keeps its figures.
    pub(super) fn add_point(
        &mut self,
        (k, plan): (usize, &Plan),
        experiment: &Experiment,
        point: PointRun,
        top: &Path,
    ) -> Result<(), RunFailure> {
        let plan_choice = plan.choice(k);
        let point_label = plan.label(k);
        let choice_label = plan_choice.map(|c| match point_label {
            Some(label) => format!("{label}: {}", experiment::choice_label(c)),
            None => experiment::choice_label(c),
        });
        let context = OutputContext {
            experiment,
            preprocessing: &point.preprocessing,
            hierarchy_bytes: point.hierarchy_bytes,
            frames_resident_bytes: point.frames_resident_bytes,
            record: &self.record,
        };
        let folder = match (point_label, plan_choice) {
            (Some(label), _) => label.to_string(),
            (None, Some(choice)) => point_folder(choice),
            (None, None) => String::new(),
        };
        let point_dir = top.join(&folder);
        let figures = write_outputs(&context, &point.results, &point_dir)?;
        if point.results.iter().any(|r| r.tuning.is_some()) {
            let final_dir = self.outcome.out_dir.join(&folder);
            let dirs = (point_dir.as_path(), final_dir.as_path());
            if let Some(missing) = write_tuned_experiment((k, experiment), &point.results, dirs)? {
                self.outcome.goal_flags.push(missing);
            }
        }
        self.plots |= experiment.plots;
        let outcome = &mut self.outcome;
        outcome.frames += experiment.flight.n_frames();
        outcome.meshes += experiment.flight.n_frames() * experiment.algorithms.len() as u64;
        outcome.goal_flags.extend(goal_flags(
            experiment,
            &point.results,
            (choice_label.as_deref(), &folder),
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
                label: point_label.map(str::to_string),
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
            let report_path = top.join(REPORT_FILE);
            std::fs::write(&report_path, sweep_report_markdown(&sweep))
                .map_err(io_error(&report_path))?;
            if self.plots {
                let plots = top.join("plots");
                std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
                write_sweep_plots(&plots, &sweep)?;
            }
        }
        let mut outcome = self.outcome;
        let point_folders: Vec<&str> = outcome.points.iter().map(|p| p.folder.as_str()).collect();
        outcome.written = written_at(staging.path(), &point_folders)?;
        staging.commit()?;
        Ok(outcome)
    }
}

/// Each entry tuned to an audited error target, with its target and its line in
/// `triangles_for_error_target`: entries of one algorithm whose parameters but the tuned one are
/// the same share a line, named by the algorithm, or by the first entry's label when several
/// lines share an algorithm.
fn error_targets(experiment: &Experiment, results: &[AlgorithmResult]) -> Vec<Option<ErrorTarget>> {
    /// A tuned-to-error entry: its line's key (algorithm and every other parameter), algorithm,
    /// target, whether reached, label.
    struct Tuned<'e> {
        key: String,
        name: &'e str,
        target: f64,
        reached: bool,
        label: &'e str,
    }
    let tuned: Vec<Option<Tuned>> = experiment
        .algorithms
        .iter()
        .zip(results)
        .map(|(spec, result)| {
            let tune = spec.tune.as_ref()?;
            let TuneTarget::AuditP95Px(target) = tune.target else {
                return None;
            };
            let mut others = spec.parameters.clone();
            if let Some(map) = others.as_object_mut() {
                map.remove(tune.parameter);
            }
            Some(Tuned {
                key: format!("{} {others}", spec.config.name()),
                name: spec.config.name(),
                target,
                reached: result.tuning.as_ref().is_some_and(|t| t.reached),
                label: &spec.label,
            })
        })
        .collect();
    // Each line's first entry, in order.
    let mut firsts: Vec<&Tuned> = Vec::new();
    for entry in tuned.iter().flatten() {
        if !firsts.iter().any(|first| first.key == entry.key) {
            firsts.push(entry);
        }
    }
    tuned
        .iter()
        .map(|entry| {
            let entry = entry.as_ref()?;
            let lines_of_algorithm = firsts.iter().filter(|f| f.name == entry.name).count();
            let line = if lines_of_algorithm > 1 {
                firsts
                    .iter()
                    .find(|f| f.key == entry.key)?
                    .label
                    .to_string()
            } else {
                entry.name.to_string()
            };
            Some(ErrorTarget {
                target_px: entry.target,
                reached: entry.reached,
                line,
            })
        })
        .collect()
}

/// Writes point `k`'s `tuned-experiment.json` into `dir` (staged), its paths relative to
/// `final_dir`, where `dir` will be once committed (`edge::output::tuned_experiment`). The
/// experiment file is read again, and must not have changed since the run read it: when it
/// cannot be read or has changed, nothing is written and the warning saying so is returned (the
/// run's other outputs stand).
fn write_tuned_experiment(
    (k, experiment): (usize, &Experiment),
    results: &[AlgorithmResult],
    (dir, final_dir): (&Path, &Path),
) -> Result<Option<String>, RunFailure> {
    let file = &experiment.file;
    let missing = |why: String| {
        Some(format!(
            "{TUNED_EXPERIMENT_FILE} not written: {} {why}; summary.json lists the values found",
            file.display()
        ))
    };
    let bytes = match std::fs::read(file) {
        Ok(bytes) => bytes,
        Err(error) => return Ok(missing(format!("cannot be read again ({error})"))),
    };
    let sha: String = Sha256::digest(&bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let document = (sha == experiment.content_sha256)
        .then(|| experiment::point_document(&bytes, k))
        .flatten();
    let Some(document) = document else {
        return Ok(missing("changed since the run read it".to_string()));
    };
    let algorithms = experiment
        .algorithms
        .iter()
        .zip(results)
        .map(|(spec, result)| {
            let parameters = spec
                .tune
                .as_ref()
                .zip(result.tuning.as_ref())
                .and_then(|(tune, record)| tuned_spec(spec, tune, record.value).ok())
                .map_or_else(|| spec.parameters.clone(), |tuned| tuned.parameters);
            entry_as_run(spec.config.name(), &spec.label, &parameters)
        })
        .collect();
    let n_frames = experiment.flight.n_frames();
    let run = FrozenRun {
        document: &document,
        algorithms,
        first_frames: (n_frames < experiment.frames_in_file).then_some(n_frames),
    };
    let experiment_folder = file.parent().unwrap_or(Path::new("."));
    let from = absolute_folder(final_dir);
    let rewrite = |written: &str| -> String {
        let target = std::fs::canonicalize(experiment_folder.join(written))
            .unwrap_or_else(|_| experiment_folder.join(written));
        from.as_deref()
            .and_then(|from| relative_path(from, &target))
            .unwrap_or(target)
            .to_string_lossy()
            .replace('\\', "/")
    };
    let text = serde_json::to_string_pretty(&tuned_experiment(&run, &rewrite)).unwrap_or_default();
    let path = dir.join(TUNED_EXPERIMENT_FILE);
    std::fs::write(&path, text + "\n").map_err(io_error(&path))?;
    Ok(None)
}

/// `folder` as an absolute path with links resolved, when its parent exists (the output
/// folder's does: its staging folder was made beside it).
fn absolute_folder(folder: &Path) -> Option<PathBuf> {
    let mut existing = folder.to_path_buf();
    let mut rest = Vec::new();
    while std::fs::canonicalize(&existing).is_err() {
        rest.push(existing.file_name()?.to_os_string());
        existing = existing.parent()?.to_path_buf();
        if existing.as_os_str().is_empty() {
            existing = PathBuf::from(".");
        }
    }
    let mut absolute = std::fs::canonicalize(&existing).ok()?;
    absolute.extend(rest.iter().rev());
    Some(absolute)
}

/// What `top` holds, as the end of the run lists it: its files, and its folders with a `/`, the
/// points' own folders and hidden names (the manifest) left out; sorted.
fn written_at(top: &Path, point_folders: &[&str]) -> Result<Vec<String>, RunFailure> {
    let mut written = Vec::new();
    for entry in std::fs::read_dir(top).map_err(io_error(top))? {
        let entry = entry.map_err(io_error(top))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') || point_folders.contains(&name.as_str()) {
            continue;
        }
        let is_dir = entry.file_type().map_err(io_error(&entry.path()))?.is_dir();
        written.push(if is_dir { format!("{name}/") } else { name });
    }
    written.sort();
    Ok(written)
}

/// The point's entries that did not hold their budget or target over the summarised frames, or
/// whose search did not reach its target, as `label: why (report.md, "section")` (prefixed with
/// `(choice) ` for a sweep point, whose report is in its `folder`). The section is named by the
/// constant `report.md` writes its heading from, and is written whenever such a flag is: a
/// budget or target entry always gets a row of *Budgets and targets*, a tuned entry one of
/// *Tuned entries*.
fn goal_flags(
    experiment: &Experiment,
    results: &[AlgorithmResult],
    (choice_label, folder): (Option<&str>, &str),
) -> Vec<String> {
    let point = choice_label.map_or(String::new(), |c| format!("({c}) "));
    let report = if folder.is_empty() {
        REPORT_FILE.to_string()
    } else {
        format!("{folder}/{REPORT_FILE}")
    };
    let pointer = |heading: &str| format!(" ({report}, \"{heading}\")");
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
            flags.push(format!(
                "{point}{}: {reason}{}",
                spec.label,
                pointer(section::BUDGETS_AND_TARGETS)
            ));
        }
        if let Some(tuning) = &result.tuning
            && !tuning.reached
        {
            let plateau = tuning.plateau.as_ref().map_or(String::new(), |p| {
                format!(
                    "; it stopped on a plateau: {}",
                    p.sentence(tuning.parameter, tuning.target)
                )
            });
            flags.push(format!(
                "{point}{}: tune did not reach {} {} within {}: the closest probe gave {} at {} = {}{plateau}{}",
                spec.label,
                tuning.target.value(),
                tuning.target.unit(),
                tuning.tolerance,
                significant(tuning.probe_mean),
                tuning.parameter,
                significant(tuning.value),
                pointer(section::TUNED_ENTRIES)
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

/// Writes one point's `frames.csv`, `flight.csv`, `summary.json`, `report.md` and plots into `dir`
/// (inside the staged output folder); returns each entry's report figures.
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
    let flight_path = dir.join("flight.csv");
    let flight_text = flight_csv(&experiment.flight, &experiment.field, experiment.speed);
    std::fs::write(&flight_path, flight_text).map_err(io_error(&flight_path))?;
    write_summary(context, results, &tables, dir)?;
    write_report(context, &tables, dir)?;
    write_meshes(experiment, results, dir)?;
    if experiment.plots {
        let plots = dir.join("plots");
        std::fs::create_dir_all(&plots).map_err(io_error(&plots))?;
        let violation_frames: Vec<u64> = experiment.violations.iter().map(|v| v.frame).collect();
        let shifts_base: Vec<bool> = experiment
            .algorithms
            .iter()
            .map(|spec| matches!(&spec.config, AlgorithmConfig::Wu(wu) if wu.budget.is_some()))
            .collect();
        write_run_plots(
            &plots,
            &RunPlotInputs {
                runs: &tables.runs,
                names: &tables.names,
                audited,
                speed_violation_frames: &violation_frames,
                shifts_base: &shifts_base,
                error_targets: &error_targets(experiment, results),
                horizontal_m_per_frame: experiment.speed.horizontal,
                warm_up_frames: experiment.warm_up_frames,
            },
        )?;
        let title = format!(
            "The flight over {}: {} frames",
            experiment.terrain.source,
            experiment.flight.n_frames()
        );
        let flight = FlightOnMap {
            flight: &experiment.flight,
            view: experiment.view,
            violations: &experiment.violations,
        };
        write_flight_map(&plots, &experiment.field, &title, Some(flight))?;
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
            counters: counter_means(run),
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
    let report_path = dir.join(REPORT_FILE);
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
