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
//! Memory: the assembled grid (4 bytes a sample, allocated once, refused with a clear error when
//! it cannot be) plus one tile as read.

use super::geotiff::{TiffGeoreference, TiffModel, read_placement};
use super::vrt::{VrtMosaic, parse_vrt_bytes};
use super::{
    LoadedTerrain, METRES_PER_DEGREE_LATITUDE, ReadOptions, TerrainFormat, TerrainReadError, hgt,
    read_terrain,
};
use crate::sim::terrain::{SampleGrid, Spacing};
use std::path::{Path, PathBuf};

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

/// A mosaic of files GDAL opens, whatever their format (a `.vrt` is one raster to GDAL,
/// resampling included), placed by their GeoTransforms on one lattice as GeoTIFF tiles are.
#[cfg(feature = "gdal")]
pub fn lay_out_gdal_mosaic(files: &[PathBuf]) -> Result<MosaicLayout, TerrainReadError> {
    let first = files.first().ok_or_else(|| {
        TerrainReadError::new(Path::new(""), "no files: expected at least one tile")
    })?;
    let name = first
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(first)
        .to_path_buf();
    let mut tiles = Vec::with_capacity(files.len());
    for path in files {
        file_length(path)?;
        tiles.push(super::gdal_raster::georeferenced_tile(path)?);
    }
    lay_out_georeferenced(name, MosaicKind::Gdal, TerrainFormat::Gdal, &tiles)
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

/// SRTM tiles: placed by their names, one resolution, a full rectangle of tiles.
fn lay_out_srtm(name: PathBuf, files: &[PathBuf]) -> Result<MosaicLayout, TerrainReadError> {
    struct Tile<'a> {
        path: &'a Path,
        south: i32,
        west: i32,
        side: usize,
    }
    let mut tiles: Vec<Tile> = Vec::with_capacity(files.len());
    for path in files {
        let (south, west) = hgt::tile_corner(path).ok_or_else(|| {
            TerrainReadError::new(
                path,
                "the file name is not an SRTM tile name: a tile is placed by its name; expected \
                 a name such as N48E009.hgt (the south-west corner's latitude and longitude)",
            )
        })?;
        let n_bytes = file_length(path)?;
        let side = hgt::tile_side(n_bytes).ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!(
                    "{n_bytes} bytes is not the size of an SRTM tile: expected 2884802 bytes \
                     (SRTM3, 1201×1201 samples) or 25934402 bytes (SRTM1, 3601×3601)"
                ),
            )
        })?;
        if let Some(first) = tiles.first()
            && first.side != side
        {
            return Err(TerrainReadError::new(
                path,
                format!(
                    "mixed resolutions: this tile has {side}×{side} posts but {} has {}×{}: \
                     expected tiles of one resolution (all SRTM3 or all SRTM1)",
                    first.path.display(),
                    first.side,
                    first.side
                ),
            ));
        }
        if let Some(twin) = tiles.iter().find(|t| (t.south, t.west) == (south, west)) {
            return Err(TerrainReadError::new(
                path,
                format!(
                    "names the same tile as {}: expected each tile once",
                    twin.path.display()
                ),
            ));
        }
        tiles.push(Tile {
            path,
            south,
            west,
            side,
        });
    }
    let side = tiles[0].side;
    let south = tiles.iter().map(|t| t.south).min().unwrap_or(0);
    let north = tiles.iter().map(|t| t.south).max().unwrap_or(0) + 1;
    let west = tiles.iter().map(|t| t.west).min().unwrap_or(0);
    let east = tiles.iter().map(|t| t.west).max().unwrap_or(0) + 1;
    let mut missing = Vec::new();
    for latitude in (south..north).rev() {
        for longitude in west..east {
            if !tiles
                .iter()
                .any(|t| (t.south, t.west) == (latitude, longitude))
            {
                missing.push(srtm_tile_name(latitude, longitude));
            }
        }
    }
    if let Some(first) = missing.first() {
        let folder = tiles[0].path.parent().unwrap_or(Path::new(""));
        let shown: Vec<&str> = missing.iter().take(8).map(String::as_str).collect();
        let more = if missing.len() > shown.len() {
            format!(" and {} more", missing.len() - shown.len())
        } else {
            String::new()
        };
        return Err(TerrainReadError::new(
            &folder.join(first),
            format!(
                "a gap: the tiles span {} to {} (south-west to north-east corners) but no tile \
                 covers {}{more}: expected every tile of that rectangle",
                corner_name(south, west),
                corner_name(north, east),
                shown.join(", ")
            ),
        ));
    }
    let step = side - 1;
    let columns = span(&name, (east - west) as usize, step)?;
    let rows = span(&name, (north - south) as usize, step)?;
    let pieces = tiles
        .iter()
        .map(|tile| Piece {
            path: tile.path.to_path_buf(),
            format: TerrainFormat::Hgt,
            file_columns: side,
            file_rows: side,
            source: Window {
                column: 0,
                row: 0,
                columns: side,
                rows: side,
            },
            destination: Window {
                column: (tile.west - west) as usize * step,
                row: (north - 1 - tile.south) as usize * step,
                columns: side,
                rows: side,
            },
            nodata: None,
        })
        .collect();
    let centre_latitude = f64::from(south + north) / 2.0;
    Ok(MosaicLayout {
        kind: MosaicKind::Srtm,
        name,
        columns,
        rows,
        pieces,
        spacing: hgt::spacing_at(side, centre_latitude),
        spacing_note: None,
        nodata: None,
    })
}

/// Posts along `n_tiles` tiles of `step` + 1 posts sharing their edges.
fn span(name: &Path, n_tiles: usize, step: usize) -> Result<usize, TerrainReadError> {
    n_tiles
        .checked_mul(step)
        .and_then(|posts| posts.checked_add(1))
        .ok_or_else(|| {
            TerrainReadError::new(name, "the mosaic is larger than this machine can address")
        })
}

/// `N49E010.hgt`: the tile whose south-west corner is at that latitude and longitude.
fn srtm_tile_name(latitude: i32, longitude: i32) -> String {
    format!("{}.hgt", corner_name(latitude, longitude))
}

/// `N49E010`, `S01W072`.
fn corner_name(latitude: i32, longitude: i32) -> String {
    format!(
        "{}{:02}{}{:03}",
        if latitude < 0 { 'S' } else { 'N' },
        latitude.unsigned_abs(),
        if longitude < 0 { 'W' } else { 'E' },
        longitude.unsigned_abs()
    )
}

/// How close to the shared lattice a tile's samples must lie, in samples.
const LATTICE_TOLERANCE_SAMPLES: f64 = 1e-3;

/// How close two tiles' pixel scales must be, relative.
const SCALE_TOLERANCE: f64 = 1e-9;

/// GeoTIFF tiles: placed by their georeference on one lattice, no gaps.
fn lay_out_geotiff(name: PathBuf, files: &[PathBuf]) -> Result<MosaicLayout, TerrainReadError> {
    let mut tiles = Vec::with_capacity(files.len());
    for path in files {
        let file = std::fs::File::open(path).map_err(|error| {
            TerrainReadError::new(path, format!("cannot read the tile: {error}"))
        })?;
        let placement = read_placement(path, std::io::BufReader::new(file))?;
        let Some(georeference) = placement.georeference else {
            return Err(TerrainReadError::new(
                path,
                "the GeoTIFF has no ModelTiepointTag and ModelPixelScaleTag: a GeoTIFF tile is \
                 placed by its georeference; expected both",
            ));
        };
        tiles.push(GeoreferencedTile {
            path: path.clone(),
            columns: placement.columns,
            rows: placement.rows,
            georeference,
            model: placement.model,
        });
    }
    lay_out_georeferenced(name, MosaicKind::GeoTiff, TerrainFormat::GeoTiff, &tiles)
}

/// A north-up tile's size and place, however its format says them.
pub(super) struct GeoreferencedTile {
    pub(super) path: PathBuf,
    pub(super) columns: usize,
    pub(super) rows: usize,
    pub(super) georeference: TiffGeoreference,
    pub(super) model: TiffModel,
}

/// Tiles placed by their georeference on one lattice (one pixel scale, one model), no gaps; the
/// spacing from the model as for one GeoTIFF.
pub(super) fn lay_out_georeferenced(
    name: PathBuf,
    kind: MosaicKind,
    format: TerrainFormat,
    tiles: &[GeoreferencedTile],
) -> Result<MosaicLayout, TerrainReadError> {
    let Some(first) = tiles.first() else {
        return Err(TerrainReadError::new(
            &name,
            "no tiles: expected at least one",
        ));
    };
    let ((scale_x, scale_y), model) = (first.georeference.scale, first.model);
    let close = |a: f64, b: f64| (a - b).abs() <= SCALE_TOLERANCE * a.abs().max(b.abs());
    for tile in &tiles[1..] {
        let (x, y) = tile.georeference.scale;
        if !(close(scale_x, x) && close(scale_y, y)) {
            return Err(TerrainReadError::new(
                &tile.path,
                format!(
                    "mixed resolutions: this tile's pixel scale is {x} × {y} but {}'s is \
                     {scale_x} × {scale_y}: expected tiles of one resolution (resampling is not \
                     done)",
                    first.path.display(),
                ),
            ));
        }
        if tile.model != model {
            return Err(TerrainReadError::new(
                &tile.path,
                format!(
                    "this tile's model is {:?} but {}'s is {model:?}: expected tiles in one \
                     coordinate system",
                    tile.model,
                    first.path.display()
                ),
            ));
        }
    }
    let west = tiles
        .iter()
        .map(|t| t.georeference.north_west_centre.0)
        .fold(f64::INFINITY, f64::min);
    let north = tiles
        .iter()
        .map(|t| t.georeference.north_west_centre.1)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut pieces = Vec::with_capacity(tiles.len());
    for tile in tiles {
        let (x, y) = tile.georeference.north_west_centre;
        let column = lattice_offset(&tile.path, (x - west) / scale_x, "east")?;
        let row = lattice_offset(&tile.path, (north - y) / scale_y, "south")?;
        pieces.push(Piece {
            path: tile.path.clone(),
            format,
            file_columns: tile.columns,
            file_rows: tile.rows,
            source: Window {
                column: 0,
                row: 0,
                columns: tile.columns,
                rows: tile.rows,
            },
            destination: Window {
                column,
                row,
                columns: tile.columns,
                rows: tile.rows,
            },
            nodata: None,
        });
    }
    let columns = extent(&name, &pieces, |w| (w.column, w.columns))?;
    let rows = extent(&name, &pieces, |w| (w.row, w.rows))?;
    if let Some(gap) = first_gap(columns, rows, &pieces) {
        let (x0, y0) = (
            west + gap.column as f64 * scale_x,
            north - gap.row as f64 * scale_y,
        );
        let (x1, y1) = (
            west + (gap.column + gap.columns - 1) as f64 * scale_x,
            north - (gap.row + gap.rows - 1) as f64 * scale_y,
        );
        return Err(TerrainReadError::new(
            &name,
            format!(
                "a gap: no tile covers {} of the {columns}×{rows} mosaic (sample centres x \
                 {x0} to {x1}, y {y0} to {y1} in the tiles' coordinates): expected tiles \
                 covering the whole rectangle",
                gap.describe()
            ),
        ));
    }
    let (spacing, spacing_note) = match model {
        TiffModel::Projected {
            metres_per_unit: Some(metres),
        } => (
            Some(Spacing {
                dx: scale_x * metres,
                dy: scale_y * metres,
            }),
            None,
        ),
        TiffModel::Projected {
            metres_per_unit: None,
        } => (
            None,
            Some(
                "the tiles' ProjLinearUnitsGeoKey names a unit the reader does not know"
                    .to_string(),
            ),
        ),
        TiffModel::Geographic => {
            // The north edge of the north row, less half the mosaic's height.
            let centre_latitude = north + scale_y / 2.0 - rows as f64 * scale_y / 2.0;
            if !(-90.0..=90.0).contains(&centre_latitude) {
                return Err(TerrainReadError::new(
                    &name,
                    format!(
                        "the geographic mosaic's centre lies at latitude {centre_latitude}°; \
                         expected −90° to 90°"
                    ),
                ));
            }
            let dy = scale_y * METRES_PER_DEGREE_LATITUDE;
            let dx = scale_x * METRES_PER_DEGREE_LATITUDE * centre_latitude.to_radians().cos();
            (Some(Spacing { dx, dy }), None)
        }
        TiffModel::Undeclared => (
            None,
            Some(
                "the tiles' GeoKeyDirectoryTag declares no model type (projected or \
                 geographic), so the units of their pixel scale are unknown"
                    .to_string(),
            ),
        ),
    };
    Ok(MosaicLayout {
        kind,
        name,
        columns,
        rows,
        pieces,
        spacing,
        spacing_note,
        nodata: None,
    })
}

/// A tile's offset in whole samples from the mosaic's north-west sample, or an error when it is
/// off the lattice.
fn lattice_offset(path: &Path, samples: f64, direction: &str) -> Result<usize, TerrainReadError> {
    let whole = samples.round();
    let on_lattice = (samples - whole).abs() <= LATTICE_TOLERANCE_SAMPLES;
    if !on_lattice || whole > i32::MAX as f64 {
        return Err(TerrainReadError::new(
            path,
            format!(
                "the tile's samples lie {samples:.3} samples {direction} of the mosaic's first \
                 ones, off their lattice: expected a whole number of samples (tiles that would \
                 need resampling are not read; one tile in PixelIsPoint and another in \
                 PixelIsArea gives half a sample)"
            ),
        ));
    }
    Ok(whole as usize)
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

/// A VRT: its sources' sizes from their headers, windows inside them, no gaps.
fn lay_out_vrt(path: &Path) -> Result<MosaicLayout, TerrainReadError> {
    let bytes = std::fs::read(path)
        .map_err(|error| TerrainReadError::new(path, format!("cannot read the file: {error}")))?;
    let vrt = parse_vrt_bytes(path, &bytes)?;
    let mut pieces = Vec::with_capacity(vrt.sources.len());
    for (k, source) in vrt.sources.iter().enumerate() {
        let source_error = |problem: String| {
            TerrainReadError::new(
                path,
                format!("source {} ({}): {problem}", k + 1, source.path.display()),
            )
        };
        let (format, file_columns, file_rows) = match kind_from_extension(&source.path) {
            Some(MosaicKind::Srtm) => {
                let n_bytes = file_length(&source.path)?;
                let side = hgt::tile_side(n_bytes).ok_or_else(|| {
                    TerrainReadError::new(
                        &source.path,
                        format!(
                            "{n_bytes} bytes is not the size of an SRTM tile: expected 2884802 \
                             bytes (SRTM3) or 25934402 bytes (SRTM1)"
                        ),
                    )
                })?;
                (TerrainFormat::Hgt, side, side)
            }
            Some(MosaicKind::GeoTiff) => {
                let file = std::fs::File::open(&source.path).map_err(|error| {
                    TerrainReadError::new(&source.path, format!("cannot read the tile: {error}"))
                })?;
                let placement = read_placement(&source.path, std::io::BufReader::new(file))?;
                (TerrainFormat::GeoTiff, placement.columns, placement.rows)
            }
            _ => {
                return Err(source_error(
                    "expected a .hgt, .tif or .tiff source (a nested .vrt or another format is \
                     not read)"
                        .to_string(),
                ));
            }
        };
        let source_window = source.source_window.unwrap_or(Window {
            column: 0,
            row: 0,
            columns: file_columns,
            rows: file_rows,
        });
        if source_window.column + source_window.columns > file_columns
            || source_window.row + source_window.rows > file_rows
        {
            return Err(source_error(format!(
                "its <SrcRect> {} reaches past the file's {file_columns}×{file_rows} samples: \
                 expected a window inside the file",
                source_window.describe()
            )));
        }
        let destination = source.destination_window.unwrap_or(Window {
            column: 0,
            row: 0,
            columns: vrt.columns,
            rows: vrt.rows,
        });
        if (destination.columns, destination.rows) != (source_window.columns, source_window.rows) {
            return Err(source_error(format!(
                "its source window {} and destination {} differ in size, which would resample: \
                 expected windows of the same size",
                source_window.describe(),
                destination.describe()
            )));
        }
        pieces.push(Piece {
            path: source.path.clone(),
            format,
            file_columns,
            file_rows,
            source: source_window,
            destination,
            nodata: source.nodata,
        });
    }
    if let Some(gap) = first_gap(vrt.columns, vrt.rows, &pieces) {
        return Err(TerrainReadError::new(
            path,
            format!(
                "a gap: no source covers {} of the {}×{} raster: expected sources covering the \
                 whole raster",
                gap.describe(),
                vrt.columns,
                vrt.rows
            ),
        ));
    }
    let (spacing, spacing_note) = vrt_spacing(path, &vrt)?;
    Ok(MosaicLayout {
        kind: MosaicKind::Vrt,
        name: path.to_path_buf(),
        columns: vrt.columns,
        rows: vrt.rows,
        pieces,
        spacing,
        spacing_note,
        nodata: vrt.nodata,
    })
}

/// A VRT's spacing from its GeoTransform and SRS, as an ASCII grid's from its cell size and
/// `.prj`: degrees converted at the centre latitude when the SRS is geographic, metres when it
/// is projected, none (with the reason) otherwise.
fn vrt_spacing(
    path: &Path,
    vrt: &VrtMosaic,
) -> Result<(Option<Spacing>, Option<String>), TerrainReadError> {
    let Some([_, step_x, _, top, _, step_y]) = vrt.geo_transform else {
        return Ok((None, Some("the VRT has no <GeoTransform>".to_string())));
    };
    let (dx, dy) = (step_x, -step_y);
    let srs = vrt.srs.as_deref().unwrap_or("");
    let upper = srs.to_ascii_uppercase();
    let geographic = super::ascii_grid::prj_is_geographic(srs)
        || upper == "EPSG:4326"
        || upper.contains("+PROJ=LONGLAT");
    let projected =
        super::ascii_grid::prj_is_projected(srs) || (upper.starts_with("+PROJ=") && !geographic);
    if geographic {
        let centre_latitude = top - dy * vrt.rows as f64 / 2.0;
        if !(-90.0..=90.0).contains(&centre_latitude) {
            return Err(TerrainReadError::new(
                path,
                format!(
                    "the <SRS> is geographic but the raster's centre lies at latitude \
                     {centre_latitude}° (from <GeoTransform>); expected −90° to 90°"
                ),
            ));
        }
        let spacing = Spacing {
            dx: dx * METRES_PER_DEGREE_LATITUDE * centre_latitude.to_radians().cos(),
            dy: dy * METRES_PER_DEGREE_LATITUDE,
        };
        let note = format!(
            "pixel size {dx}° × {dy}° (geographic, from the <SRS>) converted at the raster's \
             centre latitude {centre_latitude:.4}°: {:.3} m × {:.3} m",
            spacing.dx, spacing.dy
        );
        return Ok((Some(spacing), Some(note)));
    }
    if projected {
        return Ok((Some(Spacing { dx, dy }), None));
    }
    Ok((
        None,
        Some("the VRT's <SRS> says neither a geographic nor a projected system".to_string()),
    ))
}

/// Reads every file of a laid-out mosaic into one grid (row 0 the south edge, voids marked),
/// one file at a time, refusing overlaps that disagree. The format is the first file's.
pub fn read_mosaic(
    layout: &MosaicLayout,
    options: &ReadOptions,
) -> Result<LoadedTerrain, TerrainReadError> {
    for (name, value) in [
        ("height_scale", options.height_scale),
        ("height_offset", options.height_offset),
    ] {
        if !value.is_finite() {
            return Err(TerrainReadError::new(
                &layout.name,
                format!("the read option {name} is {value}; expected a finite number"),
            ));
        }
    }
    let (columns, rows) = (layout.columns, layout.rows);
    let n_samples = columns.checked_mul(rows).ok_or_else(|| {
        TerrainReadError::new(
            &layout.name,
            format!("a {columns}×{rows} mosaic has more samples than this machine can address"),
        )
    })?;
    // NaN marks a sample not yet placed or void: placed heights are finite.
    let mut heights: Vec<f32> = Vec::new();
    heights.try_reserve_exact(n_samples).map_err(|error| {
        TerrainReadError::new(
            &layout.name,
            format!(
                "cannot allocate the {columns}×{rows} mosaic ({} MB of heights): {error}",
                n_samples.saturating_mul(4) / 1_000_000
            ),
        )
    })?;
    heights.resize(n_samples, f32::NAN);
    for (k, piece) in layout.pieces.iter().enumerate() {
        let tile = read_piece(layout, piece, options)?;
        for row in 0..piece.source.rows {
            let tile_row = piece.file_rows - 1 - (piece.source.row + row);
            let mosaic_row_from_north = piece.destination.row + row;
            let mosaic_row = rows - 1 - mosaic_row_from_north;
            for column in 0..piece.source.columns {
                let value = tile[tile_row * piece.file_columns + piece.source.column + column];
                let mosaic_column = piece.destination.column + column;
                let slot = &mut heights[mosaic_row * columns + mosaic_column];
                if slot.is_nan() {
                    *slot = value;
                } else if !value.is_nan() && value != *slot {
                    let earlier: Vec<String> = layout.pieces[..k]
                        .iter()
                        .filter(|p| p.destination.contains(mosaic_column, mosaic_row_from_north))
                        .map(|p| p.path.display().to_string())
                        .collect();
                    return Err(TerrainReadError::new(
                        &piece.path,
                        format!(
                            "an overlap that disagrees: its sample at column {}, row {} (from \
                             its north-west corner, counted from 1) is {value} m, but {} has \
                             {} m at the same place (column {}, row {} of the mosaic): expected \
                             overlapping tiles to agree (or one of them to be void there)",
                            piece.source.column + column + 1,
                            piece.source.row + row + 1,
                            earlier.join(" or "),
                            *slot,
                            mosaic_column + 1,
                            mosaic_row_from_north + 1
                        ),
                    ));
                }
            }
        }
    }
    let mut void_indices = Vec::new();
    for (index, height) in heights.iter_mut().enumerate() {
        if height.is_nan() {
            *height = 0.0;
            void_indices.push(index);
        }
    }
    let grid = SampleGrid::new(columns, rows, heights, void_indices)
        .map_err(|error| TerrainReadError::new(&layout.name, error.to_string()))?;
    Ok(LoadedTerrain {
        grid,
        spacing: layout.spacing,
        spacing_note: layout.spacing_note.clone(),
        format: layout.pieces[0].format,
    })
}

/// One file's heights in its own grid (row 0 the south edge), scaled, NaN where void.
fn read_piece(
    layout: &MosaicLayout,
    piece: &Piece,
    options: &ReadOptions,
) -> Result<Vec<f32>, TerrainReadError> {
    // Read as stored with the first nodata marker; the others (the VRT's) and the scale are
    // applied here, exactly as the readers apply them (stored as f64 · scale + offset, as f32).
    let mut markers: Vec<f64> = [options.nodata, piece.nodata, layout.nodata]
        .into_iter()
        .flatten()
        .collect();
    markers.dedup_by(|a, b| a == b || (a.is_nan() && b.is_nan()));
    let as_stored = ReadOptions {
        height_scale: 1.0,
        height_offset: 0.0,
        nodata: markers.first().copied(),
    };
    let loaded = read_terrain(&piece.path, piece.format, &as_stored)?;
    let grid = loaded.grid;
    if (grid.width(), grid.height()) != (piece.file_columns, piece.file_rows) {
        return Err(TerrainReadError::new(
            &piece.path,
            format!(
                "the file holds {}×{} samples, but its header said {}×{} when the mosaic was \
                 laid out: expected it unchanged",
                grid.width(),
                grid.height(),
                piece.file_columns,
                piece.file_rows
            ),
        ));
    }
    let mut values = grid.heights().to_vec();
    for (index, value) in values.iter_mut().enumerate() {
        let stored = *value;
        let is_marked = markers
            .iter()
            .skip(1)
            .any(|&marker| stored == marker as f32);
        if is_marked {
            *value = f32::NAN;
            continue;
        }
        let height = (f64::from(stored) * options.height_scale + options.height_offset) as f32;
        if !height.is_finite() {
            return Err(TerrainReadError::new(
                &piece.path,
                format!(
                    "the sample at column {}, row {} (from the south-west) gives the height \
                     {height} m (value × height_scale + height_offset), outside the f32 range",
                    index % grid.width() + 1,
                    index / grid.width() + 1
                ),
            ));
        }
        *value = height;
    }
    for &index in grid.void_indices() {
        values[index] = f32::NAN;
    }
    Ok(values)
}
