//! A terrain from many files (`"terrain": {"mosaic": …}`, `docs/experiment-format.md`,
//! "Mosaics"): the shipped SRTM tile cut into 2×2 tiles, as SRTM cuts them (neighbours share
//! their edge row and column), and read back as a mosaic of `.hgt` tiles, of GeoTIFF tiles and
//! through a GDAL VRT equals the uncut grid bit for bit; gaps, overlaps that disagree, mixed
//! resolutions, missing tiles and an empty folder are refused naming the file.
//!
//! The `.hgt` tiles have fixed sizes, so their "original" is a 2401² grid made from the shipped
//! 1201² tile and its mirror images (which agree on the shared edges by construction), written
//! as one raw file; the GeoTIFF tiles cut the shipped tile itself.

mod common;

use common::experiment::{quickstart, save};
use roamsim::edge::experiment::plan;
use roamsim::edge::terrain_readers::{
    LoadedTerrain, MosaicSource, RawLayout, RawSample, ReadOptions, TerrainFormat, lay_out_mosaic,
    read_mosaic, read_terrain,
};
use serde_json::json;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use tiff::encoder::{TiffEncoder, colortype};
use tiff::tags::Tag;

const SRTM3_SIDE: usize = 1201;
const SRTM_VOID: i16 = -32768;

/// A grid of stored samples, north row first (as SRTM and GeoTIFF store them).
#[derive(Clone)]
struct StoredGrid {
    columns: usize,
    rows: usize,
    samples: Vec<i16>,
}

impl StoredGrid {
    fn at(&self, column: usize, row_from_north: usize) -> i16 {
        self.samples[row_from_north * self.columns + column]
    }

    /// The window of `columns × rows` samples from (`column`, `row_from_north`).
    fn window(&self, column: usize, row_from_north: usize, columns: usize, rows: usize) -> Self {
        let mut samples = Vec::with_capacity(columns * rows);
        for row in row_from_north..row_from_north + rows {
            for c in column..column + columns {
                samples.push(self.at(c, row));
            }
        }
        StoredGrid {
            columns,
            rows,
            samples,
        }
    }

    fn big_endian_bytes(&self) -> Vec<u8> {
        self.samples.iter().flat_map(|s| s.to_be_bytes()).collect()
    }
}

/// The shipped SRTM3 tile, N48E009, with two voids added (one inside, one on the row a 2×2 cut
/// shares), read once.
fn shipped_tile() -> &'static StoredGrid {
    static TILE: OnceLock<StoredGrid> = OnceLock::new();
    TILE.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/data/N48E009.hgt");
        let bytes = std::fs::read(path).unwrap();
        let mut samples: Vec<i16> = bytes
            .chunks_exact(2)
            .map(|b| i16::from_be_bytes([b[0], b[1]]))
            .collect();
        samples[300 * SRTM3_SIDE + 200] = SRTM_VOID;
        samples[600 * SRTM3_SIDE + 900] = SRTM_VOID;
        StoredGrid {
            columns: SRTM3_SIDE,
            rows: SRTM3_SIDE,
            samples,
        }
    })
}

/// 2401² samples: the shipped tile and its mirror images east, north and north-east, so that
/// the four 1201² quarters agree on the row and column they share.
fn two_by_two_degrees() -> &'static StoredGrid {
    static GRID: OnceLock<StoredGrid> = OnceLock::new();
    GRID.get_or_init(|| {
        let tile = shipped_tile();
        let side = 2 * (SRTM3_SIDE - 1) + 1;
        let mirror = |k: usize| if k < SRTM3_SIDE { k } else { side - 1 - k };
        let mut samples = Vec::with_capacity(side * side);
        for row in 0..side {
            for column in 0..side {
                samples.push(tile.at(mirror(column), mirror(row)));
            }
        }
        StoredGrid {
            columns: side,
            rows: side,
            samples,
        }
    })
}

/// The four SRTM tiles of [`two_by_two_degrees`] (N48–N49, E009–E010) written to `folder`.
fn write_srtm_quarters(folder: &Path) -> Vec<PathBuf> {
    let grid = two_by_two_degrees();
    let step = SRTM3_SIDE - 1;
    let mut paths = Vec::new();
    for (name, column, row) in [
        ("N49E009.hgt", 0, 0),
        ("N49E010.hgt", step, 0),
        ("N48E009.hgt", 0, step),
        ("N48E010.hgt", step, step),
    ] {
        let path = folder.join(name);
        let quarter = grid.window(column, row, SRTM3_SIDE, SRTM3_SIDE);
        std::fs::write(&path, quarter.big_endian_bytes()).unwrap();
        paths.push(path);
    }
    paths
}

/// The uncut grid, read by the raw reader with SRTM's void marker.
fn read_uncut(folder: &Path, grid: &StoredGrid) -> LoadedTerrain {
    let path = folder.join("uncut.raw");
    std::fs::write(&path, grid.big_endian_bytes()).unwrap();
    let layout = RawLayout {
        columns: grid.columns,
        rows: grid.rows,
        sample: RawSample::I16Be,
        north_first: true,
    };
    let options = ReadOptions {
        nodata: Some(f64::from(SRTM_VOID)),
        ..ReadOptions::AS_STORED
    };
    read_terrain(&path, TerrainFormat::Raw(layout), &options).unwrap()
}

fn read(source: MosaicSource) -> Result<LoadedTerrain, String> {
    let layout = lay_out_mosaic(&source).map_err(|e| e.to_string())?;
    read_mosaic(&layout, &ReadOptions::AS_STORED).map_err(|e| e.to_string())
}

/// Bit for bit: the same size, the same void samples and the same bits in every height.
fn assert_same_grid(mosaic: &LoadedTerrain, uncut: &LoadedTerrain) {
    let (a, b) = (&mosaic.grid, &uncut.grid);
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    assert_eq!(a.void_indices(), b.void_indices());
    let first_difference = a
        .heights()
        .iter()
        .zip(b.heights())
        .position(|(x, y)| x.to_bits() != y.to_bits());
    assert_eq!(first_difference, None, "the first sample that differs");
}

#[test]
fn four_srtm_tiles_read_as_a_mosaic_equal_the_uncut_grid_bit_for_bit() {
    let folder = tempfile::tempdir().unwrap();
    write_srtm_quarters(folder.path());
    let mosaic = read(MosaicSource::Folder(folder.path().to_path_buf())).unwrap();
    let uncut = read_uncut(folder.path(), two_by_two_degrees());
    assert_same_grid(&mosaic, &uncut);
    // The void added on the shared row lies in two tiles; it is one void of the mosaic.
    let shared_row_void = (2400 - 600) * 2401 + 900;
    assert!(mosaic.grid.void_indices().contains(&shared_row_void));
    // Spacing as one tile's, at the mosaic's centre latitude, 49°N.
    let spacing = mosaic.spacing.unwrap();
    assert!((spacing.dy - 92.6).abs() < 1e-9, "{spacing:?}");
    assert!((spacing.dx - 92.6 * 49.0_f64.to_radians().cos()).abs() < 1e-9);
}

#[test]
fn the_order_of_the_tiles_does_not_change_the_mosaic() {
    let folder = tempfile::tempdir().unwrap();
    let mut paths = write_srtm_quarters(folder.path());
    let listed = read(MosaicSource::Files(paths.clone())).unwrap();
    paths.reverse();
    let reversed = read(MosaicSource::Files(paths)).unwrap();
    assert_same_grid(&listed, &reversed);
}

#[test]
fn a_missing_srtm_tile_is_a_gap_named_by_its_tile_name() {
    let folder = tempfile::tempdir().unwrap();
    let paths = write_srtm_quarters(folder.path());
    let three: Vec<PathBuf> = paths
        .into_iter()
        .filter(|p| !p.ends_with("N49E010.hgt"))
        .collect();
    let error = lay_out_mosaic(&MosaicSource::Files(three)).unwrap_err();
    assert!(error.path.ends_with("N49E010.hgt"), "{error}");
    assert!(error.to_string().contains("a gap"), "{error}");
    assert!(error.to_string().contains("N48E009 to N50E011"), "{error}");
}

#[test]
fn an_srtm_overlap_that_disagrees_names_both_tiles_and_the_sample() {
    let folder = tempfile::tempdir().unwrap();
    let paths = write_srtm_quarters(folder.path());
    // N49E010's west column is N49E009's east column: change one sample of it, 1 m up.
    let east = &paths[1];
    let mut bytes = std::fs::read(east).unwrap();
    let at = 2 * (500 * SRTM3_SIDE);
    let changed = i16::from_be_bytes([bytes[at], bytes[at + 1]]) + 1;
    bytes[at..at + 2].copy_from_slice(&changed.to_be_bytes());
    std::fs::write(east, bytes).unwrap();
    let error = read(MosaicSource::Files(paths)).unwrap_err();
    assert!(
        error.contains("N49E010.hgt: an overlap that disagrees"),
        "{error}"
    );
    assert!(error.contains("N49E009.hgt has"), "{error}");
    assert!(error.contains("column 1, row 501"), "{error}");
}

#[test]
fn srtm_tiles_of_two_resolutions_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    let srtm3 = folder.path().join("N48E009.hgt");
    let srtm1 = folder.path().join("N48E010.hgt");
    std::fs::write(&srtm3, vec![0_u8; 2 * SRTM3_SIDE * SRTM3_SIDE]).unwrap();
    std::fs::write(&srtm1, vec![0_u8; 2 * 3601 * 3601]).unwrap();
    let error = lay_out_mosaic(&MosaicSource::Folder(folder.path().to_path_buf())).unwrap_err();
    assert_eq!(error.path, srtm1);
    assert!(error.to_string().contains("mixed resolutions"), "{error}");
    assert!(
        error.to_string().contains("N48E009.hgt has 1201×1201"),
        "{error}"
    );
}

#[test]
fn a_tile_that_does_not_exist_an_empty_folder_and_mixed_formats_are_named() {
    let folder = tempfile::tempdir().unwrap();
    let absent = folder.path().join("N50E009.hgt");
    let error = lay_out_mosaic(&MosaicSource::Files(vec![absent.clone()])).unwrap_err();
    assert_eq!(error.path, absent);
    assert!(
        error.to_string().contains("cannot read the tile"),
        "{error}"
    );

    std::fs::write(folder.path().join("README.txt"), "not a tile").unwrap();
    let error = lay_out_mosaic(&MosaicSource::Folder(folder.path().to_path_buf())).unwrap_err();
    assert!(
        error.to_string().contains("holds no .hgt, .tif or .tiff"),
        "{error}"
    );

    let mixed = vec![
        folder.path().join("N48E009.hgt"),
        folder.path().join("a.tif"),
    ];
    let error = lay_out_mosaic(&MosaicSource::Files(mixed)).unwrap_err();
    assert!(error.to_string().contains("mixed formats"), "{error}");

    let not_a_tile_name = folder.path().join("dem.hgt");
    std::fs::write(&not_a_tile_name, [0_u8; 8]).unwrap();
    let error = lay_out_mosaic(&MosaicSource::Files(vec![not_a_tile_name])).unwrap_err();
    assert!(
        error.to_string().contains("not an SRTM tile name"),
        "{error}"
    );
}

/// How a GeoTIFF's tiepoint names its pixels (GTRasterTypeGeoKey).
#[derive(Clone, Copy)]
enum RasterType {
    PixelIsArea,
    PixelIsPoint,
}

/// A geographic int16 GeoTIFF of `grid` whose north-west sample lies at (`west`, `north`)
/// degrees, samples 1/1200° apart, with SRTM's void as GDAL_NODATA.
fn geotiff(grid: &StoredGrid, west: f64, north: f64, raster_type: RasterType) -> Vec<u8> {
    geotiff_with_step(grid, west, north, raster_type, 1.0 / 1200.0)
}

fn geotiff_with_step(
    grid: &StoredGrid,
    west: f64,
    north: f64,
    raster_type: RasterType,
    step: f64,
) -> Vec<u8> {
    let (tiepoint, raster_type_key) = match raster_type {
        RasterType::PixelIsArea => (
            [0.0, 0.0, 0.0, west - step / 2.0, north + step / 2.0, 0.0],
            1,
        ),
        RasterType::PixelIsPoint => ([0.0, 0.0, 0.0, west, north, 0.0], 2),
    };
    let geo_keys: [u16; 12] = [1, 1, 0, 2, 1024, 0, 1, 2, 1025, 0, 1, raster_type_key];
    let mut cursor = Cursor::new(Vec::new());
    let mut encoder = TiffEncoder::new(&mut cursor).unwrap();
    let mut image = encoder
        .new_image::<colortype::GrayI16>(grid.columns as u32, grid.rows as u32)
        .unwrap();
    let scale = [step, step, 0.0];
    image
        .encoder()
        .write_tag(Tag::ModelPixelScaleTag, &scale[..])
        .unwrap();
    image
        .encoder()
        .write_tag(Tag::ModelTiepointTag, &tiepoint[..])
        .unwrap();
    image
        .encoder()
        .write_tag(Tag::GeoKeyDirectoryTag, &geo_keys[..])
        .unwrap();
    image
        .encoder()
        .write_tag(Tag::GdalNodata, "-32768")
        .unwrap();
    image.write_data(&grid.samples).unwrap();
    cursor.into_inner()
}

/// The shipped tile cut into 2×2 GeoTIFF tiles of 601² sharing the middle row and column.
fn write_geotiff_quarters(folder: &Path, raster_type: RasterType) -> Vec<PathBuf> {
    let tile = shipped_tile();
    let half = (SRTM3_SIDE - 1) / 2;
    let mut paths = Vec::new();
    for (name, column, row) in [
        ("nw.tif", 0, 0),
        ("ne.tif", half, 0),
        ("sw.tif", 0, half),
        ("se.tif", half, half),
    ] {
        let quarter = tile.window(column, row, half + 1, half + 1);
        let west = 9.0 + column as f64 / 1200.0;
        let north = 49.0 - row as f64 / 1200.0;
        let path = folder.join(name);
        std::fs::write(&path, geotiff(&quarter, west, north, raster_type)).unwrap();
        paths.push(path);
    }
    paths
}

fn read_shipped_tile_as_hgt(folder: &Path) -> LoadedTerrain {
    let path = folder.join("N48E009.hgt");
    std::fs::write(&path, shipped_tile().big_endian_bytes()).unwrap();
    read_terrain(&path, TerrainFormat::Hgt, &ReadOptions::AS_STORED).unwrap()
}

#[test]
fn four_geotiff_tiles_read_as_a_mosaic_equal_the_uncut_tile_bit_for_bit() {
    for raster_type in [RasterType::PixelIsArea, RasterType::PixelIsPoint] {
        let folder = tempfile::tempdir().unwrap();
        let paths = write_geotiff_quarters(folder.path(), raster_type);
        let mosaic = read(MosaicSource::Files(paths)).unwrap();
        let uncut = read_shipped_tile_as_hgt(folder.path());
        assert_same_grid(&mosaic, &uncut);
        // The same spacing as the tile's own: its pixel scale at its centre latitude, 48.5°N.
        let (a, b) = (mosaic.spacing.unwrap(), uncut.spacing.unwrap());
        assert!(
            (a.dx - b.dx).abs() < 1e-9 && (a.dy - b.dy).abs() < 1e-9,
            "{a:?} {b:?}"
        );
    }
}

#[test]
fn a_missing_geotiff_tile_is_a_gap_with_its_place() {
    let folder = tempfile::tempdir().unwrap();
    let paths = write_geotiff_quarters(folder.path(), RasterType::PixelIsArea);
    std::fs::remove_file(&paths[3]).unwrap();
    let error = lay_out_mosaic(&MosaicSource::Folder(folder.path().to_path_buf()))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("a gap: no tile covers columns 602–1201, rows 602–1201"),
        "{error}"
    );
}

#[test]
fn geotiff_tiles_of_two_pixel_scales_or_off_the_lattice_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    let quarter = shipped_tile().window(0, 0, 601, 601);
    let a = folder.path().join("a.tif");
    std::fs::write(&a, geotiff(&quarter, 9.0, 49.0, RasterType::PixelIsArea)).unwrap();
    // Half a sample east of the lattice (what a PixelIsArea tiepoint tagged PixelIsPoint gives).
    let b = folder.path().join("b.tif");
    let half_sample = 0.5 / 1200.0;
    let bytes = geotiff(&quarter, 9.5 + half_sample, 49.0, RasterType::PixelIsPoint);
    std::fs::write(&b, bytes).unwrap();
    let error = lay_out_mosaic(&MosaicSource::Files(vec![a.clone(), b.clone()])).unwrap_err();
    assert_eq!(error.path, b);
    assert!(
        error.to_string().contains("600.500 samples east"),
        "{error}"
    );
    assert!(error.to_string().contains("off their lattice"), "{error}");

    let c = folder.path().join("c.tif");
    let bytes = geotiff_with_step(&quarter, 9.5, 49.0, RasterType::PixelIsArea, 1.0 / 3600.0);
    std::fs::write(&c, bytes).unwrap();
    let error = lay_out_mosaic(&MosaicSource::Files(vec![a.clone(), c.clone()])).unwrap_err();
    assert_eq!(error.path, c);
    assert!(error.to_string().contains("mixed resolutions"), "{error}");
    assert!(error.to_string().contains("a.tif's is"), "{error}");
}

/// A VRT of the four SRTM tiles as `gdalbuildvrt` writes one (2401², the later tile's window
/// over the shared edge), `SrcRect` optionally trimming the shared edges away.
fn srtm_vrt(trim_shared_edges: bool) -> String {
    let step = SRTM3_SIDE - 1;
    let mut sources = String::new();
    for (name, column, row) in [
        ("N49E009.hgt", 0, 0),
        ("N49E010.hgt", step, 0),
        ("N48E009.hgt", 0, step),
        ("N48E010.hgt", step, step),
    ] {
        let (skip_column, skip_row) = if trim_shared_edges {
            (usize::from(column > 0), usize::from(row > 0))
        } else {
            (0, 0)
        };
        let (columns, rows) = (SRTM3_SIDE - skip_column, SRTM3_SIDE - skip_row);
        sources.push_str(&format!(
            "<ComplexSource><SourceFilename relativeToVRT=\"1\">{name}</SourceFilename>\
             <SourceBand>1</SourceBand>\
             <SourceProperties RasterXSize=\"1201\" RasterYSize=\"1201\" DataType=\"Int16\"/>\
             <SrcRect xOff=\"{skip_column}\" yOff=\"{skip_row}\" xSize=\"{columns}\" ySize=\"{rows}\"/>\
             <DstRect xOff=\"{}\" yOff=\"{}\" xSize=\"{columns}\" ySize=\"{rows}\"/>\
             <NODATA>-32768</NODATA></ComplexSource>\n",
            column + skip_column,
            row + skip_row
        ));
    }
    format!(
        "<VRTDataset rasterXSize=\"2401\" rasterYSize=\"2401\">\n\
         <SRS dataAxisToSRSAxisMapping=\"2,1\">GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],\
         PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]]</SRS>\n\
         <GeoTransform> 8.9995833333333337e+00, 8.3333333333333339e-04, 0.0, \
         5.0000416666666666e+01, 0.0, -8.3333333333333339e-04</GeoTransform>\n\
         <VRTRasterBand dataType=\"Int16\" band=\"1\">\n<NoDataValue>-32768</NoDataValue>\n\
         <ColorInterp>Gray</ColorInterp>\n{sources}</VRTRasterBand>\n</VRTDataset>\n"
    )
}

#[test]
fn a_vrt_of_the_four_tiles_equals_the_uncut_grid_bit_for_bit() {
    let folder = tempfile::tempdir().unwrap();
    write_srtm_quarters(folder.path());
    let uncut = read_uncut(folder.path(), two_by_two_degrees());
    for trim_shared_edges in [false, true] {
        let vrt = folder.path().join("tiles.vrt");
        std::fs::write(&vrt, srtm_vrt(trim_shared_edges)).unwrap();
        let mosaic = read(MosaicSource::Files(vec![vrt])).unwrap();
        assert_same_grid(&mosaic, &uncut);
        let spacing = mosaic.spacing.unwrap();
        assert!((spacing.dy - 92.6).abs() < 1e-6, "{spacing:?}");
    }
}

#[test]
fn a_vrt_with_a_source_left_out_is_a_gap_naming_the_window() {
    let folder = tempfile::tempdir().unwrap();
    write_srtm_quarters(folder.path());
    let text = srtm_vrt(true);
    let last = text.rfind("<ComplexSource>").unwrap();
    let end = text.rfind("</ComplexSource>").unwrap() + "</ComplexSource>".len();
    let vrt = folder.path().join("tiles.vrt");
    std::fs::write(&vrt, format!("{}{}", &text[..last], &text[end..])).unwrap();
    let error = lay_out_mosaic(&MosaicSource::Files(vec![vrt.clone()])).unwrap_err();
    assert_eq!(error.path, vrt);
    assert!(
        error
            .to_string()
            .contains("no source covers columns 1202–2401, rows 1202–2401"),
        "{error}"
    );
}

/// The quickstart with its terrain a mosaic of the given files or folder.
fn quickstart_on_mosaic(mosaic: serde_json::Value) -> serde_json::Value {
    let mut experiment = quickstart();
    experiment["terrain"] = json!({ "mosaic": mosaic });
    experiment
}

#[test]
fn an_experiment_flies_over_a_folder_of_tiles() {
    let folder = tempfile::tempdir().unwrap();
    std::fs::create_dir(folder.path().join("tiles")).unwrap();
    write_srtm_quarters(&folder.path().join("tiles"));
    let experiment = quickstart_on_mosaic(json!({ "folder": "tiles", "fit": "crop" }));
    let path = save(folder.path(), "mosaic", &experiment);
    let loaded = plan(&path).unwrap().load_point(0).unwrap();
    assert_eq!(loaded.terrain.format, "hgt mosaic");
    assert_eq!(
        (loaded.terrain.source_columns, loaded.terrain.source_rows),
        (2401, 2401)
    );
    assert_eq!(loaded.terrain.side, 2049);
    let n_voids = two_by_two_degrees()
        .samples
        .iter()
        .filter(|&&s| s == SRTM_VOID)
        .count();
    assert_eq!(loaded.terrain.voids_filled, n_voids);
    assert_eq!(loaded.terrain.spacing_from, "file");
}

#[test]
fn a_gap_is_reported_when_the_plan_is_made_before_any_height_is_read() {
    let folder = tempfile::tempdir().unwrap();
    let paths = write_srtm_quarters(folder.path());
    std::fs::remove_file(&paths[0]).unwrap();
    let experiment = quickstart_on_mosaic(json!({
        "files": ["N48E009.hgt", "N48E010.hgt", "N49E010.hgt"],
        "fit": "crop"
    }));
    let path = save(folder.path(), "gap", &experiment);
    let error = plan(&path).err().expect("a gap is refused by the plan");
    let message = error.to_string();
    assert!(message.contains("terrain.mosaic.files: "), "{message}");
    assert!(message.contains("N49E009.hgt: a gap"), "{message}");
}

#[test]
fn mosaic_keys_are_checked_with_their_paths() {
    let folder = tempfile::tempdir().unwrap();
    let experiment = quickstart_on_mosaic(json!({
        "files": ["a.hgt", "b.tif", "c.png", "a.hgt"],
        "fit": "pad",
        "crop_origin": [0, 0]
    }));
    let path = save(folder.path(), "keys", &experiment);
    let message = plan(&path).err().expect("refused").to_string();
    for expected in [
        "terrain.mosaic.crop_origin: a crop origin was given",
        "terrain.mosaic.files[1]: 'b.tif' is not in the format of files[0]",
        "terrain.mosaic.files[2]: 'c.png': expected .hgt",
        "terrain.mosaic.files[3]: 'a.hgt' is listed twice",
    ] {
        assert!(
            message.contains(expected),
            "expected '{expected}' in: {message}"
        );
    }
    let both = quickstart_on_mosaic(json!({ "files": ["a.hgt"], "folder": ".", "fit": "pad" }));
    let message = plan(&save(folder.path(), "both", &both))
        .err()
        .unwrap()
        .to_string();
    assert!(message.contains("both files and folder"), "{message}");
}

#[cfg(not(feature = "gdal"))]
#[test]
fn the_gdal_format_is_refused_by_a_build_without_gdal() {
    let folder = tempfile::tempdir().unwrap();
    let experiment =
        quickstart_on_mosaic(json!({ "files": ["a.img"], "format": "gdal", "fit": "pad" }));
    let message = plan(&save(folder.path(), "gdal", &experiment))
        .err()
        .unwrap()
        .to_string();
    assert!(
        message.contains("terrain.mosaic.format: \"gdal\": this roamsim was built without GDAL"),
        "{message}"
    );
}

/// The GDAL reader (the `gdal` feature) against the pure-Rust readers: the same bits.
#[cfg(feature = "gdal")]
mod gdal {
    use super::*;
    use roamsim::edge::terrain_readers::lay_out_gdal_mosaic;

    fn read_with_gdal(path: &Path) -> LoadedTerrain {
        read_terrain(path, TerrainFormat::Gdal, &ReadOptions::AS_STORED).unwrap()
    }

    fn assert_same_spacing(a: &LoadedTerrain, b: &LoadedTerrain) {
        let (a, b) = (a.spacing.unwrap(), b.spacing.unwrap());
        assert!(
            (a.dx - b.dx).abs() < 1e-6 && (a.dy - b.dy).abs() < 1e-6,
            "{a:?} {b:?}"
        );
    }

    #[test]
    fn gdal_and_the_pure_rust_reader_give_identical_heights_for_the_shipped_tile() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/data/N48E009.hgt");
        let native = read_terrain(&path, TerrainFormat::Hgt, &ReadOptions::AS_STORED).unwrap();
        let gdal = read_with_gdal(&path);
        assert_same_grid(&gdal, &native);
        assert_same_spacing(&gdal, &native);
    }

    #[test]
    fn gdal_reads_the_cut_tiles_and_their_vrt_as_the_pure_rust_mosaic_does() {
        let folder = tempfile::tempdir().unwrap();
        let srtm = write_srtm_quarters(folder.path());
        let native = read(MosaicSource::Files(srtm.clone())).unwrap();
        let layout = lay_out_gdal_mosaic(&srtm).unwrap();
        let gdal = read_mosaic(&layout, &ReadOptions::AS_STORED).unwrap();
        assert_same_grid(&gdal, &native);
        assert_same_spacing(&gdal, &native);

        // GDAL reads the VRT as one raster.
        let vrt = folder.path().join("tiles.vrt");
        std::fs::write(&vrt, srtm_vrt(true)).unwrap();
        assert_same_grid(&read_with_gdal(&vrt), &native);

        let geotiffs = write_geotiff_quarters(folder.path(), RasterType::PixelIsPoint);
        let native = read(MosaicSource::Files(geotiffs.clone())).unwrap();
        let layout = lay_out_gdal_mosaic(&geotiffs).unwrap();
        let gdal = read_mosaic(&layout, &ReadOptions::AS_STORED).unwrap();
        assert_same_grid(&gdal, &native);
        assert_same_spacing(&gdal, &native);
    }
}
