//! Terrain readers: SRTM `.hgt`, 8- or 16-bit grayscale PNG, GeoTIFF, ESRI ASCII grid and raw
//! samples (SPEC §11; the formats and options an experiment names are in
//! `docs/experiment-format.md`, "Terrain"). Readers only read: filling the voids and fitting the
//! grid into (2^n + 1)² are the core's (`sim::terrain::fill`, `sim::terrain::embed`).
//!
//! Every reader turns a file into a [`SampleGrid`] (row 0 = south edge, voids marked) plus the
//! grid spacing the file itself declares, if any. Every failure is a [`TerrainReadError`] that
//! names the file and says what was wrong and what was expected. Readers never panic on bad
//! input and never accept a NaN or infinite height that is not the declared nodata value
//! (SPEC §9's last case).
//!
//! Every reader parses bytes already in memory. [`read_terrain`] reads the file (and an ASCII
//! grid's `.prj` beside it) and hands the bytes on; [`read_terrain_bytes`] is the same without
//! the file and with no `.prj`, the entry point of the fuzz targets and the parser property
//! tests. The path then only names the file in errors (and gives an `.hgt` tile its name).
//!
//! **Many files as one terrain** (`mosaic/`): SRTM tiles placed by their names, GeoTIFF tiles
//! by their georeference, or the sources of a GDAL VRT (`vrt.rs`, parsed by
//! [`parse_vrt_bytes`], the VRT's fuzz and property entry point) by its windows, laid out from
//! the files' headers first ([`lay_out_mosaic`]: gaps, mixed resolutions and missing tiles are
//! refused before any height is read), then read one file at a time with the readers above into
//! one [`SampleGrid`] ([`read_mosaic`]: overlaps must agree).
//!
//! **The `gdal` feature** (off by default) adds `TerrainFormat::Gdal` (`gdal_raster.rs`): band 1
//! of any raster the system's libgdal opens, read by its path, as one file or as mosaic tiles
//! placed by their GeoTransform (`lay_out_gdal_mosaic`). The default build reads every format
//! above in pure Rust.

mod ascii_grid;
#[cfg(feature = "gdal")]
mod gdal_raster;
mod geotiff;
mod hgt;
mod mosaic;
mod png;
mod raw;
pub(crate) use raw::decode_sample;
mod vrt;

#[cfg(feature = "gdal")]
pub use mosaic::lay_out_gdal_mosaic;
pub use mosaic::{MosaicKind, MosaicLayout, MosaicSource, lay_out_mosaic, read_mosaic};
pub use vrt::{VrtMosaic, parse_vrt_bytes};

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
    /// Band 1 of any raster the system's GDAL opens (the `gdal` feature).
    #[cfg(feature = "gdal")]
    Gdal,
}

impl TerrainFormat {
    /// The format's name as the experiment format spells it (`hgt`, `png`, `geotiff`,
    /// `ascii_grid`, `raw`).
    pub fn name(self) -> &'static str {
        match self {
            TerrainFormat::Hgt => "hgt",
            TerrainFormat::Png => "png",
            TerrainFormat::GeoTiff => "geotiff",
            TerrainFormat::AsciiGrid => "ascii_grid",
            TerrainFormat::Raw(_) => "raw",
            #[cfg(feature = "gdal")]
            TerrainFormat::Gdal => "gdal",
        }
    }
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
    /// How the spacing was read when it was converted (a geographic grid: degrees at a
    /// latitude), or why the file's own cell size was not taken: for the user, said aloud.
    pub spacing_note: Option<String>,
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
    #[cfg(feature = "gdal")]
    if format == TerrainFormat::Gdal {
        let (grid, spacing, spacing_note) = gdal_raster::read(path, options)?;
        return Ok(LoadedTerrain {
            grid,
            spacing,
            spacing_note,
            format,
        });
    }
    let bytes = std::fs::read(path)
        .map_err(|error| TerrainReadError::new(path, format!("cannot read the file: {error}")))?;
    // An ESRI ASCII grid says nothing of its units; the `.prj` beside it (when there is one)
    // says whether its cell size is in degrees.
    let prj = match format {
        TerrainFormat::AsciiGrid => std::fs::read(path.with_extension("prj"))
            .ok()
            .map(|bytes| String::from_utf8_lossy(&bytes).into_owned()),
        _ => None,
    };
    read_with_sidecar(path, &bytes, format, options, prj.as_deref())
}

/// Reads a terrain file's bytes, already in memory, in the given format. `path` only names the
/// file in errors (and, for `.hgt`, gives the tile name the spacing comes from). This is the
/// entry point of the fuzz targets and the parser property tests.
pub fn read_terrain_bytes(
    path: &Path,
    bytes: &[u8],
    format: TerrainFormat,
    options: &ReadOptions,
) -> Result<LoadedTerrain, TerrainReadError> {
    read_with_sidecar(path, bytes, format, options, None)
}

/// [`read_terrain_bytes`] with the text of an ASCII grid's `.prj` sidecar, if any.
fn read_with_sidecar(
    path: &Path,
    bytes: &[u8],
    format: TerrainFormat,
    options: &ReadOptions,
    prj: Option<&str>,
) -> Result<LoadedTerrain, TerrainReadError> {
    let (grid, spacing, spacing_note) = match format {
        TerrainFormat::Hgt => with_no_note(hgt::read(path, bytes, options)?),
        TerrainFormat::Png => with_no_note(png::read(path, bytes, options)?),
        TerrainFormat::GeoTiff => with_no_note(geotiff::read(path, bytes, options)?),
        TerrainFormat::AsciiGrid => ascii_grid::read(path, bytes, options, prj)?,
        TerrainFormat::Raw(layout) => with_no_note(raw::read(path, bytes, &layout, options)?),
        #[cfg(feature = "gdal")]
        TerrainFormat::Gdal => {
            return Err(TerrainReadError::new(
                path,
                "GDAL reads a file by its path, not bytes in memory: expected read_terrain",
            ));
        }
    };
    Ok(LoadedTerrain {
        grid,
        spacing,
        spacing_note,
        format,
    })
}

fn with_no_note(
    (grid, spacing): (SampleGrid, Option<Spacing>),
) -> (SampleGrid, Option<Spacing>, Option<String>) {
    (grid, spacing, None)
}

// ---------------------------------------------------------------------------------------------
// Private helpers shared by the readers.
// ---------------------------------------------------------------------------------------------

/// Metres per degree of latitude: 60 nautical miles of 1852 m (a nautical mile is by definition
/// one arc-minute of latitude on a sphere of mean radius). The true value ranges from 110 574 m at
/// the equator to 111 694 m at the poles, so this is within 0.5 % everywhere; the readers use it
/// only to derive grid spacing from geographic post spacing.
const METRES_PER_DEGREE_LATITUDE: f64 = 111_120.0;

/// The most a deflate (zlib) stream can expand: 1032 output bytes per input byte. A PNG whose
/// header declares more sample bytes than this times its byte length cannot be genuine, so the
/// readers refuse it before allocating.
const DEFLATE_MAX_EXPANSION: usize = 1032;

/// In which order the rows of a file are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FileRowOrder {
    /// The first row in the file is the north edge (every north-up raster format).
    NorthFirst,
    /// The first row in the file is the south edge (raw files that say so).
    SouthFirst,
}

/// How exactly a nodata marker is compared with stored values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum StoredPrecision {
    /// Stored values are integers or f64: compare with the marker as given.
    Exact,
    /// Stored values are f32: compare with the marker rounded to f32, as GDAL does for float32
    /// bands (so "-3.4028235e+38" matches `f32::MIN` although the two differ as f64).
    Float32,
}

/// Collects stored values in file order (row by row, west to east) and builds the south-up
/// [`SampleGrid`]: it applies the height scale and offset, marks voids, flips north-first files,
/// and names the file's own row and column in every error.
///
/// Allocates `columns × rows` f32 once, in [`SampleCollector::new`]; callers must have checked
/// that size against the file's byte length first.
struct SampleCollector<'a> {
    path: &'a Path,
    columns: usize,
    rows: usize,
    row_order: FileRowOrder,
    height_scale: f64,
    height_offset: f64,
    /// Stored values that mark a void (the file's own and the caller's), already rounded to the
    /// stored precision. A NaN marker matches every NaN.
    void_markers: Vec<f64>,
    heights: Vec<f32>,
    void_indices: Vec<usize>,
    n_collected: usize,
}

impl<'a> SampleCollector<'a> {
    fn new(
        path: &'a Path,
        columns: usize,
        rows: usize,
        row_order: FileRowOrder,
        precision: StoredPrecision,
        file_nodata: Option<f64>,
        options: &ReadOptions,
    ) -> Result<SampleCollector<'a>, TerrainReadError> {
        for (name, value) in [
            ("height_scale", options.height_scale),
            ("height_offset", options.height_offset),
        ] {
            if !value.is_finite() {
                return Err(TerrainReadError::new(
                    path,
                    format!("the read option {name} is {value}; expected a finite number"),
                ));
            }
        }
        if columns < 3 || rows < 3 {
            let error = crate::sim::terrain::SampleGridError::TooSmall {
                width: columns,
                height: rows,
            };
            return Err(TerrainReadError::new(path, error.to_string()));
        }
        let n_samples = columns.checked_mul(rows).ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!("a {columns}×{rows} grid has more samples than this machine can address"),
            )
        })?;
        let mut heights = Vec::new();
        heights.try_reserve_exact(n_samples).map_err(|error| {
            TerrainReadError::new(
                path,
                format!("cannot allocate {columns}×{rows} heights: {error}"),
            )
        })?;
        heights.resize(n_samples, 0.0_f32);
        let void_markers = [file_nodata, options.nodata]
            .into_iter()
            .flatten()
            .map(|marker| match precision {
                StoredPrecision::Exact => marker,
                StoredPrecision::Float32 => f64::from(marker as f32),
            })
            .collect();
        Ok(SampleCollector {
            path,
            columns,
            rows,
            row_order,
            height_scale: options.height_scale,
            height_offset: options.height_offset,
            void_markers,
            heights,
            void_indices: Vec::new(),
            n_collected: 0,
        })
    }

    /// Takes the next stored value in file order.
    fn push(&mut self, stored: f64) -> Result<(), TerrainReadError> {
        let file_row = self.n_collected / self.columns;
        let column = self.n_collected % self.columns;
        if file_row >= self.rows {
            return Err(TerrainReadError::new(
                self.path,
                format!(
                    "more than the {} × {} values the grid holds",
                    self.columns, self.rows
                ),
            ));
        }
        let grid_row = match self.row_order {
            FileRowOrder::NorthFirst => self.rows - 1 - file_row,
            FileRowOrder::SouthFirst => file_row,
        };
        let index = grid_row * self.columns + column;
        let is_void = self
            .void_markers
            .iter()
            .any(|&marker| stored == marker || (stored.is_nan() && marker.is_nan()));
        if is_void {
            self.void_indices.push(index);
        } else if !stored.is_finite() {
            return Err(TerrainReadError::new(
                self.path,
                format!(
                    "{}: the stored value is {stored}; expected a finite height or the nodata \
                     value ({})",
                    self.describe_position(file_row, column),
                    self.describe_void_markers()
                ),
            ));
        } else {
            let height = stored * self.height_scale + self.height_offset;
            let height_f32 = height as f32;
            if !height_f32.is_finite() {
                return Err(TerrainReadError::new(
                    self.path,
                    format!(
                        "{}: the stored value {stored} gives the height {height} m \
                         (value × height_scale + height_offset), which is outside the f32 range",
                        self.describe_position(file_row, column)
                    ),
                ));
            }
            self.heights[index] = height_f32;
        }
        self.n_collected += 1;
        Ok(())
    }

    /// "row 3 of 5 (counted from the north edge, as stored), column 2 of 4".
    fn describe_position(&self, file_row: usize, column: usize) -> String {
        describe_position(file_row, self.rows, column, self.columns, self.row_order)
    }

    fn describe_void_markers(&self) -> String {
        if self.void_markers.is_empty() {
            "none is declared".to_string()
        } else {
            let markers: Vec<String> = self.void_markers.iter().map(f64::to_string).collect();
            markers.join(" or ")
        }
    }

    /// Builds the grid once every value has been pushed.
    fn finish(self) -> Result<SampleGrid, TerrainReadError> {
        let expected = self.columns * self.rows;
        if self.n_collected != expected {
            return Err(TerrainReadError::new(
                self.path,
                format!(
                    "the file holds {} of the {expected} values a {}×{} grid needs",
                    self.n_collected, self.columns, self.rows
                ),
            ));
        }
        SampleGrid::new(self.columns, self.rows, self.heights, self.void_indices)
            .map_err(|error| TerrainReadError::new(self.path, error.to_string()))
    }
}

/// Names a sample by the file's own row and column, counted from 1.
fn describe_position(
    file_row: usize,
    rows: usize,
    column: usize,
    columns: usize,
    row_order: FileRowOrder,
) -> String {
    let edge = match row_order {
        FileRowOrder::NorthFirst => "north",
        FileRowOrder::SouthFirst => "south",
    };
    format!(
        "row {} of {rows} (counted from the {edge} edge, as stored), column {} of {columns}",
        file_row + 1,
        column + 1
    )
}
