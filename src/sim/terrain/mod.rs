//! Height fields: the raw sample grid a reader produced, and the (2^n+1)² height field
//! every algorithm runs on (SPEC §2's conventions: z up, metres, sample (i, j) at (i·dx, j·dy),
//! row 0 the south edge; voids filled, any grid of at least 3×3 embedded), and seeded synthetic
//! terrains for the sizes real tiles cannot give (SPEC §11).
//!
//! The path from a file to a [`Heightfield`] is: a reader (in `edge::terrain_readers`) builds a
//! [`SampleGrid`] with its voids marked, [`fill::fill_voids`] replaces the voids, and
//! [`embed::embed`] pads or crops the grid into a (2^n+1)² square. Each step reports what it did
//! so the run metadata can say it. Nothing here reads files.

pub mod embed;
pub mod fill;
mod heightfield;
pub mod paged;
mod sample_grid;
pub mod synthetic;

pub use heightfield::{
    Heightfield, HeightfieldError, MAX_LEVEL, MAX_PAGED_LEVEL, MAX_SIDE, Spacing,
};
pub use sample_grid::{SampleGrid, SampleGridError};
