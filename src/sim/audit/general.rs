//! The audit of a triangle list, and of any mesh against synthesised detail (SPEC §7, over the
//! meshes outside the 4-8 family that SPEC §3 lists, and the detail of Lauritsen–Nielsen
//! §3.3–3.4): the drawn heights from the general rasteriser ([`SampleRaster`], whose tie rule
//! is written in `sim::mesh::raster`), the holes and crack gaps that a triangle list can have
//! and a 4-8 mesh cannot, and the measurement of the samples in view one at a time. A 4-8 mesh
//! against the source's samples goes through `lattice.rs`.
//!
//! Decisions:
//!
//! - **What is surface.** Surface and stitch triangles are; skirts and degenerate triangles
//!   never are. A sample no surface triangle covers is a **hole**: counted, and left out of the
//!   error figures and of popping.
//! - **Crack gaps.** The tie rule gives every sample of a tiling to exactly one triangle, whose
//!   height is the drawn one; the crack gap at a sample is the spread of the heights of every
//!   surface triangle touching it (a T-junction, heights that differ across a border), counted
//!   and measured in metres and projected pixels (a vertical segment from the lowest height).
//!   Two triangles sharing an edge give a sample on it bit-identical heights, so the gap is
//!   exactly zero where there is no crack.
//! - **Skirts.** The skirts hung at a cracked sample (vertical triangles) cover the part of the
//!   gap their vertical extent spans; what no skirt spans is the gap left **uncovered**, the
//!   crack a viewer could see through (counted and measured too; without skirts it is the
//!   whole gap).
//! - **The truth with synthesised detail.** An auditor of depth k ([`Auditor::refined`]) audits
//!   the source grid refined 2^k times against the synthesised surface at its deepest level;
//!   its samples are at a fixed-point step of 1/2^k cell, off the integer rasteriser's grid,
//!   so every mesh goes through the general rasteriser there, 4-8 meshes included.
//! - **One sample at a time.** Holes and cracks must be counted at every sample in view, so
//!   this path hands the batch the samples in view one at a time, in row order, and measures
//!   them with the batch's loop (`batch.rs`): the same arithmetic as the lattice path's.

use super::Auditor;
use super::batch::{BATCH, ErrorBatch, Sinks, put_popping, put_segment};
use super::geometry::ErrorGeometry;
use super::popping::PoppingSums;
use super::tiles::{TILE, columns_in_view};
use crate::sim::algorithm::chunked::detail::DetailField;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::raster::SampleRaster;
use crate::sim::mesh::{MeshOutput, SUBGRID_UNITS_PER_CELL, TriangleRole};
use crate::sim::metrics::projected_error_px;
use crate::sim::stats::SurfaceCoverage;
use crate::sim::terrain::{Heightfield, Spacing};
use crate::sim::view::Camera;
use glam::DVec3;
use std::borrow::Cow;

/// The lowest and highest height any surface triangle draws at each audited sample, and the
/// vertical spans skirts cover at the samples where those differ.
pub(super) struct CrackHeights {
    pub(super) low: Vec<f32>,
    pub(super) high: Vec<f32>,
    /// (sample index, lowest, highest height) of each skirt triangle over a cracked sample,
    /// sorted by index then height.
    pub(super) skirt_spans: Vec<(usize, f32, f32)>,
}

impl CrackHeights {
    /// The length of the crack gap at `index` that no skirt spans, metres.
    #[inline]
    pub(super) fn uncovered(&self, index: usize) -> f64 {
        let (low, high) = (f64::from(self.low[index]), f64::from(self.high[index]));
        let first = self.skirt_spans.partition_point(|span| span.0 < index);
        let mut reached = low;
        let mut open = 0.0;
        for &(at, span_low, span_high) in &self.skirt_spans[first..] {
            if at != index || reached >= high {
                break;
            }
            let (span_low, span_high) = (f64::from(span_low), f64::from(span_high));
            if span_low > reached {
                open += span_low.min(high) - reached;
            }
            reached = reached.max(span_high);
        }
        open + (high - reached).max(0.0)
    }

    /// Counts the crack gap at sample `index` (at `sample`) into `coverage`, when there is one,
    /// and the part of it no skirt spans.
    #[inline]
    fn count(&self, coverage: &mut SurfaceCoverage, camera: &Camera, sample: DVec3, index: usize) {
        let (low, high) = (self.low[index], self.high[index]);
        if low < high {
            let gap = f64::from(high) - f64::from(low);
            coverage.crack_samples += 1;
            coverage.crack_gap_max_m = coverage.crack_gap_max_m.max(gap);
            let base = DVec3::new(sample.x, sample.y, f64::from(low));
            if let Some(px) = projected_error_px(camera, base, gap) {
                coverage.crack_gap_max_px = coverage.crack_gap_max_px.max(px);
            }
            let open = self.uncovered(index);
            if open > 0.0 {
                coverage.cracks_uncovered += 1;
                coverage.crack_uncovered_max_m = coverage.crack_uncovered_max_m.max(open);
                if let Some(px) = projected_error_px(camera, base, open) {
                    coverage.crack_uncovered_max_px = coverage.crack_uncovered_max_px.max(px);
                }
            }
        }
    }
}

impl Auditor {
    /// Triangle lists: the general rasteriser over the surface triangles; holes stay NaN.
    pub(super) fn rasterise_general(&mut self, hierarchy: &Hierarchy, mesh: MeshOutput) {
        let n = self.mesh_height.len();
        // Taken out for the frame, so that the tile filter can borrow the rest.
        let mut crack = self.crack.take().unwrap_or_else(|| CrackHeights {
            low: vec![0.0; n],
            high: vec![0.0; n],
            skirt_spans: Vec::new(),
        });
        let mut mesh_height = std::mem::take(&mut self.mesh_height);
        mesh_height.fill(f32::NAN);
        crack.low.fill(f32::INFINITY);
        crack.high.fill(f32::NEG_INFINITY);
        crack.skirt_spans.clear();
        let domain_max = i64::from(hierarchy.lattice().cells()) * SUBGRID_UNITS_PER_CELL;
        let raster = SampleRaster::new(
            (self.stride as i64 * SUBGRID_UNITS_PER_CELL) >> self.refine,
            self.lattice_side,
            domain_max,
        );
        let tiles = self.tiles_kept();
        mesh.for_each_triangle(hierarchy, |triangle| {
            if !triangle.info.role.is_surface() || !tiles.may_touch(&triangle.corners) {
                return;
            }
            raster.for_each_covered_sample(&triangle.corners, |sample| {
                let height = sample.height as f32;
                if sample.owned {
                    mesh_height[sample.index] = height;
                }
                crack.low[sample.index] = crack.low[sample.index].min(height);
                crack.high[sample.index] = crack.high[sample.index].max(height);
            });
        });
        let has_skirts = mesh
            .counts(0)
            .is_some_and(|counts| counts.triangles_by_role[TriangleRole::Skirt.index()] > 0);
        if has_skirts {
            let spans = &mut crack.skirt_spans;
            let (low, high) = (&crack.low, &crack.high);
            mesh.for_each_triangle(hierarchy, |triangle| {
                if triangle.info.role != TriangleRole::Skirt || !tiles.may_touch(&triangle.corners)
                {
                    return;
                }
                raster.for_each_vertical_span(&triangle.corners, |index, bottom, top| {
                    if low[index] < high[index] {
                        spans.push((index, bottom as f32, top as f32));
                    }
                });
            });
            spans.sort_unstable_by(|a, b| {
                (a.0.cmp(&b.0))
                    .then(a.1.total_cmp(&b.1))
                    .then(a.2.total_cmp(&b.2))
            });
        }
        self.crack = Some(crack);
        self.mesh_height = mesh_height;
    }

    /// Measures the drawn heights against the truth (the source's samples, or `truth`, the
    /// synthesised surface at this auditor's depth) at every audited sample in view, adding
    /// the figures to this frame's, holes and crack gaps to `coverage`, and popping's to
    /// `popping` when it is measured.
    pub(super) fn measure_general(
        &mut self,
        field: &Heightfield,
        camera: &Camera,
        geometry: &ErrorGeometry,
        truth: Option<&DetailField>,
        mut coverage: Option<&mut SurfaceCoverage>,
        popping: Option<&mut PoppingSums>,
    ) {
        let samples = GeneralSamples {
            camera,
            eye: camera.eye,
            axes: (camera.right, camera.up, camera.forward),
            crack: self.crack.as_ref(),
            previous: self.previous_height.as_deref(),
            truth,
            field,
            spacing: field.spacing(),
            fine: 1.0 / f64::from(1u32 << self.refine),
            stride: self.stride,
            lattice_side: self.lattice_side,
        };
        let mut sinks = Sinks {
            projected: &mut self.projected,
            view_angle: &mut self.view_angle,
            popping,
        };
        let batch = &mut self.batch;
        // The samples in view go to the batch in order, `n` of them waiting.
        let mut n = 0;
        let (tiles_x, lattice_side) = (self.tiles_x, self.lattice_side);
        for lj in 0..self.lattice_rows {
            let tile_row = &self.tile_in_view[(lj / TILE) * tiles_x..][..tiles_x];
            if !tile_row.contains(&true) {
                continue; // No sample in view: its heights are not read (a paged field's).
            }
            let row = samples.row(lj, &self.mesh_height[lj * lattice_side..][..lattice_side]);
            for columns in columns_in_view(tile_row, self.lattice_columns) {
                for li in columns {
                    if samples.put(batch, n, &row, li, coverage.as_deref_mut()) {
                        n += 1;
                        if n == BATCH {
                            batch.measure(n, geometry, camera, &mut sinks);
                            n = 0;
                        }
                    }
                }
            }
        }
        batch.measure(n, geometry, camera, &mut sinks);
    }
}

/// What the general path reads of one frame to put its samples in view into the batch.
struct GeneralSamples<'a> {
    camera: &'a Camera,
    /// The camera's eye and axes (right, up, forward), taken once.
    eye: DVec3,
    axes: (DVec3, DVec3, DVec3),
    /// The heights holes and crack gaps are found from (a triangle list's).
    crack: Option<&'a CrackHeights>,
    /// The previous frame's drawn heights, with popping measured.
    previous: Option<&'a [f32]>,
    /// The synthesised surface (`None`: the source's samples, read a row at a time from
    /// `field`).
    truth: Option<&'a DetailField>,
    field: &'a Heightfield,
    spacing: Spacing,
    /// A refined sample's spacing in source cells, 1/2^refine.
    fine: f64,
    stride: usize,
    lattice_side: usize,
}

/// One row of the general path's samples: its index in the lattice and in the truth's grid,
/// its y, and the products of `Camera::to_camera` that depend on the row only.
struct GeneralRow<'a> {
    lj: usize,
    j: usize,
    y: f64,
    dy: f64,
    right_y: f64,
    up_y: f64,
    forward_y: f64,
    /// The source's heights of the row (empty against synthesised detail): borrowed, or read
    /// for a paged field.
    heights: Cow<'a, [f32]>,
    /// The drawn heights of its audited samples.
    drawn: &'a [f32],
}

impl GeneralSamples<'_> {
    /// Row `lj` (`drawn`: the drawn heights of its audited samples).
    #[inline(always)]
    fn row<'r>(&'r self, lj: usize, drawn: &'r [f32]) -> GeneralRow<'r> {
        let (eye, (right, up, forward)) = (self.eye, self.axes);
        let j = lj * self.stride;
        // The sample's y, as `Heightfield::position` (or the synthesised surface) has it, and
        // the products of `Camera::to_camera` that depend on the row only.
        let y = match self.truth {
            None => j as f64 * self.spacing.dy,
            Some(_) => j as f64 * self.spacing.dy * self.fine,
        };
        let dy = y - eye.y;
        let (right_y, up_y, forward_y) = (dy * right.y, dy * up.y, dy * forward.y);
        let heights = match self.truth {
            None => self.field.row(j),
            Some(_) => Cow::Borrowed(&[][..]),
        };
        GeneralRow {
            lj,
            j,
            y,
            dy,
            right_y,
            up_y,
            forward_y,
            heights,
            drawn,
        }
    }

    /// Puts sample `li` of `row` into the batch as its `n`-th segment waiting, when it is in
    /// view and not a hole (then returns true), counting its crack gap or hole into
    /// `coverage`.
    #[inline(always)]
    fn put(
        &self,
        batch: &mut ErrorBatch,
        n: usize,
        row: &GeneralRow,
        li: usize,
        coverage: Option<&mut SurfaceCoverage>,
    ) -> bool {
        let (camera, eye, (right, up, forward)) = (self.camera, self.eye, self.axes);
        let (spacing, dy) = (self.spacing, row.dy);
        let i = li * self.stride;
        // The truth: the field's sample, or the synthesised surface's.
        let (x, z) = match self.truth {
            None => (i as f64 * spacing.dx, f64::from(row.heights[i])),
            Some(truth) => (
                i as f64 * spacing.dx * self.fine,
                f64::from(truth.height(i as u32, row.j as u32)),
            ),
        };
        let sample = DVec3::new(x, row.y, z);
        // `Camera::to_camera`, its sums in the same order.
        let (dx, dz) = (x - eye.x, z - eye.z);
        let (right_xy, up_xy, forward_xy) = (
            dx * right.x + row.right_y,
            dx * up.x + row.up_y,
            dx * forward.x + row.forward_y,
        );
        let in_camera = DVec3::new(
            right_xy + dz * right.z,
            up_xy + dz * up.z,
            forward_xy + dz * forward.z,
        );
        if !camera.sees_camera(in_camera) {
            return false;
        }
        let index = row.lj * self.lattice_side + li;
        let drawn = row.drawn[li];
        if let (Some(coverage), Some(crack)) = (coverage, self.crack) {
            crack.count(coverage, camera, sample, index);
            if drawn.is_nan() {
                coverage.holes += 1;
                return false;
            }
        }
        let mesh_z = f64::from(drawn);
        // `Camera::to_camera` of a point above or below the sample.
        let in_camera_at = |z: f64| {
            let dz = z - eye.z;
            DVec3::new(
                right_xy + dz * right.z,
                up_xy + dz * up.z,
                forward_xy + dz * forward.z,
            )
        };
        if let Some(previous) = self.previous {
            // The change since the previous frame (none at a hole), its segment from the lower
            // of the two heights.
            let before = f64::from(previous[index]);
            let counts = !before.is_nan() && !mesh_z.is_nan();
            let base = in_camera_at(before.min(mesh_z));
            put_popping(batch, n, counts, (mesh_z - before).abs(), base);
        }
        // The segment from the lower of the sample and the surface, `length` long; its base in
        // camera coordinates differs from the sample's in the z terms only (and is the
        // sample's, bit for bit, when it starts there: no branch).
        let base_z = z.min(mesh_z);
        let length = (z - mesh_z).abs();
        let base_dz = base_z - eye.z;
        let base_in_camera = in_camera_at(base_z);
        put_segment(
            &mut batch.segments,
            n,
            base_in_camera,
            DVec3::new(dx, dy, base_dz),
            length,
        );
        true
    }
}
