//! The SRTM `.hgt` reader: a headerless square of big-endian int16 metres, north row first
//! (SPEC §11's tiles; the options it takes: `docs/experiment-format.md`, "Terrain"). The rows
//! are turned over so that grid row 0 is the south edge, as every reader's grid is. It does not
//! fill voids: the core does (`sim::terrain::fill`).
//!
//! The size comes from the byte length alone: 1201² samples (SRTM3, 3″ posts) or 3601² (SRTM1,
//! 1″ posts). −32768 marks a void. The spacing is derived from the tile name (`N48E009.hgt`)
//! when it parses as one; the reader does not look at neighbouring tiles, and it does not drop
//! the row and column every tile shares with its neighbours. Placing tiles by their names and
//! joining them on those shared edges is the mosaic's (`mosaic/`), which uses this module's
//! tile names, sizes and spacing.

use super::{
    FileRowOrder, METRES_PER_DEGREE_LATITUDE, ReadOptions, SampleCollector, StoredPrecision,
    TerrainReadError,
};
use crate::sim::terrain::{SampleGrid, Spacing};
use std::path::Path;

/// Reads an SRTM tile; the spacing is `None` when the file name is not a tile name.
pub(super) fn read(
    path: &Path,
    bytes: &[u8],
    options: &ReadOptions,
) -> Result<(SampleGrid, Option<Spacing>), TerrainReadError> {
    let tile = SrtmTileKind::from_byte_length(bytes.len()).ok_or_else(|| {
        TerrainReadError::new(
            path,
            format!(
                "{} bytes is not the size of an SRTM tile: expected {} bytes (SRTM3, {}×{} \
                 big-endian int16 samples) or {} bytes (SRTM1, {}×{})",
                bytes.len(),
                SrtmTileKind::Srtm3.byte_length(),
                SrtmTileKind::Srtm3.side(),
                SrtmTileKind::Srtm3.side(),
                SrtmTileKind::Srtm1.byte_length(),
                SrtmTileKind::Srtm1.side(),
                SrtmTileKind::Srtm1.side(),
            ),
        )
    })?;
    let side = tile.side();
    let mut collector = SampleCollector::new(
        path,
        side,
        side,
        FileRowOrder::NorthFirst,
        StoredPrecision::Exact,
        Some(f64::from(SRTM_VOID)),
        options,
    )?;
    for sample_bytes in bytes.chunks_exact(2) {
        let stored = i16::from_be_bytes([sample_bytes[0], sample_bytes[1]]);
        collector.push(f64::from(stored))?;
    }
    let grid = collector.finish()?;
    let spacing = tile_south_latitude(path).map(|south_latitude| tile.spacing(south_latitude));
    Ok((grid, spacing))
}

/// The stored value SRTM uses for a void.
const SRTM_VOID: i16 = -32768;

/// The two SRTM tile sizes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SrtmTileKind {
    /// 1201×1201 posts, 3 arc-seconds apart.
    Srtm3,
    /// 3601×3601 posts, 1 arc-second apart.
    Srtm1,
}

impl SrtmTileKind {
    fn from_byte_length(n_bytes: usize) -> Option<SrtmTileKind> {
        [SrtmTileKind::Srtm3, SrtmTileKind::Srtm1]
            .into_iter()
            .find(|kind| kind.byte_length() == n_bytes)
    }

    fn side(self) -> usize {
        match self {
            SrtmTileKind::Srtm3 => 1201,
            SrtmTileKind::Srtm1 => 3601,
        }
    }

    fn byte_length(self) -> usize {
        2 * self.side() * self.side()
    }

    fn post_spacing_arc_seconds(self) -> f64 {
        match self {
            SrtmTileKind::Srtm3 => 3.0,
            SrtmTileKind::Srtm1 => 1.0,
        }
    }

    /// Spacing in metres: dy is the post spacing in arc-seconds times the mean metres per
    /// arc-second of latitude (111 120 / 3600 ≈ 30.87 m); dx shrinks with the cosine of the
    /// latitude of the tile centre, half a degree north of its south edge (N48 → 48.5°,
    /// S12 → −11.5°).
    fn spacing(self, south_latitude_degrees: i32) -> Spacing {
        self.spacing_at(f64::from(south_latitude_degrees) + 0.5)
    }

    /// Spacing in metres at a given latitude (a mosaic's centre: `mosaic/srtm.rs`).
    fn spacing_at(self, centre_latitude_degrees: f64) -> Spacing {
        let dy = self.post_spacing_arc_seconds() * METRES_PER_DEGREE_LATITUDE / 3600.0;
        let dx = dy * centre_latitude_degrees.to_radians().cos();
        Spacing { dx, dy }
    }
}

/// The side in posts (1201 or 3601) of an SRTM tile of `n_bytes` bytes, if that is a tile size.
pub(super) fn tile_side(n_bytes: u64) -> Option<usize> {
    let n_bytes = usize::try_from(n_bytes).ok()?;
    SrtmTileKind::from_byte_length(n_bytes).map(SrtmTileKind::side)
}

/// The spacing in metres of tiles of `side` posts (1201 or 3601) at a latitude, as one tile's is
/// at its centre; `None` for another side.
pub(super) fn spacing_at(side: usize, centre_latitude_degrees: f64) -> Option<Spacing> {
    [SrtmTileKind::Srtm3, SrtmTileKind::Srtm1]
        .into_iter()
        .find(|kind| kind.side() == side)
        .map(|kind| kind.spacing_at(centre_latitude_degrees))
}

/// The latitude of a tile's south edge in whole degrees (south negative), from a file name that
/// starts with `[NS]dd[EW]ddd` (case-insensitive) up to its first dot: `N48E009.hgt` → 48,
/// `s01w072.HGT` → −1. Names that are not a tile, or name a tile outside the globe (N90, E180),
/// give `None`.
fn tile_south_latitude(path: &Path) -> Option<i32> {
    tile_corner(path).map(|(south_latitude_degrees, _)| south_latitude_degrees)
}

/// The south-west corner of a tile in whole degrees (latitude, longitude; south and west
/// negative) from its file name, as [`tile_south_latitude`] reads it.
pub(super) fn tile_corner(path: &Path) -> Option<(i32, i32)> {
    let file_name = path.file_name()?.to_str()?;
    let stem = file_name.split('.').next()?.as_bytes();
    if stem.len() != 7 {
        return None;
    }
    let latitude_sign = match stem[0].to_ascii_uppercase() {
        b'N' => 1,
        b'S' => -1,
        _ => return None,
    };
    let longitude_sign = match stem[3].to_ascii_uppercase() {
        b'E' => 1,
        b'W' => -1,
        _ => return None,
    };
    let latitude = parse_digits(&stem[1..3])?;
    let longitude = parse_digits(&stem[4..7])?;
    let south_latitude_degrees = latitude_sign * latitude;
    let west_longitude_degrees = longitude_sign * longitude;
    // A tile spans one degree north and east of its corner.
    let on_globe = (-90..=89).contains(&south_latitude_degrees)
        && (-180..=179).contains(&west_longitude_degrees);
    on_globe.then_some((south_latitude_degrees, west_longitude_degrees))
}

fn parse_digits(digits: &[u8]) -> Option<i32> {
    digits.iter().try_fold(0_i32, |value, &digit| {
        digit
            .is_ascii_digit()
            .then(|| value * 10 + i32::from(digit - b'0'))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn srtm3_bytes(sample_at: impl Fn(usize, usize) -> i16) -> Vec<u8> {
        let side = SrtmTileKind::Srtm3.side();
        let mut bytes = Vec::with_capacity(2 * side * side);
        for file_row in 0..side {
            for column in 0..side {
                bytes.extend_from_slice(&sample_at(file_row, column).to_be_bytes());
            }
        }
        bytes
    }

    #[test]
    fn rows_are_flipped_and_voids_marked() {
        let bytes = srtm3_bytes(|file_row, column| match (file_row, column) {
            (0, 0) => 1000,
            (1200, 5) => SRTM_VOID,
            _ => 10,
        });
        let (grid, spacing) =
            read(Path::new("N00E000.hgt"), &bytes, &ReadOptions::AS_STORED).unwrap();
        assert_eq!((grid.width(), grid.height()), (1201, 1201));
        assert_eq!(grid.height_at(0, 1200), 1000.0);
        assert_eq!(grid.void_indices(), &[5]);
        let spacing = spacing.unwrap();
        assert!((spacing.dy - 92.6).abs() < 1e-9);
        assert!((spacing.dx - 92.6 * 0.5_f64.to_radians().cos()).abs() < 1e-9);
    }

    #[test]
    fn scale_offset_and_caller_nodata_apply() {
        let bytes = srtm3_bytes(|file_row, _| if file_row == 0 { 7 } else { 2 });
        let options = ReadOptions {
            height_scale: 0.5,
            height_offset: 100.0,
            nodata: Some(7.0),
        };
        let (grid, _) = read(Path::new("tile.hgt"), &bytes, &options).unwrap();
        assert_eq!(grid.height_at(0, 0), 101.0);
        assert_eq!(grid.void_indices().len(), 1201);
        assert_eq!(grid.void_indices()[0], 1200 * 1201);
    }

    #[test]
    fn wrong_length_names_both_tile_sizes() {
        let error = read(Path::new("N48E009.hgt"), &[0; 100], &ReadOptions::AS_STORED)
            .unwrap_err()
            .to_string();
        assert!(error.contains("N48E009.hgt"), "{error}");
        assert!(error.contains("100 bytes"), "{error}");
        assert!(error.contains("2884802"), "{error}");
        assert!(error.contains("25934402"), "{error}");
    }

    #[test]
    fn tile_names_parse_in_any_case_and_hemisphere() {
        let corner = |name: &str| tile_south_latitude(Path::new(name));
        assert_eq!(corner("N48E009.hgt"), Some(48));
        assert_eq!(corner("data/s01w072.HGT"), Some(-1));
        assert_eq!(corner("S90W180.SRTMGL1.hgt"), Some(-90));
        assert_eq!(corner("N90E000.hgt"), None);
        assert_eq!(corner("N48E180.hgt"), None);
        assert_eq!(corner("N4xE009.hgt"), None);
        assert_eq!(corner("N48E0091.hgt"), None);
        assert_eq!(corner("terrain.hgt"), None);
    }

    #[test]
    fn southern_tiles_use_the_latitude_of_their_centre() {
        // S12 spans 12°S..11°S: its centre is at 11.5°S.
        let south_latitude = tile_south_latitude(Path::new("S12E130.hgt")).unwrap();
        assert_eq!(south_latitude, -12);
        let spacing = SrtmTileKind::Srtm1.spacing(south_latitude);
        let dy = METRES_PER_DEGREE_LATITUDE / 3600.0;
        assert!((spacing.dy - dy).abs() < 1e-12);
        assert!((spacing.dx - dy * 11.5_f64.to_radians().cos()).abs() < 1e-12);
    }
}
