//! Placeholder: the ascii_grid reader is being written.
use super::{ReadOptions, TerrainReadError};
use crate::sim::terrain::{SampleGrid, Spacing};
use std::path::Path;

pub(super) fn read(
    path: &Path,
    _bytes: &[u8],
    _options: &ReadOptions,
) -> Result<(SampleGrid, Option<Spacing>), TerrainReadError> {
    Err(TerrainReadError::new(path, "not implemented yet"))
}
