//! The (2^n+1)² height field every algorithm runs on (SPEC §2's conventions). Its constructors
//! hold its invariants: side 2^n+1 (1 ≤ n ≤ [`MAX_LEVEL`]), finite heights, positive spacing; nothing downstream
//! checks them again. It is not a reader (`edge::terrain_readers`) nor a preprocessed hierarchy
//! (`crate::sim::hierarchy`).
//!
//! Sample (i, j) sits at x = i·dx, y = j·dy (metres, z up) in the terrain's *local* frame, row 0
//! the south edge; the world position is `origin + local`, with an `f64` origin. Every
//! algorithm, the audit and the camera work in local coordinates: the runner converts each world
//! pose once, with [`Heightfield::local_pose`] (one `f64` subtraction), so a terrain far from the
//! world origin keeps all its precision, and a terrain and flight moved together 10^6 m from it
//! give the same meshes as at the origin (SPEC §9; `tests/hard_cases.rs`). Heights are stored as
//! `f32` relative to the origin: every real elevation model fits (SRTM's int16 exactly), and it
//! halves the memory of the largest terrains; every geometric computation promotes them to
//! `f64`. The field also remembers which part of it is real data (the rest is padding), so the
//! audit measures real samples only.
//!
//! A field is held in memory, or *paged* ([`Heightfield::paged`], `paged.rs`): its samples read
//! on demand through a bounded cache, never held whole; `height`, `row`, `height_range` and
//! `ground_height` answer either way, `heights` is empty for a paged field.

use super::paged::PagedSamples;
use crate::sim::view::Pose;
use glam::{DVec2, DVec3};
use std::borrow::Cow;
use std::sync::Arc;

/// The largest level n of a height field (side 2^n + 1 = 32 769): the 4-8 hierarchy numbers its
/// vertices with 32-bit ids, and 65 537² is above 2^32. A larger terrain is refused by the
/// constructors (an error, not a panic further on).
pub const MAX_LEVEL: u32 = 15;

/// The largest side of a height field, 2^[`MAX_LEVEL`] + 1.
pub const MAX_SIDE: usize = (1 << MAX_LEVEL) + 1;

/// The largest level of a *paged* field ([`Heightfield::paged`], side 2^16 + 1 = 65 537): one
/// above [`MAX_LEVEL`], because a paged field is flown only by chunked LOD, which names its
/// vertices by chunk and position, never by a 32-bit lattice id. Its hierarchy's lattice has
/// the level (`Lattice::new`), but no vertex id of it is ever computed: the run refuses, before
/// it starts, every entry that would (`edge::experiment::terrain_pyramid`).
pub const MAX_PAGED_LEVEL: u32 = 16;

/// Grid spacing in metres along x (columns) and y (rows).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spacing {
    pub dx: f64,
    pub dy: f64,
}

/// A square height field of side 2^n+1 (n ≥ 1) with finite heights.
#[derive(Clone, Debug)]
pub struct Heightfield {
    level: u32,
    side: usize,
    /// The samples, row by row; empty for a paged field.
    heights: Vec<f32>,
    /// The samples read on demand instead (`paged.rs`); `None` for a field held in memory.
    paged: Option<Arc<dyn PagedSamples>>,
    spacing: Spacing,
    data_columns: usize,
    data_rows: usize,
    origin: DVec3,
}

/// Why a [`Heightfield`] could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum HeightfieldError {
    #[error("side {side} is not 2^n+1 with n ≥ 1")]
    SideNotPowerOfTwoPlusOne { side: usize },
    #[error(
        "side {side} is above the largest side the in-memory hierarchy holds, 32769 (2^15 + 1: \
         its vertex ids are 32-bit)"
    )]
    TooLarge { side: usize },
    #[error("side {side} is above the largest side a terrain read on demand has, 65537 (2^16 + 1)")]
    TooLargePaged { side: usize },
    #[error("{found} heights for side {side} ({expected} expected)")]
    WrongLength {
        side: usize,
        expected: usize,
        found: usize,
    },
    #[error("height at column {column}, row {row} is {value}; heights must be finite")]
    NotFinite {
        column: usize,
        row: usize,
        value: f32,
    },
    #[error("grid spacing dx = {dx}, dy = {dy}; both must be finite and positive")]
    BadSpacing { dx: f64, dy: f64 },
    #[error("data extent {columns}×{rows} does not fit in side {side}")]
    BadDataExtent {
        columns: usize,
        rows: usize,
        side: usize,
    },
}

impl Heightfield {
    /// A height field whose every sample is real data.
    pub fn new(
        side: usize,
        heights: Vec<f32>,
        spacing: Spacing,
    ) -> Result<Heightfield, HeightfieldError> {
        Heightfield::with_data_extent(side, heights, spacing, side, side)
    }

    /// A height field whose real data covers columns `0..data_columns` and rows `0..data_rows`;
    /// the rest is padding.
    pub fn with_data_extent(
        side: usize,
        heights: Vec<f32>,
        spacing: Spacing,
        data_columns: usize,
        data_rows: usize,
    ) -> Result<Heightfield, HeightfieldError> {
        let level = side_level(side).ok_or(HeightfieldError::SideNotPowerOfTwoPlusOne { side })?;
        if level > MAX_LEVEL {
            return Err(HeightfieldError::TooLarge { side });
        }
        let expected = side * side;
        if heights.len() != expected {
            return Err(HeightfieldError::WrongLength {
                side,
                expected,
                found: heights.len(),
            });
        }
        if let Some(index) = heights.iter().position(|z| !z.is_finite()) {
            return Err(HeightfieldError::NotFinite {
                column: index % side,
                row: index / side,
                value: heights[index],
            });
        }
        let spacing_ok = |d: f64| d.is_finite() && d > 0.0;
        if !spacing_ok(spacing.dx) || !spacing_ok(spacing.dy) {
            return Err(HeightfieldError::BadSpacing {
                dx: spacing.dx,
                dy: spacing.dy,
            });
        }
        if data_columns == 0 || data_rows == 0 || data_columns > side || data_rows > side {
            return Err(HeightfieldError::BadDataExtent {
                columns: data_columns,
                rows: data_rows,
                side,
            });
        }
        Ok(Heightfield {
            level,
            side,
            heights,
            paged: None,
            spacing,
            data_columns,
            data_rows,
            origin: DVec3::ZERO,
        })
    }

    /// A field of side 2^`level` + 1 whose samples are read on demand from `samples` (every
    /// sample real data); none is read here. Level 1 to [`MAX_PAGED_LEVEL`] (one more than
    /// [`Heightfield::new`] takes).
    pub fn paged(
        level: u32,
        samples: Arc<dyn PagedSamples>,
        spacing: Spacing,
    ) -> Result<Heightfield, HeightfieldError> {
        let side = (1usize << level.min(usize::BITS - 2)) + 1;
        if level == 0 {
            return Err(HeightfieldError::SideNotPowerOfTwoPlusOne { side });
        }
        if level > MAX_PAGED_LEVEL {
            return Err(HeightfieldError::TooLargePaged { side });
        }
        let spacing_ok = |d: f64| d.is_finite() && d > 0.0;
        if !spacing_ok(spacing.dx) || !spacing_ok(spacing.dy) {
            return Err(HeightfieldError::BadSpacing {
                dx: spacing.dx,
                dy: spacing.dy,
            });
        }
        Ok(Heightfield {
            level,
            side,
            heights: Vec::new(),
            paged: Some(samples),
            spacing,
            data_columns: side,
            data_rows: side,
            origin: DVec3::ZERO,
        })
    }

    /// The samples read on demand, for a paged field; `None` for one held in memory.
    pub fn paged_samples(&self) -> Option<&Arc<dyn PagedSamples>> {
        self.paged.as_ref()
    }

    /// The same field placed with its sample (0, 0) at height 0 at world point `origin`.
    pub fn with_origin(mut self, origin: DVec3) -> Heightfield {
        self.origin = origin;
        self
    }

    /// World position of the local origin.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// A world pose in the terrain's local frame.
    pub fn local_pose(&self, pose: &Pose) -> Pose {
        Pose {
            position: pose.position - self.origin,
            ..*pose
        }
    }

    /// n, where the side is 2^n + 1.
    pub fn level(&self) -> u32 {
        self.level
    }

    pub fn side(&self) -> usize {
        self.side
    }

    pub fn n_samples(&self) -> usize {
        self.side * self.side
    }

    pub fn spacing(&self) -> Spacing {
        self.spacing
    }

    /// Row-major heights from the south-west corner; empty for a paged field (read it with
    /// [`Heightfield::height`] or [`Heightfield::row`]).
    pub fn heights(&self) -> &[f32] {
        &self.heights
    }

    #[inline]
    pub fn height(&self, i: usize, j: usize) -> f32 {
        match &self.paged {
            None => self.heights[j * self.side + i],
            Some(paged) => paged.height(i, j),
        }
    }

    /// Row `j`'s heights, west to east: borrowed from memory, or read into a new buffer for a
    /// paged field.
    pub fn row(&self, j: usize) -> Cow<'_, [f32]> {
        match &self.paged {
            None => Cow::Borrowed(&self.heights[j * self.side..][..self.side]),
            Some(paged) => {
                let mut row = Vec::with_capacity(self.side);
                paged.row(j, &mut row);
                Cow::Owned(row)
            }
        }
    }

    /// Local position of sample (i, j).
    pub fn position(&self, i: usize, j: usize) -> DVec3 {
        DVec3::new(
            i as f64 * self.spacing.dx,
            j as f64 * self.spacing.dy,
            f64::from(self.height(i, j)),
        )
    }

    /// Columns `0..data_columns()` hold real data; the rest is padding.
    pub fn data_columns(&self) -> usize {
        self.data_columns
    }

    /// Rows `0..data_rows()` hold real data; the rest is padding.
    pub fn data_rows(&self) -> usize {
        self.data_rows
    }

    /// Lowest and highest height.
    pub fn height_range(&self) -> (f32, f32) {
        if let Some(paged) = &self.paged {
            return paged.height_range();
        }
        self.heights
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &z| {
                (lo.min(z), hi.max(z))
            })
    }

    /// The ground's world height under world point `(x, y)`: the bilinear interpolation of the
    /// four samples of the cell holding it (continuous everywhere, exact at samples). Points
    /// outside the terrain take the height of the nearest point of its border.
    pub fn ground_height(&self, world_xy: DVec2) -> f64 {
        let cells = (self.side - 1) as f64;
        let u = ((world_xy.x - self.origin.x) / self.spacing.dx).clamp(0.0, cells);
        let v = ((world_xy.y - self.origin.y) / self.spacing.dy).clamp(0.0, cells);
        // The cell's south-west corner, kept inside so that the far border uses the last cell.
        let i = (u.floor() as usize).min(self.side - 2);
        let j = (v.floor() as usize).min(self.side - 2);
        let (fu, fv) = (u - i as f64, v - j as f64);
        let z = |i: usize, j: usize| f64::from(self.height(i, j));
        let south = z(i, j) * (1.0 - fu) + z(i + 1, j) * fu;
        let north = z(i, j + 1) * (1.0 - fu) + z(i + 1, j + 1) * fu;
        self.origin.z + south * (1.0 - fv) + north * fv
    }

    /// Whether world point `(x, y)` lies over the terrain (its border included).
    pub fn covers(&self, world_xy: DVec2) -> bool {
        let (width, depth) = self.extent();
        let local = world_xy - self.origin.truncate();
        (0.0..=width).contains(&local.x) && (0.0..=depth).contains(&local.y)
    }

    /// Extent of the terrain in metres along x and y.
    pub fn extent(&self) -> (f64, f64) {
        let cells = (self.side - 1) as f64;
        (cells * self.spacing.dx, cells * self.spacing.dy)
    }
}

/// n if `side` = 2^n + 1 with n ≥ 1.
pub(crate) fn side_level(side: usize) -> Option<u32> {
    let cells = side.checked_sub(1)?;
    (cells >= 2 && cells.is_power_of_two()).then(|| cells.trailing_zeros())
}

#[cfg(test)]
mod tests {
    use super::*;

    const UNIT: Spacing = Spacing { dx: 1.0, dy: 1.0 };

    #[test]
    fn a_side_above_the_hierarchys_limit_is_an_error() {
        let error = Heightfield::new(65_537, Vec::new(), UNIT).unwrap_err();
        assert_eq!(error, HeightfieldError::TooLarge { side: 65_537 });
        assert_eq!(MAX_SIDE, 32_769);
        // The largest side passes the size check (and fails on the empty heights).
        assert!(matches!(
            Heightfield::new(MAX_SIDE, Vec::new(), UNIT),
            Err(HeightfieldError::WrongLength { .. })
        ));
    }

    #[test]
    fn sides_of_the_form_two_to_the_n_plus_one_are_accepted() {
        assert_eq!(side_level(3), Some(1));
        assert_eq!(side_level(1025), Some(10));
        assert_eq!(side_level(2), None);
        assert_eq!(side_level(1024), None);
        assert_eq!(side_level(0), None);
    }

    #[test]
    fn a_nan_height_is_rejected_with_its_position() {
        let mut heights = vec![0.0; 9];
        heights[5] = f32::NAN;
        let error = Heightfield::new(3, heights, UNIT).unwrap_err();
        assert!(matches!(
            error,
            HeightfieldError::NotFinite {
                column: 2,
                row: 1,
                ..
            }
        ));
    }

    #[test]
    fn spacing_must_be_positive() {
        let error = Heightfield::new(3, vec![0.0; 9], Spacing { dx: 0.0, dy: 1.0 }).unwrap_err();
        assert_eq!(error, HeightfieldError::BadSpacing { dx: 0.0, dy: 1.0 });
    }

    #[test]
    fn the_ground_height_is_bilinear_in_world_coordinates_and_clamped_outside() {
        // Heights 0..8 row by row: z = i + 3j at sample (i, j), spacing 10 m, origin (100, 200, 5).
        let heights: Vec<f32> = (0..9).map(|k| k as f32).collect();
        let field = Heightfield::new(3, heights, Spacing { dx: 10.0, dy: 10.0 })
            .unwrap()
            .with_origin(DVec3::new(100.0, 200.0, 5.0));
        let at = |x: f64, y: f64| field.ground_height(DVec2::new(x, y));
        assert_eq!(at(100.0, 200.0), 5.0);
        assert_eq!(at(120.0, 220.0), 5.0 + 8.0);
        // A plane is reproduced exactly inside cells.
        assert!((at(105.0, 215.0) - (5.0 + 0.5 + 3.0 * 1.5)).abs() < 1e-12);
        // Outside: the nearest border point.
        assert_eq!(at(50.0, 200.0), 5.0);
        assert_eq!(at(500.0, 500.0), 5.0 + 8.0);
        assert!(field.covers(DVec2::new(120.0, 200.0)));
        assert!(!field.covers(DVec2::new(120.1, 200.0)));
    }
}
