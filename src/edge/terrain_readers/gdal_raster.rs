//! The GDAL reader (the `gdal` cargo feature, off by default): band 1 of any raster the
//! system's libgdal opens (Cloud-Optimized GeoTIFFs, Erdas IMG, NetCDF, VRTs with resampling,
//! SRTM tiles, …), as `"format": "gdal"` of a terrain file or of a mosaic's tiles (the options:
//! `docs/experiment-format.md`, "Terrain" and "Mosaics"). It gives the same [`SampleGrid`] as the
//! pure-Rust readers (row 0 the south edge, voids marked, every failure a [`TerrainReadError`]
//! naming the file): `tests/terrain_mosaic.rs` checks that both read the shipped tile and its
//! cuts to the same bits.
//!
//! **GDAL's conventions, as GDAL states them.** Nodata is the band's no-data value; the place
//! is the dataset's GeoTransform (the corner of the north-west pixel, GDAL's pixel-is-area
//! convention, whatever the file stores); the spacing is its step, in degrees converted at the
//! raster's centre latitude when the dataset's spatial reference is geographic, in the
//! projection's linear unit converted to metres when projected, and none otherwise. The band's
//! scale and offset metadata are not applied (give `height_scale`/`height_offset_m`), and
//! nothing is reprojected. Rows are read in blocks of [`ROWS_PER_READ`], so the raster is held
//! once, as f32.

use super::geotiff::{TiffGeoreference, TiffModel};
use super::mosaic::GeoreferencedTile;
use super::{
    FileRowOrder, METRES_PER_DEGREE_LATITUDE, ReadOptions, SampleCollector, StoredPrecision,
    TerrainReadError,
};
use crate::sim::terrain::{SampleGrid, Spacing};
use gdal::raster::GdalDataType;
use gdal::{Dataset, DatasetOptions, GdalOpenFlags};
use std::path::Path;

/// Rows read from GDAL at a time, as f64, before they are collected as f32.
const ROWS_PER_READ: usize = 256;

/// Reads band 1 of a raster GDAL opens; the spacing is `None` (with the reason) when its
/// georeference does not give one.
pub(super) fn read(
    path: &Path,
    options: &ReadOptions,
) -> Result<(SampleGrid, Option<Spacing>, Option<String>), TerrainReadError> {
    let gdal_error =
        |error: gdal::errors::GdalError| TerrainReadError::new(path, format!("GDAL: {error}"));
    let dataset = open(path)?;
    let (columns, rows) = dataset.raster_size();
    let band = dataset.rasterband(1).map_err(gdal_error)?;
    let precision = match band.band_type() {
        GdalDataType::Float32 => StoredPrecision::Float32,
        _ => StoredPrecision::Exact,
    };
    let geo_transform = dataset.geo_transform().ok();
    let row_order = match geo_transform {
        Some(transform) if transform[5] > 0.0 => FileRowOrder::SouthFirst,
        _ => FileRowOrder::NorthFirst,
    };
    let mut collector = SampleCollector::new(
        path,
        columns,
        rows,
        row_order,
        precision,
        band.no_data_value(),
        options,
    )?;
    let mut row = 0;
    while row < rows {
        let n_rows = ROWS_PER_READ.min(rows - row);
        let buffer = band
            .read_as::<f64>(
                (0, row as isize),
                (columns, n_rows),
                (columns, n_rows),
                None,
            )
            .map_err(gdal_error)?;
        for &stored in buffer.data() {
            collector.push(stored)?;
        }
        row += n_rows;
    }
    let grid = collector.finish()?;
    let (spacing, note) = spacing(path, &dataset, rows)?;
    Ok((grid, spacing, note))
}

/// A raster's size and place for a mosaic (`mosaic/`), from GDAL's GeoTransform and spatial
/// reference; no sample is read.
pub(super) fn georeferenced_tile(path: &Path) -> Result<GeoreferencedTile, TerrainReadError> {
    let dataset = open(path)?;
    let (columns, rows) = dataset.raster_size();
    let transform = dataset.geo_transform().map_err(|error| {
        TerrainReadError::new(
            path,
            format!(
                "GDAL finds no georeference ({error}): a tile is placed by its GeoTransform; \
                 expected one"
            ),
        )
    })?;
    let [x0, step_x, rotation_x, y0, rotation_y, step_y] = transform;
    if rotation_x != 0.0 || rotation_y != 0.0 || step_x <= 0.0 || step_y >= 0.0 {
        return Err(TerrainReadError::new(
            path,
            format!(
                "its GeoTransform is {transform:?}: rotated, sheared or south-up rasters cannot \
                 be placed in a mosaic; expected a north-up raster"
            ),
        ));
    }
    let model = match dataset.spatial_ref() {
        Ok(srs) if srs.is_geographic() => TiffModel::Geographic,
        Ok(srs) if srs.is_projected() => TiffModel::Projected {
            metres_per_unit: Some(srs.linear_units()).filter(|m| m.is_finite() && *m > 0.0),
        },
        _ => TiffModel::Undeclared,
    };
    Ok(GeoreferencedTile {
        path: path.to_path_buf(),
        columns,
        rows,
        georeference: TiffGeoreference {
            scale: (step_x, -step_y),
            // GDAL's GeoTransform names the corner of the north-west pixel.
            north_west_centre: (x0 + step_x / 2.0, y0 + step_y / 2.0),
        },
        model,
    })
}

fn open(path: &Path) -> Result<Dataset, TerrainReadError> {
    let options = DatasetOptions {
        open_flags: GdalOpenFlags::GDAL_OF_RASTER | GdalOpenFlags::GDAL_OF_READONLY,
        ..DatasetOptions::default()
    };
    let dataset = Dataset::open_ex(path, options).map_err(|error| {
        TerrainReadError::new(path, format!("GDAL cannot open it as a raster: {error}"))
    })?;
    if dataset.raster_count() == 0 {
        return Err(TerrainReadError::new(
            path,
            "GDAL finds no raster band: expected at least one (band 1 is read)",
        ));
    }
    Ok(dataset)
}

/// The spacing in metres from the GeoTransform and spatial reference, or why there is none.
fn spacing(
    path: &Path,
    dataset: &Dataset,
    rows: usize,
) -> Result<(Option<Spacing>, Option<String>), TerrainReadError> {
    let Ok([_, step_x, rotation_x, top, rotation_y, step_y]) = dataset.geo_transform() else {
        return Ok((None, Some("GDAL finds no GeoTransform".to_string())));
    };
    if rotation_x != 0.0 || rotation_y != 0.0 {
        return Ok((
            None,
            Some("its GeoTransform is rotated or sheared (not read)".to_string()),
        ));
    }
    let (dx, dy) = (step_x.abs(), step_y.abs());
    match dataset.spatial_ref() {
        Ok(srs) if srs.is_geographic() => {
            let centre_latitude = top + step_y * rows as f64 / 2.0;
            if !(-90.0..=90.0).contains(&centre_latitude) {
                return Err(TerrainReadError::new(
                    path,
                    format!(
                        "its spatial reference is geographic but its centre lies at latitude \
                         {centre_latitude}° (from the GeoTransform); expected −90° to 90°"
                    ),
                ));
            }
            let spacing = Spacing {
                dx: dx * METRES_PER_DEGREE_LATITUDE * centre_latitude.to_radians().cos(),
                dy: dy * METRES_PER_DEGREE_LATITUDE,
            };
            let note = format!(
                "pixel size {dx}° × {dy}° (geographic, from GDAL) converted at the raster's \
                 centre latitude {centre_latitude:.4}°: {:.3} m × {:.3} m",
                spacing.dx, spacing.dy
            );
            Ok((Some(spacing), Some(note)))
        }
        Ok(srs) if srs.is_projected() => {
            let metres = srs.linear_units();
            if metres.is_finite() && metres > 0.0 {
                Ok((
                    Some(Spacing {
                        dx: dx * metres,
                        dy: dy * metres,
                    }),
                    None,
                ))
            } else {
                Ok((
                    None,
                    Some("GDAL gives its projection no linear unit".to_string()),
                ))
            }
        }
        _ => Ok((
            None,
            Some("GDAL finds no geographic or projected spatial reference".to_string()),
        )),
    }
}
