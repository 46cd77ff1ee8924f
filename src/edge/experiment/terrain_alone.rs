//! A terrain file read exactly as an experiment's `"terrain": {"file": …}` reads it, without an
//! experiment: what `roamsim info TERRAIN` does with its options. The options are the `file`
//! keys themselves (`height_scale`, `height_offset_m`, `nodata`, `spacing_m`, `fit`,
//! `crop_origin`, `origin_m`, a raw `format`), parsed by the format's own type (`format.rs`),
//! checked by the experiment's own check (`check.rs`) and loaded by its own loader (`load.rs`),
//! so `info` cannot describe a terrain differently from a run. Not a second reader.
//!
//! One difference, said where it is printed: a file that declares no grid spacing, read without
//! `spacing_m`, is described with 1 m assumed (an experiment must give `spacing_m`; `info`
//! is how a user finds that out).

use super::check::check_terrain;
use super::format::TerrainEntry;
use super::load::{TerrainReport, load_terrain_assuming};
use super::problems::{ExperimentError, Problems, decode};
use crate::sim::terrain::{Heightfield, Spacing};
use serde_json::Value;
use std::path::Path;

/// The spacing assumed for a file that declares none and is read without `spacing_m`.
pub const ASSUMED_SPACING_M: f64 = 1.0;

/// Reads the terrain file `file` (a `terrain.file` object: `{"path": …, "fit": …, …}`, its
/// path relative to the current folder) as an experiment would. Errors name `path` and the
/// key (`terrain.file.height_scale`).
pub fn load_terrain_file(
    path: &Path,
    file: &Value,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
    let mut problems = Problems::default();
    let terrain = serde_json::json!({ "file": file });
    let entry: Option<TerrainEntry> = decode("terrain", &terrain, &mut problems);
    if let Some(entry) = &entry {
        check_terrain(entry, &mut problems);
    }
    match entry {
        Some(entry) if problems.list.is_empty() => {
            let assumed = Spacing {
                dx: ASSUMED_SPACING_M,
                dy: ASSUMED_SPACING_M,
            };
            load_terrain_assuming(path, Path::new(""), &entry, None, Some(assumed))
        }
        _ => Err(ExperimentError {
            file: path.to_path_buf(),
            problems: problems.list,
        }),
    }
}
