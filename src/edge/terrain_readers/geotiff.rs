//! The GeoTIFF reader: the first image of a single-band int16, uint16 or float32 TIFF, north row
//! first, with nodata from the GDAL_NODATA tag and spacing from the GeoTIFF tags (the options it
//! takes: `docs/experiment-format.md`, "Terrain"). The rows are turned over so that grid row 0
//! is the south edge, as every reader's grid is. A TIFF of several bands is refused, not split.
//!
//! Spacing comes from ModelPixelScaleTag when the GeoKeyDirectoryTag declares the model type:
//! projected rasters are taken to be in metres (or in feet, when ProjLinearUnitsGeoKey says so),
//! geographic rasters in degrees converted at the latitude of the raster centre. The reader does
//! not read ModelTransformationTag, does not reproject, and ignores every other GeoKey; rotated
//! or sheared rasters therefore get no spacing rather than a wrong one.

use super::{
    DEFLATE_MAX_EXPANSION, FileRowOrder, METRES_PER_DEGREE_LATITUDE, ReadOptions, SampleCollector,
    StoredPrecision, TerrainReadError,
};
use crate::sim::terrain::{SampleGrid, Spacing};
use std::io::{Cursor, Read, Seek};
use std::path::Path;
use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::tags::{CompressionMethod, SampleFormat, Tag};

/// Reads a GeoTIFF; the spacing is `None` when the file does not declare a usable one.
pub(super) fn read(
    path: &Path,
    bytes: &[u8],
    options: &ReadOptions,
) -> Result<(SampleGrid, Option<Spacing>), TerrainReadError> {
    let tiff_error = |error: tiff::TiffError| {
        TerrainReadError::new(path, format!("cannot decode the TIFF: {error}"))
    };
    let mut decoder = Decoder::new(Cursor::new(bytes)).map_err(tiff_error)?;
    let (width, height) = decoder.dimensions().map_err(tiff_error)?;
    let (columns, rows) = (width as usize, height as usize);
    let sample_kind = sample_kind(path, &mut decoder)?;

    let declared_bytes = columns
        .checked_mul(rows)
        .and_then(|n_samples| n_samples.checked_mul(sample_kind.bytes()));
    let compression = decoder
        .find_tag_unsigned::<u16>(Tag::Compression)
        .map_err(tiff_error)?
        .map_or(
            CompressionMethod::None,
            CompressionMethod::from_u16_exhaustive,
        );
    // Uncompressed samples must fit in the file; compressed ones can expand at most as far as
    // deflate allows (LZW and PackBits expand less on real data; a genuine DEM is far below).
    let plausible_bytes = if compression == CompressionMethod::None {
        bytes.len()
    } else {
        bytes.len().saturating_mul(DEFLATE_MAX_EXPANSION)
    };
    let declared_bytes = match declared_bytes {
        Some(declared) if declared <= plausible_bytes => declared,
        _ => {
            return Err(TerrainReadError::new(
                path,
                format!(
                    "the TIFF declares {columns}×{rows} {} samples, more than a {}-byte file \
                     with compression {compression:?} can hold",
                    sample_kind.name(),
                    bytes.len()
                ),
            ));
        }
    };
    let mut limits = Limits::default();
    limits.decoding_buffer_size = limits.decoding_buffer_size.max(declared_bytes);
    limits.intermediate_buffer_size = limits.intermediate_buffer_size.max(declared_bytes);
    let mut decoder = decoder.with_limits(limits);

    let file_nodata = gdal_nodata(path, &mut decoder)?;
    let spacing = declared_spacing(path, &mut decoder, rows)?;
    let image = decoder.read_image().map_err(tiff_error)?;

    let precision = match sample_kind {
        TiffSampleKind::Float32 => StoredPrecision::Float32,
        TiffSampleKind::Int16 | TiffSampleKind::UInt16 => StoredPrecision::Exact,
    };
    let mut collector = SampleCollector::new(
        path,
        columns,
        rows,
        FileRowOrder::NorthFirst,
        precision,
        file_nodata,
        options,
    )?;
    let n_samples = columns * rows;
    let decoded_samples = match &image {
        DecodingResult::I16(values) => values.len(),
        DecodingResult::U16(values) => values.len(),
        DecodingResult::F32(values) => values.len(),
        _ => 0,
    };
    if decoded_samples < n_samples {
        return Err(TerrainReadError::new(
            path,
            format!(
                "the TIFF decoder returned {decoded_samples} {} samples for a {columns}×{rows} \
                 image",
                sample_kind.name()
            ),
        ));
    }
    match &image {
        DecodingResult::I16(values) => {
            for &stored in &values[..n_samples] {
                collector.push(f64::from(stored))?;
            }
        }
        DecodingResult::U16(values) => {
            for &stored in &values[..n_samples] {
                collector.push(f64::from(stored))?;
            }
        }
        DecodingResult::F32(values) => {
            for &stored in &values[..n_samples] {
                collector.push(f64::from(stored))?;
            }
        }
        _ => {}
    }
    let grid = collector.finish()?;
    Ok((grid, spacing))
}

/// Where a GeoTIFF lies, from its tags alone (its samples are not decoded): what a mosaic
/// (`mosaic/`) places it by.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct TiffPlacement {
    pub(super) columns: usize,
    pub(super) rows: usize,
    /// `None` when the file has no ModelPixelScaleTag and ModelTiepointTag.
    pub(super) georeference: Option<TiffGeoreference>,
    /// The model type of the GeoKeyDirectoryTag.
    pub(super) model: TiffModel,
}

/// A north-up GeoTIFF's pixel grid in model units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TiffGeoreference {
    /// Pixel scale (ModelPixelScaleTag's sx, sy): both positive and finite.
    pub(super) scale: (f64, f64),
    /// Model coordinates of the centre of the north-west pixel: GDAL's reading of the tiepoint,
    /// which names the pixel's corner unless GTRasterTypeGeoKey says PixelIsPoint.
    pub(super) north_west_centre: (f64, f64),
}

/// What GTModelTypeGeoKey (and ProjLinearUnitsGeoKey) say of the model's units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum TiffModel {
    /// Projected, in metres per unit (`None`: a unit the reader does not know).
    Projected { metres_per_unit: Option<f64> },
    /// Longitude and latitude in degrees.
    Geographic,
    /// No GeoKeyDirectoryTag or no model type.
    Undeclared,
}

/// Reads the tags of a GeoTIFF's first image: its size, sample type (refused as [`read`] refuses
/// it) and georeference. Reads the header and the tags only, however large the image.
pub(super) fn read_placement<R: Read + Seek>(
    path: &Path,
    reader: R,
) -> Result<TiffPlacement, TerrainReadError> {
    let tiff_error = |error: tiff::TiffError| {
        TerrainReadError::new(path, format!("cannot decode the TIFF: {error}"))
    };
    let tag_error = |tag: &str, error: tiff::TiffError| {
        TerrainReadError::new(path, format!("cannot read {tag}: {error}"))
    };
    let mut decoder = Decoder::new(reader).map_err(tiff_error)?;
    let (width, height) = decoder.dimensions().map_err(tiff_error)?;
    sample_kind(path, &mut decoder)?;
    let keys = match decoder
        .find_tag(Tag::GeoKeyDirectoryTag)
        .map_err(|error| tag_error("GeoKeyDirectoryTag", error))?
    {
        Some(value) => value
            .into_u16_vec()
            .map_err(|error| tag_error("GeoKeyDirectoryTag", error))?,
        None => Vec::new(),
    };
    let model = match geo_key(&keys, GT_MODEL_TYPE_GEO_KEY) {
        Some(MODEL_TYPE_PROJECTED) => TiffModel::Projected {
            metres_per_unit: match geo_key(&keys, PROJ_LINEAR_UNITS_GEO_KEY) {
                None | Some(LINEAR_METER) => Some(1.0),
                Some(LINEAR_FOOT) => Some(0.3048),
                Some(LINEAR_FOOT_US_SURVEY) => Some(1200.0 / 3937.0),
                Some(_) => None,
            },
        },
        Some(MODEL_TYPE_GEOGRAPHIC) => TiffModel::Geographic,
        _ => TiffModel::Undeclared,
    };
    let raster_type = geo_key(&keys, GT_RASTER_TYPE_GEO_KEY);
    if decoder
        .find_tag(Tag::ModelTransformationTag)
        .map_err(|error| tag_error("ModelTransformationTag", error))?
        .is_some()
    {
        return Err(TerrainReadError::new(
            path,
            "the GeoTIFF is placed by a ModelTransformationTag (tag 34264), which is not read;              expected ModelTiepointTag and ModelPixelScaleTag (a north-up raster)",
        ));
    }
    let scale = decoder
        .find_tag(Tag::ModelPixelScaleTag)
        .map_err(|error| tag_error("ModelPixelScaleTag", error))?;
    let tiepoint = decoder
        .find_tag(Tag::ModelTiepointTag)
        .map_err(|error| tag_error("ModelTiepointTag", error))?;
    let georeference = match (scale, tiepoint) {
        (Some(scale), Some(tiepoint)) => {
            let scale = scale
                .into_f64_vec()
                .map_err(|error| tag_error("ModelPixelScaleTag", error))?;
            let tiepoint = tiepoint
                .into_f64_vec()
                .map_err(|error| tag_error("ModelTiepointTag", error))?;
            let (scale_x, scale_y) = match scale.as_slice() {
                [x, y, ..] if x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0 => (*x, *y),
                _ => {
                    return Err(TerrainReadError::new(
                        path,
                        format!(
                            "ModelPixelScaleTag (tag 33550) is {scale:?}; expected [sx, sy, sz]                              with positive finite sx and sy"
                        ),
                    ));
                }
            };
            let [raster_i, raster_j, _, model_x, model_y, _] = tiepoint.as_slice() else {
                return Err(TerrainReadError::new(
                    path,
                    format!(
                        "ModelTiepointTag (tag 33922) has {} values; expected one tiepoint of 6                          (I, J, K, X, Y, Z): several tiepoints (control points) cannot place a                          tile",
                        tiepoint.len()
                    ),
                ));
            };
            // GDAL: the tiepoint names raster coordinates, whose integers are pixel corners
            // under PixelIsArea (the default) and pixel centres under PixelIsPoint.
            let centre_offset = if raster_type == Some(RASTER_PIXEL_IS_POINT) {
                0.0
            } else {
                0.5
            };
            let north_west_centre = (
                model_x + (centre_offset - raster_i) * scale_x,
                model_y - (centre_offset - raster_j) * scale_y,
            );
            if !(north_west_centre.0.is_finite() && north_west_centre.1.is_finite()) {
                return Err(TerrainReadError::new(
                    path,
                    format!(
                        "ModelTiepointTag (tag 33922) is {tiepoint:?}; expected finite                          coordinates"
                    ),
                ));
            }
            Some(TiffGeoreference {
                scale: (scale_x, scale_y),
                north_west_centre,
            })
        }
        _ => None,
    };
    Ok(TiffPlacement {
        columns: width as usize,
        rows: height as usize,
        georeference,
        model,
    })
}

/// The sample types the reader accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TiffSampleKind {
    Int16,
    UInt16,
    Float32,
}

impl TiffSampleKind {
    fn bytes(self) -> usize {
        match self {
            TiffSampleKind::Int16 | TiffSampleKind::UInt16 => 2,
            TiffSampleKind::Float32 => 4,
        }
    }

    fn name(self) -> &'static str {
        match self {
            TiffSampleKind::Int16 => "int16",
            TiffSampleKind::UInt16 => "uint16",
            TiffSampleKind::Float32 => "float32",
        }
    }
}

/// The sample type of a single-band image, or an error naming what the file holds.
fn sample_kind<R: Read + Seek>(
    path: &Path,
    decoder: &mut Decoder<R>,
) -> Result<TiffSampleKind, TerrainReadError> {
    let tiff_error = |error: tiff::TiffError| {
        TerrainReadError::new(path, format!("cannot decode the TIFF: {error}"))
    };
    let samples_per_pixel = decoder
        .find_tag_unsigned::<u16>(Tag::SamplesPerPixel)
        .map_err(tiff_error)?
        .unwrap_or(1);
    if samples_per_pixel != 1 {
        return Err(TerrainReadError::new(
            path,
            format!(
                "the TIFF has {samples_per_pixel} samples per pixel; expected a single band \
                 (int16, uint16 or float32)"
            ),
        ));
    }
    let bits_per_sample = decoder
        .find_tag_unsigned_vec::<u16>(Tag::BitsPerSample)
        .map_err(tiff_error)?
        .and_then(|bits| bits.first().copied())
        .unwrap_or(1);
    let sample_format = decoder
        .find_tag_unsigned_vec::<u16>(Tag::SampleFormat)
        .map_err(tiff_error)?
        .and_then(|formats| formats.first().copied())
        .map_or(SampleFormat::Uint, SampleFormat::from_u16_exhaustive);
    match (sample_format, bits_per_sample) {
        (SampleFormat::Int, 16) => Ok(TiffSampleKind::Int16),
        (SampleFormat::Uint, 16) => Ok(TiffSampleKind::UInt16),
        (SampleFormat::IEEEFP, 32) => Ok(TiffSampleKind::Float32),
        (format, bits) => {
            let format_name = match format {
                SampleFormat::Int => "signed integer".to_string(),
                SampleFormat::Uint => "unsigned integer".to_string(),
                SampleFormat::IEEEFP => "floating point".to_string(),
                other => format!("{other:?}"),
            };
            Err(TerrainReadError::new(
                path,
                format!(
                    "the TIFF samples are {bits}-bit {format_name}; expected int16, uint16 or \
                     float32"
                ),
            ))
        }
    }
}

/// The nodata value of the GDAL_NODATA tag (ASCII, e.g. "-32768" or "nan"), if present.
fn gdal_nodata(
    path: &Path,
    decoder: &mut Decoder<Cursor<&[u8]>>,
) -> Result<Option<f64>, TerrainReadError> {
    let Some(value) = decoder.find_tag(Tag::GdalNodata).map_err(|error| {
        TerrainReadError::new(path, format!("cannot read GDAL_NODATA: {error}"))
    })?
    else {
        return Ok(None);
    };
    let text = value.into_string().map_err(|error| {
        TerrainReadError::new(
            path,
            format!("GDAL_NODATA (tag 42113) is not ASCII text ({error}); expected a number"),
        )
    })?;
    let trimmed = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
    trimmed.parse::<f64>().map(Some).map_err(|_| {
        TerrainReadError::new(
            path,
            format!(
                "GDAL_NODATA (tag 42113) is '{trimmed}'; expected a number such as -32768 or nan"
            ),
        )
    })
}

/// GeoKey ids and values the reader understands (GeoTIFF 1.0, section 6).
const GT_MODEL_TYPE_GEO_KEY: u16 = 1024;
const GT_RASTER_TYPE_GEO_KEY: u16 = 1025;
const RASTER_PIXEL_IS_POINT: u16 = 2;
const PROJ_LINEAR_UNITS_GEO_KEY: u16 = 3076;
const MODEL_TYPE_PROJECTED: u16 = 1;
const MODEL_TYPE_GEOGRAPHIC: u16 = 2;
const LINEAR_METER: u16 = 9001;
const LINEAR_FOOT: u16 = 9002;
const LINEAR_FOOT_US_SURVEY: u16 = 9003;

/// The spacing in metres the GeoTIFF tags declare, `None` when they declare none the reader can
/// use, or an error when they are malformed.
fn declared_spacing(
    path: &Path,
    decoder: &mut Decoder<Cursor<&[u8]>>,
    rows: usize,
) -> Result<Option<Spacing>, TerrainReadError> {
    let tag_error = |tag: &str, error: tiff::TiffError| {
        TerrainReadError::new(path, format!("cannot read {tag}: {error}"))
    };
    let Some(scale) = decoder
        .find_tag(Tag::ModelPixelScaleTag)
        .map_err(|error| tag_error("ModelPixelScaleTag", error))?
    else {
        return Ok(None);
    };
    let scale = scale
        .into_f64_vec()
        .map_err(|error| tag_error("ModelPixelScaleTag", error))?;
    let (scale_x, scale_y) = match scale.as_slice() {
        [x, y, ..] if x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0 => (*x, *y),
        _ => {
            return Err(TerrainReadError::new(
                path,
                format!(
                    "ModelPixelScaleTag (tag 33550) is {scale:?}; expected [sx, sy, sz] with \
                     positive finite sx and sy"
                ),
            ));
        }
    };
    let geo_keys = match decoder
        .find_tag(Tag::GeoKeyDirectoryTag)
        .map_err(|error| tag_error("GeoKeyDirectoryTag", error))?
    {
        Some(value) => value
            .into_u16_vec()
            .map_err(|error| tag_error("GeoKeyDirectoryTag", error))?,
        None => return Ok(None),
    };
    match geo_key(&geo_keys, GT_MODEL_TYPE_GEO_KEY) {
        Some(MODEL_TYPE_PROJECTED) => {
            let metres_per_unit = match geo_key(&geo_keys, PROJ_LINEAR_UNITS_GEO_KEY) {
                None | Some(LINEAR_METER) => 1.0,
                Some(LINEAR_FOOT) => 0.3048,
                Some(LINEAR_FOOT_US_SURVEY) => 1200.0 / 3937.0,
                Some(_) => return Ok(None),
            };
            Ok(Some(Spacing {
                dx: scale_x * metres_per_unit,
                dy: scale_y * metres_per_unit,
            }))
        }
        Some(MODEL_TYPE_GEOGRAPHIC) => {
            let Some(tiepoint) = decoder
                .find_tag(Tag::ModelTiepointTag)
                .map_err(|error| tag_error("ModelTiepointTag", error))?
            else {
                return Ok(None);
            };
            let tiepoint = tiepoint
                .into_f64_vec()
                .map_err(|error| tag_error("ModelTiepointTag", error))?;
            let [_, raster_j, _, _, model_y, ..] = tiepoint.as_slice() else {
                return Err(TerrainReadError::new(
                    path,
                    format!(
                        "ModelTiepointTag (tag 33922) has {} values; expected at least 6 \
                         (I, J, K, X, Y, Z)",
                        tiepoint.len()
                    ),
                ));
            };
            // Raster row j lies at latitude Y − (j − J)·sy; the centre row is rows / 2.
            let centre_latitude = model_y - (rows as f64 / 2.0 - raster_j) * scale_y;
            if !(-90.0..=90.0).contains(&centre_latitude) {
                return Err(TerrainReadError::new(
                    path,
                    format!(
                        "the geographic raster's centre lies at latitude {centre_latitude}° \
                         (from ModelTiepointTag and ModelPixelScaleTag); expected −90° to 90°"
                    ),
                ));
            }
            let dy = scale_y * METRES_PER_DEGREE_LATITUDE;
            let dx = scale_x * METRES_PER_DEGREE_LATITUDE * centre_latitude.to_radians().cos();
            Ok(Some(Spacing { dx, dy }))
        }
        _ => Ok(None),
    }
}

/// The value of a GeoKey stored directly in the GeoKeyDirectoryTag (TIFFTagLocation 0): the
/// directory is a header [version, revision, minor, count] then `count` entries of
/// [key id, location, count, value].
fn geo_key(directory: &[u16], key_id: u16) -> Option<u16> {
    let n_keys = usize::from(*directory.get(3)?);
    directory
        .get(4..)?
        .chunks_exact(4)
        .take(n_keys)
        .find(|entry| entry[0] == key_id && entry[1] == 0)
        .map(|entry| entry[3])
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiff::encoder::{TiffEncoder, colortype};

    fn read_tiff(bytes: &[u8]) -> Result<(SampleGrid, Option<Spacing>), TerrainReadError> {
        read(Path::new("dem.tif"), bytes, &ReadOptions::AS_STORED)
    }

    /// A 3×3 float32 GeoTIFF with the given tags.
    fn float_tiff(values: &[f32; 9], tags: &[(Tag, TagValue)]) -> Vec<u8> {
        let mut cursor = Cursor::new(Vec::new());
        let mut encoder = TiffEncoder::new(&mut cursor).unwrap();
        let mut image = encoder.new_image::<colortype::Gray32Float>(3, 3).unwrap();
        for (tag, value) in tags {
            match value {
                TagValue::Text(text) => image.encoder().write_tag(*tag, *text).unwrap(),
                TagValue::Doubles(doubles) => image.encoder().write_tag(*tag, *doubles).unwrap(),
                TagValue::Shorts(shorts) => image.encoder().write_tag(*tag, *shorts).unwrap(),
            }
        }
        image.write_data(values).unwrap();
        cursor.into_inner()
    }

    enum TagValue {
        Text(&'static str),
        Doubles(&'static [f64]),
        Shorts(&'static [u16]),
    }

    #[test]
    fn float_samples_are_flipped() {
        let values = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.5];
        let (grid, spacing) = read_tiff(&float_tiff(&values, &[])).unwrap();
        assert_eq!(grid.height_at(0, 2), 1.0);
        assert_eq!(grid.height_at(2, 0), 9.5);
        assert_eq!(spacing, None);
    }

    #[test]
    fn float_nodata_is_compared_at_f32_precision() {
        let mut values = [1.0_f32; 9];
        values[4] = f32::MIN;
        // "-3.4028235e+38" is not f32::MIN as an f64, but it rounds to it as an f32.
        let tags = [(Tag::GdalNodata, TagValue::Text("-3.4028235e+38"))];
        let (grid, _) = read_tiff(&float_tiff(&values, &tags)).unwrap();
        assert_eq!(grid.void_indices(), &[4]);
        // "-3.40282e+38" is 17 f32 steps away: an ordinary (if odd) height.
        let tags = [(Tag::GdalNodata, TagValue::Text("-3.40282e+38"))];
        let (grid, _) = read_tiff(&float_tiff(&values, &tags)).unwrap();
        assert!(grid.void_indices().is_empty());
    }

    #[test]
    fn unparseable_gdal_nodata_is_named() {
        let tags = [(Tag::GdalNodata, TagValue::Text("none"))];
        let error = read_tiff(&float_tiff(&[0.0; 9], &tags))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("GDAL_NODATA (tag 42113) is 'none'"),
            "{error}"
        );
    }

    #[test]
    fn projected_scale_is_metres_and_feet_are_converted() {
        let tags = [
            (
                Tag::ModelPixelScaleTag,
                TagValue::Doubles(&[30.0, 25.0, 0.0]),
            ),
            (
                Tag::GeoKeyDirectoryTag,
                TagValue::Shorts(&[1, 1, 0, 1, GT_MODEL_TYPE_GEO_KEY, 0, 1, 1]),
            ),
        ];
        let (_, spacing) = read_tiff(&float_tiff(&[0.0; 9], &tags)).unwrap();
        assert_eq!(spacing, Some(Spacing { dx: 30.0, dy: 25.0 }));

        let tags = [
            (
                Tag::ModelPixelScaleTag,
                TagValue::Doubles(&[10.0, 10.0, 0.0]),
            ),
            (
                Tag::GeoKeyDirectoryTag,
                TagValue::Shorts(&[1, 1, 0, 2, 1024, 0, 1, 1, 3076, 0, 1, 9002]),
            ),
        ];
        let (_, spacing) = read_tiff(&float_tiff(&[0.0; 9], &tags)).unwrap();
        assert_eq!(
            spacing,
            Some(Spacing {
                dx: 3.048,
                dy: 3.048
            })
        );
    }

    #[test]
    fn geographic_scale_is_converted_at_the_centre_latitude() {
        // Three rows of 1° from 61.5°N (tiepoint at the top-left corner): centre at 60°N.
        let tags = [
            (Tag::ModelPixelScaleTag, TagValue::Doubles(&[1.0, 1.0, 0.0])),
            (
                Tag::ModelTiepointTag,
                TagValue::Doubles(&[0.0, 0.0, 0.0, 9.0, 61.5, 0.0]),
            ),
            (
                Tag::GeoKeyDirectoryTag,
                TagValue::Shorts(&[1, 1, 0, 1, 1024, 0, 1, 2]),
            ),
        ];
        let (_, spacing) = read_tiff(&float_tiff(&[0.0; 9], &tags)).unwrap();
        let spacing = spacing.unwrap();
        assert!((spacing.dy - 111_120.0).abs() < 1e-6);
        assert!((spacing.dx - 55_560.0).abs() < 1e-6);
    }

    #[test]
    fn scale_without_model_type_gives_no_spacing() {
        let tags = [(Tag::ModelPixelScaleTag, TagValue::Doubles(&[1.0, 1.0, 0.0]))];
        let (_, spacing) = read_tiff(&float_tiff(&[0.0; 9], &tags)).unwrap();
        assert_eq!(spacing, None);
    }

    #[test]
    fn a_bad_pixel_scale_is_named() {
        let tags = [(
            Tag::ModelPixelScaleTag,
            TagValue::Doubles(&[-1.0, 1.0, 0.0]),
        )];
        let error = read_tiff(&float_tiff(&[0.0; 9], &tags))
            .unwrap_err()
            .to_string();
        assert!(error.contains("ModelPixelScaleTag (tag 33550)"), "{error}");
    }

    #[test]
    fn other_sample_types_are_refused_by_name() {
        let mut cursor = Cursor::new(Vec::new());
        TiffEncoder::new(&mut cursor)
            .unwrap()
            .write_image::<colortype::Gray8>(3, 3, &[0; 9])
            .unwrap();
        let error = read_tiff(cursor.get_ref()).unwrap_err().to_string();
        assert!(error.contains("8-bit unsigned integer"), "{error}");
        assert!(
            error.contains("expected int16, uint16 or float32"),
            "{error}"
        );

        let mut cursor = Cursor::new(Vec::new());
        TiffEncoder::new(&mut cursor)
            .unwrap()
            .write_image::<colortype::RGB8>(3, 3, &[0; 27])
            .unwrap();
        let error = read_tiff(cursor.get_ref()).unwrap_err().to_string();
        assert!(error.contains("3 samples per pixel"), "{error}");
    }

    #[test]
    fn uint16_samples_read_unsigned() {
        let mut cursor = Cursor::new(Vec::new());
        let values: Vec<u16> = (0..9).map(|v| 60_000 + v).collect();
        TiffEncoder::new(&mut cursor)
            .unwrap()
            .write_image::<colortype::Gray16>(3, 3, &values)
            .unwrap();
        let (grid, _) = read_tiff(cursor.get_ref()).unwrap();
        assert_eq!(grid.height_at(0, 0), 60_006.0);
    }

    #[test]
    fn garbage_is_reported_with_the_crate_message() {
        let error = read_tiff(b"not a tiff at all").unwrap_err().to_string();
        assert!(error.contains("dem.tif: cannot decode the TIFF"), "{error}");
    }

    #[test]
    fn geo_key_lookup_tolerates_short_directories() {
        assert_eq!(geo_key(&[], 1024), None);
        assert_eq!(geo_key(&[1, 1, 0, 5, 1024, 0], 1024), None);
        assert_eq!(geo_key(&[1, 1, 0, 1, 1024, 0, 1, 2], 1024), Some(2));
        // A key stored in another tag (location ≠ 0) is not read.
        assert_eq!(geo_key(&[1, 1, 0, 1, 1024, 34736, 1, 0], 1024), None);
    }
}
