//! A GDAL VRT as a mosaic: its sources' sizes from their headers, their windows inside them
//! (`../vrt.rs` parses the XML), no gaps, and the spacing from its GeoTransform and SRS. Reads
//! no height.

use super::{MosaicKind, MosaicLayout, Piece, Window, file_length, first_gap, kind_from_extension};
use crate::edge::terrain_readers::geotiff::read_placement;
use crate::edge::terrain_readers::vrt::{VrtMosaic, parse_vrt_bytes};
use crate::edge::terrain_readers::{
    METRES_PER_DEGREE_LATITUDE, TerrainFormat, TerrainReadError, ascii_grid, hgt,
};
use crate::sim::terrain::Spacing;
use std::path::Path;

/// A VRT: its sources' sizes from their headers, windows inside them, no gaps.
pub(super) fn lay_out_vrt(path: &Path) -> Result<MosaicLayout, TerrainReadError> {
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
    let geographic = ascii_grid::prj_is_geographic(srs)
        || upper == "EPSG:4326"
        || upper.contains("+PROJ=LONGLAT");
    let projected =
        ascii_grid::prj_is_projected(srs) || (upper.starts_with("+PROJ=") && !geographic);
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
