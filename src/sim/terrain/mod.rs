//! Height fields: the raw sample grid a reader produced, and the (2^n+1)² height field
//! every algorithm runs on.
//!
//! The path from a file to a [`Heightfield`] is: a reader (in `edge::terrain_readers`) builds a
//! [`SampleGrid`] with its voids marked, [`fill::fill_voids`] replaces the voids, and
//! [`embed::embed`] pads or crops the grid into a (2^n+1)² square. Each step reports what it did
//! so the run metadata can say it. Nothing here reads files.

pub mod embed;
pub mod fill;
mod heightfield;
mod sample_grid;
pub mod synthetic;

pub use heightfield::{Heightfield, HeightfieldError, Spacing};
pub use sample_grid::{SampleGrid, SampleGridError};
