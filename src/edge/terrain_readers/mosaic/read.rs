//! Reading a laid-out mosaic: every file in turn into the one assembled grid, holding one file
//! beside it, overlaps checked sample by sample (a void yields, a disagreement is refused
//! naming both files and the sample).

use super::{MosaicLayout, Piece};
use crate::edge::terrain_readers::{LoadedTerrain, ReadOptions, TerrainReadError, read_terrain};
use crate::sim::terrain::SampleGrid;

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
