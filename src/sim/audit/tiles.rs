//! The tiles of audited samples (SPEC §7's samples in the view volume, found exactly and
//! cheaply): each tile of [`TILE`]² samples has a box (its samples' square and height range);
//! per frame, the tiles that may be in view, the tiles whose drawn heights are kept, the
//! triangle filter that follows from them, and the runs of columns in view along a row. It
//! tests no sample against the view (the measuring paths do, with `Camera::sees`'s arithmetic).
//!
//! Decisions (the audit's exact shortcuts, each leaving every figure bit-identical):
//!
//! - **A tile is skipped only when it surely misses the view**: its box is outside one plane of
//!   the view volume by a margin far above `Camera::sees`'s rounding
//!   ([`Camera::surely_misses_box`]), so every sample in it would fail `sees`. The samples of
//!   the other tiles are still visited row by row, west to east, so the figures are summed in
//!   the same order as without tiles.
//! - **Triangles that touch no tile kept are not rasterised** (for a 4-8 mesh, whole bintree
//!   subtrees: a triangle holds its descendants). Without popping the tiles kept are those
//!   that may be in view (a sample's drawn height is read only where it is in view); with
//!   popping, also those the next frame may see, when the run has told the auditor its camera
//!   (`popping.rs`), and every tile when it has not.
//! - **A refined auditor tests every tile**: its truth is synthesised per frame, so there are no
//!   height ranges to box its tiles with.

use super::Auditor;
use crate::sim::mesh::raster::floor_div;
use crate::sim::mesh::{SUBGRID_UNITS_PER_CELL, SurfacePoint};
use crate::sim::terrain::Heightfield;
use crate::sim::view::Camera;
use glam::DVec3;

/// Audited samples per side of a tile: the unit of the exact skip of samples out of view.
pub(super) const TILE: usize = 16;

/// The box of every tile of `lattice_columns` × `lattice_rows` audited samples (every
/// `stride`-th of the source's), row-major, and the tiles per row: x and y of its first and
/// last sample, and the range of the source's heights over its samples. With `skip_tiles`
/// false (a refined auditor, whose truth is synthesised per frame, tests every tile) every
/// box is zero.
pub(super) fn tile_boxes(
    field: &Heightfield,
    stride: usize,
    (lattice_columns, lattice_rows): (usize, usize),
    skip_tiles: bool,
) -> (Vec<(DVec3, DVec3)>, usize) {
    let tiles_x = lattice_columns.div_ceil(TILE);
    let tiles_y = lattice_rows.div_ceil(TILE);
    let mut tile_boxes = Vec::with_capacity(tiles_x * tiles_y);
    for ty in 0..tiles_y {
        for tx in 0..tiles_x {
            if !skip_tiles {
                tile_boxes.push((DVec3::ZERO, DVec3::ZERO));
                continue;
            }
            let rows = ty * TILE..((ty + 1) * TILE).min(lattice_rows);
            let columns = tx * TILE..((tx + 1) * TILE).min(lattice_columns);
            let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
            for lj in rows.clone() {
                for li in columns.clone() {
                    let z = f64::from(field.height(li * stride, lj * stride));
                    low = low.min(z);
                    high = high.max(z);
                }
            }
            let first = field.position(columns.start * stride, rows.start * stride);
            let last = field.position((columns.end - 1) * stride, (rows.end - 1) * stride);
            tile_boxes.push((
                DVec3::new(first.x, first.y, low),
                DVec3::new(last.x, last.y, high),
            ));
        }
    }
    (tile_boxes, tiles_x)
}

impl Auditor {
    /// Finds this frame's tiles that may be in view from `camera` and those whose drawn
    /// heights are kept: with popping, also those the `next` camera may see (all, not knowing
    /// it).
    pub(super) fn find_tiles(&mut self, camera: &Camera, next: Option<&Camera>) {
        let skip_tiles = self.refine == 0;
        for (in_view, &(low, high)) in self.tile_in_view.iter_mut().zip(&self.tile_boxes) {
            *in_view = !skip_tiles || !camera.surely_misses_box(low, high);
        }
        // With popping, the tiles whose heights the next frame may read too (all, not knowing
        // its camera).
        self.tile_kept = match (self.popping, next) {
            (false, _) => TilesKept::InView,
            (true, None) => TilesKept::All,
            (true, Some(next)) => {
                let tiles = self.tile_in_view.iter().zip(&self.tile_boxes);
                let kept = tiles.map(|(&in_view, &(low, high))| {
                    in_view || !skip_tiles || !next.surely_misses_box(low, high)
                });
                self.tile_in_either_view.clear();
                self.tile_in_either_view.extend(kept);
                TilesKept::InEitherView
            }
        };
    }

    /// Which triangles to rasterise: those that may touch a tile whose heights are kept
    /// (`tile_kept`). Without popping, a sample's drawn height is read only where it is in
    /// view, and every triangle that covers such a sample touches its tile, so skipping the
    /// others changes no figure (a shared sample's last writer is kept). With popping, the
    /// next frame reads this frame's heights where it sees: the tiles that may be in view from
    /// either camera are kept, or every one when the next camera is not known.
    pub(super) fn tiles_kept(&self) -> TileFilter<'_> {
        TileFilter {
            kept: match self.tile_kept {
                TilesKept::InView => Some(self.tile_in_view.as_slice()),
                TilesKept::InEitherView => Some(self.tile_in_either_view.as_slice()),
                TilesKept::All => None,
            },
            tiles_x: self.tiles_x,
            lattice_columns: self.lattice_columns,
            lattice_rows: self.lattice_rows,
            units_per_sample: (self.stride as i64 * SUBGRID_UNITS_PER_CELL) >> self.refine,
        }
    }
}

/// The audited columns of one row of tiles that may be in view (`tile_row`: per tile), as
/// runs of consecutive tiles, west to east.
#[inline]
pub(super) fn columns_in_view(
    tile_row: &[bool],
    lattice_columns: usize,
) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    let mut tx = 0;
    std::iter::from_fn(move || {
        while tx < tile_row.len() && !tile_row[tx] {
            tx += 1;
        }
        let start = tx;
        while tx < tile_row.len() && tile_row[tx] {
            tx += 1;
        }
        (start < tx).then(|| start * TILE..(tx * TILE).min(lattice_columns))
    })
}

/// The tiles whose drawn heights a frame keeps.
#[derive(Clone, Copy, Debug)]
pub(super) enum TilesKept {
    /// Those that may be in view (no popping: nothing else is read).
    InView,
    /// Those that may be in view from this frame's camera or the next's.
    InEitherView,
    /// Every tile (popping, the next camera unknown).
    All,
}

/// The tiles of audited samples whose drawn heights a frame keeps ([`TilesKept`]), as a
/// triangle filter.
pub(super) struct TileFilter<'a> {
    /// Per tile, whether its heights are kept; `None`: every tile's (popping, the next camera
    /// unknown).
    pub(super) kept: Option<&'a [bool]>,
    tiles_x: usize,
    lattice_columns: usize,
    lattice_rows: usize,
    /// Fixed-point units between neighbouring audited samples.
    units_per_sample: i64,
}

impl TileFilter<'_> {
    /// Whether the triangle's bounding box (widened to the audited samples around it) meets a
    /// tile whose heights are kept.
    #[inline]
    pub(super) fn may_touch(&self, corners: &[SurfacePoint; 3]) -> bool {
        let Some(kept) = self.kept else {
            return true;
        };
        let raw = corners.map(|c| c.position.raw());
        let (x_min, x_max) = (
            raw.iter().map(|p| p.0).min().unwrap_or(0),
            raw.iter().map(|p| p.0).max().unwrap_or(0),
        );
        let (y_min, y_max) = (
            raw.iter().map(|p| p.1).min().unwrap_or(0),
            raw.iter().map(|p| p.1).max().unwrap_or(0),
        );
        let sample_range = |low: i64, high: i64, count: usize| {
            let first = floor_div(low, self.units_per_sample).max(0) as usize;
            let last = (floor_div(high, self.units_per_sample) + 1).max(0) as usize;
            (first.min(count - 1), last.min(count - 1))
        };
        let (i0, i1) = sample_range(x_min, x_max, self.lattice_columns);
        let (j0, j1) = sample_range(y_min, y_max, self.lattice_rows);
        (j0 / TILE..=j1 / TILE)
            .any(|ty| (i0 / TILE..=i1 / TILE).any(|tx| kept[ty * self.tiles_x + tx]))
    }
}
