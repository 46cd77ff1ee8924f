//! Where a drawn vertex sits: a position in the terrain's plane in fixed-point grid units, and a
//! height of its own (SPEC §3: the families beyond 4-8 draw vertices at fractional positions and
//! heights between levels). These are the vertices of the general mesh form; a 4-8 mesh's
//! vertices are grid samples, held by vertex id in a [`super::VertexSet`].
//!
//! Positions are measured in grid cells from sample (0, 0) (x along columns, y along rows), in
//! `i64` fixed point with [`SUBGRID_BITS`] fractional bits: 1/65 536 of a cell, the sub-texel
//! precision a GPU tessellator works at. Grid samples are exact (`SubgridPoint::grid`), and so is
//! every dyadic fraction down to that precision; other fractions (a continuous tessellation
//! factor's vertices) are rounded to the nearest representable point once, when the algorithm
//! makes the vertex, so every consumer afterwards sees the same exact point. Integer coordinates
//! are what make the audit's inside tests exact (no two triangles both claim, or both miss, a
//! sample on their shared edge): coordinates are at most 2^32, differences of two coordinates
//! fit 34 bits, products of two differences fit an `i128`, so the inside tests multiply in
//! `i128`, exactly.
//!
//! Heights are `f32` metres in the terrain's local frame, like the stored samples: a morphed or
//! resampled height is whatever the algorithm computed, rounded as a GPU vertex buffer would hold
//! it. Consumers interpolate heights between corners in `f64` (`raster`).

use crate::sim::hierarchy::GridPoint;
use crate::sim::terrain::{MAX_PAGED_LEVEL, Spacing};
use glam::DVec3;

/// Fractional bits of a [`SubgridPoint`] coordinate.
pub const SUBGRID_BITS: u32 = 16;
/// Fixed-point units per grid cell.
pub const SUBGRID_UNITS_PER_CELL: i64 = 1 << SUBGRID_BITS;

/// A point in the terrain's plane, in 1/65 536 of a grid cell. Coordinates are non-negative and
/// at most 2^(16 + 16) (the largest terrain, a paged one, has 2^16 cells:
/// `terrain::MAX_PAGED_LEVEL`); [`crate::sim::mesh::TriangleList`] checks that its vertices lie
/// inside its terrain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SubgridPoint {
    x: i64,
    y: i64,
}

/// The largest coordinate any point may have: 2^16 cells (`terrain::MAX_PAGED_LEVEL`).
const MAX_COORDINATE: i64 = (1 << MAX_PAGED_LEVEL) * SUBGRID_UNITS_PER_CELL;

impl SubgridPoint {
    /// Grid sample (i, j), exactly.
    pub const fn grid(i: u32, j: u32) -> SubgridPoint {
        SubgridPoint {
            x: (i as i64) << SUBGRID_BITS,
            y: (j as i64) << SUBGRID_BITS,
        }
    }

    /// The point of grid coordinates (x, y) (cells, fractions allowed), rounded to the nearest
    /// 1/65 536 of a cell (ties away from zero). `None` when a coordinate is not finite or lies
    /// outside [0, 2^16].
    pub fn from_grid_units(x: f64, y: f64) -> Option<SubgridPoint> {
        let fixed = |v: f64| {
            let scaled = (v * SUBGRID_UNITS_PER_CELL as f64).round();
            (scaled.is_finite() && (0.0..=MAX_COORDINATE as f64).contains(&scaled))
                .then_some(scaled as i64)
        };
        Some(SubgridPoint {
            x: fixed(x)?,
            y: fixed(y)?,
        })
    }

    /// The point with raw fixed-point coordinates (units of 1/65 536 cell). `None` outside
    /// [0, 2^32].
    pub fn from_raw(x: i64, y: i64) -> Option<SubgridPoint> {
        let valid = |v: i64| (0..=MAX_COORDINATE).contains(&v);
        (valid(x) && valid(y)).then_some(SubgridPoint { x, y })
    }

    /// Raw fixed-point coordinates (units of 1/65 536 cell).
    pub fn raw(self) -> (i64, i64) {
        (self.x, self.y)
    }

    /// Grid coordinates in cells (exact: a coordinate is at most 2^32 units).
    pub fn grid_units(self) -> (f64, f64) {
        let scale = 1.0 / SUBGRID_UNITS_PER_CELL as f64;
        (self.x as f64 * scale, self.y as f64 * scale)
    }

    /// The grid sample at this point, when it sits exactly on one.
    pub fn grid_point(self) -> Option<GridPoint> {
        let mask = SUBGRID_UNITS_PER_CELL - 1;
        (self.x & mask == 0 && self.y & mask == 0).then(|| {
            GridPoint::new(
                (self.x >> SUBGRID_BITS) as u32,
                (self.y >> SUBGRID_BITS) as u32,
            )
        })
    }
}

impl From<GridPoint> for SubgridPoint {
    fn from(p: GridPoint) -> SubgridPoint {
        SubgridPoint::grid(p.i, p.j)
    }
}

/// A drawn vertex: where it sits in the plane and the height the algorithm gave it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    pub position: SubgridPoint,
    /// Metres in the terrain's local frame.
    pub z: f32,
}

impl SurfacePoint {
    /// Terrain-local metres. For a grid sample with its own height this is exactly
    /// [`crate::sim::terrain::Heightfield::position`].
    pub fn local(self, spacing: Spacing) -> DVec3 {
        let (x, y) = self.position.grid_units();
        DVec3::new(x * spacing.dx, y * spacing.dy, f64::from(self.z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_samples_are_exact_and_come_back_as_grid_points() {
        let p = SubgridPoint::grid(1025, 7);
        assert_eq!(p.grid_point(), Some(GridPoint::new(1025, 7)));
        assert_eq!(p.grid_units(), (1025.0, 7.0));
        assert_eq!(SubgridPoint::from_grid_units(1025.0, 7.0), Some(p));
    }

    #[test]
    fn fractions_round_to_the_nearest_unit_and_are_not_grid_points() {
        let p = SubgridPoint::from_grid_units(2.5, 1.0 / 3.0).unwrap();
        assert_eq!(p.raw(), (5 << 15, 21845));
        assert_eq!(p.grid_point(), None);
    }

    #[test]
    fn points_outside_the_largest_lattice_or_not_finite_are_refused() {
        assert_eq!(SubgridPoint::from_grid_units(-0.5, 0.0), None);
        assert_eq!(SubgridPoint::from_grid_units(f64::NAN, 0.0), None);
        assert_eq!(SubgridPoint::from_grid_units(65536.5, 0.0), None);
        assert!(SubgridPoint::from_grid_units(65536.0, 65536.0).is_some());
        assert_eq!(SubgridPoint::from_raw(0, -1), None);
    }

    #[test]
    fn a_sample_with_its_own_height_is_where_the_field_puts_it() {
        let spacing = Spacing { dx: 30.0, dy: 92.5 };
        let point = SurfacePoint {
            position: SubgridPoint::grid(3, 9),
            z: 12.25,
        };
        assert_eq!(point.local(spacing), DVec3::new(90.0, 832.5, 12.25));
    }
}
