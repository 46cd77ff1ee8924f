//! Loading a checked experiment (stage 3, the IO; SPEC §8): reading or generating the terrain
//! (one file, or a mosaic of files laid out first: [`lay_out_terrain_mosaic`]), filling its
//! voids and embedding it, reading a recorded flight log and building the flight.
//! Also the runnable [`Experiment`] this produces. Not the checks of the file's meaning (stage 2,
//! `check.rs`), which have all passed before anything here runs; reading stops at the first
//! problem.
//!
//! **An undeclared rotation bound is the flight's own largest turn.** An experiment without
//! `speed_bounds.rotation_rad_per_frame` gets, once its flight is built, the largest angle
//! between consecutive look directions ([`largest_turn`], the angle the motion check measures;
//! 0 for a flight that never turns), and [`Experiment::rotation_bound`] records that it was
//! [`BoundOrigin::Derived`] so that summary.json, report.md and `validate` say so. It is derived
//! whenever the file declares none, whether or not an entry uses it (Wu's view keys, ROAM's
//! deferral): it is the flight's truth, so no frame breaks it, and entries that ignore the bound
//! are unaffected. What it replaces, π, bounded nothing and made those entries re-test nearly
//! everything every frame without saying so. A declared bound stays a promise, checked every
//! frame. The horizontal and vertical bounds are required by the format and never derived. The
//! turn is the whole flight's as the file has it: `--frames` shortens the flight afterwards, so
//! a shortened run's first frames are those of the whole run.

use super::check::{DeclaredSpeedBounds, MeshExports};
use super::entries::AlgorithmSpec;
use super::format::{
    AltitudeEntry, FitEntry, FlightEntry, InterpolationEntry, LookEntry, MosaicFormatEntry,
    PathEntry, RawSampleEntry, SpacingEntry, SyntheticEntry, TerrainEntry, TerrainFileEntry,
    TerrainFormatEntry, TerrainMosaicEntry,
};
use super::problems::ExperimentError;
use super::sweep::SweepChoice;
use crate::edge::flight_log::read_flight_log;
#[cfg(feature = "gdal")]
use crate::edge::terrain_readers::lay_out_gdal_mosaic;
use crate::edge::terrain_readers::{
    LoadedTerrain, MosaicLayout, MosaicSource, RawLayout, RawSample, ReadOptions, TerrainFormat,
    format_from_extension, lay_out_mosaic, read_mosaic, read_terrain,
};
use crate::sim::flight::{
    Altitude, Flight, FlightPath, Interpolation, Look, SpeedViolation, Waypoint, largest_turn,
};
use crate::sim::run::Effects;
use crate::sim::terrain::embed::{Fit, embed};
use crate::sim::terrain::fill::fill_voids;
use crate::sim::terrain::synthetic::{SyntheticTerrain, generate};
use crate::sim::terrain::{Heightfield, Spacing};
use crate::sim::view::ViewSettings;
use crate::sim::zone::SpeedBound;
use glam::{DVec2, DVec3};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A checked, loaded experiment: everything a run needs.
pub struct Experiment {
    pub name: String,
    pub description: Option<String>,
    pub file: PathBuf,
    /// SHA-256 of the experiment file's bytes, hex.
    pub content_sha256: String,
    /// The terrain, shared with the run's hierarchy (one copy of the heights per run).
    pub field: Arc<Heightfield>,
    pub terrain: TerrainReport,
    pub view: ViewSettings,
    /// `view.fovy_deg` as the experiment gives it (the view holds radians): echoed as written.
    pub fovy_deg: f64,
    /// `limits.max_triangles`: a frame of any entry with more triangles stops the run.
    pub max_triangles: u64,
    /// The motion bounds the algorithms assume and the flight is checked against.
    pub speed: SpeedBound,
    /// Whether `speed.rotation` was declared or derived from the flight (the module docs).
    pub rotation_bound: BoundOrigin,
    pub flight: Flight,
    pub flight_kind: &'static str,
    /// The flight's length as the file has it, before any `--frames` shortening.
    pub frames_in_file: u64,
    pub violations: Vec<SpeedViolation>,
    /// The frames whose eye is below the ground (over the terrain; see
    /// [`Flight::frames_below_ground`]).
    pub below_ground_frames: Vec<u64>,
    pub algorithms: Vec<AlgorithmSpec>,
    pub effects: Effects,
    pub plots: bool,
    /// The first frames left out of the summaries (`outputs.warm_up_frames`; see
    /// `edge::output::warm_up`), fewer than the flight's frames.
    pub warm_up_frames: u64,
    /// Meshes to write as PLY files (`outputs.meshes`); `None`: none.
    pub mesh_exports: Option<MeshExports>,
    /// The point of the experiment's top-level sweep this is (`None` without a sweep).
    pub sweep_point: Option<SweepChoice>,
}

/// Where a motion bound of an [`Experiment`] comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundOrigin {
    /// The experiment file declares it: a promise the flight is checked against.
    Declared,
    /// The file declares none: the flight's own largest figure, which no frame breaks.
    Derived,
}

impl DeclaredSpeedBounds {
    /// The bounds for `flight`: a missing rotation bound becomes its largest turn.
    pub(super) fn for_flight(self, flight: &Flight) -> (SpeedBound, BoundOrigin) {
        let (rotation, origin) = match self.rotation {
            Some(rotation) => (rotation, BoundOrigin::Declared),
            None => (largest_turn(flight), BoundOrigin::Derived),
        };
        let speed = SpeedBound {
            horizontal: self.horizontal,
            vertical: self.vertical,
            rotation,
        };
        (speed, origin)
    }
}

impl Experiment {
    /// The warm-up must leave at least one frame to summarise (checked when the flight is
    /// built, and again after `--frames` shortened it).
    pub fn check_warm_up(&self) -> Result<(), ExperimentError> {
        let n_frames = self.flight.n_frames();
        if self.warm_up_frames < n_frames {
            return Ok(());
        }
        let shortened = if n_frames < self.frames_in_file {
            format!(" (shortened by --frames from {})", self.frames_in_file)
        } else {
            String::new()
        };
        Err(ExperimentError::single(
            &self.file,
            "outputs.warm_up_frames",
            format!(
                "{} leaves no frame to summarise of the {n_frames}-frame flight{shortened}: \
                 expected fewer warm-up frames than the flight has",
                self.warm_up_frames
            ),
        ))
    }

    /// Runs only the first `n_frames` frames of the flight (`roamsim run --frames N`): the
    /// flight, its speed violations and the mesh exports past the end are cut; the frames kept
    /// are exactly the full flight's. A flight already that short is left whole.
    pub fn keep_first_frames(&mut self, n_frames: u64) {
        self.flight.keep_first(n_frames);
        let n = self.flight.n_frames();
        self.violations.retain(|v| v.frame < n);
        self.below_ground_frames.retain(|&f| f < n);
        if let Some(exports) = &mut self.mesh_exports {
            exports.frames.retain(|&f| f < n);
        }
    }
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
    /// `file`, `experiment` or `synthetic`; a converted file spacing says how (`file: cell size
    /// … (geographic, from the .prj) converted at …`).
    pub spacing_from: String,
    pub height_min_m: f32,
    pub height_max_m: f32,
}

/// Stage 3a: the terrain, read or generated, filled and embedded.
/// A mosaic's layout, when the plan made it (`plan.rs`), saves laying it out again.
pub(super) fn load_terrain(
    experiment: &Path,
    folder: &Path,
    entry: &TerrainEntry,
    mosaic_layout: Option<&MosaicLayout>,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
    load_terrain_assuming(experiment, folder, entry, mosaic_layout, None)
}

/// [`load_terrain`], with `assumed` as the spacing of a file that declares none and is read
/// without `spacing_m` (where an experiment is refused: `roamsim info` describes such a file).
pub(super) fn load_terrain_assuming(
    experiment: &Path,
    folder: &Path,
    entry: &TerrainEntry,
    mosaic_layout: Option<&MosaicLayout>,
    assumed: Option<Spacing>,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
    match entry {
        TerrainEntry::Synthetic(s) => generate_terrain(experiment, s),
        TerrainEntry::Pyramid(pyramid) => {
            super::terrain_pyramid::read_terrain_pyramid(experiment, folder, pyramid)
        }
        TerrainEntry::File(file) => read_terrain_file(experiment, folder, file, assumed),
        TerrainEntry::Mosaic(mosaic) => {
            let laid_out;
            let layout = match mosaic_layout {
                Some(layout) => layout,
                None => {
                    laid_out = lay_out_terrain_mosaic(experiment, folder, mosaic)?;
                    &laid_out
                }
            };
            read_terrain_mosaic(experiment, mosaic, layout)
        }
    }
}

/// Stage 3's first step for a mosaic, done for every point when the plan is made: its files
/// laid out from their headers (existence, names, sizes, georeference, gaps), no height read.
pub(super) fn lay_out_terrain_mosaic(
    experiment: &Path,
    folder: &Path,
    mosaic: &TerrainMosaicEntry,
) -> Result<MosaicLayout, ExperimentError> {
    let (source, field) = match (&mosaic.files, &mosaic.folder) {
        (Some(files), _) => (
            MosaicSource::Files(files.iter().map(|f| folder.join(f)).collect()),
            "terrain.mosaic.files",
        ),
        (None, Some(tiles)) => (
            MosaicSource::Folder(folder.join(tiles)),
            "terrain.mosaic.folder",
        ),
        (None, None) => (MosaicSource::Files(Vec::new()), "terrain.mosaic"),
    };
    let layout = match (mosaic.format, source) {
        (None, source) => lay_out_mosaic(&source),
        #[cfg(feature = "gdal")]
        (Some(MosaicFormatEntry::Gdal), MosaicSource::Files(files)) => lay_out_gdal_mosaic(&files),
        // Refused by the check (no feature, or a folder); kept a value, not a panic.
        (Some(MosaicFormatEntry::Gdal), _) => {
            return Err(ExperimentError::single(
                experiment,
                "terrain.mosaic.format",
                "\"gdal\": expected a build with the gdal feature and a list of files",
            ));
        }
    };
    layout.map_err(|e| ExperimentError::single(experiment, field, e.to_string()))
}

/// A mosaic's files read into one grid, its voids filled, embedded as one file is.
fn read_terrain_mosaic(
    experiment: &Path,
    mosaic: &TerrainMosaicEntry,
    layout: &MosaicLayout,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
    let options = ReadOptions {
        height_scale: mosaic.height_scale.unwrap_or(1.0),
        height_offset: mosaic.height_offset_m.unwrap_or(0.0),
        nodata: mosaic.nodata,
    };
    let loaded = read_mosaic(layout, &options)
        .map_err(|e| ExperimentError::single(experiment, "terrain.mosaic", e.to_string()))?;
    let source = match (&mosaic.files, &mosaic.folder) {
        (Some(files), _) if files.len() > 4 => format!(
            "{} and {} more files",
            files[..3].join(", "),
            files.len() - 3
        ),
        (Some(files), _) => files.join(", "),
        (None, Some(folder)) => format!("{folder} ({} tiles)", layout.n_files()),
        (None, None) => String::new(),
    };
    let grid_keys = GridKeys {
        field: "terrain.mosaic",
        path: PathBuf::from(&source),
        source,
        format: layout.kind().name().to_string(),
        spacing_m: mosaic.spacing_m,
        assumed: None,
        fit: mosaic.fit,
        crop_origin: mosaic.crop_origin,
        origin_m: mosaic.origin_m,
    };
    embed_loaded(experiment, &grid_keys, loaded)
}

/// What `file` and `mosaic` share once their grid is read: how to space, fit and name it.
struct GridKeys {
    /// `terrain.file` or `terrain.mosaic`, for errors.
    field: &'static str,
    /// Names the grid in errors.
    path: PathBuf,
    /// As the report gives it.
    source: String,
    format: String,
    spacing_m: Option<SpacingEntry>,
    /// The spacing of a grid that declares none and is given no `spacing_m` (`roamsim info`).
    assumed: Option<Spacing>,
    fit: FitEntry,
    crop_origin: Option<[usize; 2]>,
    origin_m: Option<[f64; 3]>,
}

/// A grid read from a file or a mosaic: spaced, its voids filled, embedded, reported.
fn embed_loaded(
    experiment: &Path,
    keys: &GridKeys,
    loaded: LoadedTerrain,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
    let path = &keys.path;
    let field_error = |problem: String| ExperimentError::single(experiment, keys.field, problem);
    let (spacing, spacing_from) = grid_spacing(
        experiment,
        keys.field,
        path,
        (keys.spacing_m, keys.assumed),
        &loaded,
    )?;
    let (source_columns, source_rows) = (loaded.grid.width(), loaded.grid.height());
    let (filled, fill) =
        fill_voids(loaded.grid).map_err(|e| field_error(format!("{}: {e}", path.display())))?;
    let fit = match keys.fit {
        FitEntry::Pad => Fit::Pad,
        FitEntry::Crop => Fit::Crop {
            origin: keys.crop_origin.map(|[i, j]| (i, j)),
        },
    };
    let (field, embedded) = embed(&filled, fit, spacing)
        .map_err(|e| field_error(format!("{}: {e}", path.display())))?;
    let field = field.with_origin(origin(keys.origin_m));
    let (lo, hi) = field.height_range();
    let report = TerrainReport {
        source: keys.source.clone(),
        format: keys.format.clone(),
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

/// A synthetic terrain generated by diamond-square.
fn generate_terrain(
    experiment: &Path,
    s: &SyntheticEntry,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
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
        spacing_from: "synthetic".to_string(),
        height_min_m: lo,
        height_max_m: hi,
    };
    Ok((field, report))
}

/// A terrain file read (its format given or from its extension), its voids filled, embedded in
/// the grid by padding or cropping.
fn read_terrain_file(
    experiment: &Path,
    folder: &Path,
    file: &TerrainFileEntry,
    assumed: Option<Spacing>,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
    let path = folder.join(&file.path);
    let field_error =
        |problem: String| ExperimentError::single(experiment, "terrain.file", problem);
    let format = terrain_format(experiment, &path, file)?;
    let options = ReadOptions {
        height_scale: file.height_scale.unwrap_or(1.0),
        height_offset: file.height_offset_m.unwrap_or(0.0),
        nodata: file.nodata,
    };
    let loaded = read_terrain(&path, format, &options).map_err(|e| field_error(e.to_string()))?;
    let grid_keys = GridKeys {
        field: "terrain.file",
        path,
        source: file.path.clone(),
        format: format.name().to_string(),
        spacing_m: file.spacing_m,
        assumed,
        fit: file.fit,
        crop_origin: file.crop_origin,
        origin_m: file.origin_m,
    };
    embed_loaded(experiment, &grid_keys, loaded)
}

/// The terrain file's format: the one declared, else the one its extension names.
pub(super) fn terrain_format(
    experiment: &Path,
    path: &Path,
    file: &TerrainFileEntry,
) -> Result<TerrainFormat, ExperimentError> {
    let field_error =
        |problem: String| ExperimentError::single(experiment, "terrain.file", problem);
    Ok(match &file.format {
        None => format_from_extension(path).map_err(|e| field_error(e.to_string()))?,
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
        #[cfg(feature = "gdal")]
        Some(TerrainFormatEntry::Gdal) => TerrainFormat::Gdal,
        // Refused by the check without the feature; kept a value, not a panic.
        #[cfg(not(feature = "gdal"))]
        Some(TerrainFormatEntry::Gdal) => {
            return Err(field_error(
                "\"gdal\": this roamsim was built without GDAL".to_string(),
            ));
        }
    })
}

/// The terrain's grid spacing and where it came from: the experiment's `spacing_m` when it gives
/// one, else the file's (or mosaic's) own, else the `assumed` one (an error when there is none).
fn grid_spacing(
    experiment: &Path,
    field: &str,
    path: &Path,
    (given, assumed): (Option<SpacingEntry>, Option<Spacing>),
    loaded: &LoadedTerrain,
) -> Result<(Spacing, String), ExperimentError> {
    match (given, loaded.spacing) {
        (Some(s), _) => Ok((Spacing { dx: s.dx, dy: s.dy }, "experiment".to_string())),
        (None, Some(s)) => Ok((
            s,
            match &loaded.spacing_note {
                Some(note) => format!("file: {note}"),
                None => "file".to_string(),
            },
        )),
        (None, None) if let Some(s) = assumed => Ok((
            s,
            format!(
                "file: none usable{}; {} m assumed here, an experiment must give spacing_m",
                loaded
                    .spacing_note
                    .as_ref()
                    .map_or(String::new(), |n| format!(" ({n})")),
                s.dx
            ),
        )),
        (None, None) => {
            let why = match &loaded.spacing_note {
                Some(note) => note.clone(),
                None => "it does not declare its grid spacing".to_string(),
            };
            Err(ExperimentError::single(
                experiment,
                format!("{field}.spacing_m"),
                format!(
                    "{}: {why}: expected spacing_m {{dx, dy}} in metres",
                    path.display()
                ),
            ))
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

/// Stage 3b: the flight, with a recorded log read from its file.
pub(super) fn build_flight(
    experiment: &Path,
    folder: &Path,
    entry: &FlightEntry,
    field: &Heightfield,
) -> Result<Flight, ExperimentError> {
    let look = flight_look(entry);
    let path = flight_path(experiment, folder, &entry.path)?;
    let altitude = match entry.altitude {
        None | Some(AltitudeEntry::Absolute) => Altitude::Absolute,
        Some(AltitudeEntry::AboveGround) => Altitude::AboveGround(field),
    };
    Flight::with_altitude(&path, &look, entry.frames.unwrap_or(0), altitude)
        .map_err(|e| ExperimentError::single(experiment, "flight", e.to_string()))
}

/// Where the camera looks: an orbit at its target, else as the entry's `look` says (yaw and
/// pitch 0 without one: a recorded flight brings its own view direction).
fn flight_look(entry: &FlightEntry) -> Look {
    if let PathEntry::Orbit { target_m, .. } = &entry.path {
        return Look::At {
            target: v3(*target_m),
        };
    }
    match entry.look {
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
    }
}

/// The flight's path, with a recorded log read from its file (relative to the experiment's
/// folder).
fn flight_path(
    experiment: &Path,
    folder: &Path,
    path: &PathEntry,
) -> Result<FlightPath, ExperimentError> {
    Ok(match path {
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
        } => FlightPath::Circle {
            centre: v2(*centre_m),
            radius: *radius_m,
            altitude: *altitude_m,
            frames_per_lap: *frames_per_lap,
            phase: phase_deg.to_radians(),
        },
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
    })
}

fn v2(a: [f64; 2]) -> DVec2 {
    DVec2::new(a[0], a[1])
}

fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::new(a[0], a[1], a[2])
}
