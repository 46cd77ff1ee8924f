//! The audit (SPEC §7): the real error of the drawn surface against the full-resolution height
//! field, and (when asked) popping, its change from one frame to the next.
//!
//! For every audited sample (every `stride`-th column and row of the real data, padding
//! excluded) the height of the drawn surface above or below it is found by rasterising the
//! mesh's triangles, read through the mesh visitor ([`MeshOutput::for_each_triangle`]), over the
//! sample lattice ([`crate::sim::mesh::raster`]):
//!
//! - a 4-8 mesh goes through the exact integer rasteriser the audit has always used (a sample
//!   on a shared edge gets the same height from either side), with each corner at its drawn
//!   height (morphed heights included): its figures are those of every earlier release, bit for
//!   bit;
//! - a triangle list goes through the general rasteriser with its tie rule (a sample on an edge
//!   or a vertex belongs to exactly one triangle of a tiling). Only surface and stitch triangles
//!   are surface; skirts and degenerate triangles never are. A sample no surface triangle covers
//!   is a **hole** (counted, and left out of the error figures); where the triangles meeting at
//!   a sample disagree on its height (a T-junction, heights that differ across a border) the
//!   disagreement is a **crack gap**, counted and measured in metres and projected pixels. The
//!   skirts hung there (vertical triangles) cover the part of the gap their vertical extent
//!   spans; what no skirt spans is the gap left **uncovered**, the crack a viewer could see
//!   through (counted and measured too; without skirts it is the whole gap).
//!
//! The vertical segment between the sample and the surface is measured as projected
//! screen-space pixels and as view-angle pixels from the current eye, over the samples inside
//! the view volume. Per frame: max, mean and nearest-rank p95 of each; samples with zero error
//! count (they are part of the mean).
//!
//! **Popping** (the 2019 stitching-strips paper's measure, an effect the experiment switches
//! on): at the same samples in view, the change of the drawn height since the previous frame,
//! as RMSE and maximum in metres and in projected pixels from the current eye (a vertical
//! segment of the change's length at the sample). Samples that were a hole in either frame are
//! left out; the first frame has no previous one. Off, it keeps no previous frame.
//!
//! The truth is the field's samples ([`Auditor::audit`]), or, for an entry that synthesises
//! detail below the source (`chunked`'s detail effect), the synthesised surface at its deepest
//! level ([`Auditor::refined`], [`Auditor::audit_against`]): the same audit over the source grid
//! refined 2^k times, through the general rasteriser (its samples are at a fixed-point step of
//! 1/2^k cell). The runner reports both for such an entry, named apart (`audit_*`: against the
//! source; `audit_detail_*`: against the detail-extended surface).
//!
//! Cost: O(audited samples + triangles) per frame; buffers are reused across frames, and those
//! of the general path and of popping are allocated only when first needed. Every shortcut is
//! exact (the figures equal [`reference::ReferenceAuditor`]'s bit for bit): tiles and bintree
//! subtrees out of view skipped, the error arithmetic batched into columns with the same
//! operations in the same order, the p95 selected inside the histogram bucket of its rank.

pub mod reference;

use crate::sim::algorithm::chunked::detail::DetailField;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::raster::{SampleRaster, floor_div, rasterise_lattice_triangle};
use crate::sim::mesh::{
    DrawnTriangle, MeshOutput, SUBGRID_UNITS_PER_CELL, SurfacePoint, TriangleRole,
};
use crate::sim::metrics::{projected_error_px, projected_error_px_at};
use crate::sim::stats::{AuditFrame, ErrorSummary, PoppingFrame, SurfaceCoverage};
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

/// Audited samples per side of a tile: the unit of the exact skip of samples out of view.
const TILE: usize = 16;

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

/// The lowest and highest height any surface triangle draws at each audited sample, and the
/// vertical spans skirts cover at the samples where those differ.
struct CrackHeights {
    low: Vec<f32>,
    high: Vec<f32>,
    /// (sample index, lowest, highest height) of each skirt triangle over a cracked sample,
    /// sorted by index then height.
    skirt_spans: Vec<(usize, f32, f32)>,
}

impl CrackHeights {
    /// The length of the crack gap at `index` that no skirt spans, metres.
    fn uncovered(&self, index: usize) -> f64 {
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
        let tiles_x = lattice_columns.div_ceil(TILE);
        let tiles_y = lattice_rows.div_ceil(TILE);
        // Tile boxes from the source's heights; a refined auditor's truth is synthesised per
        // frame, so it tests every tile (`skip_tiles` false).
        let skip_tiles = refine == 0;
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

    /// One frame's audit against `truth`, knowing the next frame's camera or not.
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
        // The previous frame kept heights only where the camera it was promised may see.
        if let Some(promised) = self.promised_next.take() {
            assert!(
                promised == *camera,
                "the audit was promised the next frame's camera {promised:?} and is given {camera:?}"
            );
        }
        if self.popping {
            self.promised_next = next.copied();
        }
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
        let general = matches!(mesh, MeshOutput::Triangles(_)) || self.refine > 0;
        if general {
            self.rasterise_general(hierarchy, mesh);
        } else {
            self.rasterise_lattice(hierarchy, mesh);
        }
        let field = hierarchy.field();
        let (stride, lattice_side) = (self.stride, self.lattice_side);
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
        let previous = self.previous_height.as_deref();
        // Row by row, every sample in order as `sees` finds it (the order the figures are
        // summed in), the tiles the view surely misses skipped: their samples would all fail
        // `sees`.
        let tiles_x = self.tiles_x;
        let spacing = field.spacing();
        let fine = 1.0 / f64::from(1u32 << self.refine);
        let (heights, field_side) = (field.heights(), field.side());
        let eye = camera.eye;
        let (right, up, forward) = (camera.right, camera.up, camera.forward);
        let (batch, run) = (&mut self.batch, &mut *self.run);
        let mut sinks = Sinks {
            projected: &mut self.projected,
            view_angle: &mut self.view_angle,
            popping: previous.is_some().then_some(&mut popping),
        };
        if !general {
            let lattice = LatticeRows {
                tile_in_view: &self.tile_in_view,
                tiles_x,
                lattice_columns: self.lattice_columns,
                lattice_rows: self.lattice_rows,
                lattice_side,
                drawn: &self.mesh_height,
                previous,
                heights,
                field_side,
                stride,
                spacing_y: spacing.dy,
                column_x: &self.column_x,
            };
            let measure = MeasureLattice {
                batch,
                run,
                lattice: &lattice,
                geometry: &geometry,
                camera,
                sinks: &mut sinks,
            };
            measure.run(self.wide_vectors);
        } else {
            // The samples in view go to the batch in order, `n` of them waiting.
            let mut n = 0;
            let mut measure = |batch: &mut ErrorBatch, n: usize| {
                batch.measure(n, &geometry, camera, &mut sinks);
            };
            for lj in 0..self.lattice_rows {
                let j = lj * stride;
                let tile_row = &self.tile_in_view[(lj / TILE) * tiles_x..][..tiles_x];
                // The sample's y, as `Heightfield::position` (or the synthesised surface) has
                // it, and the products of `Camera::to_camera` that depend on the row only.
                let y = match truth {
                    None => j as f64 * spacing.dy,
                    Some(_) => j as f64 * spacing.dy * fine,
                };
                let dy = y - eye.y;
                let (right_y, up_y, forward_y) = (dy * right.y, dy * up.y, dy * forward.y);
                let height_row = &heights[if truth.is_none() { j * field_side } else { 0 }..];
                let mesh_row = &self.mesh_height[lj * lattice_side..][..lattice_side];
                for columns in columns_in_view(tile_row, self.lattice_columns) {
                    for li in columns {
                        let i = li * stride;
                        // The truth: the field's sample, or the synthesised surface's.
                        let (x, z) = match truth {
                            None => (i as f64 * spacing.dx, f64::from(height_row[i])),
                            Some(truth) => (
                                i as f64 * spacing.dx * fine,
                                f64::from(truth.height(i as u32, j as u32)),
                            ),
                        };
                        let sample = DVec3::new(x, y, z);
                        // `Camera::to_camera`, its sums in the same order.
                        let (dx, dz) = (x - eye.x, z - eye.z);
                        let (right_xy, up_xy, forward_xy) = (
                            dx * right.x + right_y,
                            dx * up.x + up_y,
                            dx * forward.x + forward_y,
                        );
                        let in_camera = DVec3::new(
                            right_xy + dz * right.z,
                            up_xy + dz * up.z,
                            forward_xy + dz * forward.z,
                        );
                        if !camera.sees_camera(in_camera) {
                            continue;
                        }
                        let index = lj * lattice_side + li;
                        let drawn = mesh_row[li];
                        if let (Some(coverage), Some(crack)) =
                            (coverage.as_mut(), self.crack.as_ref())
                        {
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
                                    coverage.crack_uncovered_max_m =
                                        coverage.crack_uncovered_max_m.max(open);
                                    if let Some(px) = projected_error_px(camera, base, open) {
                                        coverage.crack_uncovered_max_px =
                                            coverage.crack_uncovered_max_px.max(px);
                                    }
                                }
                            }
                            if drawn.is_nan() {
                                coverage.holes += 1;
                                continue;
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
                        if let Some(previous) = previous {
                            // The change since the previous frame (none at a hole), its
                            // segment from the lower of the two heights.
                            let before = f64::from(previous[index]);
                            let counts = !before.is_nan() && !mesh_z.is_nan();
                            let base = in_camera_at(before.min(mesh_z));
                            put_popping(batch, n, counts, (mesh_z - before).abs(), base);
                        }
                        // The segment from the lower of the sample and the surface, `length`
                        // long; its base in camera coordinates differs from the sample's in the
                        // z terms only (and is the sample's, bit for bit, when it starts there:
                        // no branch).
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
                        n += 1;
                        if n == BATCH {
                            measure(batch, n);
                            n = 0;
                        }
                    }
                }
            }
            measure(batch, n);
        }
        let popping = popping.summary(previous.is_some());
        if self.popping {
            // Keep this frame's heights for the next; the old buffer becomes next frame's
            // scratch (both paths write every sample of the tiles kept, and only those are read).
            let previous = self
                .previous_height
                .get_or_insert_with(|| vec![0.0; self.mesh_height.len()]);
            std::mem::swap(previous, &mut self.mesh_height);
        }
        AuditFrame {
            samples_in_view: self.view_angle.len() as u64,
            projected: self.projected.summary(&mut self.scratch),
            view_angle: self.view_angle.summary(&mut self.scratch),
            coverage,
            popping,
        }
    }

    /// 4-8 meshes: the exact integer rasteriser, every sample of the tiles kept written (a
    /// closed mesh covers the whole domain).
    fn rasterise_lattice(&mut self, hierarchy: &Hierarchy, mesh: MeshOutput) {
        let stride = self.stride as i64;
        let lattice_side = self.lattice_side;
        // Taken out for the frame, so that the tile filter can borrow the rest.
        let mut mesh_height = std::mem::take(&mut self.mesh_height);
        let tiles = self.tiles_kept();
        let rasterise = |triangle: &DrawnTriangle| {
            rasterise_lattice_triangle(&triangle.corners, stride, lattice_side, &mut mesh_height);
        };
        if tiles.kept.is_some() {
            // A triangle that touches no tile kept holds none that does: its subtree is
            // skipped, and every triangle visited (a leaf of the bintree too) passed the test.
            let within = |corners: &[SurfacePoint; 3]| tiles.may_touch(corners);
            mesh.for_each_triangle_within(hierarchy, within, rasterise);
        } else {
            mesh.for_each_triangle(hierarchy, rasterise);
        }
        self.mesh_height = mesh_height;
    }

    /// Which triangles to rasterise: those that may touch a tile whose heights are kept
    /// (`tile_kept`). Without popping, a sample's drawn height is read only where it is in
    /// view, and every triangle that covers such a sample touches its tile, so skipping the
    /// others changes no figure (a shared sample's last writer is kept). With popping, the
    /// next frame reads this frame's heights where it sees: the tiles that may be in view from
    /// either camera are kept, or every one when the next camera is not known.
    fn tiles_kept(&self) -> TileFilter<'_> {
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

    /// Triangle lists: the general rasteriser over the surface triangles; holes stay NaN.
    fn rasterise_general(&mut self, hierarchy: &Hierarchy, mesh: MeshOutput) {
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
}

/// The audited columns of one row of tiles that may be in view (`tile_row`: per tile), as
/// runs of consecutive tiles, west to east.
fn columns_in_view(
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
enum TilesKept {
    /// Those that may be in view (no popping: nothing else is read).
    InView,
    /// Those that may be in view from this frame's camera or the next's.
    InEitherView,
    /// Every tile (popping, the next camera unknown).
    All,
}

/// The tiles of audited samples whose drawn heights a frame keeps ([`TilesKept`]), as a
/// triangle filter.
struct TileFilter<'a> {
    /// Per tile, whether its heights are kept; `None`: every tile's (popping, the next camera
    /// unknown).
    kept: Option<&'a [bool]>,
    tiles_x: usize,
    lattice_columns: usize,
    lattice_rows: usize,
    /// Fixed-point units between neighbouring audited samples.
    units_per_sample: i64,
}

impl TileFilter<'_> {
    /// Whether the triangle's bounding box (widened to the audited samples around it) meets a
    /// tile whose heights are kept.
    fn may_touch(&self, corners: &[SurfacePoint; 3]) -> bool {
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

/// Running sums of one frame's popping.
#[derive(Default)]
struct PoppingSums {
    samples: u64,
    squares_m: f64,
    max_m: f64,
    px_samples: u64,
    squares_px: f64,
    max_px: f64,
}

impl PoppingSums {
    /// Adds the change at one sample in view from `before` to `now` (either NaN: a hole, left
    /// out). The reference's way; the batch measures the same with [`PoppingSums::add_measured`].
    fn add(&mut self, camera: &Camera, sample: DVec3, before: f64, now: f64) {
        if before.is_nan() || now.is_nan() {
            return;
        }
        let change = (now - before).abs();
        let base = DVec3::new(sample.x, sample.y, before.min(now));
        self.add_measured(change, projected_error_px(camera, base, change));
    }

    /// Adds a change of `change` metres, `px` pixels when its segment is not behind the near
    /// plane.
    fn add_measured(&mut self, change: f64, px: Option<f64>) {
        self.samples += 1;
        self.squares_m += change * change;
        self.max_m = self.max_m.max(change);
        if let Some(px) = px {
            self.px_samples += 1;
            self.squares_px += px * px;
            self.max_px = self.max_px.max(px);
        }
    }

    fn summary(&self, measured: bool) -> Option<PoppingFrame> {
        (measured && self.samples > 0).then(|| PoppingFrame {
            samples: self.samples,
            rmse_m: (self.squares_m / self.samples as f64).sqrt(),
            max_m: self.max_m,
            rmse_px: (self.squares_px / self.px_samples.max(1) as f64).sqrt(),
            max_px: self.max_px,
        })
    }
}

/// The camera's constants of one frame's error segments.
struct ErrorGeometry {
    /// `Camera::direction_to_camera((0, 0, δ))` is `zero + δ · axis.z` per camera axis: the
    /// sums of its two zero products, which depend on the camera only (their sign of zero).
    zero: DVec3,
    right_z: f64,
    up_z: f64,
    forward_z: f64,
    near: f64,
    pixels_per_unit: f64,
    pixel_angle: f64,
    /// The view angle of a segment with the eye at an end, in pixels.
    eye_on_segment: f64,
}

impl ErrorGeometry {
    fn new(camera: &Camera) -> ErrorGeometry {
        let zero_products = |axis: DVec3| 0.0 * axis.x + 0.0 * axis.y;
        ErrorGeometry {
            zero: DVec3::new(
                zero_products(camera.right),
                zero_products(camera.up),
                zero_products(camera.forward),
            ),
            right_z: camera.right.z,
            up_z: camera.up.z,
            forward_z: camera.forward.z,
            near: camera.settings.near,
            pixels_per_unit: camera.pixels_per_unit(),
            pixel_angle: camera.settings.pixel_angle(),
            eye_on_segment: std::f64::consts::PI / camera.settings.pixel_angle(),
        }
    }
}

/// What the lattice path reads of one frame: the lattice's rows, their tiles and heights.
struct LatticeRows<'a> {
    tile_in_view: &'a [bool],
    tiles_x: usize,
    lattice_columns: usize,
    lattice_rows: usize,
    lattice_side: usize,
    /// The drawn height at every audited sample, and the previous frame's (with popping).
    drawn: &'a [f32],
    previous: Option<&'a [f32]>,
    /// The source's heights, `field_side` per row.
    heights: &'a [f32],
    field_side: usize,
    stride: usize,
    spacing_y: f64,
    /// Per audited column: its x, as `Heightfield::position` has it.
    column_x: &'a [f64],
}

/// The lattice path's measurement of one frame: a 4-8 mesh against the source's samples, each
/// run of samples in tiles that may be in view measured whole, in row order.
struct MeasureLattice<'a, 'b> {
    batch: &'a mut ErrorBatch,
    run: &'a mut RunColumns,
    lattice: &'a LatticeRows<'b>,
    geometry: &'a ErrorGeometry,
    camera: &'a Camera,
    sinks: &'a mut Sinks<'b>,
}

impl MeasureLattice<'_, '_> {
    /// Measures, with 256-bit vector instructions where `wide` (the CPU has AVX2): the same
    /// IEEE operations on more values at once, so the same figures, bit for bit.
    fn run(self, wide: bool) {
        #[cfg(target_arch = "x86_64")]
        if wide && std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the one requirement of calling a function compiled for AVX2 is a CPU
            // that has it, checked just above.
            #[allow(unsafe_code)]
            unsafe {
                self.run_avx2();
            }
            return;
        }
        let _ = wide;
        self.run_here();
    }

    /// [`MeasureLattice::run_here`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn run_avx2(self) {
        self.run_here();
    }

    #[inline(always)]
    fn run_here(self) {
        let MeasureLattice {
            batch,
            run,
            lattice,
            geometry,
            camera,
            sinks,
        } = self;
        let (eye, right, up, forward) = (camera.eye, camera.right, camera.up, camera.forward);
        let (tiles_x, lattice_side) = (lattice.tiles_x, lattice.lattice_side);
        for lj in 0..lattice.lattice_rows {
            let j = lj * lattice.stride;
            let tile_row = &lattice.tile_in_view[(lj / TILE) * tiles_x..][..tiles_x];
            let dy = j as f64 * lattice.spacing_y - eye.y;
            let row = Row {
                heights: &lattice.heights[j * lattice.field_side..][..lattice.field_side],
                drawn: &lattice.drawn[lj * lattice_side..][..lattice_side],
                stride: lattice.stride,
                x: lattice.column_x,
                previous: (lattice.previous)
                    .map(|previous| &previous[lj * lattice_side..][..lattice_side]),
                dy,
                right_y: dy * right.y,
                up_y: dy * up.y,
                forward_y: dy * forward.y,
            };
            for columns in columns_in_view(tile_row, lattice.lattice_columns) {
                batch.measure_row(run, &row, columns, geometry, camera, sinks);
            }
        }
        batch.finish(geometry, camera, sinks);
    }
}

/// Segments measured at once: their columns stay in the first-level cache.
const BATCH: usize = 128;

/// Error segments of samples in view waiting to be measured, as columns (a structure of
/// arrays), so that their divisions and square roots run as vector instructions. Every value
/// is computed with exactly the operations of [`projected_error_px_at`] and
/// [`view_angle_error_px`](crate::sim::metrics::view_angle_error_px) in the same order, so
/// each is bit-identical to theirs.
///
/// Two ways in: [`put_segment`] and [`ErrorBatch::measure`] (the general path: one segment at
/// a time, those of samples in view only), and [`ErrorBatch::measure_row`] (a 4-8 mesh
/// against the source's samples, with or without popping: a run of one row's samples measured
/// whole, with no branch, those out of view dropped after).
struct ErrorBatch {
    /// Per segment: its base in camera coordinates (x, y, z), its base minus the eye on the
    /// world axes (x, y, z), and its length in metres. [`ErrorBatch::measure_row`] keeps only
    /// the base and the length, for the segments the near plane cuts.
    segments: Box<[[f64; BATCH]; 7]>,
    /// Per segment waiting: [`SegmentFigures`]' projected length, sine, cosine and special
    /// angle.
    results: Box<[[f64; BATCH]; 4]>,
    /// Per segment waiting: whether both its ends are in front of the near plane.
    in_front: Box<[bool; BATCH]>,
    /// Per segment waiting, with popping measured: the change of the drawn height since the
    /// previous frame (metres), the base of its segment (from the lower of the two heights) in
    /// camera coordinates (x, y, z), and its projected length when both ends are in front of
    /// the near plane.
    popping: Box<[[f64; BATCH]; 5]>,
    /// Per segment waiting, with popping measured: whether the change counts (neither height a
    /// hole) and whether both ends of its segment are in front of the near plane.
    popping_counts: Box<[bool; BATCH]>,
    popping_in_front: Box<[bool; BATCH]>,
    /// Segments waiting in `results`.
    waiting: usize,
}

/// One run of a row's samples (at most [`BATCH`]) as [`ErrorBatch::measure_row`] reads them:
/// the truth and drawn heights, and whether each is in view.
struct RunColumns {
    truth: [f64; BATCH],
    drawn: [f64; BATCH],
    /// The drawn heights of the previous frame, with popping measured.
    before: [f64; BATCH],
    seen: [bool; BATCH],
}

impl Default for ErrorBatch {
    fn default() -> ErrorBatch {
        ErrorBatch {
            segments: Box::new([[0.0; BATCH]; 7]),
            results: Box::new([[0.0; BATCH]; 4]),
            in_front: Box::new([false; BATCH]),
            popping: Box::new([[0.0; BATCH]; 5]),
            popping_counts: Box::new([false; BATCH]),
            popping_in_front: Box::new([false; BATCH]),
            waiting: 0,
        }
    }
}

impl Default for RunColumns {
    fn default() -> RunColumns {
        RunColumns {
            truth: [0.0; BATCH],
            drawn: [0.0; BATCH],
            before: [0.0; BATCH],
            seen: [false; BATCH],
        }
    }
}

/// Writes segment `n` of a batch.
#[inline(always)]
fn put_segment(
    segments: &mut [[f64; BATCH]; 7],
    n: usize,
    base_in_camera: DVec3,
    to_base: DVec3,
    length: f64,
) {
    let n = n % BATCH;
    segments[0][n] = base_in_camera.x;
    segments[1][n] = base_in_camera.y;
    segments[2][n] = base_in_camera.z;
    segments[3][n] = to_base.x;
    segments[4][n] = to_base.y;
    segments[5][n] = to_base.z;
    segments[6][n] = length;
}

/// Writes the popping of segment `n` of a batch: whether it counts, the change, and the base
/// of its segment in camera coordinates.
#[inline(always)]
fn put_popping(batch: &mut ErrorBatch, n: usize, counts: bool, change: f64, base: DVec3) {
    let n = n % BATCH;
    batch.popping_counts[n] = counts;
    batch.popping[0][n] = change;
    batch.popping[1][n] = base.x;
    batch.popping[2][n] = base.y;
    batch.popping[3][n] = base.z;
}

/// What one segment's figures need before the view angle's `atan2`.
struct SegmentFigures {
    /// Its projected length in pixels, when both ends are in front of the near plane.
    projected: f64,
    in_front: bool,
    /// The two arguments of the view angle's `atan2`.
    sine: f64,
    cosine: f64,
    /// The view angle in pixels of a segment of no length (0) or with the eye at an end
    /// (π / pixel angle); −1: none, the angle is `atan2(sine, cosine)` / pixel angle.
    special: f64,
}

/// The figures of the vertical segment `delta` long whose base is `a` in camera coordinates
/// and `to_base` from the eye: [`projected_error_px_at`]'s and `view_angle_error_px`'s
/// operations in their order, with no branch (the compiler makes vector instructions of a
/// loop of it).
#[inline(always)]
fn segment_figures(g: &ErrorGeometry, a: DVec3, to_base: DVec3, delta: f64) -> SegmentFigures {
    let (projected, in_front) = projected_segment(g, a, delta);
    // view_angle_error_px: |to_base × to_top| and to_base · to_top.
    let (tx, ty, tz) = (to_base.x, to_base.y, to_base.z);
    let (sx, sy, sz) = (tx + 0.0, ty + 0.0, tz + delta);
    let cx = ty * sz - sy * tz;
    let cy = tz * sx - sz * tx;
    let cz = tx * sy - sx * ty;
    // Its special cases (`x + 0.0 == 0.0` is `x == 0.0`).
    let eye_at_end = (tx == 0.0) & (ty == 0.0) & ((tz == 0.0) | (sz == 0.0));
    let special = if eye_at_end { g.eye_on_segment } else { -1.0 };
    SegmentFigures {
        projected,
        in_front,
        sine: (cx * cx + cy * cy + cz * cz).sqrt(),
        cosine: tx * sx + ty * sy + tz * sz,
        special: if delta == 0.0 { 0.0 } else { special },
    }
}

/// [`projected_error_px_at`] of the vertical segment `delta` long whose base is `a` in camera
/// coordinates, with no branch: its length in pixels and whether both its ends are in front of
/// the near plane (otherwise the length is not the segment's).
#[inline(always)]
fn projected_segment(g: &ErrorGeometry, a: DVec3, delta: f64) -> (f64, bool) {
    let (ax, ay, az) = (a.x, a.y, a.z);
    // b = a + direction_to_camera((0, 0, δ)), both projected.
    let bx = ax + (g.zero.x + delta * g.right_z);
    let by = ay + (g.zero.y + delta * g.up_z);
    let bz = az + (g.zero.z + delta * g.forward_z);
    let (pax, pay) = (ax / az * g.pixels_per_unit, ay / az * g.pixels_per_unit);
    let (pbx, pby) = (bx / bz * g.pixels_per_unit, by / bz * g.pixels_per_unit);
    let (dx, dy) = (pax - pbx, pay - pby);
    ((dx * dx + dy * dy).sqrt(), (az >= g.near) & (bz >= g.near))
}

/// One row of the lattice as [`ErrorBatch::measure_row`] reads it.
struct Row<'a> {
    /// The source's heights of the row (every `stride`-th is audited) and the drawn heights of
    /// its audited samples.
    heights: &'a [f32],
    drawn: &'a [f32],
    stride: usize,
    /// Per audited column: its x, as `Heightfield::position` has it.
    x: &'a [f64],
    /// The drawn heights of the previous frame, with popping measured.
    previous: Option<&'a [f32]>,
    /// The row's y minus the eye's, and its products with the camera's axes.
    dy: f64,
    right_y: f64,
    up_y: f64,
    forward_y: f64,
}

impl ErrorBatch {
    /// Measures the samples of `row` in `columns` that the camera sees, in order: the samples
    /// of the run measured at once (with no branch) into the batch's free places, then those
    /// out of view dropped (packing the rest, when there are any). With `popping`, the change
    /// since the previous frame too (`row.previous` must then be there).
    #[inline(always)]
    fn measure_row(
        &mut self,
        run: &mut RunColumns,
        row: &Row,
        columns: std::ops::Range<usize>,
        geometry: &ErrorGeometry,
        camera: &Camera,
        sinks: &mut Sinks,
    ) {
        match (row.previous, sinks.popping.is_some()) {
            (Some(_), true) => {
                self.measure_row_as::<true>(run, row, columns, geometry, camera, sinks)
            }
            (None, false) => {
                self.measure_row_as::<false>(run, row, columns, geometry, camera, sinks)
            }
            _ => unreachable!("popping is measured exactly when there is a previous frame"),
        }
    }

    #[inline(always)]
    fn measure_row_as<const POPPING: bool>(
        &mut self,
        run: &mut RunColumns,
        row: &Row,
        columns: std::ops::Range<usize>,
        geometry: &ErrorGeometry,
        camera: &Camera,
        sinks: &mut Sinks,
    ) {
        let g = geometry;
        let (eye, right, up, forward) = (camera.eye, camera.right, camera.up, camera.forward);
        let (tan_x, tan_y) = camera.tan_half_fov();
        let far = camera.settings.far;
        let mut start = columns.start;
        while start < columns.end {
            let free = self.waiting..BATCH;
            let m = (columns.end - start).min(free.len());
            let x = &row.x[start..][..m];
            let heights = row.heights[start * row.stride..].iter().step_by(row.stride);
            for (truth, &height) in run.truth[..m].iter_mut().zip(heights) {
                *truth = f64::from(height);
            }
            for (drawn, &height) in run.drawn[..m].iter_mut().zip(&row.drawn[start..][..m]) {
                *drawn = f64::from(height);
            }
            if let (true, Some(previous)) = (POPPING, row.previous) {
                for (before, &height) in run.before[..m].iter_mut().zip(&previous[start..][..m]) {
                    *before = f64::from(height);
                }
            }
            let [base_x, base_y, base_z, .., length] = self
                .segments
                .each_mut()
                .map(|column| &mut column[free.start..][..m]);
            let [out_projected, sine, cosine, special] = self
                .results
                .each_mut()
                .map(|column| &mut column[free.start..][..m]);
            let in_front = &mut self.in_front[free.start..][..m];
            let [change, pop_x, pop_y, pop_z, pop_projected] = self
                .popping
                .each_mut()
                .map(|column| &mut column[free.start..][..m]);
            let pop_counts = &mut self.popping_counts[free.start..][..m];
            let pop_in_front = &mut self.popping_in_front[free.start..][..m];
            let mut seen = 0;
            for k in 0..m {
                // `Camera::to_camera` of the sample, its sums in the same order, and
                // `Camera::sees_camera`.
                let (z, mesh_z) = (run.truth[k], run.drawn[k]);
                let (dx, dz) = (x[k] - eye.x, z - eye.z);
                let (right_xy, up_xy, forward_xy) = (
                    dx * right.x + row.right_y,
                    dx * up.x + row.up_y,
                    dx * forward.x + row.forward_y,
                );
                let (cx, cy, cz) = (
                    right_xy + dz * right.z,
                    up_xy + dz * up.z,
                    forward_xy + dz * forward.z,
                );
                run.seen[k] = (cz >= g.near)
                    & (cz <= far)
                    & (cx.abs() <= cz * tan_x)
                    & (cy.abs() <= cz * tan_y);
                seen += usize::from(run.seen[k]);
                // The segment from the lower of the sample and the surface, `length` long;
                // its base in camera coordinates differs from the sample's in the z terms
                // only.
                let in_camera_at = |z: f64| {
                    let dz = z - eye.z;
                    DVec3::new(
                        right_xy + dz * right.z,
                        up_xy + dz * up.z,
                        forward_xy + dz * forward.z,
                    )
                };
                let a = in_camera_at(z.min(mesh_z));
                let delta = (z - mesh_z).abs();
                let to_base = DVec3::new(dx, row.dy, z.min(mesh_z) - eye.z);
                let f = segment_figures(g, a, to_base, delta);
                (base_x[k], base_y[k], base_z[k], length[k]) = (a.x, a.y, a.z, delta);
                (out_projected[k], sine[k], cosine[k], special[k]) =
                    (f.projected, f.sine, f.cosine, f.special);
                in_front[k] = f.in_front;
            }
            if POPPING {
                // `PoppingSums::add`: the change since the previous frame, its segment from the
                // lower of the two heights (a loop of its own, so that it too runs as vector
                // instructions).
                for k in 0..m {
                    let (before, now) = (run.before[k], run.drawn[k]);
                    let dx = x[k] - eye.x;
                    let dz = before.min(now) - eye.z;
                    let p = DVec3::new(
                        (dx * right.x + row.right_y) + dz * right.z,
                        (dx * up.x + row.up_y) + dz * up.z,
                        (dx * forward.x + row.forward_y) + dz * forward.z,
                    );
                    let moved = (now - before).abs();
                    (change[k], pop_x[k], pop_y[k], pop_z[k]) = (moved, p.x, p.y, p.z);
                    (pop_projected[k], pop_in_front[k]) = projected_segment(g, p, moved);
                    pop_counts[k] = !before.is_nan() & !now.is_nan();
                }
            }
            if seen < m {
                // Those in view packed, in order (`kept <= k`: no value is overwritten before
                // it is read).
                let mut kept = 0;
                for k in 0..m {
                    if run.seen[k] {
                        (base_x[kept], base_y[kept], base_z[kept]) =
                            (base_x[k], base_y[k], base_z[k]);
                        (length[kept], out_projected[kept]) = (length[k], out_projected[k]);
                        (sine[kept], cosine[kept], special[kept]) =
                            (sine[k], cosine[k], special[k]);
                        in_front[kept] = in_front[k];
                        if POPPING {
                            (change[kept], pop_projected[kept]) = (change[k], pop_projected[k]);
                            (pop_x[kept], pop_y[kept], pop_z[kept]) =
                                (pop_x[k], pop_y[k], pop_z[k]);
                            (pop_counts[kept], pop_in_front[kept]) =
                                (pop_counts[k], pop_in_front[k]);
                        }
                        kept += 1;
                    }
                }
            }
            self.waiting += seen;
            if self.waiting == BATCH {
                self.finish(g, camera, sinks);
            }
            start += m;
        }
    }

    /// Measures the first `n` segments (general path) and adds their figures to `sinks`.
    fn measure(&mut self, n: usize, geometry: &ErrorGeometry, camera: &Camera, sinks: &mut Sinks) {
        debug_assert_eq!(
            self.waiting, 0,
            "the general path measures its own segments"
        );
        let n = n.min(BATCH);
        let [
            base_x,
            base_y,
            base_z,
            to_base_x,
            to_base_y,
            to_base_z,
            length,
        ] = self.segments.each_ref().map(|column| &column[..n]);
        let [out_projected, out_sine, out_cosine, out_special] =
            self.results.each_mut().map(|column| &mut column[..n]);
        let in_front = &mut self.in_front[..n];
        // No branch: the compiler makes vector instructions of it.
        for k in 0..n {
            let a = DVec3::new(base_x[k], base_y[k], base_z[k]);
            let to_base = DVec3::new(to_base_x[k], to_base_y[k], to_base_z[k]);
            let f = segment_figures(geometry, a, to_base, length[k]);
            (out_projected[k], out_sine[k], out_cosine[k], out_special[k]) =
                (f.projected, f.sine, f.cosine, f.special);
            in_front[k] = f.in_front;
        }
        if sinks.popping.is_some() {
            let [change, pop_x, pop_y, pop_z, pop_projected] =
                self.popping.each_mut().map(|column| &mut column[..n]);
            for k in 0..n {
                let p = DVec3::new(pop_x[k], pop_y[k], pop_z[k]);
                (pop_projected[k], self.popping_in_front[k]) =
                    projected_segment(geometry, p, change[k]);
            }
        }
        self.waiting = n;
        self.finish(geometry, camera, sinks);
    }

    /// Adds the figures of the segments waiting to `sinks`, in order, and empties the batch.
    #[inline(always)]
    fn finish(&mut self, g: &ErrorGeometry, camera: &Camera, sinks: &mut Sinks) {
        let n = std::mem::take(&mut self.waiting);
        let [out_projected, out_sine, out_cosine, out_special] =
            self.results.each_mut().map(|column| &mut column[..n]);
        // The view angles: the calls of `atan2` alone in their loop (nothing else lives across
        // them), then those of the special segments put in, with no branch.
        for (sine, &cosine) in out_sine.iter_mut().zip(&*out_cosine) {
            *sine = sine.atan2(cosine);
        }
        for (angle, &special) in out_sine.iter_mut().zip(&*out_special) {
            let measured = *angle / g.pixel_angle;
            *angle = if special >= 0.0 { special } else { measured };
        }
        // The projected errors: as measured when both ends are in front of the near plane;
        // otherwise (rare) packed, a segment cut by the near plane measured again, one behind
        // it left out.
        let kept = if self.in_front[..n].iter().all(|&in_front| in_front) {
            n
        } else {
            let mut kept = 0;
            for k in 0..n {
                let projected_px = if self.in_front[k] {
                    Some(out_projected[k])
                } else {
                    let a = DVec3::new(
                        self.segments[0][k],
                        self.segments[1][k],
                        self.segments[2][k],
                    );
                    projected_error_px_at(camera, a, self.segments[6][k])
                };
                // `kept <= k`: the packed value never overwrites one still to be read.
                out_projected[kept] = projected_px.unwrap_or(0.0);
                kept += usize::from(projected_px.is_some());
            }
            kept
        };
        Figures::extend_both(
            (sinks.projected, &out_projected[..kept]),
            (sinks.view_angle, &out_sine[..n]),
        );
        // Popping's sums, in order (a segment the near plane cuts measured again).
        if let Some(popping) = sinks.popping.as_deref_mut() {
            let [change, pop_x, pop_y, pop_z, pop_projected] = &*self.popping;
            for k in (0..n).filter(|&k| self.popping_counts[k]) {
                let px = if self.popping_in_front[k] {
                    Some(pop_projected[k])
                } else {
                    let p = DVec3::new(pop_x[k], pop_y[k], pop_z[k]);
                    projected_error_px_at(camera, p, change[k])
                };
                popping.add_measured(change[k], px);
            }
        }
    }
}

/// Where a batch's figures go: the values of the two error figures and, with popping
/// measured, popping's sums.
struct Sinks<'a> {
    projected: &'a mut Figures,
    view_angle: &'a mut Figures,
    popping: Option<&'a mut PoppingSums>,
}

/// Buckets of the histogram of a figure's values: by their top 16 bits in total order.
const BUCKETS: usize = 1 << 16;

/// Values a figure takes in at once: its maximum and its histogram are kept per lane, so
/// that neither waits on the value before (runs of values in one bucket are the rule).
const LANES: usize = 4;

/// A key that orders `f64`s as [`f64::total_cmp`] does, as an unsigned integer.
fn total_order_key(value: f64) -> u64 {
    let bits = value.to_bits();
    bits ^ ((((bits as i64) >> 63) as u64) >> 1) ^ (1 << 63)
}

/// One error measure's values over a frame's samples in view, in the order they were found,
/// with their running sum, maximum and a histogram of their top bits: the summary then reads
/// only the values of the p95's bucket again.
struct Figures {
    values: Vec<f64>,
    sum: f64,
    max: f64,
    /// Values per bucket (`total_order_key >> 48`) and lane: bucket `b`'s count is the sum
    /// of `histogram[b * LANES..][..LANES]`.
    histogram: Box<[u32]>,
    /// The lowest and highest bucket holding a value (empty: `BUCKETS`, 0): the summary
    /// scans and the next frame clears only these.
    buckets: (usize, usize),
}

impl Default for Figures {
    fn default() -> Figures {
        Figures {
            values: Vec::new(),
            sum: -0.0,
            max: f64::NEG_INFINITY,
            histogram: vec![0; BUCKETS * LANES].into_boxed_slice(),
            buckets: (BUCKETS, 0),
        }
    }
}

impl Figures {
    fn clear(&mut self) {
        let (low, high) = self.buckets;
        if low <= high {
            self.histogram[low * LANES..(high + 1) * LANES].fill(0);
        }
        self.buckets = (BUCKETS, 0);
        self.values.clear();
        // The sum and the maximum start where `Iterator::sum` and the reference's fold do.
        self.sum = -0.0;
        self.max = f64::NEG_INFINITY;
    }

    /// Adds `first` to one figure and `second` to another, each in order: one loop, so that
    /// the two sums (chains of additions, each waiting on the one before) run side by side.
    #[inline(always)]
    fn extend_both(first: (&mut Figures, &[f64]), second: (&mut Figures, &[f64])) {
        let ((a, first), (b, second)) = (first, second);
        a.values.extend_from_slice(first);
        b.values.extend_from_slice(second);
        let (mut a_sums, mut b_sums) = (Sums::new(a), Sums::new(b));
        let (first_chunks, second_chunks) = (first.chunks_exact(LANES), second.chunks_exact(LANES));
        let common = first_chunks.len().min(second_chunks.len());
        for (x, y) in first_chunks.zip(second_chunks) {
            for lane in 0..LANES {
                a_sums.add(lane, x[lane]);
                b_sums.add(lane, y[lane]);
            }
        }
        for (sums, values) in [(&mut a_sums, first), (&mut b_sums, second)] {
            for chunk in values[common * LANES..].chunks(LANES) {
                for (lane, &value) in chunk.iter().enumerate() {
                    sums.add(lane, value);
                }
            }
        }
        let (a_figures, b_figures) = (a_sums.finish(), b_sums.finish());
        (a.sum, a.max, a.buckets) = a_figures;
        (b.sum, b.max, b.buckets) = b_figures;
    }

    fn len(&self) -> usize {
        self.values.len()
    }

    /// Max, mean and nearest-rank p95 (the rule of [`crate::sim::stats::nearest_rank`]): the
    /// p95 is found in the histogram's bucket that holds its rank, by selection among that
    /// bucket's values only. `f64::total_cmp` orders bit patterns, so the value found is the
    /// one a selection over all values finds, to the bit.
    fn summary(&self, scratch: &mut Vec<f64>) -> Option<ErrorSummary> {
        let n = self.len();
        if n == 0 {
            return None;
        }
        let rank = ((0.95 * n as f64).ceil() as usize).clamp(1, n);
        let mut below = 0;
        let (low, high) = self.buckets;
        let mut bucket = low as u64;
        let counts = self.histogram[low * LANES..(high + 1) * LANES].chunks_exact(LANES);
        for (k, count) in counts.map(|lanes| lanes.iter().sum::<u32>()).enumerate() {
            if below + count as usize >= rank {
                bucket = (low + k) as u64;
                break;
            }
            below += count as usize;
        }
        scratch.clear();
        // Eight values at a time (a vector comparison), most of them holding none of the
        // bucket's.
        let in_bucket = |value: f64| total_order_key(value) >> 48 == bucket;
        let chunks = self.values.chunks_exact(8);
        let rest = chunks.remainder();
        for chunk in chunks {
            if chunk
                .iter()
                .fold(false, |any, &value| any | in_bucket(value))
            {
                scratch.extend(chunk.iter().copied().filter(|&value| in_bucket(value)));
            }
        }
        scratch.extend(rest.iter().copied().filter(|&value| in_bucket(value)));
        let (_, p95, _) = scratch.select_nth_unstable_by(rank - 1 - below, f64::total_cmp);
        Some(ErrorSummary {
            max: self.max,
            mean: self.sum / n as f64,
            p95: *p95,
        })
    }
}

/// A figure's running sum, maximum, histogram and bucket range while values are added: the
/// maximum and the bucket range per lane, so that neither waits on the value before (runs of
/// values in one bucket are the rule); the sum in order (its rounding must be that of a sum
/// in order). The lanes' maxima equal the maximum in order because no value is −0.0 (each is
/// a square root, an `atan2` of a non-negative sine, or 0 or π over the pixel angle) and
/// `f64::max` skips NaN either way.
struct Sums<'a> {
    sum: f64,
    max: [f64; LANES],
    low: [usize; LANES],
    high: [usize; LANES],
    histogram: &'a mut [u32],
}

impl Sums<'_> {
    fn new(figures: &mut Figures) -> Sums<'_> {
        Sums {
            sum: figures.sum,
            max: [figures.max; LANES],
            low: [figures.buckets.0; LANES],
            high: [figures.buckets.1; LANES],
            histogram: &mut figures.histogram,
        }
    }

    #[inline(always)]
    fn add(&mut self, lane: usize, value: f64) {
        self.sum += value;
        self.max[lane] = self.max[lane].max(value);
        let bucket = (total_order_key(value) >> 48) as usize;
        self.histogram[bucket * LANES + lane] += 1;
        self.low[lane] = self.low[lane].min(bucket);
        self.high[lane] = self.high[lane].max(bucket);
    }

    /// The figure's sum, maximum and bucket range.
    fn finish(self) -> (f64, f64, (usize, usize)) {
        let max = self.max.into_iter().fold(f64::NEG_INFINITY, f64::max);
        let low = self.low.into_iter().min().unwrap_or(BUCKETS);
        let high = self.high.into_iter().max().unwrap_or(0);
        (self.sum, max, (low, high))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::hierarchy::Lattice;
    use crate::sim::mesh::{
        CrackPolicy, SubgridPoint, TriangleInfo, TriangleList, TriangleRole, VertexSet,
    };
    use crate::sim::metrics::view_angle_error_px;
    use crate::sim::terrain::{Heightfield, Spacing};
    use crate::sim::view::{Pose, ViewSettings};

    #[test]
    fn the_histogram_summary_equals_the_selection_over_all_values_bit_for_bit() {
        // Values spread over many buckets, crowded into one, repeated, zero, and counts where
        // the p95's rank falls on a bucket's first or last value.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut sets: Vec<Vec<f64>> = vec![vec![0.0], vec![3.5; 7], vec![0.0, 1.0]];
        for n in [1, 2, 19, 20, 21, 100, 1000, 4001] {
            sets.push((0..n).map(|_| (next() % 1_000_000) as f64 * 1e-4).collect());
            sets.push(
                (0..n)
                    .map(|_| 1.0 + (next() % 1000) as f64 * 1e-12)
                    .collect(),
            );
            sets.push((0..n).map(|_| (next() % 4) as f64).collect());
            sets.push(
                (0..n)
                    .map(|_| f64::from_bits(next() >> 2) % 1e6)
                    .map(f64::abs)
                    .collect(),
            );
        }
        let (mut figures, mut other) = (Figures::default(), Figures::default());
        let mut scratch = Vec::new();
        for values in sets {
            // Added in pieces of every length (lanes and the tail of a piece), beside another
            // figure taking every third value.
            figures.clear();
            other.clear();
            let thirds: Vec<f64> = values.iter().copied().step_by(3).collect();
            let (mut at, mut piece) = (0, 1);
            while at < values.len() {
                let end = (at + piece).min(values.len());
                let other_piece = &thirds[(at / 3).min(thirds.len())..(end / 3).min(thirds.len())];
                Figures::extend_both((&mut figures, &values[at..end]), (&mut other, other_piece));
                (at, piece) = (end, piece % 9 + 1);
            }
            let rest = &thirds[(values.len() / 3).min(thirds.len())..];
            Figures::extend_both((&mut figures, &[]), (&mut other, rest));
            for (figures, values) in [(&figures, &values), (&other, &thirds)] {
                let ours = figures.summary(&mut scratch);
                let theirs = reference::summarise_in_place(&mut values.clone());
                assert_eq!(
                    format!("{ours:?}"),
                    format!("{theirs:?}"),
                    "{} values",
                    values.len()
                );
            }
        }
        figures.clear();
        assert_eq!(figures.summary(&mut scratch), None);
    }

    fn settings(stride: u32, popping: bool) -> AuditSettings {
        AuditSettings {
            stride,
            popping,
            detail_stride: None,
        }
    }

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
        let mut auditor = Auditor::new(&hierarchy, settings(1, true));
        let mut full = VertexSet::new(lattice);
        for id in 0..lattice.n_vertices() as u32 {
            full.insert(id);
        }
        let exact = auditor.audit(&hierarchy, MeshOutput::lattice(&full), &camera);
        assert_eq!(exact.samples_in_view, 81);
        assert_eq!(exact.view_angle.unwrap().max, 0.0);
        assert_eq!(exact.projected.unwrap().max, 0.0);
        assert_eq!((exact.coverage, exact.popping), (None, None));

        let base_mesh = VertexSet::base_mesh(lattice);
        let base = auditor.audit(&hierarchy, MeshOutput::lattice(&base_mesh), &camera);
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
        // From the full mesh to the base mesh only the spike's sample moved: 8 m of 81 samples.
        let popping = base.popping.unwrap();
        assert_eq!((popping.samples, popping.max_m), (81, 8.0));
        assert!((popping.rmse_m - 8.0 / 9.0).abs() < 1e-12);
        let spike_px = projected_error_px(&camera, DVec3::new(40.0, 40.0, 0.0), 8.0).unwrap();
        assert!((popping.max_px - spike_px).abs() < 1e-9);
    }

    /// Over the spike field's 8×8 cells: the west half as two triangles, the east half as two
    /// squares meeting at the spike (4, 4), so the west half's edge x = 4 has a T-junction
    /// there; `drop_one` leaves out a triangle of the south-east square.
    fn t_junction_list(drop_one: bool) -> TriangleList {
        let mut list = TriangleList::new(&Lattice::new(3), CrackPolicy::Skirted);
        let mut v = |i: u32, j: u32| {
            let z = if (i, j) == (4, 4) { 8.0 } else { 0.0 };
            list.add_vertex(SubgridPoint::grid(i, j), z)
        };
        let corners = [
            [v(0, 0), v(4, 0), v(4, 8)],
            [v(0, 0), v(4, 8), v(0, 8)],
            [v(4, 0), v(8, 0), v(8, 4)],
            [v(4, 0), v(8, 4), v(4, 4)],
            [v(4, 4), v(8, 4), v(8, 8)],
            [v(4, 4), v(8, 8), v(4, 8)],
        ];
        for (k, corners) in corners.into_iter().enumerate() {
            if !(drop_one && k == 3) {
                let info = TriangleInfo {
                    role: TriangleRole::Surface,
                    group: 0,
                    level: 0,
                };
                list.add_triangle(corners, info);
            }
        }
        list
    }

    #[test]
    fn a_t_junction_is_a_crack_and_a_missing_triangle_leaves_holes() {
        let hierarchy = spike_field();
        let camera = camera_above(&hierarchy);
        let mut auditor = Auditor::new(&hierarchy, settings(1, true));
        let whole = t_junction_list(false);
        let frame = auditor.audit(&hierarchy, MeshOutput::triangles(&whole), &camera);
        let coverage = frame.coverage.unwrap();
        // Along x = 4 the west half draws 0 m; the east half rises to the spike: 2, 4, 6, 8,
        // 6, 4, 2 m at j = 1..=7.
        assert_eq!(coverage.holes, 0);
        assert_eq!((coverage.crack_samples, coverage.crack_gap_max_m), (7, 8.0));
        assert!(coverage.crack_gap_max_px > 0.0);
        assert_eq!(frame.samples_in_view, 81);

        // The spike's sample belongs to the east half (the tie rule nudges it east), which draws
        // it at 8 m: flattening the surface moves it by 8 m, more than any other sample.
        let mut flat = TriangleList::new(&Lattice::new(3), CrackPolicy::Closed);
        let corners = [(0, 0), (8, 0), (8, 8), (0, 8)]
            .map(|(i, j)| flat.add_vertex(SubgridPoint::grid(i, j), 0.0));
        let surface = TriangleInfo {
            role: TriangleRole::Surface,
            group: 0,
            level: 0,
        };
        flat.add_triangle([corners[0], corners[1], corners[2]], surface);
        flat.add_triangle([corners[0], corners[2], corners[3]], surface);
        let frame = auditor.audit(&hierarchy, MeshOutput::triangles(&flat), &camera);
        let popping = frame.popping.unwrap();
        assert_eq!((popping.samples, popping.max_m), (81, 8.0));

        let torn = t_junction_list(true);
        let frame = auditor.audit(&hierarchy, MeshOutput::triangles(&torn), &camera);
        let coverage = frame.coverage.unwrap();
        // The missing triangle's three inner samples and the three on its west edge (which
        // the tie rule gives to the east side); its diagonal belongs to its neighbour.
        assert_eq!(coverage.holes, 6);
        assert_eq!(frame.samples_in_view, 75);
        assert_eq!(coverage.crack_samples, 4);
        assert_eq!(
            frame.popping.unwrap().samples,
            75,
            "holes are left out of popping"
        );
    }

    #[test]
    fn skirts_cover_the_part_of_a_crack_they_span_and_the_rest_is_left_open() {
        let hierarchy = spike_field();
        let camera = camera_above(&hierarchy);
        let mut auditor = Auditor::new(&hierarchy, settings(1, false));
        // The T-junction of `t_junction_list`: along x = 4 the east half rises to 8 m over the
        // west half's 0 m. A skirt hung from the east half's edges reaching `depth` below.
        let skirted = |depth: f32| {
            let mut list = t_junction_list(false);
            let skirt = TriangleInfo {
                role: TriangleRole::Skirt,
                group: 1,
                level: 0,
            };
            for (from, to) in [((4, 0, 0.0), (4, 4, 8.0)), ((4, 4, 8.0), (4, 8, 0.0))] {
                let mut v =
                    |(i, j, z): (u32, u32, f32)| list.add_vertex(SubgridPoint::grid(i, j), z);
                let (top_a, top_b) = (v(from), v(to));
                let (bottom_a, bottom_b) = (
                    v((from.0, from.1, from.2 - depth)),
                    v((to.0, to.1, to.2 - depth)),
                );
                list.add_triangle([top_a, top_b, bottom_b], skirt);
                list.add_triangle([top_a, bottom_b, bottom_a], skirt);
            }
            list
        };
        let coverage = |list: &TriangleList, auditor: &mut Auditor| {
            auditor
                .audit(&hierarchy, MeshOutput::triangles(list), &camera)
                .coverage
                .unwrap()
        };
        let bare = coverage(&t_junction_list(false), &mut auditor);
        assert_eq!((bare.crack_samples, bare.cracks_uncovered), (7, 7));
        assert_eq!(bare.crack_uncovered_max_m, 8.0);
        // Deep enough: every crack covered.
        let deep = coverage(&skirted(8.0), &mut auditor);
        assert_eq!((deep.crack_samples, deep.cracks_uncovered), (7, 0));
        assert_eq!(deep.crack_uncovered_max_m, 0.0);
        // 3 m deep: the gaps of 2, 4, 6, 8, 6, 4, 2 m keep 0, 1, 3, 5, 3, 1, 0 m open.
        let shallow = coverage(&skirted(3.0), &mut auditor);
        assert_eq!((shallow.crack_samples, shallow.cracks_uncovered), (7, 5));
        assert_eq!(shallow.crack_uncovered_max_m, 5.0);
        assert!(shallow.crack_uncovered_max_px > 0.0);
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
        let mut auditor = Auditor::new(&hierarchy, settings(2, false));
        let base_mesh = VertexSet::base_mesh(hierarchy.lattice());
        let frame = auditor.audit(&hierarchy, MeshOutput::lattice(&base_mesh), &camera);
        assert_eq!(frame.samples_in_view, 0);
        assert_eq!(frame.view_angle, None);
    }

    #[test]
    fn the_batched_view_angle_equals_the_metric_in_its_special_cases_bit_for_bit() {
        let camera = camera_above(&spike_field());
        let g = ErrorGeometry::new(&camera);
        let pixel_angle = camera.settings.pixel_angle();
        // (eye to base, length): no length, the eye at the base or at the top (with zeros of
        // either sign), on the segment's line but off it, and ordinary segments.
        let cases = [
            (DVec3::new(0.0, 0.0, 0.0), 0.0),
            (DVec3::new(3.0, 4.0, -2.0), 0.0),
            (DVec3::new(0.0, 0.0, 0.0), 5.0),
            (DVec3::new(-0.0, 0.0, -0.0), 5.0),
            (DVec3::new(0.0, 0.0, -5.0), 5.0),
            (DVec3::new(-0.0, -0.0, -5.0), 5.0),
            (DVec3::new(0.0, 0.0, -7.0), 5.0),
            (DVec3::new(0.0, 0.0, 2.0), 5.0),
            (DVec3::new(1e-300, 0.0, -5.0), 5.0),
            (DVec3::new(3.0, 4.0, -2.0), 1.5),
            (DVec3::new(-30.0, 400.0, -200.0), 0.25),
        ];
        for (to_base, delta) in cases {
            let f = segment_figures(&g, DVec3::new(1.0, 1.0, 10.0), to_base, delta);
            let ours = if f.special >= 0.0 {
                f.special
            } else {
                f.sine.atan2(f.cosine) / pixel_angle
            };
            // The metric with the eye at the origin: its eye-to-base vector is `to_base`.
            let theirs = view_angle_error_px(DVec3::ZERO, to_base, delta, pixel_angle);
            assert_eq!(ours.to_bits(), theirs.to_bits(), "{to_base:?}, {delta}");
        }
    }

    #[test]
    #[should_panic(expected = "was promised the next frame's camera")]
    fn popping_refuses_a_camera_other_than_the_one_promised() {
        let hierarchy = spike_field();
        let camera = camera_above(&hierarchy);
        let elsewhere = Camera::new(
            &Pose {
                position: camera.eye + DVec3::new(5.0, 0.0, 0.0),
                yaw: 0.0,
                pitch: -std::f64::consts::FRAC_PI_2,
            },
            camera.settings,
        );
        let mut auditor = Auditor::new(&hierarchy, settings(1, true));
        let base_mesh = VertexSet::base_mesh(hierarchy.lattice());
        let mesh = MeshOutput::lattice(&base_mesh);
        auditor.audit_followed_by(&hierarchy, mesh, &camera, &camera);
        // Kept as promised: the same camera again.
        auditor.audit_followed_by(&hierarchy, mesh, &camera, &camera);
        auditor.audit(&hierarchy, mesh, &elsewhere);
    }
}
