//! Rasterising drawn triangles over a lattice of samples: which samples a triangle covers, and
//! the height it draws there. Shared by the audit (SPEC §7: mesh heights at audited samples) and
//! the triangle-list validator (every sample covered exactly once). It measures no error and
//! decides no sample set: which samples are audited is the audit's (`sim::audit::tiles`).
//!
//! Two rasterisers, both with exact integer inside tests:
//!
//! - [`rasterise_lattice_triangle`], the 4-8 fast path: corners on grid samples, a sample on an
//!   edge counts as inside (a closed 4-8 mesh has no T-junction, so both triangles of a shared
//!   edge give it the same height up to rounding, and the last one drawn writes it). This is
//!   the audit's arithmetic since the first release, kept bit for bit.
//! - [`SampleRaster`], the general path: corners anywhere (fixed-point [`super::SubgridPoint`]s), with a
//!   **tie rule** that gives every sample of a tiling to exactly one triangle: a sample on an edge
//!   or a vertex belongs to the triangle it would fall in if nudged by an infinitesimal step east
//!   (west on the domain's east border) and an infinitely smaller step north (south on the
//!   north border). This is the top-left rule of GPU rasterisers, written as the perturbation it
//!   is: every point of a tiling then has exactly one triangle, with shared vertices or not, so
//!   T-junctions, collapsed borders and stitches need no special case; positions are fixed-point
//!   integers (1/65 536 of a cell), so the inside tests are exact. Heights are
//!   interpolated inside the triangle; on an edge, from the edge's two ends only, in a canonical
//!   order of the ends, so two triangles with the same edge give a sample on it bit-identical
//!   heights and a crack gap is exactly zero where there is no crack; on a vertex, the vertex's
//!   own height.
//!
//! Samples are the points (i·step, j·step) in fixed-point units, i and j below the lattice's
//! side: the audit's every `stride`-th grid sample has step = stride cells; a finer lattice
//! (a truth surface with more detail than the source samples) would have a step below one cell.

//!
//! Files: `lattice.rs` the 4-8 fast path and its bounding-box reference, `sample.rs` the
//! general path; each with its tests.

mod lattice;
mod sample;

pub(crate) use lattice::floor_div;
pub use lattice::{rasterise_lattice_triangle, rasterise_lattice_triangle_by_box};
pub use sample::{CoveredSample, SampleRaster};
