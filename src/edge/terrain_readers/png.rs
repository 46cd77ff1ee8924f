//! The PNG reader: 8- or 16-bit grayscale height maps, north row first (the options it takes:
//! `docs/experiment-format.md`, "Terrain"). The rows are turned over so that grid row 0 is the
//! south edge, as every reader's grid is. It is not an image reader (what it refuses, below).
//!
//! Only plain grayscale is accepted: no alpha, palette or colour, and no 1-, 2- or 4-bit depths,
//! because a height map stored that way is almost certainly an image that is not a height map.
//! PNG declares neither nodata nor spacing: voids come only from [`ReadOptions::nodata`], and
//! the `tRNS` chunk is ignored. Only the first frame of an animated PNG is read.

use super::{
    DEFLATE_MAX_EXPANSION, FileRowOrder, ReadOptions, SampleCollector, StoredPrecision,
    TerrainReadError,
};
use crate::sim::terrain::{SampleGrid, Spacing};
use std::io::Cursor;
use std::path::Path;

/// What a refused colour PNG is told: roamsim does not guess which of the colour encodings of
/// heights (grey stored as RGB, Mapbox Terrain-RGB, Terrarium, a colour ramp) the file uses.
const HOW_TO_CONVERT_COLOUR: &str = ". roamsim does not guess how colour encodes height: \
    a grey image saved as RGB converts with `magick IN.png -colorspace Gray -depth 16 OUT.png` \
    (ImageMagick) or `gdal_translate -b 1 -ot UInt16 IN.png OUT.png` (GDAL); an encoded DEM \
    (Mapbox Terrain-RGB: h = −10000 + 0.1·(65536·R + 256·G + B); Terrarium: h = 256·R + G + \
    B/256 − 32768) must be decoded to heights first, e.g. into a float32 GeoTIFF";

/// What a refused grey-with-alpha PNG is told.
const HOW_TO_DROP_ALPHA: &str = ": drop the alpha channel, e.g. `magick IN.png -alpha off \
    OUT.png`, and mark voids with `nodata` instead";

/// Reads a grayscale PNG; the spacing is always `None`.
pub(super) fn read(
    path: &Path,
    bytes: &[u8],
    options: &ReadOptions,
) -> Result<(SampleGrid, Option<Spacing>), TerrainReadError> {
    let png_error = |error: ::png::DecodingError| {
        TerrainReadError::new(path, format!("not a valid PNG: {error}"))
    };
    let mut decoder = ::png::Decoder::new(Cursor::new(bytes));
    decoder.set_transformations(::png::Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(png_error)?;
    let info = reader.info();
    let (columns, rows) = (info.width as usize, info.height as usize);
    let bytes_per_sample = match (info.color_type, info.bit_depth) {
        (::png::ColorType::Grayscale, ::png::BitDepth::Eight) => 1,
        (::png::ColorType::Grayscale, ::png::BitDepth::Sixteen) => 2,
        (color_type, bit_depth) => {
            let how = match color_type {
                ::png::ColorType::Rgb | ::png::ColorType::Rgba => HOW_TO_CONVERT_COLOUR,
                ::png::ColorType::GrayscaleAlpha => HOW_TO_DROP_ALPHA,
                _ => "",
            };
            return Err(TerrainReadError::new(
                path,
                format!(
                    "the PNG is {}-bit {}; expected 8- or 16-bit grayscale \
                     (no alpha, no palette, no colour){how}",
                    bit_depth as u8,
                    colour_type_name(color_type)
                ),
            ));
        }
    };
    let declared_bytes = columns
        .checked_mul(rows)
        .and_then(|n_samples| n_samples.checked_mul(bytes_per_sample));
    let plausible_bytes = bytes.len().saturating_mul(DEFLATE_MAX_EXPANSION);
    if declared_bytes.is_none_or(|declared| declared > plausible_bytes) {
        return Err(TerrainReadError::new(
            path,
            format!(
                "the PNG header declares {columns}×{rows} samples, more than a {}-byte file can \
                 hold (deflate expands at most {DEFLATE_MAX_EXPANSION}-fold)",
                bytes.len()
            ),
        ));
    }
    let buffer_length = reader.output_buffer_size().ok_or_else(|| {
        TerrainReadError::new(path, "the PNG image is too large for this machine")
    })?;
    let mut buffer = Vec::new();
    buffer.try_reserve_exact(buffer_length).map_err(|error| {
        TerrainReadError::new(path, format!("cannot allocate the PNG image: {error}"))
    })?;
    buffer.resize(buffer_length, 0_u8);
    let frame = reader.next_frame(&mut buffer).map_err(png_error)?;
    let mut collector = SampleCollector::new(
        path,
        columns,
        rows,
        FileRowOrder::NorthFirst,
        StoredPrecision::Exact,
        None,
        options,
    )?;
    let row_bytes = columns * bytes_per_sample;
    for file_row in 0..rows {
        let row_start = file_row * frame.line_size;
        let row = buffer
            .get(row_start..row_start + row_bytes)
            .ok_or_else(|| {
                TerrainReadError::new(
                    path,
                    format!(
                        "the PNG decoder returned too few bytes for row {} of {rows}",
                        file_row + 1
                    ),
                )
            })?;
        if bytes_per_sample == 1 {
            for &stored in row {
                collector.push(f64::from(stored))?;
            }
        } else {
            for sample in row.chunks_exact(2) {
                collector.push(f64::from(u16::from_be_bytes([sample[0], sample[1]])))?;
            }
        }
    }
    let grid = collector.finish()?;
    Ok((grid, None))
}

fn colour_type_name(color_type: ::png::ColorType) -> &'static str {
    match color_type {
        ::png::ColorType::Grayscale => "grayscale",
        ::png::ColorType::Rgb => "RGB",
        ::png::ColorType::Indexed => "palette (indexed colour)",
        ::png::ColorType::GrayscaleAlpha => "grayscale with alpha",
        ::png::ColorType::Rgba => "RGBA",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn encode(
        columns: u32,
        rows: u32,
        color_type: ::png::ColorType,
        bit_depth: ::png::BitDepth,
        data: &[u8],
    ) -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut encoder = ::png::Encoder::new(&mut bytes, columns, rows);
        encoder.set_color(color_type);
        encoder.set_depth(bit_depth);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(data).unwrap();
        writer.finish().unwrap();
        bytes
    }

    fn read_png(bytes: &[u8], options: &ReadOptions) -> Result<SampleGrid, TerrainReadError> {
        read(Path::new("heights.png"), bytes, options).map(|(grid, _)| grid)
    }

    #[test]
    fn eight_bit_grayscale_is_flipped_and_scaled() {
        let data: Vec<u8> = (0..12).collect();
        let bytes = encode(
            4,
            3,
            ::png::ColorType::Grayscale,
            ::png::BitDepth::Eight,
            &data,
        );
        let options = ReadOptions {
            height_scale: 10.0,
            height_offset: -5.0,
            nodata: Some(11.0),
        };
        let grid = read_png(&bytes, &options).unwrap();
        assert_eq!((grid.width(), grid.height()), (4, 3));
        // File row 0 (north) is grid row 2.
        assert_eq!(grid.height_at(0, 2), -5.0);
        assert_eq!(grid.height_at(1, 0), 85.0);
        assert_eq!(grid.void_indices(), &[3]);
    }

    #[test]
    fn sixteen_bit_samples_are_big_endian() {
        let values: Vec<u16> = (0..9).map(|v| 1000 * v + 7).collect();
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
        let bytes = encode(
            3,
            3,
            ::png::ColorType::Grayscale,
            ::png::BitDepth::Sixteen,
            &data,
        );
        let grid = read_png(&bytes, &ReadOptions::AS_STORED).unwrap();
        assert_eq!(grid.height_at(2, 0), 8007.0);
        assert_eq!(grid.height_at(0, 2), 7.0);
    }

    #[test]
    fn colour_and_low_bit_depths_are_refused_by_name() {
        let rgba = encode(
            3,
            3,
            ::png::ColorType::Rgba,
            ::png::BitDepth::Eight,
            &[0; 36],
        );
        let error = read_png(&rgba, &ReadOptions::AS_STORED)
            .unwrap_err()
            .to_string();
        assert!(error.contains("heights.png"), "{error}");
        assert!(error.contains("8-bit RGBA"), "{error}");
        assert!(error.contains("expected 8- or 16-bit grayscale"), "{error}");
        assert!(error.contains("-colorspace Gray -depth 16"), "{error}");
        assert!(error.contains("Terrarium"), "{error}");

        let four_bit = encode(
            4,
            3,
            ::png::ColorType::Grayscale,
            ::png::BitDepth::Four,
            &[0; 6],
        );
        let error = read_png(&four_bit, &ReadOptions::AS_STORED)
            .unwrap_err()
            .to_string();
        assert!(error.contains("4-bit grayscale"), "{error}");
    }

    #[test]
    fn garbage_is_not_a_png() {
        let error = read_png(b"GIF89a and more", &ReadOptions::AS_STORED)
            .unwrap_err()
            .to_string();
        assert!(error.contains("heights.png: not a valid PNG"), "{error}");
    }

    #[test]
    fn a_header_declaring_a_huge_image_is_refused_before_allocating() {
        let mut bytes = encode(
            3,
            3,
            ::png::ColorType::Grayscale,
            ::png::BitDepth::Sixteen,
            &[0; 18],
        );
        // IHDR width and height sit at bytes 16..24; set both to 65535 and fix the CRC.
        bytes[16..20].copy_from_slice(&65535_u32.to_be_bytes());
        bytes[20..24].copy_from_slice(&65535_u32.to_be_bytes());
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        let error = read_png(&bytes, &ReadOptions::AS_STORED)
            .unwrap_err()
            .to_string();
        assert!(error.contains("65535×65535"), "{error}");
    }

    /// The CRC-32 PNG chunks carry (ISO 3309), bit by bit.
    fn crc32(data: &[u8]) -> u32 {
        let mut crc = 0xFFFF_FFFF_u32;
        for &byte in data {
            crc ^= u32::from(byte);
            for _ in 0..8 {
                let mask = (crc & 1).wrapping_neg();
                crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
            }
        }
        !crc
    }
}
