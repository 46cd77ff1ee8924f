//! From the experiment file's text to a runnable [`Experiment`].
//!
//! Stage 1 parses JSON into the format types (serde reports the field path of a type error).
//! Stage 2 checks meaning, collecting every problem with its field path. Stage 3 does the IO:
//! reads the terrain (or generates it), fills voids, embeds it, reads a recorded flight, builds
//! the flight and checks it against the speed bounds.

use super::format::{
    AlgorithmEntry, DistanceEntry, ExperimentFile, FORMAT_VERSION, FitEntry, FlightEntry,
    InterpolationEntry, LindstromParameters, LookEntry, MeshesEntry, NestingEntry, PathEntry,
    RawSampleEntry, ReferenceParameters, RoamParameters, RottgerParameters, TerrainEntry,
    TerrainFormatEntry, WuParameters, ZoneEntry,
};
use super::sweep::{
    ExperimentPoint, MAX_SWEEP_POINTS, SweepChoice, cartesian, choice_label, expand_experiment,
};
use super::{ExperimentError, FieldProblem};
use crate::edge::flight_log::read_flight_log;
use crate::edge::terrain_readers::{
    RawLayout, RawSample, ReadOptions, TerrainFormat, format_from_extension, read_terrain,
};
use crate::sim::algorithm::{
    AlgorithmConfig, BudgetConfig, LindstromConfig, ReferenceConfig, RoamConfig, RoamGoal,
    RottgerConfig, SplitThreshold, WuConfig,
};
use crate::sim::audit::AuditSettings;
use crate::sim::flight::{
    Flight, FlightPath, Interpolation, Look, SpeedViolation, Waypoint, speed_violations,
};
use crate::sim::hierarchy::NestingRule;
use crate::sim::run::Effects;
use crate::sim::terrain::embed::{Fit, embed};
use crate::sim::terrain::fill::fill_voids;
use crate::sim::terrain::synthetic::{SyntheticTerrain, generate};
use crate::sim::terrain::{Heightfield, Spacing};
use crate::sim::view::ViewSettings;
use crate::sim::zone::{SpeedBound, ZoneVariant};
use glam::{DVec2, DVec3};
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Algorithms this build knows, as the experiment file names them.
pub const KNOWN_ALGORITHMS: &[&str] = &[
    "reference",
    "wu",
    "lindstrom",
    "roam",
    "roam-rebuild",
    "rottger",
];

/// A validated, loaded experiment: everything a run needs.
pub struct Experiment {
    pub name: String,
    pub description: Option<String>,
    pub file: PathBuf,
    /// SHA-256 of the experiment file's bytes, hex.
    pub content_sha256: String,
    pub field: Heightfield,
    pub terrain: TerrainReport,
    pub view: ViewSettings,
    pub speed: SpeedBound,
    pub flight: Flight,
    pub flight_kind: &'static str,
    pub violations: Vec<SpeedViolation>,
    pub algorithms: Vec<AlgorithmSpec>,
    pub effects: Effects,
    pub plots: bool,
    /// Meshes to write as PLY files (`outputs.meshes`); `None`: none.
    pub mesh_exports: Option<MeshExports>,
    /// The point of the experiment's top-level sweep this is (`None` without a sweep).
    pub sweep_point: Option<SweepChoice>,
}

/// Which entries' meshes to export at which frames, checked: every frame inside the flight,
/// every entry an index into [`Experiment::algorithms`]; both sorted, without repeats.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshExports {
    pub frames: Vec<u64>,
    pub entries: Vec<usize>,
}

/// One algorithm entry: its label, configuration and the parameters as written.
#[derive(Clone)]
pub struct AlgorithmSpec {
    pub label: String,
    pub config: AlgorithmConfig,
    pub parameters: Value,
}

/// Where the terrain came from and what was done to it, for the run metadata.
#[derive(Clone, Debug, PartialEq)]
pub struct TerrainReport {
    /// The file (as written in the experiment) or `synthetic`.
    pub source: String,
    pub format: String,
    pub source_columns: usize,
    pub source_rows: usize,
    pub side: usize,
    pub padded_columns: usize,
    pub padded_rows: usize,
    pub crop_origin: Option<(usize, usize)>,
    pub voids_filled: usize,
    pub spacing: Spacing,
    /// `file`, `experiment` or `synthetic`.
    pub spacing_from: &'static str,
    pub height_min_m: f32,
    pub height_max_m: f32,
}

/// Reads, validates and loads an experiment file without a top-level sweep (an experiment with
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
    parsed: ExperimentFile,
    checked: Checked,
}

/// Stages 1 and 2 for every point of the experiment's top-level sweep (one point without a
/// sweep): every problem of every point is reported at once, before any terrain is read.
pub fn plan(path: &Path) -> Result<Plan, ExperimentError> {
    let bytes = std::fs::read(path).map_err(|error| {
        ExperimentError::single(path, "", format!("cannot read the file: {error}"))
    })?;
    plan_bytes(path, &bytes)
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
    for ExperimentPoint { choice, document } in points {
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
                parsed,
                checked,
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

    /// The swept values of point `k` (`None` without a sweep).
    pub fn choice(&self, k: usize) -> Option<&SweepChoice> {
        self.points[k].choice.as_ref()
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
            load_terrain(path, folder, &parsed.terrain).map_err(prefix_errors)?;
        let flight = build_flight(path, folder, &parsed.flight).map_err(prefix_errors)?;
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
        let violations = speed_violations(&flight, checked.speed);
        Ok(Experiment {
            name: parsed.name.clone(),
            description: parsed.description.clone(),
            file: path.to_path_buf(),
            content_sha256: self.content_sha256.clone(),
            field,
            terrain,
            view: checked.view,
            speed: checked.speed,
            flight,
            flight_kind: path_kind(&parsed.flight.path),
            violations,
            algorithms: checked.algorithms.clone(),
            effects: checked.effects,
            plots: parsed.outputs.plots,
            mesh_exports: checked.mesh_exports.clone(),
            sweep_point: point.choice.clone(),
        })
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

struct Checked {
    view: ViewSettings,
    speed: SpeedBound,
    algorithms: Vec<AlgorithmSpec>,
    effects: Effects,
    mesh_exports: Option<MeshExports>,
}

/// Stage 2: every semantic problem, with its field path.
fn check(path: &Path, file: &ExperimentFile) -> Result<Checked, ExperimentError> {
    let mut problems = Problems::default();
    if file.format_version != FORMAT_VERSION {
        problems.add(
            "format_version",
            format!(
                "{} is not a version this build reads: expected {FORMAT_VERSION}",
                file.format_version
            ),
        );
    }
    if file.name.is_empty()
        || !file
            .name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
        || file.name.starts_with('.')
    {
        problems.add(
            "name",
            format!(
                "{:?}: expected a non-empty name of letters, digits, '-', '_' and '.' \
                 (it names the output folder), not starting with '.'",
                file.name
            ),
        );
    }
    check_terrain(&file.terrain, &mut problems);
    let view = &file.view;
    problems.positive_int("view.width_px", view.width_px);
    problems.positive_int("view.height_px", view.height_px);
    if !(view.fovy_deg > 0.0 && view.fovy_deg < 180.0) {
        problems.add(
            "view.fovy_deg",
            format!(
                "{}: expected an angle strictly between 0 and 180",
                view.fovy_deg
            ),
        );
    }
    problems.positive("view.near_m", view.near_m);
    if !(view.far_m > view.near_m && view.far_m.is_finite()) {
        problems.add(
            "view.far_m",
            format!(
                "{}: expected a finite distance beyond near_m ({})",
                view.far_m, view.near_m
            ),
        );
    }
    let bounds = &file.speed_bounds;
    problems.non_negative(
        "speed_bounds.horizontal_m_per_frame",
        bounds.horizontal_m_per_frame,
    );
    problems.non_negative(
        "speed_bounds.vertical_m_per_frame",
        bounds.vertical_m_per_frame,
    );
    check_flight(&file.flight, &mut problems);
    let algorithms = check_algorithms(&file.algorithms, &mut problems);
    if let Some(audit) = &file.effects.audit {
        problems.positive_int("effects.audit.stride", audit.stride);
    }
    let mesh_exports = file
        .outputs
        .meshes
        .as_ref()
        .map(|meshes| check_mesh_exports(meshes, &algorithms, &mut problems));
    if !problems.list.is_empty() {
        return Err(ExperimentError {
            file: path.to_path_buf(),
            problems: problems.list,
        });
    }
    Ok(Checked {
        view: ViewSettings {
            width_px: view.width_px,
            height_px: view.height_px,
            fovy: view.fovy_deg.to_radians(),
            near: view.near_m,
            far: view.far_m,
        },
        speed: SpeedBound {
            horizontal: bounds.horizontal_m_per_frame,
            vertical: bounds.vertical_m_per_frame,
        },
        algorithms,
        effects: Effects {
            audit: file.effects.audit.as_ref().map(|a| AuditSettings {
                stride: a.stride,
                popping: a.popping,
            }),
            culling: file.effects.culling,
            check_meshes: false,
        },
        mesh_exports,
    })
}

/// `outputs.meshes`: at least one frame; entries by label or algorithm name (a name selects
/// every entry of that algorithm). Frames past the flight are found when it is built.
fn check_mesh_exports(
    meshes: &MeshesEntry,
    algorithms: &[AlgorithmSpec],
    problems: &mut Problems,
) -> MeshExports {
    if meshes.frames.is_empty() {
        problems.add(
            "outputs.meshes.frames",
            "empty: expected at least one frame",
        );
    }
    let mut frames = meshes.frames.clone();
    frames.sort_unstable();
    frames.dedup();
    let mut entries: Vec<usize> = match &meshes.entries {
        None => (0..algorithms.len()).collect(),
        Some(wanted) => {
            let mut entries = Vec::new();
            for (k, wanted) in wanted.iter().enumerate() {
                let matching: Vec<usize> = algorithms
                    .iter()
                    .enumerate()
                    .filter(|(_, a)| a.label == *wanted || a.config.name() == wanted)
                    .map(|(index, _)| index)
                    .collect();
                if matching.is_empty() {
                    let labels: Vec<&str> = algorithms.iter().map(|a| a.label.as_str()).collect();
                    problems.add(
                        format!("outputs.meshes.entries[{k}]"),
                        format!(
                            "{wanted:?} names no algorithm entry: expected a label ({}) or an \
                             algorithm name",
                            labels.join(", ")
                        ),
                    );
                }
                entries.extend(matching);
            }
            entries
        }
    };
    entries.sort_unstable();
    entries.dedup();
    MeshExports { frames, entries }
}

#[derive(Default)]
struct Problems {
    list: Vec<FieldProblem>,
}

impl Problems {
    fn add(&mut self, field: impl Into<String>, problem: impl Into<String>) {
        self.list.push(FieldProblem {
            field: field.into(),
            problem: problem.into(),
        });
    }

    fn positive(&mut self, field: &str, value: f64) {
        if !(value > 0.0 && value.is_finite()) {
            self.add(field, format!("{value}: expected a finite number above 0"));
        }
    }

    fn non_negative(&mut self, field: &str, value: f64) {
        if !(value >= 0.0 && value.is_finite()) {
            self.add(
                field,
                format!("{value}: expected a finite number of at least 0"),
            );
        }
    }

    fn finite(&mut self, field: &str, values: &[f64]) {
        if values.iter().any(|v| !v.is_finite()) {
            self.add(field, format!("{values:?}: expected finite numbers"));
        }
    }

    fn positive_int(&mut self, field: &str, value: u32) {
        if value == 0 {
            self.add(field, "0: expected at least 1");
        }
    }
}

fn check_terrain(terrain: &TerrainEntry, problems: &mut Problems) {
    match terrain {
        TerrainEntry::File(file) => {
            if let Some(scale) = file.height_scale
                && !(scale.is_finite() && scale != 0.0)
            {
                problems.add(
                    "terrain.file.height_scale",
                    format!("{scale}: expected a finite, non-zero number of metres per unit"),
                );
            }
            if let Some(offset) = file.height_offset_m {
                problems.finite("terrain.file.height_offset_m", &[offset]);
            }
            if let Some(origin) = file.origin_m {
                problems.finite("terrain.file.origin_m", &origin);
            }
            if let Some(spacing) = file.spacing_m {
                problems.positive("terrain.file.spacing_m.dx", spacing.dx);
                problems.positive("terrain.file.spacing_m.dy", spacing.dy);
            }
            if file.crop_origin.is_some() && matches!(file.fit, FitEntry::Pad) {
                problems.add(
                    "terrain.file.crop_origin",
                    "a crop origin was given but fit is \"pad\": expected fit \"crop\"",
                );
            }
            if let Some(TerrainFormatEntry::Raw(raw)) = &file.format
                && (raw.columns < 3 || raw.rows < 3)
            {
                problems.add(
                    "terrain.file.format.raw",
                    format!(
                        "{}×{}: expected at least 3×3 samples",
                        raw.columns, raw.rows
                    ),
                );
            }
        }
        TerrainEntry::Synthetic(synthetic) => {
            if !(1..=14).contains(&synthetic.level) {
                problems.add(
                    "terrain.synthetic.level",
                    format!(
                        "{}: expected 1 to 14 (side 2^level + 1, 3 to 16385)",
                        synthetic.level
                    ),
                );
            }
            problems.non_negative("terrain.synthetic.amplitude_m", synthetic.amplitude_m);
            if let Some(scale) = synthetic.amplitude_scale_m {
                problems.positive("terrain.synthetic.amplitude_scale_m", scale);
            }
            if !(0.0..=1.0).contains(&synthetic.roughness) {
                problems.add(
                    "terrain.synthetic.roughness",
                    format!(
                        "{}: expected a Hurst exponent in [0, 1]",
                        synthetic.roughness
                    ),
                );
            }
            if let Some(origin) = synthetic.origin_m {
                problems.finite("terrain.synthetic.origin_m", &origin);
            }
            problems.positive("terrain.synthetic.spacing_m.dx", synthetic.spacing_m.dx);
            problems.positive("terrain.synthetic.spacing_m.dy", synthetic.spacing_m.dy);
        }
    }
}

/// Longest flight accepted, in frames (beyond it the pose table alone needs gigabytes).
const MAX_FRAMES: u64 = 20_000_000;

fn check_flight(flight: &FlightEntry, problems: &mut Problems) {
    let own_frames = matches!(
        flight.path,
        PathEntry::Waypoints { .. } | PathEntry::Recorded { .. }
    );
    match (flight.frames, own_frames) {
        (Some(_), true) => problems.add(
            "flight.frames",
            "waypoint and recorded flights bring their own frame count: expected no frames field",
        ),
        (None, false) => problems.add(
            "flight.frames",
            "missing: expected the number of frames to fly",
        ),
        (Some(frames), false) if frames == 0 || frames > MAX_FRAMES => problems.add(
            "flight.frames",
            format!("{frames}: expected 1 to {MAX_FRAMES}"),
        ),
        _ => {}
    }
    match (&flight.look, &flight.path) {
        (Some(_), PathEntry::Orbit { .. } | PathEntry::Recorded { .. }) => problems.add(
            "flight.look",
            "orbit and recorded flights set their own view direction: expected no look field",
        ),
        (None, PathEntry::Orbit { .. } | PathEntry::Recorded { .. }) => {}
        (None, _) => problems.add("flight.look", "missing: expected along_path, at or fixed"),
        (Some(look), _) => match look {
            LookEntry::AlongPath { pitch_deg } => {
                check_pitch("flight.look.along_path", *pitch_deg, problems)
            }
            LookEntry::At { target_m } => problems.finite("flight.look.at.target_m", target_m),
            LookEntry::Fixed { yaw_deg, pitch_deg } => {
                problems.finite("flight.look.fixed.yaw_deg", &[*yaw_deg]);
                check_pitch("flight.look.fixed", *pitch_deg, problems);
            }
        },
    }
    match &flight.path {
        PathEntry::Circle {
            centre_m,
            radius_m,
            altitude_m,
            frames_per_lap,
            phase_deg,
        }
        | PathEntry::Orbit {
            centre_m,
            radius_m,
            altitude_m,
            frames_per_lap,
            phase_deg,
            ..
        } => {
            let kind = path_kind(&flight.path);
            problems.finite(&format!("flight.path.{kind}.centre_m"), centre_m);
            problems.non_negative(&format!("flight.path.{kind}.radius_m"), *radius_m);
            problems.finite(&format!("flight.path.{kind}.altitude_m"), &[*altitude_m]);
            problems.positive(
                &format!("flight.path.{kind}.frames_per_lap"),
                *frames_per_lap,
            );
            problems.finite(&format!("flight.path.{kind}.phase_deg"), &[*phase_deg]);
            if let PathEntry::Orbit { target_m, .. } = &flight.path {
                problems.finite("flight.path.orbit.target_m", target_m);
            }
        }
        PathEntry::Line { from_m, to_m } => {
            problems.finite("flight.path.line.from_m", from_m);
            problems.finite("flight.path.line.to_m", to_m);
        }
        PathEntry::Spiral {
            centre_m,
            radius_start_m,
            radius_end_m,
            altitude_start_m,
            altitude_end_m,
            turns,
            phase_deg,
        } => {
            problems.finite("flight.path.spiral.centre_m", centre_m);
            problems.non_negative("flight.path.spiral.radius_start_m", *radius_start_m);
            problems.non_negative("flight.path.spiral.radius_end_m", *radius_end_m);
            problems.finite(
                "flight.path.spiral",
                &[*altitude_start_m, *altitude_end_m, *turns, *phase_deg],
            );
        }
        PathEntry::Waypoints { points, .. } => {
            if points.len() < 2 {
                problems.add(
                    "flight.path.waypoints.points",
                    format!("{} waypoints: expected at least 2", points.len()),
                );
            }
            if let Some(first) = points.first()
                && first.frame != 0
            {
                problems.add(
                    "flight.path.waypoints.points[0].frame",
                    format!("{}: expected the first waypoint at frame 0", first.frame),
                );
            }
            for (k, pair) in points.windows(2).enumerate() {
                if pair[1].frame <= pair[0].frame {
                    problems.add(
                        format!("flight.path.waypoints.points[{}].frame", k + 1),
                        format!(
                            "{}: expected a frame after the previous waypoint's ({})",
                            pair[1].frame, pair[0].frame
                        ),
                    );
                }
            }
            if let Some(last) = points.last()
                && last.frame >= MAX_FRAMES
            {
                problems.add(
                    format!("flight.path.waypoints.points[{}].frame", points.len() - 1),
                    format!("{}: expected a frame below {MAX_FRAMES}", last.frame),
                );
            }
            for (k, point) in points.iter().enumerate() {
                problems.finite(
                    &format!("flight.path.waypoints.points[{k}].position_m"),
                    &point.position_m,
                );
            }
        }
        PathEntry::Recorded { .. } => {}
    }
}

fn check_pitch(field: &str, pitch_deg: f64, problems: &mut Problems) {
    if !(-90.0..=90.0).contains(&pitch_deg) {
        problems.add(
            format!("{field}.pitch_deg"),
            format!("{pitch_deg}: expected an angle from -90 to 90"),
        );
    }
}

/// An algorithm entry after sweep expansion: where it came from, for error paths.
struct ExpandedEntry {
    /// `algorithms[k]`, or `algorithms[k] (tau_px=0.5)` for a sweep point.
    origin: String,
    name: String,
    label: String,
    parameters: serde_json::Map<String, Value>,
}

/// Expands every entry's `"sweep": {"parameter": [values…], …}` into the cartesian product of
/// its lists (parameters in alphabetical order, the first one outermost); each point is an
/// entry whose label is the entry's label followed by ` parameter=value, …`.
fn expand_sweeps(entries: &[AlgorithmEntry], problems: &mut Problems) -> Vec<ExpandedEntry> {
    let mut expanded = Vec::new();
    for (k, entry) in entries.iter().enumerate() {
        let label = entry.label.clone().unwrap_or_else(|| entry.name.clone());
        let mut parameters = entry.parameters.clone();
        let Some(sweep) = parameters.remove("sweep") else {
            expanded.push(ExpandedEntry {
                origin: format!("algorithms[{k}]"),
                name: entry.name.clone(),
                label,
                parameters,
            });
            continue;
        };
        let Some(sweep) = sweep.as_object().filter(|s| !s.is_empty()) else {
            problems.add(
                format!("algorithms[{k}].sweep"),
                "expected a non-empty object of parameter lists, e.g. {\"tau_px\": [1, 2, 4]}",
            );
            continue;
        };
        let mut axes: Vec<(String, Vec<Value>)> = Vec::new();
        for (parameter, values) in sweep {
            match values.as_array().filter(|v| !v.is_empty()) {
                Some(values) if !["name", "label", "sweep"].contains(&parameter.as_str()) => {
                    axes.push((parameter.clone(), values.clone()))
                }
                _ => problems.add(
                    format!("algorithms[{k}].sweep.{parameter}"),
                    "expected a non-empty list of values of an algorithm parameter",
                ),
            }
        }
        let points: usize = axes.iter().map(|(_, v)| v.len()).product();
        if points > MAX_SWEEP_POINTS {
            problems.add(
                format!("algorithms[{k}].sweep"),
                format!("{points} points: expected at most {MAX_SWEEP_POINTS}"),
            );
            continue;
        }
        for choice in cartesian(&axes) {
            let mut parameters = parameters.clone();
            for (parameter, value) in &choice {
                parameters.insert(parameter.clone(), value.clone());
            }
            let suffix = choice_label(&choice);
            expanded.push(ExpandedEntry {
                origin: format!("algorithms[{k}] ({suffix})"),
                name: entry.name.clone(),
                label: format!("{label} {suffix}"),
                parameters,
            });
        }
    }
    expanded
}

fn check_algorithms(entries: &[AlgorithmEntry], problems: &mut Problems) -> Vec<AlgorithmSpec> {
    if entries.is_empty() {
        problems.add("algorithms", "empty: expected at least one algorithm");
    }
    let mut labels = HashSet::new();
    let mut specs = Vec::new();
    for entry in expand_sweeps(entries, problems) {
        let k = &entry.origin;
        let label = entry.label.clone();
        if label.is_empty() || label.contains(['\n', '\r']) {
            problems.add(
                format!("{k}.label"),
                format!("{label:?}: expected a non-empty, single-line label"),
            );
        } else if !labels.insert(label.clone()) {
            problems.add(
                format!("{k}.label"),
                format!(
                    "{label:?} is already used by an earlier entry: expected unique labels \
                     (give this entry a \"label\")"
                ),
            );
        }
        let parameters = Value::Object(entry.parameters.clone());
        let k = k.as_str();
        let config = match entry.name.as_str() {
            "reference" => decode::<ReferenceParameters>(k, &parameters, problems).and_then(|p| {
                check_tau(k, p.tau_px, problems)?;
                Some(AlgorithmConfig::Reference(ReferenceConfig {
                    nesting: nesting_rule(p.nesting, NestingRule::Max),
                    tau_px: p.tau_px,
                    zone: zone_variant(p.zone),
                    threshold: SplitThreshold::LifeAtMost(0.0),
                }))
            }),
            "wu" => decode::<WuParameters>(k, &parameters, problems)
                .and_then(|p| check_wu(k, &p, problems)),
            "lindstrom" => decode::<LindstromParameters>(k, &parameters, problems).and_then(|p| {
                check_tau(k, p.tau_px, problems)?;
                check_block_level(k, p.block_level, problems)?;
                Some(AlgorithmConfig::Lindstrom(LindstromConfig {
                    nesting: nesting_rule(p.nesting, NestingRule::Max),
                    tau_px: p.tau_px,
                    block_level: p.block_level,
                }))
            }),
            name @ ("roam" | "roam-rebuild") => decode::<RoamParameters>(k, &parameters, problems)
                .and_then(|p| {
                    let config = roam_config(k, &p, problems)?;
                    if name == "roam" {
                        Some(AlgorithmConfig::Roam(config))
                    } else if config.deferral {
                        problems.add(
                            format!("{k}.deferral"),
                            "true: roam-rebuild starts from scratch every frame, expected false \
                             or absent",
                        );
                        None
                    } else {
                        Some(AlgorithmConfig::RoamRebuild(config))
                    }
                }),
            "rottger" => decode::<RottgerParameters>(k, &parameters, problems)
                .and_then(|p| check_rottger(k, &p, problems)),
            other => {
                problems.add(
                    format!("{k}.name"),
                    format!(
                        "{other:?} is not an algorithm this build knows: expected one of {}",
                        KNOWN_ALGORITHMS.join(", ")
                    ),
                );
                None
            }
        };
        if let Some(config) = config {
            specs.push(AlgorithmSpec {
                label,
                config,
                parameters,
            });
        }
    }
    specs
}

fn decode<T: serde::de::DeserializeOwned>(
    origin: &str,
    parameters: &Value,
    problems: &mut Problems,
) -> Option<T> {
    serde_path_to_error::deserialize(parameters)
        .map_err(|error| {
            let inner = error.path().to_string();
            let field = if inner == "." {
                origin.to_string()
            } else {
                format!("{origin}.{inner}")
            };
            problems.add(field, error.into_inner().to_string());
        })
        .ok()
}

fn roam_config(origin: &str, p: &RoamParameters, problems: &mut Problems) -> Option<RoamConfig> {
    let goal = match (p.target_triangles, p.tau_px) {
        (Some(target), None) => RoamGoal::TargetTriangles(target),
        (None, Some(tau)) => {
            check_tau(origin, tau, problems)?;
            RoamGoal::TolerancePx(tau)
        }
        _ => {
            problems.add(
                origin.to_string(),
                "expected exactly one of \"target_triangles\" and \"tau_px\"",
            );
            return None;
        }
    };
    if p.deferral && matches!(goal, RoamGoal::TargetTriangles(_)) {
        problems.add(
            format!("{origin}.deferral"),
            "true with \"target_triangles\": deferral needs a fixed crossover, expected \
             \"tau_px\" (or no deferral)",
        );
        return None;
    }
    Some(RoamConfig {
        nesting: nesting_rule(p.nesting, NestingRule::MaxPlusOwn),
        goal,
        deferral: p.deferral,
        culling_flags: p.culling_flags,
        strips: p.strips,
    })
}

fn nesting_rule(entry: Option<NestingEntry>, default: NestingRule) -> NestingRule {
    match entry {
        None => default,
        Some(NestingEntry::Max) => NestingRule::Max,
        Some(NestingEntry::MaxPlusOwn) => NestingRule::MaxPlusOwn,
    }
}

fn check_tau(origin: &str, tau_px: f64, problems: &mut Problems) -> Option<()> {
    if tau_px >= 0.0 && tau_px.is_finite() {
        Some(())
    } else {
        problems.add(
            format!("{origin}.tau_px"),
            format!("{tau_px}: expected a finite tolerance of at least 0 pixels"),
        );
        None
    }
}

/// Defaults of Wu's optional parameters (documented in docs/experiment-format.md).
const WU_DEFAULT_BASE_LIMIT: i64 = 1000;
const WU_DEFAULT_INITIAL_TAU_K: f64 = 1.5;
const WU_DEFAULT_WHEEL_LINKS: u32 = 256;
const WU_MAX_WHEEL_LINKS: u32 = 1 << 20;

fn check_wu(origin: &str, p: &WuParameters, problems: &mut Problems) -> Option<AlgorithmConfig> {
    let field = |name: &str| format!("{origin}.{name}");
    let n_problems = problems.list.len();
    if p.tau_px.is_none() && p.budget_triangles.is_none() {
        problems.add(
            origin.to_string(),
            "neither tau_px nor budget_triangles: expected a fixed τ, a triangle budget, or both",
        );
    }
    if let Some(tau) = p.tau_px {
        check_tau(origin, tau, problems);
    }
    if p.budget_triangles == Some(0) {
        problems.add(field("budget_triangles"), "0: expected at least 1 triangle");
    }
    if p.budget_triangles.is_none() {
        for (name, given) in [
            ("dead_band_triangles", p.dead_band_triangles.is_some()),
            ("base_limit", p.base_limit.is_some()),
            ("initial_tau_k", p.initial_tau_k.is_some()),
        ] {
            if given {
                problems.add(
                    field(name),
                    "only applies with a budget: expected budget_triangles as well",
                );
            }
        }
    }
    if let Some(limit) = p.base_limit
        && limit < 0
    {
        problems.add(field("base_limit"), format!("{limit}: expected at least 0"));
    }
    if let Some(k) = p.initial_tau_k
        && !(k > 0.0 && k.is_finite())
    {
        problems.add(
            field("initial_tau_k"),
            format!("{k}: expected a finite number above 0"),
        );
    }
    let wheel_links = p.wheel_links.unwrap_or(WU_DEFAULT_WHEEL_LINKS);
    if !(2..=WU_MAX_WHEEL_LINKS).contains(&wheel_links) {
        problems.add(
            field("wheel_links"),
            format!("{wheel_links}: expected 2 to {WU_MAX_WHEEL_LINKS}"),
        );
    }
    if problems.list.len() > n_problems {
        return None;
    }
    Some(AlgorithmConfig::Wu(WuConfig {
        nesting: nesting_rule(p.nesting, NestingRule::Max),
        tau_px: p.tau_px,
        budget: p.budget_triangles.map(|triangles| BudgetConfig {
            triangles,
            dead_band: p.dead_band_triangles.unwrap_or(0),
            base_limit: p.base_limit.unwrap_or(WU_DEFAULT_BASE_LIMIT),
            initial_tau_k: p.initial_tau_k.unwrap_or(WU_DEFAULT_INITIAL_TAU_K),
        }),
        zone: zone_variant(p.zone),
        block_priority: p.block_priority.unwrap_or(false),
        depth_limit: p.depth_limit,
        cone_culling: p.cone_culling.unwrap_or(false),
        wheel_links,
    }))
}

/// Lindstrom's blocks have (2^k + 1)² samples; the largest grid has level 15.
fn check_block_level(origin: &str, block_level: u32, problems: &mut Problems) -> Option<()> {
    if (1..=15).contains(&block_level) {
        Some(())
    } else {
        problems.add(
            format!("{origin}.block_level"),
            format!(
                "{block_level}: expected a block level k from 1 to 15 (blocks of (2^k+1)² samples)"
            ),
        );
        None
    }
}

/// Röttger's parameters: C ≥ 2 (the paper's K bound), c ≥ 0 fixed or > 0 as a load target's
/// start (default 1), at most one target of at least 1.
fn check_rottger(
    origin: &str,
    p: &RottgerParameters,
    problems: &mut Problems,
) -> Option<AlgorithmConfig> {
    use crate::sim::algorithm::rottger::{DistanceNorm, LoadCount, LoadTarget};
    let field = |name: &str| format!("{origin}.{name}");
    let n_problems = problems.list.len();
    let minimum = p.minimum_resolution;
    if !(minimum >= 2.0 && minimum.is_finite()) {
        problems.add(
            field("minimum_resolution"),
            format!(
                "{minimum}: expected a finite C of at least 2 (the paper's K = C/(2(C-1)) needs it)"
            ),
        );
    }
    let both_targets = p.target_triangles.is_some() && p.target_fan_vertices.is_some();
    let load = match (p.target_triangles, p.target_fan_vertices) {
        (Some(_), Some(_)) => {
            problems.add(
                origin.to_string(),
                "both target_triangles and target_fan_vertices: expected at most one load target",
            );
            None
        }
        (Some(target), None) => Some(LoadTarget {
            count: LoadCount::Triangles,
            target,
        }),
        (None, Some(target)) => Some(LoadTarget {
            count: LoadCount::FanVertices,
            target,
        }),
        (None, None) => None,
    };
    if let Some(load) = load
        && load.target == 0
    {
        let name = match load.count {
            LoadCount::Triangles => "target_triangles",
            LoadCount::FanVertices => "target_fan_vertices",
        };
        problems.add(field(name), "0: expected a target of at least 1");
    }
    let desired = match (p.desired_resolution, load) {
        (Some(c), None) if !(c >= 0.0 && c.is_finite()) => {
            problems.add(
                field("desired_resolution"),
                format!("{c}: expected a finite c of at least 0"),
            );
            c
        }
        (Some(c), Some(_)) if !(c > 0.0 && c.is_finite()) => {
            problems.add(
                field("desired_resolution"),
                format!("{c}: expected a finite starting c above 0 for the load target"),
            );
            c
        }
        (Some(c), _) => c,
        (None, Some(_)) => ROTTGER_DEFAULT_START_C,
        (None, None) if both_targets => 0.0,
        (None, None) => {
            problems.add(
                origin.to_string(),
                "neither desired_resolution nor a load target: expected a fixed c, \
                 target_triangles or target_fan_vertices",
            );
            0.0
        }
    };
    if problems.list.len() > n_problems {
        return None;
    }
    Some(AlgorithmConfig::Rottger(RottgerConfig {
        minimum_resolution: minimum,
        desired_resolution: desired,
        load,
        distance: match p.distance {
            None | Some(DistanceEntry::L1) => DistanceNorm::L1,
            Some(DistanceEntry::Euclidean) => DistanceNorm::Euclidean,
        },
        d2_propagation: p.d2_propagation,
        clipping: p.clipping,
        geomorphing: p.geomorphing,
    }))
}

/// The c a load target starts from when the entry gives none (documented in
/// docs/experiment-format.md).
const ROTTGER_DEFAULT_START_C: f64 = 1.0;

fn zone_variant(zone: Option<ZoneEntry>) -> ZoneVariant {
    match zone {
        Some(ZoneEntry::Paper) => ZoneVariant::Paper,
        Some(ZoneEntry::Conservative) | None => ZoneVariant::Conservative,
    }
}

fn path_kind(path: &PathEntry) -> &'static str {
    match path {
        PathEntry::Circle { .. } => "circle",
        PathEntry::Orbit { .. } => "orbit",
        PathEntry::Line { .. } => "line",
        PathEntry::Spiral { .. } => "spiral",
        PathEntry::Waypoints { .. } => "waypoints",
        PathEntry::Recorded { .. } => "recorded",
    }
}

/// Stage 3a: the terrain, read or generated, filled and embedded.
fn load_terrain(
    experiment: &Path,
    folder: &Path,
    entry: &TerrainEntry,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
    match entry {
        TerrainEntry::Synthetic(s) => {
            let spacing = Spacing {
                dx: s.spacing_m.dx,
                dy: s.spacing_m.dy,
            };
            // Diamond-square's displacement at a cell of length L is amplitude · (L / extent)^H;
            // anchoring it at `amplitude_scale_m` instead scales the top amplitude.
            let extent_m = (1u64 << s.level) as f64 * spacing.dx;
            let amplitude = match s.amplitude_scale_m {
                Some(scale) => s.amplitude_m * (extent_m / scale).powf(s.roughness),
                None => s.amplitude_m,
            };
            let field = generate(&SyntheticTerrain {
                level: s.level,
                seed: s.seed,
                amplitude,
                roughness: s.roughness,
                spacing,
            })
            .map_err(|e| ExperimentError::single(experiment, "terrain.synthetic", e.to_string()))?
            .with_origin(origin(s.origin_m));
            let (lo, hi) = field.height_range();
            let side = field.side();
            let report = TerrainReport {
                source: format!("synthetic (diamond-square, seed {})", s.seed),
                format: "synthetic".to_string(),
                source_columns: side,
                source_rows: side,
                side,
                padded_columns: 0,
                padded_rows: 0,
                crop_origin: None,
                voids_filled: 0,
                spacing,
                spacing_from: "synthetic",
                height_min_m: lo,
                height_max_m: hi,
            };
            Ok((field, report))
        }
        TerrainEntry::File(file) => {
            let path = folder.join(&file.path);
            let field_error =
                |problem: String| ExperimentError::single(experiment, "terrain.file", problem);
            let format = match &file.format {
                None => format_from_extension(&path).map_err(|e| field_error(e.to_string()))?,
                Some(TerrainFormatEntry::Hgt) => TerrainFormat::Hgt,
                Some(TerrainFormatEntry::Png) => TerrainFormat::Png,
                Some(TerrainFormatEntry::Geotiff) => TerrainFormat::GeoTiff,
                Some(TerrainFormatEntry::AsciiGrid) => TerrainFormat::AsciiGrid,
                Some(TerrainFormatEntry::Raw(raw)) => TerrainFormat::Raw(RawLayout {
                    columns: raw.columns,
                    rows: raw.rows,
                    sample: raw_sample(raw.sample),
                    north_first: raw.north_first,
                }),
            };
            let options = ReadOptions {
                height_scale: file.height_scale.unwrap_or(1.0),
                height_offset: file.height_offset_m.unwrap_or(0.0),
                nodata: file.nodata,
            };
            let loaded =
                read_terrain(&path, format, &options).map_err(|e| field_error(e.to_string()))?;
            let (spacing, spacing_from) = match (file.spacing_m, loaded.spacing) {
                (Some(s), _) => (Spacing { dx: s.dx, dy: s.dy }, "experiment"),
                (None, Some(s)) => (s, "file"),
                (None, None) => {
                    return Err(ExperimentError::single(
                        experiment,
                        "terrain.file.spacing_m",
                        format!(
                            "{} does not declare its grid spacing: expected spacing_m {{dx, dy}} in metres",
                            path.display()
                        ),
                    ));
                }
            };
            let (source_columns, source_rows) = (loaded.grid.width(), loaded.grid.height());
            let (filled, fill) = fill_voids(loaded.grid)
                .map_err(|e| field_error(format!("{}: {e}", path.display())))?;
            let fit = match file.fit {
                FitEntry::Pad => Fit::Pad,
                FitEntry::Crop => Fit::Crop {
                    origin: file.crop_origin.map(|[i, j]| (i, j)),
                },
            };
            let (field, embedded) = embed(&filled, fit, spacing)
                .map_err(|e| field_error(format!("{}: {e}", path.display())))?;
            let field = field.with_origin(origin(file.origin_m));
            let (lo, hi) = field.height_range();
            let report = TerrainReport {
                source: file.path.clone(),
                format: format_name(format).to_string(),
                source_columns,
                source_rows,
                side: field.side(),
                padded_columns: embedded.padded_columns,
                padded_rows: embedded.padded_rows,
                crop_origin: embedded.crop_origin,
                voids_filled: fill.voids_filled,
                spacing,
                spacing_from,
                height_min_m: lo,
                height_max_m: hi,
            };
            Ok((field, report))
        }
    }
}

fn origin(origin_m: Option<[f64; 3]>) -> DVec3 {
    origin_m.map_or(DVec3::ZERO, |[x, y, z]| DVec3::new(x, y, z))
}

fn raw_sample(sample: RawSampleEntry) -> RawSample {
    match sample {
        RawSampleEntry::I16le => RawSample::I16Le,
        RawSampleEntry::I16be => RawSample::I16Be,
        RawSampleEntry::U16le => RawSample::U16Le,
        RawSampleEntry::U16be => RawSample::U16Be,
        RawSampleEntry::F32le => RawSample::F32Le,
        RawSampleEntry::F32be => RawSample::F32Be,
    }
}

fn format_name(format: TerrainFormat) -> &'static str {
    match format {
        TerrainFormat::Hgt => "hgt",
        TerrainFormat::Png => "png",
        TerrainFormat::GeoTiff => "geotiff",
        TerrainFormat::AsciiGrid => "ascii_grid",
        TerrainFormat::Raw(_) => "raw",
    }
}

/// Stage 3b: the flight, with a recorded log read from its file.
fn build_flight(
    experiment: &Path,
    folder: &Path,
    entry: &FlightEntry,
) -> Result<Flight, ExperimentError> {
    let v2 = |a: [f64; 2]| DVec2::new(a[0], a[1]);
    let v3 = |a: [f64; 3]| DVec3::new(a[0], a[1], a[2]);
    let mut look = match entry.look {
        Some(LookEntry::AlongPath { pitch_deg }) => Look::AlongPath {
            pitch: pitch_deg.to_radians(),
        },
        Some(LookEntry::At { target_m }) => Look::At {
            target: v3(target_m),
        },
        Some(LookEntry::Fixed { yaw_deg, pitch_deg }) => Look::Fixed {
            yaw: yaw_deg.to_radians(),
            pitch: pitch_deg.to_radians(),
        },
        None => Look::Fixed {
            yaw: 0.0,
            pitch: 0.0,
        },
    };
    let path = match &entry.path {
        PathEntry::Circle {
            centre_m,
            radius_m,
            altitude_m,
            frames_per_lap,
            phase_deg,
        }
        | PathEntry::Orbit {
            centre_m,
            radius_m,
            altitude_m,
            frames_per_lap,
            phase_deg,
            ..
        } => {
            if let PathEntry::Orbit { target_m, .. } = &entry.path {
                look = Look::At {
                    target: v3(*target_m),
                };
            }
            FlightPath::Circle {
                centre: v2(*centre_m),
                radius: *radius_m,
                altitude: *altitude_m,
                frames_per_lap: *frames_per_lap,
                phase: phase_deg.to_radians(),
            }
        }
        PathEntry::Line { from_m, to_m } => FlightPath::Line {
            from: v3(*from_m),
            to: v3(*to_m),
        },
        PathEntry::Spiral {
            centre_m,
            radius_start_m,
            radius_end_m,
            altitude_start_m,
            altitude_end_m,
            turns,
            phase_deg,
        } => FlightPath::Spiral {
            centre: v2(*centre_m),
            radius_start: *radius_start_m,
            radius_end: *radius_end_m,
            altitude_start: *altitude_start_m,
            altitude_end: *altitude_end_m,
            turns: *turns,
            phase: phase_deg.to_radians(),
        },
        PathEntry::Waypoints {
            points,
            interpolation,
        } => FlightPath::Waypoints {
            points: points
                .iter()
                .map(|w| Waypoint {
                    frame: w.frame,
                    position: v3(w.position_m),
                })
                .collect(),
            interpolation: match interpolation {
                InterpolationEntry::Linear => Interpolation::Linear,
                InterpolationEntry::CatmullRom => Interpolation::CatmullRom,
            },
        },
        PathEntry::Recorded { path } => {
            let poses = read_flight_log(&folder.join(path)).map_err(|e| {
                ExperimentError::single(experiment, "flight.path.recorded.path", e.to_string())
            })?;
            FlightPath::Recorded { poses }
        }
    };
    Flight::new(&path, &look, entry.frames.unwrap_or(0))
        .map_err(|e| ExperimentError::single(experiment, "flight", e.to_string()))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}
