//! GeoTIFF tiles (and, with the `gdal` feature, files of any format GDAL opens) as one mosaic:
//! placed by their georeference on one sample lattice, one pixel scale and one model, no gaps;
//! the spacing from the model as for one GeoTIFF. Reads no height.

use super::{MosaicKind, MosaicLayout, Piece, Window, extent, first_gap};
use crate::edge::terrain_readers::geotiff::{TiffGeoreference, TiffModel, read_placement};
use crate::edge::terrain_readers::{METRES_PER_DEGREE_LATITUDE, TerrainFormat, TerrainReadError};
use crate::sim::terrain::Spacing;
use std::path::{Path, PathBuf};

/// How close to the shared lattice a tile's samples must lie, in samples.
const LATTICE_TOLERANCE_SAMPLES: f64 = 1e-3;

/// How close two tiles' pixel scales must be, relative.
const SCALE_TOLERANCE: f64 = 1e-9;

/// GeoTIFF tiles: placed by their georeference on one lattice, no gaps.
pub(super) fn lay_out_geotiff(
    name: PathBuf,
    files: &[PathBuf],
) -> Result<MosaicLayout, TerrainReadError> {
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
pub(in crate::edge::terrain_readers) struct GeoreferencedTile {
    pub(in crate::edge::terrain_readers) path: PathBuf,
    pub(in crate::edge::terrain_readers) columns: usize,
    pub(in crate::edge::terrain_readers) rows: usize,
    pub(in crate::edge::terrain_readers) georeference: TiffGeoreference,
    pub(in crate::edge::terrain_readers) model: TiffModel,
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
        super::file_length(path)?;
        tiles.push(crate::edge::terrain_readers::gdal_raster::georeferenced_tile(path)?);
    }
    lay_out_georeferenced(name, MosaicKind::Gdal, TerrainFormat::Gdal, &tiles)
}
