//! From the experiment file's bytes to a plan of checked points, and from a point to a runnable
//! [`Experiment`] (SPEC §8): the driver of the stages, which does none of their work itself
//! beyond reading the file and parsing its JSON.
//!
//! Stage 1 parses JSON into the format types (serde reports the field path of a type error).
//! Stage 2 (`check.rs`) checks meaning, collecting every problem with its field path. Stage 3
//! (`load.rs`) does the IO: reads the terrain (or generates it), fills voids, embeds it, reads a
//! recorded flight, builds the flight and checks it against the speed bounds.
//!
//! **Every point checked before any is loaded.** A swept experiment's points are all parsed and
//! checked up front, and every problem of every point is reported at once (each prefixed with
//! its point's choice) before any terrain is read; loading, one terrain at a time, waits for the
//! run. A mosaic terrain's files are laid out from their headers alone (they exist, their names
//! and sizes fit, no gap) for every point by [`plan`], with the same prefixes, before any
//! height is read; [`check_bytes`] does no IO and leaves them. Then, still before any is read,
//! every point's terrain is sized from its declared layout or its file's header and refused if
//! the run could not hold it (`terrain_size.rs`).

use super::check::{Checked, check, path_kind};
use super::format::{ExperimentFile, TerrainEntry};
use super::load::{Experiment, build_flight, lay_out_terrain_mosaic, load_terrain};
use super::problems::{ExperimentError, FieldProblem};
use super::sweep::{ExperimentPoint, SweepChoice, choice_label, expand_experiment};
use super::terrain_pyramid::check_pyramid_run;
use super::terrain_size::check_terrain_size;
use crate::edge::terrain_readers::MosaicLayout;
use crate::sim::flight::speed_violations;
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Reads, checks and loads an experiment file without a top-level sweep (an experiment with
/// one is run point by point: see [`plan`]).
pub fn load(path: &Path) -> Result<Experiment, ExperimentError> {
    let plan = plan(path)?;
    if plan.is_sweep() {
        return Err(ExperimentError::single(
            path,
            "sweep",
            format!(
                "a top-level sweep of {} points: expected an experiment without one here (`roamsim run` runs each point)",
                plan.points.len()
            ),
        ));
    }
    plan.load_point(0)
}

/// An experiment file read and checked, every sweep point of it, with nothing loaded yet.
pub struct Plan {
    file: PathBuf,
    content_sha256: String,
    points: Vec<PlannedPoint>,
}

struct PlannedPoint {
    choice: Option<SweepChoice>,
    label: Option<String>,
    parsed: ExperimentFile,
    checked: Checked,
    /// A mosaic terrain's files laid out from their headers ([`plan`] does it; `None` for other
    /// terrains and under [`check_bytes`], which does no IO).
    mosaic_layout: Option<MosaicLayout>,
}

/// Stages 1 and 2 for every point of the experiment's top-level sweep (one point without a
/// sweep): every problem of every point is reported at once, before any terrain is read; then
/// every point's terrain sized against the run's limits, reading at most file headers.
pub fn plan(path: &Path) -> Result<Plan, ExperimentError> {
    let bytes = std::fs::read(path).map_err(|error| {
        ExperimentError::single(path, "", format!("cannot read the file: {error}"))
    })?;
    let mut plan = plan_bytes(path, &bytes)?;
    lay_out_mosaics(&mut plan)?;
    check_pyramids(&plan)?;
    check_sizes(&plan)?;
    Ok(plan)
}

/// Every point's terrain sized from its declared layout or its file's header and refused when
/// the run could not hold it (`terrain_size.rs`), every point's problems reported at once.
fn check_sizes(plan: &Plan) -> Result<(), ExperimentError> {
    let path = plan.file.as_path();
    let folder = path.parent().unwrap_or(Path::new("."));
    let mut problems = Vec::new();
    for point in &plan.points {
        let sized = check_terrain_size(
            path,
            folder,
            &point.parsed.terrain,
            point.mosaic_layout.as_ref(),
            &point.checked.algorithms,
        );
        if let Err(error) = sized {
            problems.extend(prefixed(point.choice.as_ref(), error));
        }
    }
    none_or_all(&plan.file, problems)
}

/// Every point's pyramid opened (header and records checked) and every entry checked able to
/// fly it (`terrain_pyramid.rs`), before any height is read; every point's problems at once.
fn check_pyramids(plan: &Plan) -> Result<(), ExperimentError> {
    let folder = plan.file.parent().unwrap_or(Path::new("."));
    let mut problems = Vec::new();
    for point in &plan.points {
        let TerrainEntry::Pyramid(pyramid) = &point.parsed.terrain else {
            continue;
        };
        let audit_stride = point
            .parsed
            .effects
            .audit
            .as_ref()
            .map(|audit| audit.stride);
        let checked = check_pyramid_run(
            &plan.file,
            folder,
            pyramid,
            &point.checked.algorithms,
            audit_stride,
        );
        if let Err(error) = checked {
            problems.extend(prefixed(point.choice.as_ref(), error));
        }
    }
    none_or_all(&plan.file, problems)
}

/// Every point's mosaic laid out from its files' headers (existence, names, sizes,
/// georeference, gaps) before any terrain is read, every point's problems reported at once.
fn lay_out_mosaics(plan: &mut Plan) -> Result<(), ExperimentError> {
    let folder = plan.file.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut problems = Vec::new();
    for point in &mut plan.points {
        let TerrainEntry::Mosaic(mosaic) = &point.parsed.terrain else {
            continue;
        };
        match lay_out_terrain_mosaic(&plan.file, &folder, mosaic) {
            Ok(layout) => point.mosaic_layout = Some(layout),
            Err(error) => problems.extend(prefixed(point.choice.as_ref(), error)),
        }
    }
    none_or_all(&plan.file, problems)
}

/// `error`'s problems, each field prefixed with its point's choice (nothing without a sweep).
fn prefixed(
    choice: Option<&SweepChoice>,
    error: ExperimentError,
) -> impl Iterator<Item = FieldProblem> {
    let prefix = choice
        .map(|c| format!("({}) ", choice_label(c)))
        .unwrap_or_default();
    error.problems.into_iter().map(move |p| FieldProblem {
        field: format!("{prefix}{}", p.field),
        problem: p.problem,
    })
}

/// Nothing when no point had a problem, else every point's problems at once.
fn none_or_all(file: &Path, problems: Vec<FieldProblem>) -> Result<(), ExperimentError> {
    if problems.is_empty() {
        Ok(())
    } else {
        Err(ExperimentError {
            file: file.to_path_buf(),
            problems,
        })
    }
}

/// Stages 1 and 2 only: parses an experiment's bytes and checks their meaning, every sweep point
/// of it, with no IO (the terrain and a recorded flight log are not read, the flight is not
/// built). `path` only names the file in errors. Returns the number of algorithm entries over all
/// points, sweeps expanded. This is the entry point of the fuzz target and the parser property
/// tests.
pub fn check_bytes(path: &Path, bytes: &[u8]) -> Result<usize, ExperimentError> {
    let plan = plan_bytes(path, bytes)?;
    Ok(plan.points.iter().map(|p| p.checked.algorithms.len()).sum())
}

fn plan_bytes(path: &Path, bytes: &[u8]) -> Result<Plan, ExperimentError> {
    let document = parse_document(path, bytes)?;
    let points = expand_experiment(document).map_err(|problem| ExperimentError {
        file: path.to_path_buf(),
        problems: vec![problem],
    })?;
    let mut problems = Vec::new();
    let mut planned = Vec::new();
    for ExperimentPoint {
        choice,
        label,
        document,
    } in points
    {
        let prefix = choice
            .as_ref()
            .map(|c| format!("({}) ", choice_label(c)))
            .unwrap_or_default();
        let checked = parse(path, document).and_then(|parsed| {
            let checked = check(path, &parsed)?;
            Ok((parsed, checked))
        });
        match checked {
            Ok((parsed, checked)) => planned.push(PlannedPoint {
                choice,
                label,
                parsed,
                checked,
                mosaic_layout: None,
            }),
            Err(error) => problems.extend(error.problems.into_iter().map(|p| FieldProblem {
                field: format!("{prefix}{}", p.field),
                problem: p.problem,
            })),
        }
    }
    if !problems.is_empty() {
        return Err(ExperimentError {
            file: path.to_path_buf(),
            problems,
        });
    }
    Ok(Plan {
        file: path.to_path_buf(),
        content_sha256: hex(&Sha256::digest(bytes)),
        points: planned,
    })
}

impl Plan {
    /// Whether the file declares a top-level sweep (its points then carry their choices).
    pub fn is_sweep(&self) -> bool {
        self.points.iter().any(|p| p.choice.is_some())
    }

    pub fn n_points(&self) -> usize {
        self.points.len()
    }

    /// The experiment's name (the same for every point).
    pub fn name(&self) -> &str {
        &self.points[0].parsed.name
    }

    /// The experiment's description (the same for every point unless swept).
    pub fn description(&self) -> Option<&str> {
        self.points[0].parsed.description.as_deref()
    }

    /// SHA-256 of the experiment file's bytes, hex.
    pub fn content_sha256(&self) -> &str {
        &self.content_sha256
    }

    /// The number of algorithm entries of point `k`.
    pub fn n_entries(&self, k: usize) -> usize {
        self.points[k].checked.algorithms.len()
    }

    /// The swept values of point `k` (`None` without a sweep).
    pub fn choice(&self, k: usize) -> Option<&SweepChoice> {
        self.points[k].choice.as_ref()
    }

    /// The short label of point `k` (the sweep's `"labels"`), if the sweep gives one.
    pub fn label(&self, k: usize) -> Option<&str> {
        self.points[k].label.as_deref()
    }

    /// Stage 3 for point `k`: reads or generates its terrain, builds its flight.
    pub fn load_point(&self, k: usize) -> Result<Experiment, ExperimentError> {
        let path = self.file.as_path();
        let point = &self.points[k];
        let prefix_errors = |error: ExperimentError| match &point.choice {
            None => error,
            Some(choice) => ExperimentError {
                problems: error
                    .problems
                    .into_iter()
                    .map(|p| FieldProblem {
                        field: format!("({}) {}", choice_label(choice), p.field),
                        problem: p.problem,
                    })
                    .collect(),
                ..error
            },
        };
        let parsed = &point.parsed;
        let checked = &point.checked;
        let folder = path.parent().unwrap_or(Path::new("."));
        let (field, terrain) =
            load_terrain(path, folder, &parsed.terrain, point.mosaic_layout.as_ref())
                .map_err(prefix_errors)?;
        let flight = build_flight(path, folder, &parsed.flight, &field).map_err(prefix_errors)?;
        if let Some(exports) = &checked.mesh_exports
            && let Some(&frame) = exports.frames.iter().find(|&&f| f >= flight.n_frames())
        {
            return Err(prefix_errors(ExperimentError::single(
                path,
                "outputs.meshes.frames",
                format!(
                    "{frame} is past the flight's last frame {}",
                    flight.n_frames() - 1
                ),
            )));
        }
        let (speed, rotation_bound) = checked.speed.for_flight(&flight);
        let violations = speed_violations(&flight, speed);
        let below_ground_frames = flight.frames_below_ground(&field);
        let mut experiment = Experiment {
            name: parsed.name.clone(),
            description: parsed.description.clone(),
            file: path.to_path_buf(),
            content_sha256: self.content_sha256.clone(),
            field: Arc::new(field),
            terrain,
            view: checked.view,
            fovy_deg: parsed.view.fovy_deg,
            max_triangles: checked.max_triangles,
            speed,
            rotation_bound,
            flight_kind: path_kind(&parsed.flight.path),
            frames_in_file: flight.n_frames(),
            flight,
            violations,
            below_ground_frames,
            algorithms: checked.algorithms.clone(),
            effects: checked.effects,
            plots: parsed.outputs.plots,
            mesh_exports: checked.mesh_exports.clone(),
            warm_up_frames: parsed.outputs.warm_up_frames,
            sweep_point: point.choice.clone(),
        };
        if let Some(n_frames) = parsed.flight.first_frames {
            experiment.keep_first_frames(n_frames);
        }
        experiment.check_warm_up().map_err(prefix_errors)?;
        Ok(experiment)
    }
}

/// Stage 1a: the file's text as JSON (syntax errors carry line and column).
fn parse_document(path: &Path, bytes: &[u8]) -> Result<Value, ExperimentError> {
    serde_json::from_slice(bytes)
        .map_err(|error| ExperimentError::single(path, "", error.to_string()))
}

/// Stage 1b: a point's JSON into the format types (serde reports the path of a type error).
fn parse(path: &Path, document: Value) -> Result<ExperimentFile, ExperimentError> {
    serde_path_to_error::deserialize(document).map_err(|error| {
        let field = error.path().to_string();
        let field = if field == "." { String::new() } else { field };
        ExperimentError::single(path, field, error.into_inner().to_string())
    })
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
