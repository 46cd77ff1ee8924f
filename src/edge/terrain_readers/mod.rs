//! Terrain readers: SRTM `.hgt`, 16-bit grayscale PNG, GeoTIFF, ESRI ASCII grid and raw samples.
//!
//! Every reader turns a file into a [`SampleGrid`] (row 0 = south edge, voids marked) plus the
//! grid spacing the file itself declares, if any. Every failure is a [`TerrainReadError`] that
//! names the file and says what was wrong and what was expected. Readers never panic on bad
//! input and never accept a NaN or infinite height that is not the declared nodata value.

mod ascii_grid;
mod geotiff;
mod hgt;
mod png;
mod raw;

use crate::sim::terrain::{SampleGrid, Spacing};
use std::fmt;
use std::path::{Path, PathBuf};

/// A terrain file format.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TerrainFormat {
    /// SRTM `.hgt`: big-endian int16, 1201² (SRTM3) or 3601² (SRTM1), −32768 = void.
    Hgt,
    /// 8- or 16-bit grayscale PNG; heights = value · height_scale + height_offset.
    Png,
    /// GeoTIFF with int16, uint16 or float32 samples, nodata from the GDAL_NODATA tag.
    GeoTiff,
    /// ESRI ASCII grid (`ncols`, `nrows`, `xllcorner`/`xllcenter`, …, `cellsize`, `NODATA_value`).
    AsciiGrid,
    /// Headerless samples of a declared layout.
    Raw(RawLayout),
}

/// The layout of a raw sample file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawLayout {
    pub columns: usize,
    pub rows: usize,
    pub sample: RawSample,
    /// Whether the first row in the file is the north edge (true) or the south edge.
    pub north_first: bool,
}

/// Sample types of raw files.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RawSample {
    I16Le,
    I16Be,
    U16Le,
    U16Be,
    F32Le,
    F32Be,
}

impl RawSample {
    pub fn bytes(self) -> usize {
        match self {
            RawSample::I16Le | RawSample::I16Be | RawSample::U16Le | RawSample::U16Be => 2,
            RawSample::F32Le | RawSample::F32Be => 4,
        }
    }
}

/// Options that apply to every reader.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Metres per stored unit (applied to every format; 1 for SRTM).
    pub height_scale: f64,
    /// Metres added after scaling.
    pub height_offset: f64,
    /// A stored value that marks a void, overriding (or adding to) the file's own.
    pub nodata: Option<f64>,
}

impl ReadOptions {
    /// Heights as stored, with only the file's own nodata value.
    pub const AS_STORED: ReadOptions = ReadOptions {
        height_scale: 1.0,
        height_offset: 0.0,
        nodata: None,
    };
}

/// A grid read from a file.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedTerrain {
    pub grid: SampleGrid,
    /// Spacing the file declares (in metres), if it declares one.
    pub spacing: Option<Spacing>,
    pub format: TerrainFormat,
}

/// A terrain file could not be read: the file and the problem.
#[derive(Clone, Debug, PartialEq)]
pub struct TerrainReadError {
    pub path: PathBuf,
    pub problem: String,
}

impl fmt::Display for TerrainReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.problem)
    }
}

impl std::error::Error for TerrainReadError {}

impl TerrainReadError {
    pub(crate) fn new(path: &Path, problem: impl Into<String>) -> TerrainReadError {
        TerrainReadError {
            path: path.to_path_buf(),
            problem: problem.into(),
        }
    }
}

/// The format a file name suggests, or an error listing the known extensions.
pub fn format_from_extension(path: &Path) -> Result<TerrainFormat, TerrainReadError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("hgt") => Ok(TerrainFormat::Hgt),
        Some("png") => Ok(TerrainFormat::Png),
        Some("tif" | "tiff") => Ok(TerrainFormat::GeoTiff),
        Some("asc") => Ok(TerrainFormat::AsciiGrid),
        _ => Err(TerrainReadError::new(
            path,
            "unknown terrain format: expected a .hgt, .png, .tif, .tiff or .asc file, \
             or a declared format (raw files need their layout declared)",
        )),
    }
}

/// Reads a terrain file in the given format.
pub fn read_terrain(
    path: &Path,
    format: TerrainFormat,
    options: &ReadOptions,
) -> Result<LoadedTerrain, TerrainReadError> {
    let bytes = std::fs::read(path)
        .map_err(|error| TerrainReadError::new(path, format!("cannot read the file: {error}")))?;
    let (grid, spacing) = match format {
        TerrainFormat::Hgt => hgt::read(path, &bytes, options)?,
        TerrainFormat::Png => png::read(path, &bytes, options)?,
        TerrainFormat::GeoTiff => geotiff::read(path, &bytes, options)?,
        TerrainFormat::AsciiGrid => ascii_grid::read(path, &bytes, options)?,
        TerrainFormat::Raw(layout) => raw::read(path, &bytes, &layout, options)?,
    };
    Ok(LoadedTerrain {
        grid,
        spacing,
        format,
    })
}
