//! A rectangular grid of height samples as a reader found it, before void filling and embedding
//! (SPEC §2: any input of at least 3×3; NaN or infinite heights are refused, never accepted
//! silently). It holds no spacing and no origin: those travel beside it to the
//! [`super::Heightfield`].
//!
//! Row order is the map's: row 0 of a [`SampleGrid`] is the **south** edge (y = 0), so readers of
//! north-up files (SRTM, PNG, GeoTIFF, ESRI grids) flip rows while reading. Void samples (SRTM's
//! −32768, a GeoTIFF's nodata value) are kept as a sorted list of indices; their height slots hold
//! 0.0 until [`super::fill::fill_voids`] replaces them.

/// Heights of a `width × height` grid, row-major from the south-west corner, with voids marked.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleGrid {
    width: usize,
    height: usize,
    heights: Vec<f32>,
    void_indices: Vec<usize>,
}

/// Why a [`SampleGrid`] could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SampleGridError {
    #[error("the grid is {width}×{height}; at least 3×3 samples are needed")]
    TooSmall { width: usize, height: usize },
    #[error("{found} height values were given for a {width}×{height} grid ({expected} expected)")]
    WrongLength {
        width: usize,
        height: usize,
        expected: usize,
        found: usize,
    },
    #[error(
        "sample at column {column}, row {row} (from the south-west) is {value}; heights must be finite"
    )]
    NotFinite {
        column: usize,
        row: usize,
        value: f32,
    },
    #[error("void index {index} is outside the {width}×{height} grid")]
    VoidOutside {
        index: usize,
        width: usize,
        height: usize,
    },
}

impl SampleGrid {
    /// Builds a grid; `heights` is row-major from the south-west corner. Every non-void height must
    /// be finite; `void_indices` may be in any order and may repeat (they are sorted and deduped).
    pub fn new(
        width: usize,
        height: usize,
        heights: Vec<f32>,
        mut void_indices: Vec<usize>,
    ) -> Result<SampleGrid, SampleGridError> {
        if width < 3 || height < 3 {
            return Err(SampleGridError::TooSmall { width, height });
        }
        let expected = width * height;
        if heights.len() != expected {
            return Err(SampleGridError::WrongLength {
                width,
                height,
                expected,
                found: heights.len(),
            });
        }
        void_indices.sort_unstable();
        void_indices.dedup();
        if let Some(&index) = void_indices.last()
            && index >= expected
        {
            return Err(SampleGridError::VoidOutside {
                index,
                width,
                height,
            });
        }
        let mut heights = heights;
        for &index in &void_indices {
            heights[index] = 0.0;
        }
        let mut voids = void_indices.iter().peekable();
        for (index, &value) in heights.iter().enumerate() {
            if voids.peek() == Some(&&index) {
                voids.next();
                continue;
            }
            if !value.is_finite() {
                return Err(SampleGridError::NotFinite {
                    column: index % width,
                    row: index / width,
                    value,
                });
            }
        }
        Ok(SampleGrid {
            width,
            height,
            heights,
            void_indices,
        })
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Row-major heights from the south-west corner; void slots hold 0.0.
    pub fn heights(&self) -> &[f32] {
        &self.heights
    }

    /// Sorted indices (row · width + column) of the void samples.
    pub fn void_indices(&self) -> &[usize] {
        &self.void_indices
    }

    pub fn height_at(&self, column: usize, row: usize) -> f32 {
        self.heights[row * self.width + column]
    }

    /// Lowest and highest non-void height, or `None` when every sample is void.
    pub fn height_range(&self) -> Option<(f32, f32)> {
        let mut voids = self.void_indices.iter().peekable();
        let mut range: Option<(f32, f32)> = None;
        for (index, &value) in self.heights.iter().enumerate() {
            if voids.peek() == Some(&&index) {
                voids.next();
                continue;
            }
            range = Some(match range {
                None => (value, value),
                Some((lo, hi)) => (lo.min(value), hi.max(value)),
            });
        }
        range
    }

    pub(super) fn into_parts(self) -> (usize, usize, Vec<f32>, Vec<usize>) {
        (self.width, self.height, self.heights, self.void_indices)
    }
}
