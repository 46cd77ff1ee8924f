//! The raw reader: headerless samples of a layout the caller declares (size, sample type, byte
//! order, which edge comes first; `docs/experiment-format.md`, "Terrain", `format.raw`). The file
//! does not say which row is north: with `north_first` the rows are turned over so that grid row
//! 0 is the south edge, as every reader's grid is; without it file row 0 is grid row 0. It
//! guesses no layout.
//!
//! The file must hold exactly `columns × rows` samples: nothing is skipped or padded, and a
//! header, if the file has one, is not recognised. Raw files declare no nodata value and no
//! spacing: voids come only from [`ReadOptions::nodata`].

use super::{
    FileRowOrder, RawLayout, RawSample, ReadOptions, SampleCollector, StoredPrecision,
    TerrainReadError,
};
use crate::sim::terrain::{SampleGrid, Spacing};
use std::path::Path;

/// Reads a raw file of the declared layout; the spacing is always `None`.
pub(super) fn read(
    path: &Path,
    bytes: &[u8],
    layout: &RawLayout,
    options: &ReadOptions,
) -> Result<(SampleGrid, Option<Spacing>), TerrainReadError> {
    let sample_bytes = layout.sample.bytes();
    let expected_length = layout
        .columns
        .checked_mul(layout.rows)
        .and_then(|n_samples| n_samples.checked_mul(sample_bytes));
    if expected_length != Some(bytes.len()) {
        let expected = match expected_length {
            Some(length) => format!("{length} bytes"),
            None => "more bytes than this machine can address".to_string(),
        };
        return Err(TerrainReadError::new(
            path,
            format!(
                "the file has {} bytes; the declared layout ({} columns × {} rows of {:?}, \
                 {sample_bytes} bytes each) needs {expected}",
                bytes.len(),
                layout.columns,
                layout.rows,
                layout.sample
            ),
        ));
    }
    let row_order = if layout.north_first {
        FileRowOrder::NorthFirst
    } else {
        FileRowOrder::SouthFirst
    };
    let precision = match layout.sample {
        RawSample::F32Le | RawSample::F32Be => StoredPrecision::Float32,
        _ => StoredPrecision::Exact,
    };
    let mut collector = SampleCollector::new(
        path,
        layout.columns,
        layout.rows,
        row_order,
        precision,
        None,
        options,
    )?;
    for sample in bytes.chunks_exact(sample_bytes) {
        collector.push(decode_sample(layout.sample, sample))?;
    }
    let grid = collector.finish()?;
    Ok((grid, None))
}

/// Decodes one sample; `sample` has exactly `kind.bytes()` bytes (missing bytes read as 0).
pub(crate) fn decode_sample(kind: RawSample, sample: &[u8]) -> f64 {
    let byte = |index: usize| sample.get(index).copied().unwrap_or(0);
    let two = [byte(0), byte(1)];
    let four = [byte(0), byte(1), byte(2), byte(3)];
    match kind {
        RawSample::I16Le => f64::from(i16::from_le_bytes(two)),
        RawSample::I16Be => f64::from(i16::from_be_bytes(two)),
        RawSample::U16Le => f64::from(u16::from_le_bytes(two)),
        RawSample::U16Be => f64::from(u16::from_be_bytes(two)),
        RawSample::F32Le => f64::from(f32::from_le_bytes(four)),
        RawSample::F32Be => f64::from(f32::from_be_bytes(four)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(sample: RawSample, north_first: bool) -> RawLayout {
        RawLayout {
            columns: 3,
            rows: 3,
            sample,
            north_first,
        }
    }

    fn read_raw(bytes: &[u8], layout: RawLayout) -> Result<SampleGrid, TerrainReadError> {
        read(
            Path::new("terrain.raw"),
            bytes,
            &layout,
            &ReadOptions::AS_STORED,
        )
        .map(|(grid, _)| grid)
    }

    #[test]
    fn every_sample_type_decodes() {
        let values: Vec<i16> = (1..=9).collect();
        type Encode = fn(i16) -> Vec<u8>;
        let encodings: [(RawSample, Encode); 6] = [
            (RawSample::I16Le, |v| v.to_le_bytes().to_vec()),
            (RawSample::I16Be, |v| v.to_be_bytes().to_vec()),
            (RawSample::U16Le, |v| (v as u16).to_le_bytes().to_vec()),
            (RawSample::U16Be, |v| (v as u16).to_be_bytes().to_vec()),
            (RawSample::F32Le, |v| f32::from(v).to_le_bytes().to_vec()),
            (RawSample::F32Be, |v| f32::from(v).to_be_bytes().to_vec()),
        ];
        for (sample, encode) in encodings {
            let bytes: Vec<u8> = values.iter().flat_map(|&v| encode(v)).collect();
            let grid = read_raw(&bytes, layout(sample, false)).unwrap();
            let expected: Vec<f32> = values.iter().map(|&v| f32::from(v)).collect();
            assert_eq!(grid.heights(), expected.as_slice(), "{sample:?}");
        }
    }

    #[test]
    fn north_first_files_are_flipped() {
        let bytes: Vec<u8> = (1..=9_i16).flat_map(|v| v.to_le_bytes()).collect();
        let grid = read_raw(&bytes, layout(RawSample::I16Le, true)).unwrap();
        assert_eq!(
            grid.heights(),
            &[7.0, 8.0, 9.0, 4.0, 5.0, 6.0, 1.0, 2.0, 3.0]
        );
    }

    #[test]
    fn unsigned_samples_above_i16_range_are_kept() {
        let bytes: Vec<u8> = (0..9_u16).flat_map(|v| (v + 65000).to_be_bytes()).collect();
        let grid = read_raw(&bytes, layout(RawSample::U16Be, false)).unwrap();
        assert_eq!(grid.height_at(2, 2), 65008.0);
    }

    #[test]
    fn wrong_length_names_both_numbers() {
        let error = read_raw(&[0; 17], layout(RawSample::I16Le, false))
            .unwrap_err()
            .to_string();
        assert!(error.contains("terrain.raw"), "{error}");
        assert!(error.contains("17 bytes"), "{error}");
        assert!(error.contains("needs 18 bytes"), "{error}");
    }

    #[test]
    fn overflowing_layout_is_an_error_not_a_panic() {
        let huge = RawLayout {
            columns: usize::MAX,
            rows: 3,
            sample: RawSample::F32Le,
            north_first: false,
        };
        let error = read_raw(&[0; 8], huge).unwrap_err().to_string();
        assert!(error.contains("more bytes than"), "{error}");
    }

    #[test]
    fn nan_is_an_error_unless_it_is_the_nodata_value() {
        let mut values = [1.0_f32; 9];
        values[1] = f32::NAN;
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let error = read_raw(&bytes, layout(RawSample::F32Le, true))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("row 1 of 3 (counted from the north edge"),
            "{error}"
        );
        assert!(error.contains("column 2 of 3"), "{error}");
        assert!(error.contains("NaN"), "{error}");

        let options = ReadOptions {
            nodata: Some(f64::NAN),
            ..ReadOptions::AS_STORED
        };
        let (grid, _) = read(
            Path::new("terrain.raw"),
            &bytes,
            &layout(RawSample::F32Le, true),
            &options,
        )
        .unwrap();
        assert_eq!(grid.void_indices(), &[7]);
    }

    #[test]
    fn a_grid_smaller_than_three_by_three_is_refused() {
        let tiny = RawLayout {
            columns: 2,
            rows: 2,
            sample: RawSample::I16Le,
            north_first: false,
        };
        let error = read_raw(&[0; 8], tiny).unwrap_err().to_string();
        assert!(error.contains("at least 3×3"), "{error}");
    }
}
