//! A terrain given as a chunk pyramid (`"terrain": {"pyramid": {"file": …}}`): checked before
//! any long work (its header and records read, every entry able to fly it) and opened as a
//! height field read on demand (`sim::terrain::paged`, `edge::pyramid::PyramidSamples`), so the
//! run never holds the whole terrain.
//!
//! **Who can fly it.** Only chunked LOD with its `loading` effect on (the out-of-core
//! algorithm: its tree comes from the pyramid's records, its chunks' heights from a loader
//! thread) and without `detail` (the pyramid's errors are those of leaves of error 0, not of
//! the detail's estimated ε), with the pyramid's chunk level. Every other entry is refused,
//! named, with the memory its in-memory hierarchy would need and the alternatives.
//!
//! **Up to 65 537².** A pyramid may be one level larger than any other terrain
//! (`terrain::MAX_PAGED_LEVEL`, 16, against `MAX_LEVEL`, 15): the entries it admits never number
//! a vertex with the lattice's 32-bit ids. What would, above 32 769², is refused here by name:
//! every other entry (above), and an audit whose grid is larger than 32 769² (its per-sample
//! buffers are a whole grid; a `stride` of 2 or more audits a 65 537² terrain).

use super::entries::AlgorithmSpec;
use super::format::TerrainPyramidEntry;
use super::load::TerrainReport;
use super::problems::{ExperimentError, FieldProblem};
use super::terrain_size::flying_bytes;
use crate::edge::pyramid::{PyramidFile, PyramidHeader, PyramidSamples, StoredSample};
use crate::sim::algorithm::AlgorithmConfig;
use crate::sim::terrain::{Heightfield, MAX_LEVEL, MAX_PAGED_LEVEL, MAX_SIDE, Spacing};
use glam::DVec3;
use std::path::Path;
use std::sync::Arc;

const FIELD: &str = "terrain.pyramid.file";

/// Opens the pyramid `entry` names (header and records checked) and checks that every entry of
/// `entries`, and the audit of `audit_stride` if any, can fly it; every problem at once.
pub(super) fn check_pyramid_run(
    experiment: &Path,
    folder: &Path,
    entry: &TerrainPyramidEntry,
    entries: &[AlgorithmSpec],
    audit_stride: Option<u32>,
) -> Result<PyramidFile, ExperimentError> {
    let pyramid = open(experiment, folder, entry)?;
    let header = *pyramid.header();
    let mut problems: Vec<FieldProblem> = entries
        .iter()
        .enumerate()
        .filter_map(|(k, spec)| {
            entry_problem(&header, spec).map(|problem| FieldProblem {
                field: format!("algorithms[{k}]"),
                problem,
            })
        })
        .collect();
    if let Some(problem) = audit_stride.and_then(|stride| audit_problem(&header, stride)) {
        problems.push(FieldProblem {
            field: "effects.audit.stride".into(),
            problem,
        });
    }
    if problems.is_empty() {
        Ok(pyramid)
    } else {
        Err(ExperimentError {
            file: experiment.to_path_buf(),
            problems,
        })
    }
}

/// The pyramid `entry` names as a height field read on demand, and what the run reports of it.
pub(super) fn read_terrain_pyramid(
    experiment: &Path,
    folder: &Path,
    entry: &TerrainPyramidEntry,
) -> Result<(Heightfield, TerrainReport), ExperimentError> {
    let pyramid = open(experiment, folder, entry)?;
    let header = *pyramid.header();
    let spacing = Spacing {
        dx: header.dx,
        dy: header.dy,
    };
    let samples = Arc::new(PyramidSamples::new(pyramid));
    let (lo, hi) = crate::sim::terrain::paged::PagedSamples::height_range(samples.as_ref());
    let field = Heightfield::paged(header.terrain_level, samples, spacing)
        .map_err(|e| ExperimentError::single(experiment, FIELD, format!("{}: {e}", entry.file)))?
        .with_origin(
            entry
                .origin_m
                .map_or(DVec3::ZERO, |[x, y, z]| DVec3::new(x, y, z)),
        );
    let side = field.side();
    let report = TerrainReport {
        source: entry.file.clone(),
        format: format!(
            "pyramid ({} samples, chunks of {}²)",
            match header.sample {
                StoredSample::I16 => "i16",
                StoredSample::F32 => "f32",
            },
            header.cells() + 1
        ),
        source_columns: side,
        source_rows: side,
        side,
        padded_columns: 0,
        padded_rows: 0,
        crop_origin: None,
        voids_filled: 0,
        spacing,
        spacing_from: "file".into(),
        height_min_m: lo,
        height_max_m: hi,
    };
    Ok((field, report))
}

/// The pyramid, its header and records checked, within the run's largest terrain.
fn open(
    experiment: &Path,
    folder: &Path,
    entry: &TerrainPyramidEntry,
) -> Result<PyramidFile, ExperimentError> {
    let path = folder.join(&entry.file);
    let pyramid = PyramidFile::open(&path)
        .map_err(|error| ExperimentError::single(experiment, FIELD, error.to_string()))?;
    let level = pyramid.header().terrain_level;
    if level > MAX_PAGED_LEVEL {
        return Err(ExperimentError::single(
            experiment,
            FIELD,
            format!(
                "{}: a {}² terrain (level {level}); a pyramid run flies at most {}² (level \
                 {MAX_PAGED_LEVEL}). Prepare a crop of it",
                path.display(),
                pyramid.header().side(),
                (1u64 << MAX_PAGED_LEVEL) + 1
            ),
        ));
    }
    Ok(pyramid)
}

/// Why `spec` cannot fly the pyramid of `header`; `None` when it can.
fn entry_problem(header: &PyramidHeader, spec: &AlgorithmSpec) -> Option<String> {
    let label = &spec.label;
    let side = header.side() as usize;
    let AlgorithmConfig::Chunked(config) = &spec.config else {
        let need = flying_bytes(side, std::slice::from_ref(spec));
        let limit = if header.terrain_level > MAX_LEVEL {
            format!(
                ", and above {MAX_SIDE}² no in-memory hierarchy holds it at all (its vertex ids \
                 are 32-bit)"
            )
        } else {
            String::new()
        };
        return Some(format!(
            "entry `{label}` ({}) cannot fly a pyramid: its in-memory hierarchy needs the whole \
             terrain, about {:.1} GB for {side}² samples{limit}. Alternatives: crop the terrain \
             to a file (`terrain.file` with `fit: crop`) for `{label}`, or fly the pyramid with \
             `chunked` and its `loading` effect on",
            spec.config.name(),
            need / 1e9
        ));
    };
    if config.loading.is_none() {
        return Some(format!(
            "entry `{label}` (chunked) flies a pyramid only with its `loading` effect on (the \
             chunks' heights are read from the file as they are loaded): add `loading` \
             (latency_frames, bandwidth_chunks_per_frame, resident_chunks) to its parameters, \
             or crop the terrain to a file"
        ));
    }
    if config.detail.is_some() {
        return Some(format!(
            "entry `{label}` (chunked) cannot fly a pyramid with its `detail` effect: the \
             pyramid's chunk errors are for leaves of error 0, not the detail's estimated one; \
             remove `detail`, or fly a file terrain"
        ));
    }
    let chunk_level = config.chunk_level.clamp(1, header.terrain_level);
    if chunk_level != header.chunk_level {
        return Some(format!(
            "entry `{label}` has chunk_level {chunk_level} (chunks of {}²), the pyramid's chunks \
             are level {} ({}²): set chunk_level to {}, or prepare the terrain again with \
             `--chunk-level {chunk_level}`",
            (1u64 << chunk_level) + 1,
            header.chunk_level,
            header.cells() + 1,
            header.chunk_level
        ));
    }
    None
}

/// Why an audit every `stride`-th sample cannot measure the pyramid of `header`; `None` when it
/// can: its grid, (side − 1)/stride + 1 on a side, at most [`MAX_SIDE`] (what every other
/// terrain's audit has at most).
fn audit_problem(header: &PyramidHeader, stride: u32) -> Option<String> {
    let stride = u64::from(stride.max(1));
    let audited_side = (header.side() - 1) / stride + 1;
    (audited_side > MAX_SIDE as u64).then(|| {
        let least = (header.side() - 1).div_ceil(MAX_SIDE as u64 - 1);
        format!(
            "{stride}: the audit would measure a {audited_side}² grid of this {}² pyramid, above \
             the {MAX_SIDE}² an audit holds; set a stride of at least {least}, or remove the audit",
            header.side()
        )
    })
}
