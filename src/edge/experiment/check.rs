//! Checking an experiment's meaning (stage 2): every semantic problem of the parsed file, each
//! with its field path, collected at once; the checked view, speed bounds, algorithm
//! configurations, effects and mesh exports. No IO: nothing is read, generated or built here.
//! The whole file's fields are checked here; its algorithm entries in `entries.rs` (and the
//! modules below it), which this calls and which never call back.
//!
//! "Checking" is what this module does to an experiment file; "validating" in this crate means
//! the mesh validators of `sim::mesh::validate` and `sim::mesh::list_validate` (and the
//! algorithms' own), run by `--check`.
//!
//! **What needs the built flight waits for it.** Frames past the flight's end (mesh exports,
//! the warm-up) and the flight against the speed bounds are checked once the flight is built
//! (stage 3, `plan.rs`'s `Plan::load_point`): a recorded flight's frame count is known only then.

use super::entries::{AlgorithmSpec, check_algorithms};
use super::format::{
    AltitudeEntry, DEFAULT_MAX_TRIANGLES, EffectsEntry, ExperimentFile, FORMAT_VERSION, FitEntry,
    FlightEntry, LookEntry, MeshesEntry, MosaicFormatEntry, PathEntry, SpacingEntry,
    SpeedBoundsEntry, TerrainEntry, TerrainFormatEntry, TerrainMosaicEntry, ViewEntry,
    WaypointEntry,
};
use super::problems::{ExperimentError, Problems};
use crate::sim::audit::AuditSettings;
use crate::sim::run::Effects;
use crate::sim::view::ViewSettings;
use std::path::Path;

/// What stage 2 makes of a parsed file: the checked settings and entries.
pub(super) struct Checked {
    pub(super) view: ViewSettings,
    pub(super) speed: DeclaredSpeedBounds,
    pub(super) algorithms: Vec<AlgorithmSpec>,
    pub(super) effects: Effects,
    pub(super) mesh_exports: Option<MeshExports>,
    pub(super) max_triangles: u64,
}

/// Stage 2: every semantic problem, with its field path.
pub(super) fn check(path: &Path, file: &ExperimentFile) -> Result<Checked, ExperimentError> {
    let mut problems = Problems::default();
    check_version_and_name(file, &mut problems);
    check_terrain(&file.terrain, &mut problems);
    let view = check_view(&file.view, &mut problems);
    let speed = check_speed_bounds(&file.speed_bounds, &mut problems);
    check_flight(&file.flight, &mut problems);
    let algorithms = check_algorithms(
        &file.algorithms,
        file.effects.audit.is_some(),
        &mut problems,
    );
    let effects = check_effects(&file.effects, &mut problems);
    let max_triangles = match file.limits.max_triangles {
        Some(0) => {
            problems.add(
                "limits.max_triangles",
                "0: expected at least 1 (leave it out for the default of 2000000)",
            );
            0
        }
        Some(limit) => limit,
        None => DEFAULT_MAX_TRIANGLES,
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
        view,
        speed,
        algorithms,
        effects,
        mesh_exports,
        max_triangles,
    })
}

/// `format_version`: the one this build reads; `name`: a folder name (it names the output
/// folder).
fn check_version_and_name(file: &ExperimentFile, problems: &mut Problems) {
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
}

/// `view`: a screen of at least one pixel, an angle strictly between 0 and 180 degrees, a near
/// plane above 0 and a finite far plane beyond it.
fn check_view(view: &ViewEntry, problems: &mut Problems) -> ViewSettings {
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
    ViewSettings {
        width_px: view.width_px,
        height_px: view.height_px,
        fovy: view.fovy_deg.to_radians(),
        near: view.near_m,
        far: view.far_m,
    }
}

/// `speed_bounds` as the file declares them, checked. The rotation bound may be absent: load
/// derives it from the flight (`load.rs`, [`DeclaredSpeedBounds::for_flight`]), which this stage
/// has not built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct DeclaredSpeedBounds {
    pub(super) horizontal: f64,
    pub(super) vertical: f64,
    pub(super) rotation: Option<f64>,
}

/// `speed_bounds`: finite and at least 0; the rotation bound left absent when none is given.
fn check_speed_bounds(bounds: &SpeedBoundsEntry, problems: &mut Problems) -> DeclaredSpeedBounds {
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
    DeclaredSpeedBounds {
        horizontal: bounds.horizontal_m_per_frame,
        vertical: bounds.vertical_m_per_frame,
        rotation: bounds.rotation_rad_per_frame,
    }
}

/// `effects`: the audit's strides at least 1. Mesh checks are the command line's (`--check`),
/// off here.
fn check_effects(effects: &EffectsEntry, problems: &mut Problems) -> Effects {
    if let Some(audit) = &effects.audit {
        problems.positive_int("effects.audit.stride", audit.stride);
        if let Some(detail_stride) = audit.detail_stride {
            problems.positive_int("effects.audit.detail_stride", detail_stride);
        }
    }
    Effects {
        audit: effects.audit.as_ref().map(|a| AuditSettings {
            stride: a.stride,
            popping: a.popping,
            detail_stride: a.detail_stride,
        }),
        culling: effects.culling,
        check_meshes: false,
    }
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

/// Which entries' meshes to export at which frames, checked: every frame inside the flight,
/// every entry an index into [`Experiment::algorithms`](super::Experiment::algorithms); both
/// sorted, without repeats.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshExports {
    pub frames: Vec<u64>,
    pub entries: Vec<usize>,
}

pub(super) fn check_terrain(terrain: &TerrainEntry, problems: &mut Problems) {
    match terrain {
        TerrainEntry::File(file) => {
            check_grid_keys(
                "terrain.file",
                &GridKeys {
                    height_scale: file.height_scale,
                    height_offset_m: file.height_offset_m,
                    origin_m: file.origin_m,
                    spacing_m: file.spacing_m,
                    fit: file.fit,
                    crop_origin: file.crop_origin,
                },
                problems,
            );
            if matches!(file.format, Some(TerrainFormatEntry::Gdal)) {
                require_gdal_feature("terrain.file.format", problems);
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
        TerrainEntry::Mosaic(mosaic) => {
            check_grid_keys(
                "terrain.mosaic",
                &GridKeys {
                    height_scale: mosaic.height_scale,
                    height_offset_m: mosaic.height_offset_m,
                    origin_m: mosaic.origin_m,
                    spacing_m: mosaic.spacing_m,
                    fit: mosaic.fit,
                    crop_origin: mosaic.crop_origin,
                },
                problems,
            );
            check_mosaic_files(mosaic, problems);
        }
        TerrainEntry::Pyramid(pyramid) => {
            if pyramid.file.is_empty() {
                problems.add(
                    "terrain.pyramid.file",
                    "empty: expected a pyramid file that `roamsim prepare` wrote",
                );
            }
            if let Some(origin) = pyramid.origin_m {
                problems.finite("terrain.pyramid.origin_m", &origin);
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

/// The keys `file` and `mosaic` share: those that apply to a whole grid.
struct GridKeys {
    height_scale: Option<f64>,
    height_offset_m: Option<f64>,
    origin_m: Option<[f64; 3]>,
    spacing_m: Option<SpacingEntry>,
    fit: FitEntry,
    crop_origin: Option<[usize; 2]>,
}

/// `terrain.file` or `terrain.mosaic` (`prefix`): the keys that apply to a whole grid.
fn check_grid_keys(prefix: &str, keys: &GridKeys, problems: &mut Problems) {
    if let Some(scale) = keys.height_scale
        && !(scale.is_finite() && scale != 0.0)
    {
        problems.add(
            format!("{prefix}.height_scale"),
            format!("{scale}: expected a finite, non-zero number of metres per unit"),
        );
    }
    if let Some(offset) = keys.height_offset_m {
        problems.finite(&format!("{prefix}.height_offset_m"), &[offset]);
    }
    if let Some(origin) = keys.origin_m {
        problems.finite(&format!("{prefix}.origin_m"), &origin);
    }
    if let Some(spacing) = keys.spacing_m {
        problems.positive(&format!("{prefix}.spacing_m.dx"), spacing.dx);
        problems.positive(&format!("{prefix}.spacing_m.dy"), spacing.dy);
    }
    if keys.crop_origin.is_some() && matches!(keys.fit, FitEntry::Pad) {
        problems.add(
            format!("{prefix}.crop_origin"),
            "a crop origin was given but fit is \"pad\": expected fit \"crop\"",
        );
    }
}

/// `terrain.mosaic`'s files, as far as their names tell (the files themselves are laid out
/// when the plan is made, `plan.rs`): a list or a folder, tiles of one kind, a VRT alone.
fn check_mosaic_files(mosaic: &TerrainMosaicEntry, problems: &mut Problems) {
    if mosaic.format == Some(MosaicFormatEntry::Gdal) {
        require_gdal_feature("terrain.mosaic.format", problems);
        if mosaic.folder.is_some() {
            problems.add(
                "terrain.mosaic.folder",
                "a \"gdal\" mosaic lists its files (GDAL opens files of any name): expected files",
            );
        }
        if mosaic.files.as_ref().is_some_and(Vec::is_empty) {
            problems.add("terrain.mosaic.files", "empty: expected at least one file");
        }
        return;
    }
    let files = match (&mosaic.files, &mosaic.folder) {
        (Some(_), Some(_)) => {
            problems.add(
                "terrain.mosaic",
                "both files and folder were given: expected one of them",
            );
            return;
        }
        (None, None) => {
            problems.add(
                "terrain.mosaic",
                "neither files nor folder was given: expected a list of tiles or a folder of them",
            );
            return;
        }
        (None, Some(folder)) => {
            if folder.is_empty() {
                problems.add(
                    "terrain.mosaic.folder",
                    "empty: expected a folder (\".\" for the experiment's own)",
                );
            }
            return;
        }
        (Some(files), None) => files,
    };
    if files.is_empty() {
        problems.add(
            "terrain.mosaic.files",
            "empty: expected at least one tile (or one .vrt)",
        );
        return;
    }
    let kind = |file: &str| {
        let extension = Path::new(file)
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("hgt") => Some("hgt"),
            Some("tif" | "tiff") => Some("tif"),
            Some("vrt") => Some("vrt"),
            _ => None,
        }
    };
    let mut first_kind: Option<(usize, &str)> = None;
    for (k, file) in files.iter().enumerate() {
        let field = format!("terrain.mosaic.files[{k}]");
        let Some(this_kind) = kind(file) else {
            problems.add(
                field,
                format!(
                    "'{file}': expected .hgt (SRTM) or .tif/.tiff (GeoTIFF) tiles, or a single \
                     .vrt"
                ),
            );
            continue;
        };
        if let Some(j) = files[..k].iter().position(|earlier| earlier == file) {
            problems.add(
                field,
                format!("'{file}' is listed twice (also files[{j}]): expected each tile once"),
            );
            continue;
        }
        match first_kind {
            None => first_kind = Some((k, this_kind)),
            Some(_) if this_kind == "vrt" || first_kind.is_some_and(|(_, kind)| kind == "vrt") => {
                problems.add(
                    field,
                    format!("'{file}': a .vrt is a whole mosaic: expected it alone in files"),
                );
            }
            Some((j, kind)) if kind != this_kind => problems.add(
                field,
                format!(
                    "'{file}' is not in the format of files[{j}] ('{}'): expected tiles of one \
                     format, all .hgt or all .tif (a .vrt can combine them)",
                    files[j]
                ),
            ),
            Some(_) => {}
        }
    }
}

/// `"format": "gdal"` needs a build with the `gdal` feature.
fn require_gdal_feature(field: &str, problems: &mut Problems) {
    if !cfg!(feature = "gdal") {
        problems.add(
            field,
            "\"gdal\": this roamsim was built without GDAL: expected another format, or a build \
             with `cargo build --release --features gdal` (needs the system's libgdal)",
        );
    }
}

/// Longest flight accepted, in frames (beyond it the pose table alone needs gigabytes).
const MAX_FRAMES: u64 = 20_000_000;

/// `flight`: a frame count where the path does not bring its own, an altitude mode and a look
/// direction that fit the path, then the path itself.
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
    if flight.first_frames == Some(0) {
        problems.add(
            "flight.first_frames",
            "0: expected at least 1 frame (leave it out to fly the whole flight)",
        );
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
    check_path(&flight.path, problems);
}

/// `flight.path`: finite positions and angles, radii at least 0, laps of more than 0 frames,
/// waypoints in frame order.
fn check_path(path: &PathEntry, problems: &mut Problems) {
    match path {
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
            let kind = path_kind(path);
            problems.finite(&format!("flight.path.{kind}.centre_m"), centre_m);
            problems.non_negative(&format!("flight.path.{kind}.radius_m"), *radius_m);
            problems.finite(&format!("flight.path.{kind}.altitude_m"), &[*altitude_m]);
            problems.positive(
                &format!("flight.path.{kind}.frames_per_lap"),
                *frames_per_lap,
            );
            problems.finite(&format!("flight.path.{kind}.phase_deg"), &[*phase_deg]);
            if let PathEntry::Orbit { target_m, .. } = path {
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
        PathEntry::Waypoints { points, .. } => check_waypoints(points, problems),
        PathEntry::Recorded { .. } => {}
    }
}

/// A waypoint path: at least two waypoints, the first at frame 0, frames increasing and below
/// the longest flight, finite positions.
fn check_waypoints(points: &[WaypointEntry], problems: &mut Problems) {
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

fn check_pitch(field: &str, pitch_deg: f64, problems: &mut Problems) {
    if !(-90.0..=90.0).contains(&pitch_deg) {
        problems.add(
            format!("{field}.pitch_deg"),
            format!("{pitch_deg}: expected an angle from -90 to 90"),
        );
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
