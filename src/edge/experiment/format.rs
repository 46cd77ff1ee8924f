//! The experiment file as written: serde types for format version 1, nothing checked yet
//! beyond JSON types and unknown fields. `docs/experiment-format.md` documents every field.
//!
//! Field names carry their units (`_m`, `_deg`, `_px`, `_m_per_frame`). Algorithm entries are
//! kept as raw JSON here and decoded per algorithm in `parameters.rs` (and the block
//! algorithms' files), so a bad parameter is reported with the entry's own path.

use serde::Deserialize;
use serde_json::{Map, Value};

/// The only format version this build reads.
pub const FORMAT_VERSION: u32 = 1;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentFile {
    pub format_version: u32,
    pub name: String,
    #[serde(default)]
    pub description: Option<String>,
    pub terrain: TerrainEntry,
    pub view: ViewEntry,
    pub speed_bounds: SpeedBoundsEntry,
    pub flight: FlightEntry,
    pub algorithms: Vec<AlgorithmEntry>,
    #[serde(default)]
    pub effects: EffectsEntry,
    #[serde(default)]
    pub outputs: OutputsEntry,
    #[serde(default)]
    pub limits: LimitsEntry,
}

/// Limits that stop runaway work (default: [`DEFAULT_MAX_TRIANGLES`]).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsEntry {
    /// Most triangles any entry's mesh may have in a frame; the run stops with an error naming
    /// the entry and the frame when one exceeds it.
    #[serde(default)]
    pub max_triangles: Option<u64>,
}

/// The default of `limits.max_triangles`: four times the largest mesh of the shipped
/// experiments (chunked-tau, 0.51 M), a full 1025² mesh's 2.1 M not included.
pub const DEFAULT_MAX_TRIANGLES: u64 = 2_000_000;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum TerrainEntry {
    File(TerrainFileEntry),
    Mosaic(TerrainMosaicEntry),
    Synthetic(SyntheticEntry),
    Pyramid(TerrainPyramidEntry),
}

/// A chunk pyramid that `roamsim prepare` wrote, flown without ever holding the whole terrain:
/// side, spacing and sample type come from its header (`terrain_pyramid.rs`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainPyramidEntry {
    /// Relative to the experiment file's folder.
    pub file: String,
    /// World position of sample (0, 0) at height 0 (default: the world origin).
    #[serde(default)]
    pub origin_m: Option<[f64; 3]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainFileEntry {
    /// Relative to the experiment file's folder.
    pub path: String,
    #[serde(default)]
    pub format: Option<TerrainFormatEntry>,
    #[serde(default)]
    pub height_scale: Option<f64>,
    #[serde(default)]
    pub height_offset_m: Option<f64>,
    #[serde(default)]
    pub nodata: Option<f64>,
    #[serde(default)]
    pub spacing_m: Option<SpacingEntry>,
    pub fit: FitEntry,
    #[serde(default)]
    pub crop_origin: Option<[usize; 2]>,
    /// World position of sample (0, 0) at height 0 (default: the world origin).
    #[serde(default)]
    pub origin_m: Option<[f64; 3]>,
}

/// Many files as one terrain: SRTM tiles, GeoTIFF tiles or one VRT, listed or a folder's
/// (exactly one of `files` and `folder`), with the keys of `file` that apply to a whole grid.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainMosaicEntry {
    /// Relative to the experiment file's folder.
    #[serde(default)]
    pub files: Option<Vec<String>>,
    /// Relative to the experiment file's folder: every `.hgt`, `.tif` and `.tiff` in it.
    #[serde(default)]
    pub folder: Option<String>,
    /// `"gdal"`: every file opened by GDAL and placed by its GeoTransform (the `gdal` feature);
    /// absent: by the files' extensions.
    #[serde(default)]
    pub format: Option<MosaicFormatEntry>,
    #[serde(default)]
    pub height_scale: Option<f64>,
    #[serde(default)]
    pub height_offset_m: Option<f64>,
    #[serde(default)]
    pub nodata: Option<f64>,
    #[serde(default)]
    pub spacing_m: Option<SpacingEntry>,
    pub fit: FitEntry,
    #[serde(default)]
    pub crop_origin: Option<[usize; 2]>,
    #[serde(default)]
    pub origin_m: Option<[f64; 3]>,
}

#[derive(Debug, Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum MosaicFormatEntry {
    Gdal,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum TerrainFormatEntry {
    Hgt,
    Png,
    Geotiff,
    AsciiGrid,
    Raw(RawEntry),
    /// Any raster GDAL opens: only in a build with the `gdal` feature (checked in `check.rs`).
    Gdal,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawEntry {
    pub columns: usize,
    pub rows: usize,
    pub sample: RawSampleEntry,
    pub north_first: bool,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub enum RawSampleEntry {
    I16le,
    I16be,
    U16le,
    U16be,
    F32le,
    F32be,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub enum FitEntry {
    Pad,
    Crop,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub struct SpacingEntry {
    pub dx: f64,
    pub dy: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SyntheticEntry {
    /// Side 2^level + 1.
    pub level: u32,
    pub seed: u64,
    /// The corners' and the top level's displacement in metres; heights are not centred on the
    /// origin and can span more than ± this (docs/experiment-format.md).
    pub amplitude_m: f64,
    /// The horizontal length over which `amplitude_m` applies (default: the terrain's extent
    /// along x): terrains of different sizes with the same scale share their small-scale relief.
    #[serde(default)]
    pub amplitude_scale_m: Option<f64>,
    /// A Hurst exponent in [0, 1]: higher is smoother.
    pub roughness: f64,
    pub spacing_m: SpacingEntry,
    /// World position of sample (0, 0) at height 0 (default: the world origin).
    #[serde(default)]
    pub origin_m: Option<[f64; 3]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewEntry {
    pub width_px: u32,
    pub height_px: u32,
    pub fovy_deg: f64,
    pub near_m: f64,
    pub far_m: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedBoundsEntry {
    pub horizontal_m_per_frame: f64,
    pub vertical_m_per_frame: f64,
    /// Bound on the turn of the look direction per frame; absent: the flight's largest turn
    /// (derived at load).
    #[serde(default)]
    pub rotation_rad_per_frame: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlightEntry {
    /// Required for parametric paths; waypoints and recorded logs bring their own.
    #[serde(default)]
    pub frames: Option<u64>,
    #[serde(default)]
    pub look: Option<LookEntry>,
    pub path: PathEntry,
    /// What the path's heights mean (default: absolute world heights).
    #[serde(default)]
    pub altitude: Option<AltitudeEntry>,
    /// Fly only the flight's first this many frames, as `roamsim run --frames N` does (the
    /// flight and its derived rotation bound are the whole flight's); written by
    /// `tuned-experiment.json` for a run that had `--frames`.
    #[serde(default)]
    pub first_frames: Option<u64>,
}

/// `"absolute"`: the path's z values are world heights; `"above_ground"`: heights above the
/// ground under the eye.
#[derive(Debug, Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum AltitudeEntry {
    Absolute,
    AboveGround,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum LookEntry {
    AlongPath { pitch_deg: f64 },
    At { target_m: [f64; 3] },
    Fixed { yaw_deg: f64, pitch_deg: f64 },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum PathEntry {
    Circle {
        centre_m: [f64; 2],
        radius_m: f64,
        altitude_m: f64,
        frames_per_lap: f64,
        #[serde(default)]
        phase_deg: f64,
    },
    /// A circle whose camera always looks at `target_m`.
    Orbit {
        centre_m: [f64; 2],
        radius_m: f64,
        altitude_m: f64,
        frames_per_lap: f64,
        target_m: [f64; 3],
        #[serde(default)]
        phase_deg: f64,
    },
    Line {
        from_m: [f64; 3],
        to_m: [f64; 3],
    },
    Spiral {
        centre_m: [f64; 2],
        radius_start_m: f64,
        radius_end_m: f64,
        altitude_start_m: f64,
        altitude_end_m: f64,
        turns: f64,
        #[serde(default)]
        phase_deg: f64,
    },
    Waypoints {
        points: Vec<WaypointEntry>,
        interpolation: InterpolationEntry,
    },
    /// A recorded camera log (CSV), relative to the experiment file's folder.
    Recorded {
        path: String,
    },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaypointEntry {
    pub frame: u64,
    pub position_m: [f64; 3],
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub enum InterpolationEntry {
    Linear,
    CatmullRom,
}

/// `{"name": "...", "label": "...", <the algorithm's parameters>}`.
#[derive(Debug, Deserialize)]
pub struct AlgorithmEntry {
    pub name: String,
    #[serde(default)]
    pub label: Option<String>,
    #[serde(flatten)]
    pub parameters: Map<String, Value>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceParameters {
    pub tau_px: f64,
    #[serde(default)]
    pub zone: Option<ZoneEntry>,
    /// Default: everywhere.
    #[serde(default)]
    pub refine: Option<RefineEntry>,
    /// Default: Wu's max rule.
    #[serde(default)]
    pub nesting: Option<NestingEntry>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WuParameters {
    /// Default: Wu's max rule.
    #[serde(default)]
    pub nesting: Option<NestingEntry>,
    /// Fixed τ; with a budget, the starting τ (default: the paper's formula).
    #[serde(default)]
    pub tau_px: Option<f64>,
    #[serde(default)]
    pub budget_triangles: Option<u64>,
    #[serde(default)]
    pub zone: Option<ZoneEntry>,
    #[serde(default)]
    pub dead_band_triangles: Option<u64>,
    #[serde(default)]
    pub base_limit: Option<i64>,
    #[serde(default)]
    pub initial_tau_k: Option<f64>,
    #[serde(default)]
    pub block_priority: Option<bool>,
    #[serde(default)]
    pub depth_limit: Option<u32>,
    #[serde(default)]
    pub cone_culling: Option<bool>,
    /// Default: `in_view` with cone culling, else `everywhere`.
    #[serde(default)]
    pub refine: Option<RefineEntry>,
    #[serde(default)]
    pub recentre_tau: Option<bool>,
    #[serde(default)]
    pub recentre_tau_window_frames: Option<u32>,
    #[serde(default)]
    pub wheel_links: Option<u32>,
    /// Wu §7's geometry morphing: frames a vertex takes to rise or sink (≥ 1); absent: off.
    #[serde(default)]
    pub morph_frames: Option<u32>,
    /// Wu §7's incremental triangle strips, counted (`triangles_per_strip`); default off.
    #[serde(default)]
    pub strips: Option<bool>,
}

/// Where Wu (and its reference) refine: only what the view cone needs, or everywhere.
#[derive(Debug, Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum RefineEntry {
    InView,
    Everywhere,
}

/// Parameters of `lindstrom`: τ in pixels and the block level k (blocks of (2^k + 1)² samples,
/// 1 ≤ k ≤ 15; a k above the terrain's level means one block).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LindstromParameters {
    pub tau_px: f64,
    pub block_level: u32,
    /// Default: Lindstrom's max rule.
    #[serde(default)]
    pub nesting: Option<NestingEntry>,
}

/// Parameters of `roam` and `roam-rebuild`: exactly one of `target_triangles` and `tau_px`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoamParameters {
    #[serde(default)]
    pub target_triangles: Option<u64>,
    #[serde(default)]
    pub tau_px: Option<f64>,
    #[serde(default)]
    pub deferral: bool,
    #[serde(default)]
    pub culling_flags: bool,
    #[serde(default)]
    pub strips: bool,
    /// Default: ROAM's max-plus-own rule.
    #[serde(default)]
    pub nesting: Option<NestingEntry>,
    /// Default: per triangle, the paper's eq. (1).
    #[serde(default)]
    pub thickness: Option<ThicknessEntry>,
    /// Default: Duchaineau's buckets.
    #[serde(default)]
    pub queue: Option<QueueEntry>,
}

/// Where ROAM's nested wedgie thickness is kept.
#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub enum ThicknessEntry {
    PerTriangle,
    PerVertex,
}

/// ROAM's priority queue implementation.
#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub enum QueueEntry {
    Buckets,
    Heap,
}

/// Parameters of `rottger`: C (`minimum_resolution`), c (`desired_resolution`: fixed, or the
/// starting value of a load target), at most one load target, and the options.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RottgerParameters {
    pub minimum_resolution: f64,
    #[serde(default)]
    pub desired_resolution: Option<f64>,
    #[serde(default)]
    pub target_triangles: Option<u64>,
    #[serde(default)]
    pub target_fan_vertices: Option<u64>,
    /// Default: the paper's L1 norm.
    #[serde(default)]
    pub distance: Option<DistanceEntry>,
    #[serde(default = "yes")]
    pub d2_propagation: bool,
    #[serde(default)]
    pub clipping: bool,
    #[serde(default)]
    pub geomorphing: bool,
}

/// How `rottger` measures the distance from the eye to a block.
#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub enum DistanceEntry {
    L1,
    Euclidean,
}

/// How nested errors combine a vertex's own error with its descendants'.
#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub enum NestingEntry {
    Max,
    MaxPlusOwn,
}

#[derive(Debug, Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub enum ZoneEntry {
    Paper,
    Conservative,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectsEntry {
    /// Absent: no audit.
    #[serde(default)]
    pub audit: Option<AuditEntry>,
    #[serde(default)]
    pub culling: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AuditEntry {
    pub stride: u32,
    /// Also measure popping (default false).
    #[serde(default)]
    pub popping: bool,
    /// The stride of the audit against a detail-extended surface, in its samples (default:
    /// `stride`).
    #[serde(default)]
    pub detail_stride: Option<u32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputsEntry {
    #[serde(default = "yes")]
    pub plots: bool,
    /// Meshes to export (default: none).
    #[serde(default)]
    pub meshes: Option<MeshesEntry>,
    /// The first frames left out of the summaries (default 0: none).
    #[serde(default)]
    pub warm_up_frames: u64,
}

impl Default for OutputsEntry {
    fn default() -> OutputsEntry {
        OutputsEntry {
            plots: true,
            meshes: None,
            warm_up_frames: 0,
        }
    }
}

/// `{"frames": [0, 120], "entries": ["wu τ=2px"]}`: each named entry's mesh at each frame, as a
/// PLY file. Entries by label or algorithm name; absent: every entry.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshesEntry {
    pub frames: Vec<u64>,
    #[serde(default)]
    pub entries: Option<Vec<String>>,
}

fn yes() -> bool {
    true
}
