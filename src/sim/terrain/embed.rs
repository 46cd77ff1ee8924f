//! Embedding an arbitrary grid into a (2^n+1)² height field: padding or cropping (SPEC §2: the
//! smallest 2^n+1 square, padding replicating the border, cropping on request). It neither fills
//! voids (a grid with voids left is refused) nor resamples.
//!
//! Padding places the data at the south-west corner and fills the east and north margins by
//! replicating the nearest border sample, so the padding adds no new relief across the border
//! (though a border whose profile varies still has vertex errors along it, and the padding repeats
//! that profile). The height field remembers the real data extent so the audit ignores the
//! padding samples. Cropping takes the largest (2^n+1)² window that fits, at most
//! [`MAX_SIDE`]², at a chosen origin (by default centred). A padded side above [`MAX_SIDE`] is
//! refused before anything is allocated; [`fitted_side`] says the side before the grid is read.

use super::{Heightfield, HeightfieldError, MAX_SIDE, SampleGrid, Spacing};

/// How a grid that is not (2^n+1)² becomes one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fit {
    /// Grow to the smallest 2^n+1 side that holds the grid, replicating the border.
    Pad,
    /// Cut the largest 2^n+1 square that fits, at most [`MAX_SIDE`]; `origin` is its south-west
    /// sample (column, row), or `None` to centre it.
    Crop { origin: Option<(usize, usize)> },
}

/// What embedding did, for the run metadata.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EmbedReport {
    pub source_columns: usize,
    pub source_rows: usize,
    pub side: usize,
    /// Columns added on the east and rows added on the north (padding).
    pub padded_columns: usize,
    pub padded_rows: usize,
    /// South-west sample of the cropped window in the source grid (cropping).
    pub crop_origin: Option<(usize, usize)>,
}

/// Why a grid could not be embedded.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EmbedError {
    #[error("the grid still has {n_voids} void samples; fill them first")]
    VoidsLeft { n_voids: usize },
    #[error(
        "a {side}×{side} crop at column {column}, row {row} does not fit in the {columns}×{rows} grid"
    )]
    CropOutside {
        side: usize,
        column: usize,
        row: usize,
        columns: usize,
        rows: usize,
    },
    #[error(transparent)]
    Heightfield(#[from] HeightfieldError),
}

/// Embeds a void-free grid into a height field.
pub fn embed(
    grid: &SampleGrid,
    fit: Fit,
    spacing: Spacing,
) -> Result<(Heightfield, EmbedReport), EmbedError> {
    if !grid.void_indices().is_empty() {
        return Err(EmbedError::VoidsLeft {
            n_voids: grid.void_indices().len(),
        });
    }
    let (columns, rows) = (grid.width(), grid.height());
    let side = fitted_side(columns, rows, fit);
    if side > MAX_SIDE {
        return Err(HeightfieldError::TooLarge { side }.into());
    }
    match fit {
        Fit::Pad => {
            let mut heights = Vec::with_capacity(side * side);
            for j in 0..side {
                let row = j.min(rows - 1);
                for i in 0..side {
                    heights.push(grid.height_at(i.min(columns - 1), row));
                }
            }
            let field = Heightfield::with_data_extent(side, heights, spacing, columns, rows)?;
            let report = EmbedReport {
                source_columns: columns,
                source_rows: rows,
                side,
                padded_columns: side - columns,
                padded_rows: side - rows,
                crop_origin: None,
            };
            Ok((field, report))
        }
        Fit::Crop { origin } => {
            let (column, row) = origin.unwrap_or(((columns - side) / 2, (rows - side) / 2));
            if column + side > columns || row + side > rows {
                return Err(EmbedError::CropOutside {
                    side,
                    column,
                    row,
                    columns,
                    rows,
                });
            }
            let mut heights = Vec::with_capacity(side * side);
            for j in 0..side {
                for i in 0..side {
                    heights.push(grid.height_at(column + i, row + j));
                }
            }
            let field = Heightfield::new(side, heights, spacing)?;
            let report = EmbedReport {
                source_columns: columns,
                source_rows: rows,
                side,
                padded_columns: 0,
                padded_rows: 0,
                crop_origin: Some((column, row)),
            };
            Ok((field, report))
        }
    }
}

/// The side of the height field a `columns` × `rows` grid (both ≥ 3) becomes under `fit`,
/// before it is read: above [`MAX_SIDE`] only when padding, and then refused by [`embed`].
pub fn fitted_side(columns: usize, rows: usize, fit: Fit) -> usize {
    match fit {
        Fit::Pad => (columns.max(rows) - 1).next_power_of_two() + 1,
        Fit::Crop { .. } => largest_side_within(columns.min(rows)).min(MAX_SIDE),
    }
}

/// The largest 2^n+1 that is at most `limit` (limit ≥ 3).
fn largest_side_within(limit: usize) -> usize {
    let cells = limit - 1;
    (1usize << (usize::BITS - 1 - cells.leading_zeros())) + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT: Spacing = Spacing { dx: 1.0, dy: 1.0 };

    fn ramp(columns: usize, rows: usize) -> SampleGrid {
        let heights = (0..columns * rows).map(|k| k as f32).collect();
        SampleGrid::new(columns, rows, heights, Vec::new()).unwrap()
    }

    #[test]
    fn padding_a_6_by_4_grid_gives_side_9_replicating_the_border() {
        let (field, report) = embed(&ramp(6, 4), Fit::Pad, UNIT).unwrap();
        assert_eq!(field.side(), 9);
        assert_eq!((report.padded_columns, report.padded_rows), (3, 5));
        assert_eq!((field.data_columns(), field.data_rows()), (6, 4));
        // East padding replicates column 5, north padding replicates row 3.
        assert_eq!(field.height(8, 0), 5.0);
        assert_eq!(field.height(0, 8), 18.0);
        assert_eq!(field.height(8, 8), 23.0);
    }

    #[test]
    fn a_grid_of_side_two_to_the_n_plus_one_is_not_padded() {
        let (field, report) = embed(&ramp(5, 5), Fit::Pad, UNIT).unwrap();
        assert_eq!(field.side(), 5);
        assert_eq!((report.padded_columns, report.padded_rows), (0, 0));
    }

    #[test]
    fn a_grid_padded_past_the_largest_side_is_refused_before_it_is_allocated() {
        // 40 000 columns pad to 65 537²: 17 GB of heights, never allocated.
        let error = embed(&ramp(40_000, 3), Fit::Pad, UNIT).unwrap_err();
        assert_eq!(
            error,
            EmbedError::Heightfield(HeightfieldError::TooLarge { side: 65_537 })
        );
        assert!(error.to_string().contains("32769"), "{error}");
    }

    #[test]
    fn cropping_keeps_within_the_largest_side() {
        assert_eq!(
            fitted_side(70_000, 80_000, Fit::Crop { origin: None }),
            MAX_SIDE
        );
        assert_eq!(
            fitted_side(40_000, 40_000, Fit::Crop { origin: None }),
            MAX_SIDE
        );
        assert_eq!(fitted_side(40_000, 40_000, Fit::Pad), 65_537);
        assert_eq!(fitted_side(1201, 1201, Fit::Crop { origin: None }), 1025);
    }

    #[test]
    fn cropping_1201_gives_a_centred_1025_window() {
        assert_eq!(largest_side_within(1201), 1025);
        assert_eq!(largest_side_within(3), 3);
        assert_eq!(largest_side_within(8), 5);
        let (field, report) = embed(&ramp(10, 12), Fit::Crop { origin: None }, UNIT).unwrap();
        assert_eq!(field.side(), 9);
        assert_eq!(report.crop_origin, Some((0, 1)));
        assert_eq!(field.height(0, 0), 10.0);
    }

    #[test]
    fn a_crop_outside_the_grid_is_an_error() {
        let error = embed(
            &ramp(10, 10),
            Fit::Crop {
                origin: Some((2, 0)),
            },
            UNIT,
        )
        .unwrap_err();
        assert!(matches!(error, EmbedError::CropOutside { column: 2, .. }));
    }
}
