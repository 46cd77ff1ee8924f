//! The audit of a 4-8 mesh against the source's samples (SPEC §7): the drawn heights from the
//! exact integer rasteriser ([`rasterise_lattice_triangle`]), and the measurement of every
//! audited sample in view, row by row, in runs of samples measured whole (`batch.rs`). Triangle
//! lists and the audit against synthesised detail go through `general.rs` instead.
//!
//! Decisions:
//!
//! - **The rasteriser of every earlier release.** Heights come from rasterising the mesh's
//!   triangles over the audited sample lattice with exact integer inside tests. A sample on an
//!   edge counts as inside, and the last triangle drawn writes it: both sides give it the same
//!   height up to rounding, since a closed 4-8 mesh has no T-junction. So the figures are those
//!   of every earlier release, bit for bit. Morphed heights are simply the corners' heights
//!   (each corner at its drawn height). Every sample of the tiles kept is written: a closed
//!   mesh covers the whole domain.
//! - **Compiled twice, chosen at run time.** The measurement is compiled for baseline x86-64
//!   and again for AVX2 (256-bit vectors), and the AVX2 one runs where the CPU has it: the
//!   crate's one `unsafe` call (`unsafe_code` is denied, allowed there), whose only requirement
//!   is the feature check before it. Rust never fuses a product and a sum, so both give the
//!   same bits; [`super::Auditor::without_wide_vectors`] keeps the baseline one, and the
//!   differential test (`tests/audit_reference.rs`) compares both. Rejected: building the
//!   crate for x86-64-v3 (it would no longer run on CPUs without AVX2).

use super::Auditor;
use super::batch::{ErrorBatch, Row, RunColumns, Sinks};
use super::geometry::ErrorGeometry;
use super::popping::PoppingSums;
use super::tiles::{TILE, columns_in_view};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::mesh::raster::rasterise_lattice_triangle;
use crate::sim::mesh::{DrawnTriangle, MeshOutput, SurfacePoint};
use crate::sim::terrain::Heightfield;
use crate::sim::view::Camera;

impl Auditor {
    /// 4-8 meshes: the exact integer rasteriser, every sample of the tiles kept written (a
    /// closed mesh covers the whole domain).
    pub(super) fn rasterise_lattice(&mut self, hierarchy: &Hierarchy, mesh: MeshOutput) {
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

    /// Measures the drawn heights of a 4-8 mesh against the source's samples in view, adding
    /// the figures to this frame's, and popping's to `popping` when it is measured.
    pub(super) fn measure_lattice(
        &mut self,
        field: &Heightfield,
        camera: &Camera,
        geometry: &ErrorGeometry,
        popping: Option<&mut PoppingSums>,
    ) {
        let mut sinks = Sinks {
            projected: &mut self.projected,
            view_angle: &mut self.view_angle,
            popping,
        };
        let lattice = LatticeRows {
            tile_in_view: &self.tile_in_view,
            tiles_x: self.tiles_x,
            lattice_columns: self.lattice_columns,
            lattice_rows: self.lattice_rows,
            lattice_side: self.lattice_side,
            drawn: &self.mesh_height,
            previous: self.previous_height.as_deref(),
            field,
            stride: self.stride,
            spacing_y: field.spacing().dy,
            column_x: &self.column_x,
        };
        let measure = MeasureLattice {
            batch: &mut self.batch,
            run: &mut self.run,
            lattice: &lattice,
            geometry,
            camera,
            sinks: &mut sinks,
        };
        measure.run(self.wide_vectors);
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
    /// The source's heights, read a row at a time (borrowed, or read for a paged field).
    field: &'a Heightfield,
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
            if !tile_row.contains(&true) {
                continue; // No sample in view: its heights are not read (a paged field's).
            }
            let dy = j as f64 * lattice.spacing_y - eye.y;
            let heights = lattice.field.row(j);
            let row = Row {
                heights: &heights,
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
