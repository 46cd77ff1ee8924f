//! The audit's differential reference (SPEC §7): [`ReferenceAuditor`], the audit as it was
//! before it skipped the tiles out of view and solved the rasteriser's row spans (roamsim 0.1.0
//! at 7319e86). It is not used by the runner, and it has no refined (synthesised detail)
//! lattice.
//!
//! Decisions:
//!
//! - **The yardstick of every shortcut.** Every figure of [`super::Auditor`] must equal this
//!   one's to the last bit (`tests/audit_reference.rs`, through `Debug`, which prints every
//!   `f64` exactly), and `benches/hot_paths.rs` times both in one run. So its arithmetic stays
//!   as first written: every audited sample tested against the view with `Camera::sees`, every
//!   triangle rasterised over its whole bounding box, the metrics called one sample at a time,
//!   and its own summary by selection over all values.
//! - **Shared with the auditor:** what is not a shortcut, the crack and popping bookkeeping
//!   (`CrackHeights`, `PoppingSums`) and the general rasteriser.

use super::AuditSettings;
use super::general::CrackHeights;
use super::popping::PoppingSums;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::raster::{SampleRaster, rasterise_lattice_triangle_by_box};
use crate::sim::mesh::{MeshOutput, SUBGRID_UNITS_PER_CELL, TriangleRole};
use crate::sim::metrics::{projected_error_px, view_angle_error_px};
use crate::sim::stats::{AuditFrame, ErrorSummary, SurfaceCoverage};
use crate::sim::view::Camera;
use glam::DVec3;

/// The audit as it was first written (every sample of the lattice tested against the view,
/// every triangle rasterised over its whole bounding box): the reference the optimised
/// [`super::Auditor`] must equal figure for figure, bit for bit.
pub struct ReferenceAuditor {
    stride: usize,
    /// Audited samples per side: the grid side subsampled by `stride`.
    lattice_side: usize,
    /// The drawn height at every audited sample (NaN: a hole, triangle lists only).
    mesh_height: Vec<f32>,
    /// The general path's crack bookkeeping, allocated at the first triangle list.
    crack: Option<CrackHeights>,
    /// The previous frame's `mesh_height`, when popping is measured (`None` before frame 0).
    previous_height: Option<Vec<f32>>,
    popping: bool,
    projected: Vec<f64>,
    view_angle: Vec<f64>,
}

impl ReferenceAuditor {
    pub fn new(hierarchy: &Hierarchy, settings: AuditSettings) -> ReferenceAuditor {
        let stride = settings.stride.max(1) as usize;
        let lattice_side = (hierarchy.field().side() - 1) / stride + 1;
        ReferenceAuditor {
            stride,
            lattice_side,
            mesh_height: vec![0.0; lattice_side * lattice_side],
            crack: None,
            previous_height: None,
            popping: settings.popping,
            projected: Vec::new(),
            view_angle: Vec::new(),
        }
    }

    /// Measures one frame's mesh (and, with popping on, its change since the last call).
    pub fn audit(
        &mut self,
        hierarchy: &Hierarchy,
        mesh: MeshOutput,
        camera: &Camera,
    ) -> AuditFrame {
        let general = matches!(mesh, MeshOutput::Triangles(_));
        if general {
            self.rasterise_general(hierarchy, mesh);
        } else {
            self.rasterise_lattice(hierarchy, mesh);
        }
        let field = hierarchy.field();
        let (stride, lattice_side) = (self.stride, self.lattice_side);
        let pixel_angle = camera.settings.pixel_angle();
        self.projected.clear();
        self.view_angle.clear();
        let mut coverage = general.then_some(SurfaceCoverage {
            holes: 0,
            crack_samples: 0,
            crack_gap_max_m: 0.0,
            crack_gap_max_px: 0.0,
            cracks_uncovered: 0,
            crack_uncovered_max_m: 0.0,
            crack_uncovered_max_px: 0.0,
        });
        let mut popping = PoppingSums::default();
        let previous = self.previous_height.as_deref();
        for j in (0..field.data_rows()).step_by(stride) {
            for i in (0..field.data_columns()).step_by(stride) {
                // The truth: the field's sample.
                let sample = field.position(i, j);
                if !camera.sees(sample) {
                    continue;
                }
                let index = (j / stride) * lattice_side + i / stride;
                let drawn = self.mesh_height[index];
                if let (Some(coverage), Some(crack)) = (coverage.as_mut(), self.crack.as_ref()) {
                    count_crack(coverage, crack, camera, sample, index);
                    if drawn.is_nan() {
                        coverage.holes += 1;
                        continue;
                    }
                }
                let mesh_z = f64::from(drawn);
                if let Some(previous) = previous {
                    popping.add(camera, sample, f64::from(previous[index]), mesh_z);
                }
                let base = DVec3::new(sample.x, sample.y, sample.z.min(mesh_z));
                let length = (sample.z - mesh_z).abs();
                if let Some(px) = projected_error_px(camera, base, length) {
                    self.projected.push(px);
                }
                self.view_angle
                    .push(view_angle_error_px(camera.eye, base, length, pixel_angle));
            }
        }
        let popping = popping.summary(previous.is_some());
        if self.popping {
            // Keep this frame's heights for the next; the old buffer becomes next frame's
            // scratch (the lattice path overwrites every sample, the general path resets them).
            let previous = self
                .previous_height
                .get_or_insert_with(|| vec![0.0; self.mesh_height.len()]);
            std::mem::swap(previous, &mut self.mesh_height);
        }
        AuditFrame {
            samples_in_view: self.view_angle.len() as u64,
            projected: summarise_in_place(&mut self.projected),
            view_angle: summarise_in_place(&mut self.view_angle),
            coverage,
            popping,
        }
    }

    /// 4-8 meshes: the exact integer rasteriser, every sample written (a closed mesh covers
    /// the whole domain).
    fn rasterise_lattice(&mut self, hierarchy: &Hierarchy, mesh: MeshOutput) {
        let stride = self.stride as i64;
        let lattice_side = self.lattice_side;
        let mesh_height = &mut self.mesh_height;
        mesh.for_each_triangle(hierarchy, |triangle| {
            rasterise_lattice_triangle_by_box(&triangle.corners, stride, lattice_side, mesh_height);
        });
    }

    /// Triangle lists: the general rasteriser over the surface triangles; holes stay NaN.
    fn rasterise_general(&mut self, hierarchy: &Hierarchy, mesh: MeshOutput) {
        let n = self.mesh_height.len();
        let crack = self.crack.get_or_insert_with(|| CrackHeights {
            low: vec![0.0; n],
            high: vec![0.0; n],
            skirt_spans: Vec::new(),
        });
        self.mesh_height.fill(f32::NAN);
        crack.low.fill(f32::INFINITY);
        crack.high.fill(f32::NEG_INFINITY);
        crack.skirt_spans.clear();
        let domain_max = i64::from(hierarchy.lattice().cells()) * SUBGRID_UNITS_PER_CELL;
        let raster = SampleRaster::new(
            self.stride as i64 * SUBGRID_UNITS_PER_CELL,
            self.lattice_side,
            domain_max,
        );
        let mesh_height = &mut self.mesh_height;
        mesh.for_each_triangle(hierarchy, |triangle| {
            if !triangle.info.role.is_surface() {
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
                if triangle.info.role != TriangleRole::Skirt {
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
    }
}

/// Counts the crack gap at sample `index` (at `sample`) into `coverage`, when there is one,
/// and the part of it no skirt spans.
fn count_crack(
    coverage: &mut SurfaceCoverage,
    crack: &CrackHeights,
    camera: &Camera,
    sample: DVec3,
    index: usize,
) {
    let (low, high) = (crack.low[index], crack.high[index]);
    if low < high {
        let gap = f64::from(high) - f64::from(low);
        coverage.crack_samples += 1;
        coverage.crack_gap_max_m = coverage.crack_gap_max_m.max(gap);
        let base = DVec3::new(sample.x, sample.y, f64::from(low));
        if let Some(px) = projected_error_px(camera, base, gap) {
            coverage.crack_gap_max_px = coverage.crack_gap_max_px.max(px);
        }
        let open = crack.uncovered(index);
        if open > 0.0 {
            coverage.cracks_uncovered += 1;
            coverage.crack_uncovered_max_m = coverage.crack_uncovered_max_m.max(open);
            if let Some(px) = projected_error_px(camera, base, open) {
                coverage.crack_uncovered_max_px = coverage.crack_uncovered_max_px.max(px);
            }
        }
    }
}

/// Max, mean and nearest-rank p95 (the same rule as [`crate::sim::stats::nearest_rank`]),
/// in O(n) by selection instead of sorting.
pub(super) fn summarise_in_place(values: &mut [f64]) -> Option<ErrorSummary> {
    if values.is_empty() {
        return None;
    }
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let rank = ((0.95 * values.len() as f64).ceil() as usize).clamp(1, values.len());
    let (_, p95, _) = values.select_nth_unstable_by(rank - 1, f64::total_cmp);
    Some(ErrorSummary {
        max,
        mean,
        p95: *p95,
    })
}
