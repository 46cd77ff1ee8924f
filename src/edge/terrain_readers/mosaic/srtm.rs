//! SRTM tiles as one mosaic: each tile placed by the south-west corner its name gives, one
//! resolution, a full rectangle of tiles sharing their edge posts (a missing tile is named by
//! its tile name), the spacing converted at the mosaic's centre latitude. Reads no height.

use super::{MosaicKind, MosaicLayout, Piece, Window, file_length};
use crate::edge::terrain_readers::{TerrainFormat, TerrainReadError, hgt};
use std::path::{Path, PathBuf};

/// SRTM tiles: placed by their names, one resolution, a full rectangle of tiles.
pub(super) fn lay_out_srtm(
    name: PathBuf,
    files: &[PathBuf],
) -> Result<MosaicLayout, TerrainReadError> {
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
