//! The audit (SPEC §7): the real error of the drawn surface against the full-resolution height
//! field, and (when asked) popping, its change from one frame to the next. It measures whatever
//! surface an algorithm draws, read through the mesh visitor ([`MeshOutput::for_each_triangle`]),
//! never the algorithm's own error estimate, and runs only when the experiment asks for it. This
//! file is the [`Auditor`], its calls and the steps of one frame; the parts live beside it:
//!
//! - `tiles.rs`: the tiles of 16² audited samples, those that may be in view, those kept;
//! - `lattice.rs`: a 4-8 mesh against the source's samples (the exact integer rasteriser);
//! - `general.rs`: triangle lists and synthesised detail (the general rasteriser, holes, crack
//!   gaps, skirts);
//! - `batch.rs` and `geometry.rs`: the error segments of the samples in view, measured in
//!   batches;
//! - `figures.rs`: each figure's tallies and summary (max, mean, p95);
//! - `popping.rs`: popping, and the promise about the next camera;
//! - `reference.rs`: the audit as first written, the differential reference.
//!
//! A frame: the tiles that may be in view; the drawn height at every audited sample of the tiles
//! kept, rasterised from the mesh's triangles; then the samples in view measured row by row, in
//! order, and their figures summarised.
//!
//! Decisions:
//!
//! - **What is audited.** Every `stride`-th column and row of the real data (padding
//!   excluded). A sample is in view when it is inside the view volume (`Camera::sees`). The
//!   vertical segment between the sample and the drawn surface is measured in projected
//!   screen-space pixels and in view-angle pixels from the current eye; per frame: max, mean and
//!   nearest-rank p95 of each, samples with zero error included.
//! - **Two truths.** The field's samples ([`Auditor::audit`]), or, for an entry that
//!   synthesises detail below the source (`chunked`'s detail effect), the synthesised surface at
//!   its deepest level ([`Auditor::refined`], [`Auditor::audit_against`]). The runner reports
//!   both for such an entry, named apart (`audit_*`: against the source; `audit_detail_*`:
//!   against the detail-extended surface).
//! - **Every shortcut is exact.** The figures equal [`reference::ReferenceAuditor`]'s bit for bit
//!   (`tests/audit_reference.rs`), by construction, not by tolerance: the same IEEE operations
//!   in the same order, or an exact operation in their place (a quotient becomes a product only
//!   by the reciprocal of a power of two, an integer division a shift only by a power of two,
//!   integer-valued `f64` arithmetic only below 2^53). Each part's doc says which shortcuts it
//!   takes.
//! - **Cost.** O(audited samples + triangles) per frame; buffers are reused across frames, and
//!   those of the general path and of popping are allocated only when first needed.
//! - **No threads inside the audit.** Tried (bands of rows measured side by side, then joined in
//!   row order) and rejected: slower on one core, and a run already flies its entries side by
//!   side, so the study's cost would not fall.

pub mod reference;

mod batch;
mod figures;
mod general;
mod geometry;
mod lattice;
mod popping;
#[cfg(test)]
mod tests;
mod tiles;

use self::batch::{ErrorBatch, RunColumns};
use self::figures::Figures;
use self::general::CrackHeights;
use self::geometry::ErrorGeometry;
use self::popping::PoppingSums;
use self::tiles::{TilesKept, tile_boxes};
use crate::sim::algorithm::chunked::detail::DetailField;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::MeshOutput;
use crate::sim::stats::{AuditFrame, SurfaceCoverage};
use crate::sim::view::Camera;
use glam::DVec3;

/// Audit settings from the experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AuditSettings {
    /// Audit every `stride`-th sample along each axis (1 = every sample).
    pub stride: u32,
    /// Also measure popping (the change of the drawn surface since the previous frame).
    pub popping: bool,
    /// The stride of the audit against a detail-extended surface, in that surface's samples
    /// (`None`: `stride`).
    pub detail_stride: Option<u32>,
}

/// Reusable audit state.
pub struct Auditor {
    stride: usize,
    /// Levels of synthesised detail between the source samples and the audited lattice's: the
    /// lattice is the source grid refined 2^refine times (0: the source's own samples).
    refine: u32,
    /// Audited samples per side: the grid side subsampled by `stride`.
    lattice_side: usize,
    /// Audited columns and rows holding real data (padding excluded).
    lattice_columns: usize,
    lattice_rows: usize,
    /// Per tile of `TILE`² audited samples (row-major, `tiles_x` per row): the box of its
    /// samples (x, y of its first and last sample, and the height range), to skip the tiles
    /// the view surely misses.
    tile_boxes: Vec<(DVec3, DVec3)>,
    tiles_x: usize,
    /// Per tile this frame: whether it may be in view.
    tile_in_view: Vec<bool>,
    /// Per tile this frame, with popping and the next camera known: whether it may be in view
    /// from this camera or the next.
    tile_in_either_view: Vec<bool>,
    /// This frame's tiles whose drawn heights are kept (the others' triangles are skipped).
    tile_kept: TilesKept,
    /// Whether the lattice path may use 256-bit vector instructions when the CPU has them
    /// ([`Auditor::without_wide_vectors`]).
    wide_vectors: bool,
    /// Per audited column of the source's samples: its x, as `Heightfield::position` has it.
    column_x: Vec<f64>,
    /// The drawn height at every audited sample (NaN: a hole, triangle lists only).
    mesh_height: Vec<f32>,
    /// The general path's crack bookkeeping, allocated at the first triangle list.
    crack: Option<CrackHeights>,
    /// The previous frame's `mesh_height`, when popping is measured (`None` before frame 0).
    previous_height: Option<Vec<f32>>,
    popping: bool,
    /// The camera the last call promised for this one ([`Auditor::audit_followed_by`]):
    /// popping then reads heights kept only where that camera may see.
    promised_next: Option<Camera>,
    /// The samples in view whose error segments are still to be measured.
    batch: ErrorBatch,
    /// The columns of one run of samples, in view or not (the lattice path's).
    run: Box<RunColumns>,
    /// This frame's errors of the samples in view, in the order they were found.
    projected: Figures,
    view_angle: Figures,
    /// The candidates for a p95, reused.
    scratch: Vec<f64>,
}

impl Auditor {
    pub fn new(hierarchy: &Hierarchy, settings: AuditSettings) -> Auditor {
        Auditor::refined(hierarchy, settings, 0)
    }

    /// An auditor whose samples are those of the source grid refined `refine` times (every
    /// `stride`-th of them), for a truth with synthesised detail ([`DetailField`] of depth
    /// `refine`, see [`Auditor::audit_against`]).
    pub fn refined(hierarchy: &Hierarchy, settings: AuditSettings, refine: u32) -> Auditor {
        let stride = settings.stride.max(1) as usize;
        let field = hierarchy.field();
        let lattice_side = ((field.side() - 1) << refine) / stride + 1;
        // Audited columns and rows of real data: every `stride`-th sample of the source grid
        // refined 2^refine times.
        let lattice_columns = (((field.data_columns() - 1) << refine) + 1).div_ceil(stride);
        let lattice_rows = (((field.data_rows() - 1) << refine) + 1).div_ceil(stride);
        // Tile boxes from the source's heights; a refined auditor's truth is synthesised per
        // frame, so it tests every tile (`skip_tiles` false).
        let skip_tiles = refine == 0;
        let (tile_boxes, tiles_x) =
            tile_boxes(field, stride, (lattice_columns, lattice_rows), skip_tiles);
        Auditor {
            stride,
            refine,
            lattice_side,
            lattice_columns,
            lattice_rows,
            tile_in_view: vec![false; tile_boxes.len()],
            tile_in_either_view: Vec::new(),
            tile_kept: TilesKept::All,
            wide_vectors: true,
            column_x: (0..lattice_side)
                .map(|li| (li * stride) as f64 * field.spacing().dx)
                .collect(),
            tile_boxes,
            tiles_x,
            mesh_height: vec![0.0; lattice_side * lattice_side],
            crack: None,
            previous_height: None,
            popping: settings.popping,
            promised_next: None,
            batch: ErrorBatch::default(),
            run: Box::default(),
            projected: Figures::default(),
            view_angle: Figures::default(),
            scratch: Vec::new(),
        }
    }

    /// This auditor with the lattice path kept to the baseline instruction set (no 256-bit
    /// vectors even where the CPU has them): the same figures, bit for bit, more slowly; for
    /// comparing the two compilations of that path.
    pub fn without_wide_vectors(mut self) -> Auditor {
        self.wide_vectors = false;
        self
    }

    /// Measures one frame's mesh (and, with popping on, its change since the last call)
    /// against the source's samples.
    pub fn audit(
        &mut self,
        hierarchy: &Hierarchy,
        mesh: MeshOutput,
        camera: &Camera,
    ) -> AuditFrame {
        self.audit_frame(hierarchy, mesh, camera, None, None)
    }

    /// [`Auditor::audit`] when the camera of the frame audited next is known (a flight's next
    /// pose): with popping on, this frame's drawn heights are then kept only where the next
    /// frame may read them (the tiles that may be in view from either camera), so the
    /// triangles that touch none of those tiles are not rasterised. The figures are those of
    /// [`Auditor::audit`], bit for bit.
    ///
    /// # Panics
    /// With popping on, at the next call, when its camera is not `next`.
    pub fn audit_followed_by(
        &mut self,
        hierarchy: &Hierarchy,
        mesh: MeshOutput,
        camera: &Camera,
        next: &Camera,
    ) -> AuditFrame {
        self.audit_frame(hierarchy, mesh, camera, None, Some(next))
    }

    /// [`Auditor::audit`] against `truth`, the synthesised surface at this auditor's depth
    /// (`None`: the source's samples, for an auditor of depth 0).
    ///
    /// # Panics
    /// When `truth`'s depth is not this auditor's.
    pub fn audit_against(
        &mut self,
        hierarchy: &Hierarchy,
        mesh: MeshOutput,
        camera: &Camera,
        truth: Option<&DetailField>,
    ) -> AuditFrame {
        self.audit_frame(hierarchy, mesh, camera, truth, None)
    }

    /// One frame's audit against `truth`, knowing the next frame's camera or not: the tiles
    /// that may be in view, the drawn heights, then the samples in view measured in row order.
    fn audit_frame(
        &mut self,
        hierarchy: &Hierarchy,
        mesh: MeshOutput,
        camera: &Camera,
        truth: Option<&DetailField>,
        next: Option<&Camera>,
    ) -> AuditFrame {
        assert_eq!(
            truth.map_or(0, DetailField::depth),
            self.refine,
            "the audit's truth is not at its lattice's depth"
        );
        self.keep_promise(camera, next);
        self.find_tiles(camera, next);
        let general = matches!(mesh, MeshOutput::Triangles(_)) || self.refine > 0;
        if general {
            self.rasterise_general(hierarchy, mesh);
        } else {
            self.rasterise_lattice(hierarchy, mesh);
        }
        let geometry = ErrorGeometry::new(camera);
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
        let measured_popping = self.previous_height.is_some();
        let popping_sums = measured_popping.then_some(&mut popping);
        // Row by row, every sample in order as `sees` finds it (the order the figures are
        // summed in), the tiles the view surely misses skipped: their samples would all fail
        // `sees`.
        let field = hierarchy.field();
        if general {
            let coverage = coverage.as_mut();
            self.measure_general(field, camera, &geometry, truth, coverage, popping_sums);
        } else {
            self.measure_lattice(field, camera, &geometry, popping_sums);
        }
        let popping = popping.summary(measured_popping);
        self.keep_heights_for_next_frame();
        AuditFrame {
            samples_in_view: self.view_angle.len() as u64,
            projected: self.projected.summary(&mut self.scratch),
            view_angle: self.view_angle.summary(&mut self.scratch),
            coverage,
            popping,
        }
    }
}
