//! The audit (SPEC §7): the real error of a mesh against the full-resolution height field.
//!
//! For every audited sample (every `stride`-th column and row of the real data, padding
//! excluded) the mesh height above or below it is found by rasterising the mesh's triangles over
//! the sample lattice (exact integer inside tests, so a sample on a shared edge gets the same
//! height from either side). The vertical segment between the sample and the mesh is then
//! measured as projected screen-space pixels and as view-angle pixels from the current eye, over
//! the samples inside the view volume. Per frame: max, mean and nearest-rank p95 of each; samples
//! with zero error count (they are part of the mean).
//!
//! Cost: O(audited samples + triangles) per frame; buffers are reused across frames.

use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::VertexSet;
use crate::sim::mesh::triangles::for_each_triangle;
use crate::sim::metrics::{projected_error_px, view_angle_error_px};
use crate::sim::stats::{AuditFrame, ErrorSummary};
use crate::sim::view::Camera;
use glam::DVec3;

/// Audit settings from the experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AuditSettings {
    /// Audit every `stride`-th sample along each axis (1 = every sample).
    pub stride: u32,
}

/// Reusable audit state.
pub struct Auditor {
    stride: usize,
    /// Audited samples per side: the grid side subsampled by `stride`.
    lattice_side: usize,
    mesh_height: Vec<f32>,
    projected: Vec<f64>,
    view_angle: Vec<f64>,
}

impl Auditor {
    pub fn new(hierarchy: &Hierarchy, settings: AuditSettings) -> Auditor {
        let stride = settings.stride.max(1) as usize;
        let lattice_side = (hierarchy.field().side() - 1) / stride + 1;
        Auditor {
            stride,
            lattice_side,
            mesh_height: vec![0.0; lattice_side * lattice_side],
            projected: Vec::new(),
            view_angle: Vec::new(),
        }
    }

    /// Measures one frame's mesh.
    pub fn audit(
        &mut self,
        hierarchy: &Hierarchy,
        mesh: &VertexSet,
        camera: &Camera,
    ) -> AuditFrame {
        self.rasterise(hierarchy, mesh);
        let field = hierarchy.field();
        let (stride, lattice_side) = (self.stride, self.lattice_side);
        let pixel_angle = camera.settings.pixel_angle();
        self.projected.clear();
        self.view_angle.clear();
        for j in (0..field.data_rows()).step_by(stride) {
            for i in (0..field.data_columns()).step_by(stride) {
                let sample = field.position(i, j);
                if !camera.sees(sample) {
                    continue;
                }
                let mesh_z = f64::from(self.mesh_height[(j / stride) * lattice_side + i / stride]);
                let base = DVec3::new(sample.x, sample.y, sample.z.min(mesh_z));
                let length = (sample.z - mesh_z).abs();
                if let Some(px) = projected_error_px(camera, base, length) {
                    self.projected.push(px);
                }
                self.view_angle
                    .push(view_angle_error_px(camera.eye, base, length, pixel_angle));
            }
        }
        AuditFrame {
            samples_in_view: self.view_angle.len() as u64,
            projected: summarise_in_place(&mut self.projected),
            view_angle: summarise_in_place(&mut self.view_angle),
        }
    }

    /// Fills `mesh_height` at every audited sample with the mesh surface's height.
    fn rasterise(&mut self, hierarchy: &Hierarchy, mesh: &VertexSet) {
        let stride = self.stride as i64;
        let lattice_side = self.lattice_side;
        let mesh_height = &mut self.mesh_height;
        for_each_triangle(hierarchy.lattice(), mesh, |triangle| {
            let corners = [triangle.apex, triangle.left, triangle.right];
            let xy = corners.map(|p| (i64::from(p.i), i64::from(p.j)));
            let z = corners.map(|p| f64::from(hierarchy.height(p)));
            let area2 = edge(xy[0], xy[1], xy[2]);
            if area2 == 0 {
                return;
            }
            let (i_min, i_max) = (xy.iter().map(|c| c.0).min(), xy.iter().map(|c| c.0).max());
            let (j_min, j_max) = (xy.iter().map(|c| c.1).min(), xy.iter().map(|c| c.1).max());
            let (i_min, i_max, j_min, j_max) = (
                i_min.unwrap_or(0),
                i_max.unwrap_or(0),
                j_min.unwrap_or(0),
                j_max.unwrap_or(0),
            );
            let first = |low: i64| (low + stride - 1) / stride * stride;
            let mut j = first(j_min);
            while j <= j_max {
                let mut i = first(i_min);
                while i <= i_max {
                    let w0 = edge(xy[1], xy[2], (i, j));
                    let w1 = edge(xy[2], xy[0], (i, j));
                    let w2 = edge(xy[0], xy[1], (i, j));
                    let inside = if area2 > 0 {
                        w0 >= 0 && w1 >= 0 && w2 >= 0
                    } else {
                        w0 <= 0 && w1 <= 0 && w2 <= 0
                    };
                    if inside {
                        let height =
                            (w0 as f64 * z[0] + w1 as f64 * z[1] + w2 as f64 * z[2]) / area2 as f64;
                        let index = (j / stride) as usize * lattice_side + (i / stride) as usize;
                        mesh_height[index] = height as f32;
                    }
                    i += stride;
                }
                j += stride;
            }
        });
    }
}

/// Twice the signed area of (a, b, c).
fn edge(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// Max, mean and nearest-rank p95 (the same rule as [`crate::sim::stats::nearest_rank`]),
/// in O(n) by selection instead of sorting.
fn summarise_in_place(values: &mut [f64]) -> Option<ErrorSummary> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::{Heightfield, Spacing};
    use crate::sim::view::{Pose, ViewSettings};

    fn camera_above(hierarchy: &Hierarchy) -> Camera {
        let (w, h) = hierarchy.field().extent();
        Camera::new(
            &Pose {
                position: DVec3::new(w / 2.0, h / 2.0, 200.0),
                yaw: 0.0,
                pitch: -std::f64::consts::FRAC_PI_2,
            },
            ViewSettings {
                width_px: 100,
                height_px: 100,
                fovy: 120f64.to_radians(),
                near: 1.0,
                far: 1000.0,
            },
        )
    }

    fn spike_field() -> Hierarchy {
        let side = 9;
        let heights = (0..side * side)
            .map(|k| if k == 4 * side + 4 { 8.0 } else { 0.0 })
            .collect();
        Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
    }

    #[test]
    fn the_full_mesh_has_no_error_and_the_base_mesh_misses_the_spike() {
        let hierarchy = spike_field();
        let lattice = hierarchy.lattice();
        let camera = camera_above(&hierarchy);
        let mut auditor = Auditor::new(&hierarchy, AuditSettings { stride: 1 });
        let mut full = VertexSet::new(lattice);
        for id in 0..lattice.n_vertices() as u32 {
            full.insert(id);
        }
        let exact = auditor.audit(&hierarchy, &full, &camera);
        assert_eq!(exact.samples_in_view, 81);
        assert_eq!(exact.view_angle.unwrap().max, 0.0);
        assert_eq!(exact.projected.unwrap().max, 0.0);

        let base = auditor.audit(&hierarchy, &VertexSet::base_mesh(lattice), &camera);
        let worst = base.view_angle.unwrap();
        // The spike (8 m, seen from 192 m straight above) is the only error.
        let expected = view_angle_error_px(
            DVec3::new(40.0, 40.0, 200.0),
            DVec3::new(40.0, 40.0, 0.0),
            8.0,
            camera.settings.pixel_angle(),
        );
        assert!((worst.max - expected).abs() < 1e-9);
        assert!((worst.mean - expected / 81.0).abs() < 1e-9);
        assert_eq!(worst.p95, 0.0);
    }

    #[test]
    fn nothing_in_view_gives_no_error_figures() {
        let hierarchy = spike_field();
        let mut camera = camera_above(&hierarchy);
        camera = Camera::new(
            &Pose {
                position: camera.eye,
                yaw: 0.0,
                pitch: std::f64::consts::FRAC_PI_2,
            },
            camera.settings,
        );
        let mut auditor = Auditor::new(&hierarchy, AuditSettings { stride: 2 });
        let frame = auditor.audit(
            &hierarchy,
            &VertexSet::base_mesh(hierarchy.lattice()),
            &camera,
        );
        assert_eq!(frame.samples_in_view, 0);
        assert_eq!(frame.view_angle, None);
    }
}
