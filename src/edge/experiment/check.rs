//! Checking an experiment's meaning (stage 2): every semantic problem of the parsed file, each
//! with its field path, collected at once; the checked view, speed bounds, algorithm
//! configurations, effects and mesh exports. No IO: nothing is read, generated or built here.
//!
//! "Checking" is what this module does to an experiment file; "validating" in this crate means
//! the mesh validators of `sim::mesh::validate` and `sim::mesh::list_validate` (and the
//! algorithms' own), run by `--check`.

use super::format::{
    AlgorithmEntry, AltitudeEntry, DistanceEntry, ExperimentFile, FORMAT_VERSION, FitEntry,
    FlightEntry, LindstromParameters, LookEntry, MeshesEntry, NestingEntry, PathEntry,
    ReferenceParameters, RefineEntry, RoamParameters, RottgerParameters, TerrainEntry,
    TerrainFormatEntry, WuParameters, ZoneEntry,
};
use super::load::{AlgorithmSpec, MeshExports};
use super::sweep::{MAX_SWEEP_POINTS, cartesian, choice_label};
use super::tune::check_tune;
use super::{ExperimentError, FieldProblem};
use crate::sim::algorithm::{
    AlgorithmConfig, BudgetConfig, LindstromConfig, ReferenceConfig, Refinement, RoamConfig,
    RoamGoal, RottgerConfig, SplitThreshold, TauRecentring, ViewThreshold, WuConfig,
};
use crate::sim::audit::AuditSettings;
use crate::sim::hierarchy::NestingRule;
use crate::sim::run::Effects;
use crate::sim::view::ViewSettings;
use crate::sim::zone::{SpeedBound, ZoneVariant};
use serde_json::Value;
use std::collections::HashSet;
use std::path::Path;

/// Algorithms this build knows, as the experiment file names them.
pub const KNOWN_ALGORITHMS: &[&str] = &[
    "reference",
    "wu",
    "lindstrom",
    "roam",
    "roam-rebuild",
    "geomipmap",
    "chunked",
    "rottger",
    "vanek",
    "stitching-strips",
];

/// What stage 2 makes of a parsed file: the checked settings and entries.
pub(super) struct Checked {
    pub(super) view: ViewSettings,
    pub(super) speed: SpeedBound,
    pub(super) algorithms: Vec<AlgorithmSpec>,
    pub(super) effects: Effects,
    pub(super) mesh_exports: Option<MeshExports>,
    pub(super) max_triangles: u64,
}

/// Stage 2: every semantic problem, with its field path.
pub(super) fn check(path: &Path, file: &ExperimentFile) -> Result<Checked, ExperimentError> {
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
    if let Some(rotation) = bounds.rotation_rad_per_frame {
        problems.non_negative("speed_bounds.rotation_rad_per_frame", rotation);
    }
    check_flight(&file.flight, &mut problems);
    let algorithms = check_algorithms(
        &file.algorithms,
        file.effects.audit.is_some(),
        &mut problems,
    );
    if let Some(audit) = &file.effects.audit {
        problems.positive_int("effects.audit.stride", audit.stride);
        if let Some(detail_stride) = audit.detail_stride {
            problems.positive_int("effects.audit.detail_stride", detail_stride);
        }
    }
    let max_triangles = match file.limits.max_triangles {
        Some(0) => {
            problems.add(
                "limits.max_triangles",
                "0: expected at least 1 (leave it out for the default of 2000000)",
            );
            0
        }
        Some(limit) => limit,
        None => super::format::DEFAULT_MAX_TRIANGLES,
    };
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
            rotation: bounds
                .rotation_rad_per_frame
                .unwrap_or(SpeedBound::NO_ROTATION_BOUND),
        },
        algorithms,
        effects: Effects {
            audit: file.effects.audit.as_ref().map(|a| AuditSettings {
                stride: a.stride,
                popping: a.popping,
                detail_stride: a.detail_stride,
            }),
            culling: file.effects.culling,
            check_meshes: false,
        },
        mesh_exports,
        max_triangles,
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
pub(super) struct Problems {
    pub(super) list: Vec<FieldProblem>,
}

impl Problems {
    pub(super) fn add(&mut self, field: impl Into<String>, problem: impl Into<String>) {
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
    if flight.altitude == Some(AltitudeEntry::AboveGround)
        && matches!(flight.path, PathEntry::Recorded { .. })
    {
        problems.add(
            "flight.altitude",
            "a recorded flight brings its own world heights: expected \"absolute\" or no altitude field",
        );
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
        let tuned = parameters
            .get("tune")
            .and_then(|tune| super::tune::tuned_parameter(&entry.name, tune));
        let mut axes: Vec<(String, Vec<Value>)> = Vec::new();
        for (parameter, values) in sweep {
            if parameter == "tune" || Some(parameter.as_str()) == tuned {
                problems.add(
                    format!("algorithms[{k}].sweep.{parameter}"),
                    if parameter == "tune" {
                        "tune cannot be swept: expected one entry per target".to_string()
                    } else {
                        format!(
                            "the entry's tune sets {parameter}, so a sweep of it would run the \
                             value found, not the value in the label: expected it swept without \
                             tune, or tune without the sweep"
                        )
                    },
                );
                continue;
            }
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

fn check_algorithms(
    entries: &[AlgorithmEntry],
    audited: bool,
    problems: &mut Problems,
) -> Vec<AlgorithmSpec> {
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
        let mut written = entry.parameters.clone();
        let tune = written
            .remove("tune")
            .and_then(|tune| check_tune(k, &entry.name, &tune, &mut written, audited, problems));
        let parameters = Value::Object(written);
        let config = entry_config(k, &entry.name, &parameters, problems);
        if let Some(config) = config {
            specs.push(AlgorithmSpec {
                label,
                config,
                parameters,
                tune,
            });
        }
    }
    specs
}

/// The configuration of the entry at `origin` for algorithm `name` with `parameters` (as
/// written, `tune` taken out), or `None` with its problems added.
pub(super) fn entry_config(
    k: &str,
    name: &str,
    parameters: &Value,
    problems: &mut Problems,
) -> Option<AlgorithmConfig> {
    match name {
        "reference" => decode::<ReferenceParameters>(k, parameters, problems).and_then(|p| {
            check_tau(k, p.tau_px, problems)?;
            Some(AlgorithmConfig::Reference(ReferenceConfig {
                nesting: nesting_rule(p.nesting, NestingRule::Max),
                tau_px: p.tau_px,
                zone: zone_variant(p.zone),
                threshold: SplitThreshold::LifeAtMost(0.0),
                refine: refinement(p.refine.unwrap_or(RefineEntry::Everywhere)),
                view_threshold: ViewThreshold::InView,
            }))
        }),
        "wu" => {
            decode::<WuParameters>(k, parameters, problems).and_then(|p| check_wu(k, &p, problems))
        }
        "lindstrom" => decode::<LindstromParameters>(k, parameters, problems).and_then(|p| {
            check_tau(k, p.tau_px, problems)?;
            check_block_level(k, p.block_level, problems)?;
            Some(AlgorithmConfig::Lindstrom(LindstromConfig {
                nesting: nesting_rule(p.nesting, NestingRule::Max),
                tau_px: p.tau_px,
                block_level: p.block_level,
            }))
        }),
        name @ ("roam" | "roam-rebuild") => decode::<RoamParameters>(k, parameters, problems)
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
        "geomipmap" => super::block_lod::geomipmap_config(k, parameters)
            .map_err(|list| problems.list.extend(list))
            .ok(),
        "chunked" => super::block_lod::chunked_config(k, parameters)
            .map_err(|list| problems.list.extend(list))
            .ok(),
        "vanek" => super::block_lod::vanek_config(k, parameters)
            .map_err(|list| problems.list.extend(list))
            .ok(),
        "stitching-strips" => super::block_lod::stitching_config(k, parameters)
            .map_err(|list| problems.list.extend(list))
            .ok(),
        "rottger" => decode::<RottgerParameters>(k, parameters, problems)
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
    }
}

pub(super) fn decode<T: serde::de::DeserializeOwned>(
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
        (Some(0), None) => {
            problems.add(
                format!("{origin}.target_triangles"),
                "0: expected at least 1 triangle",
            );
            return None;
        }
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
    Some(RoamConfig {
        nesting: nesting_rule(p.nesting, NestingRule::MaxPlusOwn),
        thickness: roam_thickness(p.thickness),
        queue: roam_queue(p.queue),
        goal,
        deferral: p.deferral,
        culling_flags: p.culling_flags,
        strips: p.strips,
    })
}

/// ROAM's thickness scope: per triangle (eq. 1) unless the entry says otherwise.
fn roam_thickness(
    entry: Option<super::format::ThicknessEntry>,
) -> crate::sim::algorithm::ThicknessScope {
    use super::format::ThicknessEntry;
    use crate::sim::algorithm::ThicknessScope;
    match entry {
        None | Some(ThicknessEntry::PerTriangle) => ThicknessScope::PerTriangle,
        Some(ThicknessEntry::PerVertex) => ThicknessScope::PerVertex,
    }
}

/// ROAM's queues: Duchaineau's buckets unless the entry says otherwise.
fn roam_queue(entry: Option<super::format::QueueEntry>) -> crate::sim::algorithm::QueueKind {
    use super::format::QueueEntry;
    use crate::sim::algorithm::QueueKind;
    match entry {
        None | Some(QueueEntry::Buckets) => QueueKind::Buckets,
        Some(QueueEntry::Heap) => QueueKind::Heap,
    }
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
const WU_DEFAULT_RECENTRE_TAU_WINDOW_FRAMES: u32 = 16;
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
    // `refine` defaults to the paper's in-view refinement when the entry culls by the cone, and
    // `cone_culling` to on when the entry refines in view (the paper's budget counts what is in
    // view; `cone_culling: false` with `in_view` counts the whole mesh).
    let refine = p.refine.unwrap_or(if p.cone_culling == Some(true) {
        RefineEntry::InView
    } else {
        RefineEntry::Everywhere
    });
    let cone_culling = p.cone_culling.unwrap_or(refine == RefineEntry::InView);
    let recentre_tau = p.recentre_tau.unwrap_or(false);
    if recentre_tau && p.budget_triangles.is_none() {
        problems.add(
            field("recentre_tau"),
            "true without a budget: re-centring moves τ to keep b near 0, expected \
             budget_triangles as well",
        );
    }
    if let Some(window) = p.recentre_tau_window_frames {
        if !recentre_tau {
            problems.add(
                field("recentre_tau_window_frames"),
                "only applies with recentre_tau: expected \"recentre_tau\": true as well",
            );
        } else if window == 0 {
            problems.add(
                field("recentre_tau_window_frames"),
                "0: expected at least 1",
            );
        }
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
            tau_recentring: recentre_tau.then(|| TauRecentring {
                window_frames: p
                    .recentre_tau_window_frames
                    .unwrap_or(WU_DEFAULT_RECENTRE_TAU_WINDOW_FRAMES),
            }),
        }),
        zone: zone_variant(p.zone),
        block_priority: p.block_priority.unwrap_or(false),
        depth_limit: p.depth_limit,
        cone_culling,
        refine: refinement(refine),
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

fn refinement(refine: RefineEntry) -> Refinement {
    match refine {
        RefineEntry::InView => Refinement::InView,
        RefineEntry::Everywhere => Refinement::Everywhere,
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

pub(super) fn path_kind(path: &PathEntry) -> &'static str {
    match path {
        PathEntry::Circle { .. } => "circle",
        PathEntry::Orbit { .. } => "orbit",
        PathEntry::Line { .. } => "line",
        PathEntry::Spiral { .. } => "spiral",
        PathEntry::Waypoints { .. } => "waypoints",
        PathEntry::Recorded { .. } => "recorded",
    }
}
