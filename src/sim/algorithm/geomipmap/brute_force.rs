//! Geomipmap levels decided from the definitions, for differential tests: each level's error
//! measured by rasterising the level's triangles over the samples with the audit's general
//! rasteriser (not the preprocessing's cell arithmetic), nested, the criterion applied patch by
//! patch, and the one-level limit in its closed form ℓ(P) = min over every patch Q of
//! (ℓ_own(Q) + |P − Q|₁) instead of the algorithm's two sweeps. Shared with the algorithm: the
//! box distance, C and the rounding of stored errors, which `block_lod` tests on its own.

use super::super::block_lod::grid::round_up_f32;
use super::super::block_lod::threshold::{BlockBox, DetailThreshold};
use super::{GeomipmapConfig, LevelDifference};
use crate::sim::hierarchy::{GridPoint, Hierarchy};
use crate::sim::mesh::raster::SampleRaster;
use crate::sim::mesh::{SUBGRID_UNITS_PER_CELL, SubgridPoint, SurfacePoint};
use crate::sim::view::Camera;
use glam::DVec3;

/// The level of every patch (row by row from the south-west) that `geomipmap` with `config`
/// draws from `camera` at tolerance `tau_px`. O(samples · k + patches²).
pub fn levels_from_scratch(
    hierarchy: &Hierarchy,
    config: &GeomipmapConfig,
    camera: &Camera,
    tau_px: f64,
) -> Vec<u32> {
    let lattice = hierarchy.lattice();
    let k = config.patch_level.clamp(1, lattice.level());
    let cells = 1u32 << k;
    let per_side = lattice.cells() / cells;
    let spacing = hierarchy.field().spacing();
    let side = lattice.side() as usize;
    let raster = SampleRaster::new(
        SUBGRID_UNITS_PER_CELL,
        side,
        i64::from(lattice.cells()) * SUBGRID_UNITS_PER_CELL,
    );
    let corner = |i: u32, j: u32| SurfacePoint {
        position: SubgridPoint::grid(i, j),
        z: hierarchy.height(GridPoint::new(i, j)),
    };
    let threshold = DetailThreshold::new(camera.settings.pixels_per_unit(), tau_px);
    let mut own = Vec::with_capacity((per_side * per_side) as usize);
    for py in 0..per_side {
        for px in 0..per_side {
            let (x0, y0) = (px * cells, py * cells);
            // Error of each level: the largest |sample − surface| the level's triangles draw.
            let mut nested = Vec::with_capacity(k as usize + 1);
            let mut largest: f64 = 0.0;
            for level in 0..=k {
                let stride = 1u32 << level;
                for b in 0..cells / stride {
                    for a in 0..cells / stride {
                        let (i, j) = (x0 + a * stride, y0 + b * stride);
                        let (sw, se) = (corner(i, j), corner(i + stride, j));
                        let (nw, ne) = (corner(i, j + stride), corner(i + stride, j + stride));
                        for triangle in [[sw, se, ne], [sw, ne, nw]] {
                            raster.for_each_covered_sample(&triangle, |sample| {
                                let (si, sj) = (sample.index % side, sample.index / side);
                                let z = f64::from(
                                    hierarchy.height(GridPoint::new(si as u32, sj as u32)),
                                );
                                largest = largest.max((z - sample.height).abs());
                            });
                        }
                    }
                }
                nested.push(round_up_f32(largest));
            }
            let (mut z_min, mut z_max) = (f64::INFINITY, f64::NEG_INFINITY);
            for j in y0..=y0 + cells {
                for i in x0..=x0 + cells {
                    let z = f64::from(hierarchy.height(GridPoint::new(i, j)));
                    z_min = z_min.min(z);
                    z_max = z_max.max(z);
                }
            }
            let block = BlockBox {
                low: DVec3::new(
                    f64::from(x0) * spacing.dx,
                    f64::from(y0) * spacing.dy,
                    z_min,
                ),
                high: DVec3::new(
                    f64::from(x0 + cells) * spacing.dx,
                    f64::from(y0 + cells) * spacing.dy,
                    z_max,
                ),
            };
            let d = block.lod_distance(camera.eye, config.projection);
            let coarsest = (0..=k)
                .rev()
                .find(|&level| !threshold.refines(nested[level as usize], d))
                .unwrap_or(0);
            own.push(coarsest);
        }
    }
    if config.level_difference == LevelDifference::Any {
        return own;
    }
    let n = per_side as i64;
    (0..n * n)
        .map(|p| {
            (0..n * n)
                .map(|q| {
                    let distance = (p % n - q % n).abs() + (p / n - q / n).abs();
                    i64::from(own[q as usize]) + distance
                })
                .min()
                .map_or(0, |level| level as u32)
        })
        .collect()
}
