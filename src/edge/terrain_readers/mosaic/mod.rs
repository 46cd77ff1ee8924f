//! A terrain from many files: SRTM tiles placed by their names, GeoTIFF tiles placed by their
//! georeference, or the sources of a GDAL VRT placed by its windows, assembled into one
//! [`SampleGrid`] (the experiment's `"terrain": {"mosaic": …}`; the format and its errors:
//! `docs/experiment-format.md`, "Mosaics"). Filling the voids and fitting the grid are the
//! core's, on the assembled grid, as for one file.
//!
//! **Two steps: lay out, then read.** [`lay_out_mosaic`] opens no more than each file's header
//! (an `.hgt` tile's length, a GeoTIFF's tags, the VRT's XML) and refuses, naming the file and
//! what was expected: a tile that does not exist, a name that is not a tile name, mixed
//! formats or resolutions, tiles off each other's sample lattice, an empty folder, and gaps
//! (every sample of the mosaic's rectangle must lie in some tile; a missing SRTM tile is named
//! by its tile name). The experiment's plan does this for every point before any terrain is
//! read. [`read_mosaic`] then reads the tiles one at a time into the assembled grid, holding one
//! tile beside it, and refuses overlaps that disagree.
//!
//! **Overlaps must agree; a void yields.** Where tiles overlap (SRTM's shared edge row and
//! column, GeoTIFF tiles cut with a shared edge, VRT windows) every sample must have the same
//! height in each, bit for bit after the height scale and offset, or the mosaic is refused
//! naming both files and the sample. A void in one and a height in another is not a
//! disagreement: the height is kept (as GDAL keeps a source's value where a later source has
//! nodata). This is stricter than GDAL's VRT, where a later source silently paints over an
//! earlier one; the result therefore does not depend on the order of the files.
//!
//! **Placement follows GDAL.** SRTM tiles of side n span one degree from the south-west corner
//! their name gives, posts 1/(n − 1)° apart, so neighbours share their edge posts. A GeoTIFF's
//! tiepoint names a pixel corner unless GTRasterTypeGeoKey says PixelIsPoint (GDAL's reading);
//! tiles must share their pixel scale (to 1 part in 10⁹) and lie on one sample lattice (to a
//! thousandth of a sample), or they would need resampling, which is not done. A VRT's windows
//! are whole pixels (`vrt.rs`). Nodata: each file's own marker, the experiment's `nodata`, the
//! VRT band's `NoDataValue` and a ComplexSource's `NODATA` all mark voids.
//!
//! **Spacing from the geography, as for one file**: SRTM's post spacing converted at the
//! mosaic's centre latitude (a single tile's is its own centre's); a GeoTIFF mosaic's pixel
//! scale in metres (projected) or converted at its centre latitude (geographic); a VRT's
//! GeoTransform step, in degrees when its `SRS` is geographic, metres when projected.
//!
//! Not done: reprojection, resampling, mosaics of PNG, ASCII or raw files (they carry no place),
//! mixing SRTM and GeoTIFF tiles in one list (a VRT may mix them: its windows place them). With
//! the `gdal` feature, [`lay_out_gdal_mosaic`] places files of any format GDAL opens by their
//! GeoTransforms, by the same rules as GeoTIFF tiles, and reads them through GDAL.
//! Files: this one holds the layout's types, the choice of format and the checks every kind
//! shares (extent, gaps); `srtm.rs`, `georeferenced.rs` (GeoTIFF, GDAL) and `vrt.rs` lay out
//! their kind; `read.rs` reads a layout.
//!
//! Memory: the assembled grid (4 bytes a sample, allocated once, refused with a clear error when
//! it cannot be) plus one tile as read.

mod georeferenced;
mod read;
mod srtm;
mod vrt;

#[cfg(feature = "gdal")]
pub(super) use georeferenced::GeoreferencedTile;
#[cfg(feature = "gdal")]
pub use georeferenced::lay_out_gdal_mosaic;
pub use read::read_mosaic;

use super::{TerrainFormat, TerrainReadError};
use crate::sim::terrain::Spacing;
use georeferenced::lay_out_geotiff;
use srtm::lay_out_srtm;
use std::path::{Path, PathBuf};
use vrt::lay_out_vrt;

/// The files of a mosaic as an experiment names them.
#[derive(Clone, Debug, PartialEq)]
pub enum MosaicSource {
    /// SRTM tiles, GeoTIFF tiles, or one `.vrt`, in any order.
    Files(Vec<PathBuf>),
    /// Every `.hgt`, `.tif` and `.tiff` file directly in the folder, in file-name order.
    Folder(PathBuf),
}

/// A mosaic laid out from its files' headers: where each file goes, nothing read yet.
#[derive(Clone, Debug, PartialEq)]
pub struct MosaicLayout {
    kind: MosaicKind,
    /// Names the mosaic in errors no one file explains: the folder (given, or the first file's)
    /// or the VRT.
    name: PathBuf,
    columns: usize,
    rows: usize,
    pieces: Vec<Piece>,
    spacing: Option<Spacing>,
    spacing_note: Option<String>,
    /// The VRT band's `NoDataValue`.
    nodata: Option<f64>,
}

/// What a mosaic is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MosaicKind {
    Srtm,
    GeoTiff,
    Vrt,
    /// Tiles opened by GDAL, placed by their GeoTransform (the `gdal` feature).
    #[cfg(feature = "gdal")]
    Gdal,
}

impl MosaicKind {
    /// As `summary.json`'s `terrain.format` says it: `hgt mosaic`, `geotiff mosaic`, `vrt`.
    pub fn name(self) -> &'static str {
        match self {
            MosaicKind::Srtm => "hgt mosaic",
            MosaicKind::GeoTiff => "geotiff mosaic",
            MosaicKind::Vrt => "vrt",
            #[cfg(feature = "gdal")]
            MosaicKind::Gdal => "gdal mosaic",
        }
    }
}

/// A window of samples, from the north-west corner (as GDAL counts pixels).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Window {
    pub(super) column: usize,
    pub(super) row: usize,
    pub(super) columns: usize,
    pub(super) rows: usize,
}

impl Window {
    /// "columns 1–1201, rows 601–1201 (from the north-west corner, counted from 1)".
    pub(super) fn describe(&self) -> String {
        format!(
            "columns {}–{}, rows {}–{} (from the north-west corner, counted from 1)",
            self.column + 1,
            self.column + self.columns,
            self.row + 1,
            self.row + self.rows
        )
    }

    fn contains(&self, column: usize, row: usize) -> bool {
        (self.column..self.column + self.columns).contains(&column)
            && (self.row..self.row + self.rows).contains(&row)
    }
}

/// One file's window and where it goes.
#[derive(Clone, Debug, PartialEq)]
struct Piece {
    path: PathBuf,
    format: TerrainFormat,
    /// The file's size as its header gives it.
    file_columns: usize,
    file_rows: usize,
    /// In the file's samples.
    source: Window,
    /// In the mosaic's samples; the same size as `source`.
    destination: Window,
    /// A VRT ComplexSource's `NODATA`.
    nodata: Option<f64>,
}

impl MosaicLayout {
    /// Columns and rows of the assembled grid.
    pub fn size(&self) -> (usize, usize) {
        (self.columns, self.rows)
    }

    pub fn n_files(&self) -> usize {
        self.pieces.len()
    }

    pub fn kind(&self) -> MosaicKind {
        self.kind
    }
}

/// Lays out a mosaic from its files' headers; every check that needs no height is done here.
pub fn lay_out_mosaic(source: &MosaicSource) -> Result<MosaicLayout, TerrainReadError> {
    let (name, files) = match source {
        MosaicSource::Files(files) => {
            let first = files.first().ok_or_else(|| {
                TerrainReadError::new(Path::new(""), "no files: expected at least one tile")
            })?;
            let folder = first.parent().filter(|p| !p.as_os_str().is_empty());
            (folder.unwrap_or(first).to_path_buf(), files.clone())
        }
        MosaicSource::Folder(folder) => (folder.clone(), folder_tiles(folder)?),
    };
    let mut kinds = Vec::with_capacity(files.len());
    for file in &files {
        let kind = kind_from_extension(file).ok_or_else(|| {
            TerrainReadError::new(
                file,
                "not a mosaic tile: expected .hgt (SRTM) or .tif/.tiff (GeoTIFF) tiles, or a \
                 single .vrt",
            )
        })?;
        kinds.push(kind);
    }
    if let Some(k) = kinds.iter().position(|&kind| kind != kinds[0]) {
        let problem = if kinds[0] == MosaicKind::Vrt || kinds[k] == MosaicKind::Vrt {
            "a .vrt is a whole mosaic: expected it alone".to_string()
        } else {
            format!(
                "tiles in mixed formats ({} is {}, {} is {}): expected tiles of one format (a \
                 VRT can combine formats)",
                files[0].display(),
                format_name(kinds[0]),
                files[k].display(),
                format_name(kinds[k])
            )
        };
        return Err(TerrainReadError::new(&files[k], problem));
    }
    match kinds[0] {
        MosaicKind::Srtm => lay_out_srtm(name, &files),
        MosaicKind::GeoTiff => lay_out_geotiff(name, &files),
        MosaicKind::Vrt if files.len() == 1 => lay_out_vrt(&files[0]),
        MosaicKind::Vrt => Err(TerrainReadError::new(
            &files[1],
            "a .vrt is a whole mosaic: expected it alone",
        )),
        #[cfg(feature = "gdal")]
        MosaicKind::Gdal => lay_out_gdal_mosaic(&files),
    }
}

fn kind_from_extension(path: &Path) -> Option<MosaicKind> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    match extension.as_str() {
        "hgt" => Some(MosaicKind::Srtm),
        "tif" | "tiff" => Some(MosaicKind::GeoTiff),
        "vrt" => Some(MosaicKind::Vrt),
        _ => None,
    }
}

fn format_name(kind: MosaicKind) -> &'static str {
    match kind {
        MosaicKind::Srtm => "an SRTM tile",
        MosaicKind::GeoTiff => "a GeoTIFF",
        MosaicKind::Vrt => "a VRT",
        #[cfg(feature = "gdal")]
        MosaicKind::Gdal => "a raster GDAL reads",
    }
}

/// The tiles directly in a folder, in file-name order (bytes, so the same on every machine).
fn folder_tiles(folder: &Path) -> Result<Vec<PathBuf>, TerrainReadError> {
    let entries = std::fs::read_dir(folder).map_err(|error| {
        TerrainReadError::new(folder, format!("cannot read the folder: {error}"))
    })?;
    let mut files = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|error| {
            TerrainReadError::new(folder, format!("cannot read the folder: {error}"))
        })?;
        let path = entry.path();
        let is_tile = matches!(
            kind_from_extension(&path),
            Some(MosaicKind::Srtm | MosaicKind::GeoTiff)
        );
        if is_tile && path.is_file() {
            files.push(path);
        }
    }
    if files.is_empty() {
        return Err(TerrainReadError::new(
            folder,
            "the folder holds no .hgt, .tif or .tiff file: expected the mosaic's tiles",
        ));
    }
    files.sort_by(|a, b| a.file_name().cmp(&b.file_name()));
    Ok(files)
}

/// A file's length, or an error naming it (a tile that does not exist lands here).
fn file_length(path: &Path) -> Result<u64, TerrainReadError> {
    let metadata = std::fs::metadata(path)
        .map_err(|error| TerrainReadError::new(path, format!("cannot read the tile: {error}")))?;
    if !metadata.is_file() {
        return Err(TerrainReadError::new(path, "not a file: expected a tile"));
    }
    Ok(metadata.len())
}

/// The mosaic's extent along one axis: the farthest edge of any piece.
fn extent(
    name: &Path,
    pieces: &[Piece],
    axis: impl Fn(&Window) -> (usize, usize),
) -> Result<usize, TerrainReadError> {
    pieces
        .iter()
        .map(|piece| {
            let (start, length) = axis(&piece.destination);
            start.checked_add(length)
        })
        .try_fold(0_usize, |farthest, end| end.map(|end| farthest.max(end)))
        .ok_or_else(|| {
            TerrainReadError::new(name, "the mosaic is larger than this machine can address")
        })
}

/// The first window of the mosaic (from the north-west) that no piece covers, if any: a sweep
/// over the bands between the pieces' row edges, O(n² log n) in the number of pieces.
fn first_gap(columns: usize, rows: usize, pieces: &[Piece]) -> Option<Window> {
    let mut row_edges: Vec<usize> = vec![0, rows];
    for piece in pieces {
        let window = piece.destination;
        row_edges.push(window.row.min(rows));
        row_edges.push((window.row + window.rows).min(rows));
    }
    row_edges.sort_unstable();
    row_edges.dedup();
    for band in row_edges.windows(2) {
        let (top, bottom) = (band[0], band[1]);
        let mut spans: Vec<(usize, usize)> = pieces
            .iter()
            .map(|piece| piece.destination)
            .filter(|w| w.row <= top && w.row + w.rows >= bottom)
            .map(|w| (w.column, w.column + w.columns))
            .collect();
        spans.sort_unstable();
        let mut covered_to = 0;
        for (start, end) in spans.into_iter().chain([(columns, columns)]) {
            if start > covered_to {
                return Some(Window {
                    column: covered_to,
                    row: top,
                    columns: start.min(columns) - covered_to,
                    rows: bottom - top,
                });
            }
            covered_to = covered_to.max(end);
            if covered_to >= columns {
                break;
            }
        }
    }
    None
}
