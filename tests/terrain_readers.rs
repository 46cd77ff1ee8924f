//! Integration tests of the terrain readers: the real SRTM tile in `experiments/data`, round
//! trips through the `png` and `tiff` encoders, and broken files of every format, each of which
//! must give an error that names the file and the problem (SPEC §9's last case, §11).
//!
//! These tests go through the public API only (`read_terrain`, `format_from_extension`); the
//! readers' own unit tests cover their internals.

use roamsim::edge::terrain_readers::{
    RawLayout, RawSample, ReadOptions, TerrainFormat, TerrainReadError, format_from_extension,
    read_terrain,
};
use std::io::Cursor;
use std::path::{Path, PathBuf};
use tiff::encoder::{TiffEncoder, colortype};
use tiff::tags::Tag;

const SRTM3_SIDE: usize = 1201;

fn real_tile_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/data/N48E009.hgt")
}

/// Writes `bytes` to `name` in a fresh temporary directory, which the caller keeps alive.
fn temporary_file(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (directory, path)
}

/// Reads `bytes` written to a file called `name`; the error, if any, as its message.
fn read_bytes(
    name: &str,
    bytes: &[u8],
    format: TerrainFormat,
    options: &ReadOptions,
) -> Result<roamsim::edge::terrain_readers::LoadedTerrain, String> {
    let (_directory, path) = temporary_file(name, bytes);
    read_terrain(&path, format, options).map_err(|error: TerrainReadError| {
        assert_eq!(error.path, path, "the error must name the file it read");
        error.to_string()
    })
}

/// Asserts that reading fails with a message naming the file and containing every fragment.
fn check_error(name: &str, bytes: &[u8], format: TerrainFormat, fragments: &[&str]) {
    let message = match read_bytes(name, bytes, format, &ReadOptions::AS_STORED) {
        Ok(_) => panic!("{name}: expected an error"),
        Err(message) => message,
    };
    assert!(
        message.contains(name),
        "the message must name {name}: {message}"
    );
    for fragment in fragments {
        assert!(
            message.contains(fragment),
            "expected '{fragment}' in: {message}"
        );
    }
}

#[test]
fn the_real_srtm3_tile_reads_with_its_voids_range_and_spacing() {
    let path = real_tile_path();
    let loaded = read_terrain(&path, TerrainFormat::Hgt, &ReadOptions::AS_STORED).unwrap();
    let grid = &loaded.grid;
    assert_eq!((grid.width(), grid.height()), (SRTM3_SIDE, SRTM3_SIDE));
    assert_eq!(grid.height_range(), Some((173.0, 977.0)));
    assert_eq!(grid.void_indices().len(), 21);
    let spacing = loaded.spacing.expect("N48E009 is a tile name");
    assert!((spacing.dy - 92.6).abs() < 1e-6, "dy = {}", spacing.dy);
    let expected_dx = 92.6 * 48.5_f64.to_radians().cos();
    assert!(
        (spacing.dx - expected_dx).abs() < 1e-6,
        "dx = {}",
        spacing.dx
    );
    assert!((spacing.dx - 61.4).abs() < 0.1, "dx = {}", spacing.dx);
}

#[test]
fn the_real_tile_is_flipped_so_its_first_sample_is_the_north_west_corner() {
    let path = real_tile_path();
    let bytes = std::fs::read(&path).unwrap();
    let loaded = read_terrain(&path, TerrainFormat::Hgt, &ReadOptions::AS_STORED).unwrap();
    let last_row = SRTM3_SIDE - 1;
    for (column, file_offset) in [(0, 0), (1, 2), (SRTM3_SIDE - 1, 2 * (SRTM3_SIDE - 1))] {
        let stored = i16::from_be_bytes([bytes[file_offset], bytes[file_offset + 1]]);
        assert_ne!(stored, -32768, "pick a corner sample that is not a void");
        assert_eq!(loaded.grid.height_at(column, last_row), f32::from(stored));
    }
    // And the last sample in the file is the south-east corner.
    let offset = bytes.len() - 2;
    let stored = i16::from_be_bytes([bytes[offset], bytes[offset + 1]]);
    assert_eq!(loaded.grid.height_at(SRTM3_SIDE - 1, 0), f32::from(stored));
}

#[test]
fn a_truncated_hgt_reports_its_length_and_the_expected_ones() {
    let mut bytes = std::fs::read(real_tile_path()).unwrap();
    bytes.truncate(bytes.len() - 1);
    check_error(
        "N48E009.hgt",
        &bytes,
        TerrainFormat::Hgt,
        &[
            "2884801 bytes",
            "2884802 bytes (SRTM3",
            "25934402 bytes (SRTM1",
        ],
    );
}

#[test]
fn a_wrong_size_hgt_is_not_an_srtm_tile() {
    check_error(
        "N10E010.hgt",
        &vec![0; 2 * 1000 * 1000],
        TerrainFormat::Hgt,
        &["2000000 bytes is not the size of an SRTM tile"],
    );
}

#[test]
fn an_hgt_that_is_not_a_tile_name_has_no_spacing() {
    let bytes = vec![0; 2 * SRTM3_SIDE * SRTM3_SIDE];
    let loaded = read_bytes(
        "alps.hgt",
        &bytes,
        TerrainFormat::Hgt,
        &ReadOptions::AS_STORED,
    );
    assert_eq!(loaded.unwrap().spacing, None);
}

fn encode_png(
    columns: u32,
    rows: u32,
    color_type: png::ColorType,
    bit_depth: png::BitDepth,
    data: &[u8],
) -> Vec<u8> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, columns, rows);
    encoder.set_color(color_type);
    encoder.set_depth(bit_depth);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(data).unwrap();
    writer.finish().unwrap();
    bytes
}

#[test]
fn an_rgb_png_is_refused_by_colour_type() {
    let bytes = encode_png(3, 3, png::ColorType::Rgb, png::BitDepth::Eight, &[0; 27]);
    check_error(
        "photo.png",
        &bytes,
        TerrainFormat::Png,
        &["8-bit RGB", "expected 8- or 16-bit grayscale"],
    );
}

#[test]
fn a_sixteen_bit_png_round_trips_flipped_and_scaled() {
    let (columns, rows) = (5_usize, 4_usize);
    let stored: Vec<u16> = (0..columns * rows).map(|i| 3000 * i as u16 + 1).collect();
    let data: Vec<u8> = stored
        .iter()
        .flat_map(|value| value.to_be_bytes())
        .collect();
    let bytes = encode_png(
        5,
        4,
        png::ColorType::Grayscale,
        png::BitDepth::Sixteen,
        &data,
    );
    let options = ReadOptions {
        height_scale: 0.1,
        height_offset: -100.0,
        nodata: Some(f64::from(stored[7])),
    };
    let loaded = read_bytes("heights.png", &bytes, TerrainFormat::Png, &options).unwrap();
    let grid = &loaded.grid;
    assert_eq!((grid.width(), grid.height()), (columns, rows));
    assert_eq!(loaded.spacing, None);
    for file_row in 0..rows {
        for column in 0..columns {
            let index_in_file = file_row * columns + column;
            if index_in_file == 7 {
                continue;
            }
            let expected = (f64::from(stored[index_in_file]) * 0.1 - 100.0) as f32;
            assert_eq!(grid.height_at(column, rows - 1 - file_row), expected);
        }
    }
    // File row 1, column 2 is grid row 2 (of 0..4), column 2.
    assert_eq!(grid.void_indices(), &[2 * columns + 2]);
}

/// A float32 TIFF with an optional GDAL_NODATA text.
fn float_tiff(columns: u32, rows: u32, values: &[f32], nodata: Option<&str>) -> Vec<u8> {
    let mut cursor = Cursor::new(Vec::new());
    let mut encoder = TiffEncoder::new(&mut cursor).unwrap();
    let mut image = encoder
        .new_image::<colortype::Gray32Float>(columns, rows)
        .unwrap();
    if let Some(nodata) = nodata {
        image.encoder().write_tag(Tag::GdalNodata, nodata).unwrap();
    }
    image.write_data(values).unwrap();
    cursor.into_inner()
}

#[test]
fn a_float_geotiff_nan_that_is_not_nodata_is_an_error() {
    let mut values = [250.0_f32; 12];
    values[6] = f32::NAN; // file row 2 of 3, column 3 of 4
    let bytes = float_tiff(4, 3, &values, Some("-9999"));
    check_error(
        "dem.tif",
        &bytes,
        TerrainFormat::GeoTiff,
        &[
            "row 2 of 3 (counted from the north edge, as stored), column 3 of 4",
            "stored value is NaN",
            "nodata value (-9999)",
        ],
    );
}

#[test]
fn a_float_geotiff_nan_declared_by_gdal_nodata_is_a_void() {
    let mut values = [250.0_f32; 12];
    values[6] = f32::NAN;
    let bytes = float_tiff(4, 3, &values, Some("nan"));
    let loaded = read_bytes(
        "dem.tif",
        &bytes,
        TerrainFormat::GeoTiff,
        &ReadOptions::AS_STORED,
    )
    .unwrap();
    // File row 1 (from 0) of a 3-row file is grid row 1; column 2.
    assert_eq!(loaded.grid.void_indices(), &[4 + 2]);
    assert_eq!(loaded.grid.height_range(), Some((250.0, 250.0)));
}

#[test]
fn an_int16_geotiff_round_trips_with_its_gdal_nodata_and_spacing() {
    let (columns, rows) = (4_u32, 3_u32);
    let values: Vec<i16> = vec![-5, 0, 7, -32768, 100, 200, 300, 400, 1, 2, 3, 4];
    let mut cursor = Cursor::new(Vec::new());
    let mut encoder = TiffEncoder::new(&mut cursor).unwrap();
    let mut image = encoder
        .new_image::<colortype::GrayI16>(columns, rows)
        .unwrap();
    let directory = image.encoder();
    directory.write_tag(Tag::GdalNodata, "-32768").unwrap();
    directory
        .write_tag(Tag::ModelPixelScaleTag, &[25.0_f64, 20.0, 0.0][..])
        .unwrap();
    directory
        .write_tag(
            Tag::GeoKeyDirectoryTag,
            &[1_u16, 1, 0, 1, 1024, 0, 1, 1][..],
        )
        .unwrap();
    image.write_data(&values).unwrap();
    let bytes = cursor.into_inner();

    let loaded = read_bytes(
        "dem.tif",
        &bytes,
        TerrainFormat::GeoTiff,
        &ReadOptions::AS_STORED,
    )
    .unwrap();
    let grid = &loaded.grid;
    assert_eq!((grid.width(), grid.height()), (4, 3));
    assert_eq!(grid.height_at(0, 2), -5.0);
    assert_eq!(grid.height_at(3, 0), 4.0);
    assert_eq!(grid.height_at(1, 1), 200.0);
    assert_eq!(grid.void_indices(), &[2 * 4 + 3]);
    let spacing = loaded.spacing.unwrap();
    assert_eq!((spacing.dx, spacing.dy), (25.0, 20.0));
}

const ASC_HEADER: &str = "ncols 5\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 10\n";

#[test]
fn an_ascii_grid_without_nrows_names_the_key() {
    let text = "ncols 5\nxllcorner 0\nyllcorner 0\ncellsize 10\n1 2 3 4 5\n";
    check_error(
        "grid.asc",
        text.as_bytes(),
        TerrainFormat::AsciiGrid,
        &[
            "the header has no nrows",
            "expected nrows, found '1' on line 5",
        ],
    );
}

#[test]
fn an_ascii_grid_with_a_short_row_names_the_row() {
    let text = format!("{ASC_HEADER}1 2 3 4 5\n1 2 3 4\n1 2 3 4 5\n");
    check_error(
        "grid.asc",
        text.as_bytes(),
        TerrainFormat::AsciiGrid,
        &["row 2 of 3 (line 7) has 4 values, expected 5"],
    );
}

#[test]
fn an_ascii_grid_with_a_non_number_names_the_value() {
    let text = format!("{ASC_HEADER}1 2 3 4 5\n1 2 3 4 5\n1 2 3 four 5\n");
    check_error(
        "grid.asc",
        text.as_bytes(),
        TerrainFormat::AsciiGrid,
        &[
            "row 3 of 3",
            "column 4 of 5",
            "expected a number, found 'four'",
        ],
    );
}

#[test]
fn an_ascii_grid_reads_with_its_cell_size() {
    let text = format!("{ASC_HEADER}1 2 3 4 5\n6 7 8 9 10\n11 12 13 14 15\n");
    let loaded = read_bytes(
        "grid.asc",
        text.as_bytes(),
        TerrainFormat::AsciiGrid,
        &ReadOptions::AS_STORED,
    )
    .unwrap();
    assert_eq!(loaded.grid.height_at(0, 0), 11.0);
    assert_eq!(loaded.grid.height_at(4, 2), 5.0);
    let spacing = loaded.spacing.unwrap();
    assert_eq!((spacing.dx, spacing.dy), (10.0, 10.0));
}

#[test]
fn a_raw_file_of_the_wrong_length_names_both_lengths() {
    let layout = RawLayout {
        columns: 4,
        rows: 3,
        sample: RawSample::F32Be,
        north_first: true,
    };
    check_error(
        "heights.raw",
        &[0; 40],
        TerrainFormat::Raw(layout),
        &["has 40 bytes", "needs 48 bytes"],
    );
}

#[test]
fn an_unknown_extension_lists_the_known_ones() {
    let error = format_from_extension(Path::new("terrain/heights.xyz")).unwrap_err();
    let message = error.to_string();
    assert!(message.contains("heights.xyz"), "{message}");
    assert!(message.contains("unknown terrain format"), "{message}");
    assert!(
        message.contains(".hgt, .png, .tif, .tiff or .asc"),
        "{message}"
    );
    assert_eq!(
        format_from_extension(Path::new("N48E009.HGT")),
        Ok(TerrainFormat::Hgt)
    );
}

#[test]
fn a_missing_file_is_named() {
    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join("absent.hgt");
    let error = read_terrain(&path, TerrainFormat::Hgt, &ReadOptions::AS_STORED).unwrap_err();
    assert_eq!(error.path, path);
    assert!(
        error.to_string().contains("cannot read the file"),
        "{error}"
    );
}
