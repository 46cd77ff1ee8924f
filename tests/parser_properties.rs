//! Property tests of every parser on hostile input: random bytes, and random mutations (bit
//! flips, overwrites, truncations, insertions of bytes or of tokens such as `nan` and `1e999`,
//! deletions) of a valid file. Each parser must answer `Ok` or an error that names the file,
//! never panic; what it accepts must also survive what comes next (void filling and embedding
//! for terrains, a finite flight for camera logs).
//!
//! The same parsers have cargo-fuzz targets in `fuzz/` (see `docs/robustness.md`); these tests
//! keep the property in the default `cargo test`. Case counts keep the file under a few seconds.
//! This file does not check what a parser reads from a valid file: `tests/terrain_readers.rs`,
//! `tests/experiment_validation.rs` and the readers' unit tests do.

mod common;

use common::experiment::{quickstart, repository};
use proptest::prelude::*;
use proptest::sample::Index;
use roamsim::edge::experiment::check_bytes;
use roamsim::edge::flight_log::parse_flight_log_bytes;
use roamsim::edge::terrain_readers::{
    LoadedTerrain, MosaicSource, RawLayout, RawSample, ReadOptions, TerrainFormat,
    TerrainReadError, lay_out_mosaic, parse_vrt_bytes, read_mosaic, read_terrain_bytes,
};
use roamsim::sim::flight::Flight;
use roamsim::sim::terrain::Spacing;
use roamsim::sim::terrain::embed::{Fit, embed};
use roamsim::sim::terrain::fill::fill_voids;
use std::io::Cursor;
use std::path::Path;
use std::sync::OnceLock;
use tiff::encoder::{TiffEncoder, colortype};
use tiff::tags::Tag;

/// Tokens worth inserting into text formats: what a random byte flip would rarely produce.
const TOKENS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e999",
    "-1e999",
    "99999999999999999999999",
    "-32768",
    "0",
    "-0",
    "\n",
    ",",
    " ",
    "\"",
    "{",
    "}",
    "[",
    "]",
    "null",
    "ncols 100000000\n",
    "nrows 100000000\n",
    "NODATA_value nan\n",
    "cellsize 0\n",
    "\u{feff}",
    "é",
    "<",
    "/>",
    "&lt;",
    "<!DOCTYPE v [<!ENTITY e \"e\">]>",
];

/// One edit of a file.
#[derive(Clone, Debug)]
enum Mutation {
    FlipBit(Index, u8),
    Overwrite(Index, u8),
    Truncate(Index),
    InsertBytes(Index, Vec<u8>),
    InsertToken(Index, Index),
    Delete(Index, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<Index>(), 0..8u8).prop_map(|(at, bit)| Mutation::FlipBit(at, bit)),
        (any::<Index>(), any::<u8>()).prop_map(|(at, byte)| Mutation::Overwrite(at, byte)),
        any::<Index>().prop_map(Mutation::Truncate),
        (any::<Index>(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(at, bytes)| Mutation::InsertBytes(at, bytes)),
        (any::<Index>(), any::<Index>()).prop_map(|(at, token)| Mutation::InsertToken(at, token)),
        (any::<Index>(), 1..16usize).prop_map(|(at, n)| Mutation::Delete(at, n)),
    ]
}

/// One to four edits.
fn mutations() -> impl Strategy<Value = Vec<Mutation>> {
    prop::collection::vec(mutation(), 1..5)
}

fn mutate(valid: &[u8], edits: &[Mutation]) -> Vec<u8> {
    let mut bytes = valid.to_vec();
    for edit in edits {
        let len = bytes.len();
        match edit {
            _ if len == 0 => break,
            Mutation::FlipBit(at, bit) => bytes[at.index(len)] ^= 1 << bit,
            Mutation::Overwrite(at, byte) => bytes[at.index(len)] = *byte,
            Mutation::Truncate(at) => bytes.truncate(at.index(len)),
            Mutation::InsertBytes(at, inserted) => {
                let at = at.index(len + 1);
                bytes.splice(at..at, inserted.iter().copied());
            }
            Mutation::InsertToken(at, token) => {
                let at = at.index(len + 1);
                let token = TOKENS[token.index(TOKENS.len())].as_bytes();
                bytes.splice(at..at, token.iter().copied());
            }
            Mutation::Delete(at, n) => {
                let at = at.index(len);
                bytes.drain(at..(at + n).min(len));
            }
        }
    }
    bytes
}

/// The property every terrain reader keeps: `Ok` with a grid that can be filled and embedded,
/// or an error naming the file with a non-empty problem.
fn check_terrain(name: &str, bytes: &[u8], format: TerrainFormat, options: &ReadOptions) {
    let path = Path::new(name);
    let result: Result<LoadedTerrain, TerrainReadError> =
        read_terrain_bytes(path, bytes, format, options);
    match result {
        Ok(loaded) => {
            let grid = &loaded.grid;
            assert!(grid.width() >= 3 && grid.height() >= 3);
            let spacing = loaded.spacing.unwrap_or(Spacing { dx: 1.0, dy: 1.0 });
            assert!(spacing.dx > 0.0 && spacing.dy > 0.0 && spacing.dx.is_finite());
            // What an experiment does next must be a value too (an all-void grid cannot fill).
            if let Ok((filled, _)) = fill_voids(loaded.grid)
                && filled.width().max(filled.height()) <= 1025
            {
                embed(&filled, Fit::Pad, spacing).expect("a filled grid always pads");
            }
        }
        Err(error) => {
            assert_eq!(error.path, path, "the error must name the file it read");
            assert!(!error.problem.is_empty());
            assert!(error.to_string().starts_with(name), "{error}");
        }
    }
}

fn png_file() -> Vec<u8> {
    let (columns, rows) = (5_u32, 4_u32);
    let samples: Vec<u8> = (0..columns * rows)
        .flat_map(|k| (1000 + 37 * k as u16).to_be_bytes())
        .collect();
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, columns, rows);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Sixteen);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&samples).unwrap();
    writer.finish().unwrap();
    bytes
}

fn geotiff_file() -> Vec<u8> {
    let values: Vec<i16> = vec![-5, 0, 7, -32768, 100, 200, 300, 400, 1, 2, 3, 4];
    let mut cursor = Cursor::new(Vec::new());
    let mut encoder = TiffEncoder::new(&mut cursor).unwrap();
    let mut image = encoder.new_image::<colortype::GrayI16>(4, 3).unwrap();
    let directory = image.encoder();
    directory.write_tag(Tag::GdalNodata, "-32768").unwrap();
    directory
        .write_tag(Tag::ModelPixelScaleTag, &[25.0_f64, 20.0, 0.0][..])
        .unwrap();
    image.write_data(&values).unwrap();
    cursor.into_inner()
}

fn float_geotiff_file() -> Vec<u8> {
    let values: Vec<f32> = (0..12).map(|k| k as f32 * 1.5 - 3.0).collect();
    let mut cursor = Cursor::new(Vec::new());
    let mut encoder = TiffEncoder::new(&mut cursor).unwrap();
    let mut image = encoder.new_image::<colortype::Gray32Float>(4, 3).unwrap();
    image.encoder().write_tag(Tag::GdalNodata, "nan").unwrap();
    image.write_data(&values).unwrap();
    cursor.into_inner()
}

const ASCII_GRID: &str = "ncols 5\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 10\n\
                          NODATA_value -9999\n1 2 3 4 5\n6 -9999 8 9 10\n11 12 13.5 14 15\n";

const RAW_LAYOUT: RawLayout = RawLayout {
    columns: 4,
    rows: 3,
    sample: RawSample::I16Le,
    north_first: true,
};

fn raw_file() -> Vec<u8> {
    (0..12_i16)
        .flat_map(|k| (k * 100 - 50).to_le_bytes())
        .collect()
}

/// A GDAL VRT of two sources, as `gdalbuildvrt` writes one.
const VRT: &str = r#"<VRTDataset rasterXSize="4" rasterYSize="3">
  <SRS>GEOGCS["WGS 84",DATUM["WGS_1984"],UNIT["degree",0.0174532925199433]]</SRS>
  <GeoTransform> 9.0, 0.25, 0.0, 49.0, 0.0, -0.25</GeoTransform>
  <VRTRasterBand dataType="Int16" band="1">
    <NoDataValue>-32768</NoDataValue>
    <ComplexSource>
      <SourceFilename relativeToVRT="1">west.tif</SourceFilename>
      <SourceBand>1</SourceBand>
      <SrcRect xOff="0" yOff="0" xSize="2" ySize="3"/>
      <DstRect xOff="0" yOff="0" xSize="2" ySize="3"/>
      <NODATA>-32768</NODATA>
    </ComplexSource>
    <SimpleSource>
      <SourceFilename relativeToVRT="1">east.tif</SourceFilename>
      <SourceBand>1</SourceBand>
      <SrcRect xOff="1" yOff="0" xSize="2" ySize="3"/>
      <DstRect xOff="2" yOff="0" xSize="2" ySize="3"/>
    </SimpleSource>
  </VRTRasterBand>
</VRTDataset>
"#;

/// The property of the VRT parser: `Ok` with a raster of at least one sample and at least one
/// source, or an error naming the file.
fn check_vrt(bytes: &[u8]) {
    let path = Path::new("tiles.vrt");
    match parse_vrt_bytes(path, bytes) {
        Ok(mosaic) => {
            let (columns, rows) = mosaic.size();
            assert!(columns >= 1 && rows >= 1 && mosaic.n_sources() >= 1);
        }
        Err(error) => {
            assert_eq!(error.path, path, "the error must name the file it read");
            assert!(!error.problem.is_empty());
            assert!(error.to_string().starts_with("tiles.vrt"), "{error}");
        }
    }
}

/// The VRT's sources: two 3×3 int16 GeoTIFFs, in a folder kept for the whole run.
fn vrt_sources() -> &'static Path {
    static FOLDER: OnceLock<tempfile::TempDir> = OnceLock::new();
    FOLDER
        .get_or_init(|| {
            let folder = tempfile::tempdir().unwrap();
            for (name, base) in [("west.tif", 100_i16), ("east.tif", 200)] {
                let values: Vec<i16> = (0..9).map(|k| base + k).collect();
                let mut cursor = Cursor::new(Vec::new());
                TiffEncoder::new(&mut cursor)
                    .unwrap()
                    .write_image::<colortype::GrayI16>(3, 3, &values)
                    .unwrap();
                std::fs::write(folder.path().join(name), cursor.into_inner()).unwrap();
            }
            folder
        })
        .path()
}

/// The property of a VRT mosaic laid out and read over real sources: `Ok` with the raster's
/// size, or an error with a problem (naming the VRT or the source it is about).
fn check_vrt_mosaic(bytes: &[u8]) {
    let vrt = tempfile::Builder::new()
        .suffix(".vrt")
        .tempfile_in(vrt_sources())
        .unwrap();
    std::fs::write(vrt.path(), bytes).unwrap();
    let source = MosaicSource::Files(vec![vrt.path().to_path_buf()]);
    let result = lay_out_mosaic(&source).and_then(|layout| {
        Ok((
            layout.size(),
            read_mosaic(&layout, &ReadOptions::AS_STORED)?,
        ))
    });
    match result {
        Ok(((columns, rows), loaded)) => {
            assert_eq!((loaded.grid.width(), loaded.grid.height()), (columns, rows));
        }
        Err(error) => assert!(!error.problem.is_empty()),
    }
}

/// The real SRTM3 tile (2.9 MB), read once.
fn real_tile() -> &'static [u8] {
    static TILE: OnceLock<Vec<u8>> = OnceLock::new();
    TILE.get_or_init(|| std::fs::read(repository().join("experiments/data/N48E009.hgt")).unwrap())
}

const FLIGHT_LOG: &str = "frame,x_m,y_m,z_m,yaw_deg,pitch_deg\n\
                          # a comment\n0,1000,1000,2000,0,-10\n1,1010,1000,2000,5,-10\n\
                          2,1020,1001.5,1999,10,-12\n";

fn experiment_file() -> Vec<u8> {
    serde_json::to_vec_pretty(&quickstart()).unwrap()
}

/// The property of the experiment checker: `Ok` with at least one entry, or errors naming the
/// file, each with a problem.
fn check_experiment(bytes: &[u8]) {
    let path = Path::new("fuzzed.json");
    match check_bytes(path, bytes) {
        Ok(n_entries) => assert!(n_entries >= 1),
        Err(error) => {
            assert_eq!(error.file, path);
            assert!(!error.problems.is_empty());
            assert!(error.problems.iter().all(|p| !p.problem.is_empty()));
            assert!(error.to_string().starts_with("fuzzed.json"), "{error}");
        }
    }
}

/// The property of the log parser: `Ok` with finite poses that make a flight, or an error naming
/// the file and a line that exists.
fn check_flight_log(bytes: &[u8]) {
    let path = Path::new("fuzzed.csv");
    match parse_flight_log_bytes(path, bytes) {
        Ok(poses) => {
            let n = poses.len();
            let flight = Flight::from_poses(poses).expect("accepted poses are finite");
            assert_eq!(flight.n_frames(), n as u64);
        }
        Err(error) => {
            assert_eq!(error.path, path);
            assert!(!error.problem.is_empty());
            let n_lines = bytes.split(|&b| b == b'\n').count();
            assert!(error.line <= n_lines, "{error}");
        }
    }
}

#[test]
fn the_valid_files_the_mutations_start_from_are_accepted() {
    let options = &ReadOptions::AS_STORED;
    let read = |name: &str, bytes: &[u8], format| {
        read_terrain_bytes(Path::new(name), bytes, format, options)
    };
    assert!(read("dem.png", &png_file(), TerrainFormat::Png).is_ok());
    assert!(read("dem.tif", &geotiff_file(), TerrainFormat::GeoTiff).is_ok());
    assert!(read("dem.tif", &float_geotiff_file(), TerrainFormat::GeoTiff).is_ok());
    assert!(read("dem.asc", ASCII_GRID.as_bytes(), TerrainFormat::AsciiGrid).is_ok());
    assert!(read("dem.raw", &raw_file(), TerrainFormat::Raw(RAW_LAYOUT)).is_ok());
    assert!(read("N48E009.hgt", real_tile(), TerrainFormat::Hgt).is_ok());
    assert_eq!(
        parse_flight_log_bytes(Path::new("log.csv"), FLIGHT_LOG.as_bytes())
            .unwrap()
            .len(),
        3
    );
    assert!(check_bytes(Path::new("quickstart.json"), &experiment_file()).unwrap() >= 1);
    assert_eq!(
        parse_vrt_bytes(Path::new("tiles.vrt"), VRT.as_bytes())
            .unwrap()
            .n_sources(),
        2
    );
    let vrt = vrt_sources().join("valid.vrt");
    std::fs::write(&vrt, VRT).unwrap();
    let layout = lay_out_mosaic(&MosaicSource::Files(vec![vrt])).unwrap();
    let loaded = read_mosaic(&layout, options).unwrap();
    assert_eq!(loaded.grid.height_at(0, 2), 100.0);
    assert_eq!(loaded.grid.height_at(3, 0), 208.0);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic_a_terrain_reader(
        bytes in prop::collection::vec(any::<u8>(), 0..512),
        columns in 1..8usize,
        rows in 1..8usize,
    ) {
        let options = &ReadOptions::AS_STORED;
        check_terrain("random.hgt", &bytes, TerrainFormat::Hgt, options);
        check_terrain("random.png", &bytes, TerrainFormat::Png, options);
        check_terrain("random.tif", &bytes, TerrainFormat::GeoTiff, options);
        check_terrain("random.asc", &bytes, TerrainFormat::AsciiGrid, options);
        for sample in [RawSample::I16Be, RawSample::U16Le, RawSample::F32Le, RawSample::F32Be] {
            let layout = RawLayout { columns, rows, sample, north_first: columns % 2 == 0 };
            check_terrain("random.raw", &bytes, TerrainFormat::Raw(layout), options);
        }
    }

    #[test]
    fn random_text_never_panics_the_ascii_grid_reader(text in "[ -~\n]{0,300}") {
        check_terrain("random.asc", text.as_bytes(), TerrainFormat::AsciiGrid, &ReadOptions::AS_STORED);
    }

    #[test]
    fn a_mutated_png_is_read_or_refused_by_name(edits in mutations()) {
        check_terrain("dem.png", &mutate(&png_file(), &edits), TerrainFormat::Png, &ReadOptions::AS_STORED);
    }

    #[test]
    fn a_mutated_geotiff_is_read_or_refused_by_name(edits in mutations(), float in any::<bool>()) {
        let valid = if float { float_geotiff_file() } else { geotiff_file() };
        check_terrain("dem.tif", &mutate(&valid, &edits), TerrainFormat::GeoTiff, &ReadOptions::AS_STORED);
    }

    #[test]
    fn a_mutated_ascii_grid_is_read_or_refused_by_name(edits in mutations()) {
        check_terrain("dem.asc", &mutate(ASCII_GRID.as_bytes(), &edits), TerrainFormat::AsciiGrid, &ReadOptions::AS_STORED);
    }

    #[test]
    fn a_mutated_raw_file_is_read_or_refused_by_name(edits in mutations(), nodata in prop::option::of(-100.0..1200.0f64)) {
        let options = ReadOptions { nodata, ..ReadOptions::AS_STORED };
        check_terrain("dem.raw", &mutate(&raw_file(), &edits), TerrainFormat::Raw(RAW_LAYOUT), &options);
    }

    #[test]
    fn random_bytes_never_panic_the_flight_log_parser(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
        check_flight_log(&bytes);
    }

    #[test]
    fn a_mutated_flight_log_is_parsed_or_refused_with_its_line(edits in mutations()) {
        check_flight_log(&mutate(FLIGHT_LOG.as_bytes(), &edits));
    }

    #[test]
    fn random_bytes_never_panic_the_vrt_parser(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
        check_vrt(&bytes);
    }

    #[test]
    fn random_text_never_panics_the_vrt_parser(text in "[ -~\n]{0,300}") {
        check_vrt(text.as_bytes());
    }

    #[test]
    fn a_mutated_vrt_is_parsed_or_refused_by_name(edits in mutations()) {
        check_vrt(&mutate(VRT.as_bytes(), &edits));
    }

    #[test]
    fn random_bytes_never_panic_the_experiment_checker(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
        check_experiment(&bytes);
    }

    #[test]
    fn a_mutated_experiment_is_checked_or_refused_by_field(edits in mutations()) {
        check_experiment(&mutate(&experiment_file(), &edits));
    }
}

proptest! {
    // Each case writes a file and reads two.
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn a_mutated_vrt_mosaic_is_read_or_refused(edits in mutations()) {
        check_vrt_mosaic(&mutate(VRT.as_bytes(), &edits));
    }
}

proptest! {
    // Each case reads a 2.9 MB tile.
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn a_mutated_srtm_tile_is_read_or_refused_by_name(edits in mutations()) {
        check_terrain("N48E009.hgt", &mutate(real_tile(), &edits), TerrainFormat::Hgt, &ReadOptions::AS_STORED);
    }
}
