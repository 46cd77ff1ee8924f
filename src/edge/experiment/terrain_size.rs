//! Refusing a terrain the run cannot hold, before any of it is read or generated (issue #33):
//! the side the terrain will have (from the experiment's declared layout, or a header or file
//! length read cheaply) against the in-memory hierarchy's limit, [`MAX_SIDE`], and the memory
//! the run would need against what the machine has (`/proc/meminfo`). Each refusal names the
//! limit, the memory the run would need and the alternatives. Not the readers (the mosaic work
//! owns `edge::terrain_readers`): a header it cannot read here is left to the reader, whose
//! error is then the one the user sees.
//!
//! **The memory estimate.** A run's peak is the larger of loading and flying. Loading a file
//! holds its bytes and its `f32` grid, then the grid and the embedded heights (4 B a sample of
//! each); generating a synthetic terrain holds 6 B a sample (`sim::terrain::synthetic`). Flying
//! holds the heights (4 B a sample), Wu's node table (1 B a sample, when an entry reads it) and
//! the largest entry's own state, from the bytes per sample measured on the 16385² point of
//! `experiments/study-scaling.json` (Lindstrom's and ROAM's preprocessing peaks at 8193²:
//! docs/performance.md, "Memory per sample"); entries running side by side add theirs, so the
//! estimate is what a run needs with `--threads 1`.

use super::entries::AlgorithmSpec;
use super::format::{FitEntry, TerrainEntry, TerrainFileEntry};
use super::load::terrain_format;
use super::problems::ExperimentError;
use crate::edge::terrain_readers::{MosaicLayout, TerrainFormat};
use crate::sim::algorithm::AlgorithmConfig;
use crate::sim::terrain::MAX_SIDE;
use crate::sim::terrain::embed::{Fit, fitted_side};
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};

/// Checks that the terrain of an experiment (in `folder`) fits the run, reading at most a
/// file's header; `entries` are the point's algorithm entries.
pub(super) fn check_terrain_size(
    experiment: &Path,
    folder: &Path,
    terrain: &TerrainEntry,
    mosaic: Option<&MosaicLayout>,
    entries: &[AlgorithmSpec],
) -> Result<(), ExperimentError> {
    let run = RunToSize {
        experiment,
        folder,
        terrain,
        mosaic,
        entries,
    };
    run.check(machine_memory())
}

/// What [`check_terrain_size`] sizes.
struct RunToSize<'a> {
    experiment: &'a Path,
    folder: &'a Path,
    terrain: &'a TerrainEntry,
    /// A mosaic terrain's layout, laid out from its files' headers by the plan.
    mosaic: Option<&'a MosaicLayout>,
    entries: &'a [AlgorithmSpec],
}

impl RunToSize<'_> {
    /// The check against the machine's `memory` (`None`: not known, only the limit is checked).
    fn check(&self, memory: Option<MachineMemory>) -> Result<(), ExperimentError> {
        let RunToSize {
            experiment,
            folder,
            terrain,
            mosaic,
            entries,
        } = *self;
        let (need, field, what) = match terrain {
            // A pyramid is read on demand: its checks are `terrain_pyramid.rs`'s.
            TerrainEntry::Pyramid(_) => return Ok(()),
            TerrainEntry::Synthetic(s) => {
                let side = (1usize << s.level) + 1;
                let samples = (side * side) as f64;
                let need = (GENERATING_BYTES_PER_SAMPLE * samples).max(flying_bytes(side, entries));
                (
                    need,
                    "terrain.synthetic",
                    format!("the {side}² synthetic terrain"),
                )
            }
            TerrainEntry::File(_) | TerrainEntry::Mosaic(_) => {
                // A file's size from its header; a mosaic's from its layout (its tiles are read
                // one at a time, so only the assembled grid counts).
                let (path, source, fit, field) = match terrain {
                    TerrainEntry::File(file) => {
                        let path = folder.join(&file.path);
                        let Some(source) = source_size(experiment, &path, file) else {
                            return Ok(());
                        };
                        (path, source, file.fit, "terrain.file")
                    }
                    TerrainEntry::Mosaic(entry) => {
                        let Some(layout) = mosaic else {
                            return Ok(());
                        };
                        let (columns, rows) = layout.size();
                        let source = SourceSize {
                            columns,
                            rows,
                            file_bytes: 0,
                        };
                        let name = format!("the mosaic of {} files", layout.n_files());
                        (PathBuf::from(name), source, entry.fit, "terrain.mosaic")
                    }
                    TerrainEntry::Synthetic(_) | TerrainEntry::Pyramid(_) => {
                        unreachable!("matched above")
                    }
                };
                let fit = match fit {
                    FitEntry::Pad => Fit::Pad,
                    FitEntry::Crop => Fit::Crop { origin: None },
                };
                let side = fitted_side(source.columns, source.rows, fit);
                let grid_bytes = 4.0 * (source.columns * source.rows) as f64;
                let loading = (source.file_bytes as f64 + grid_bytes)
                    .max(grid_bytes + 4.0 * (side * side) as f64);
                let need = loading.max(flying_bytes(side, entries));
                let what = format!(
                    "{}: {}×{} samples, {side}² once {}",
                    path.display(),
                    source.columns,
                    source.rows,
                    match fit {
                        Fit::Pad => "padded",
                        Fit::Crop { .. } => "cropped",
                    }
                );
                if side > MAX_SIDE {
                    return Err(ExperimentError::single(
                        experiment,
                        field,
                        format!(
                            "{what}, above the largest terrain an in-memory hierarchy holds, \
                         {MAX_SIDE}² (2^15 + 1 a side: its vertex ids are 32-bit); the run would \
                         need about {}. {ALTERNATIVES}",
                            gigabytes(need)
                        ),
                    ));
                }
                (need, field, what)
            }
        };
        if let Some(memory) = memory
            && need > memory.available as f64
        {
            return Err(ExperimentError::single(
                experiment,
                field,
                format!(
                    "{what}: the run would need about {} of memory, and this machine has {} available \
                 ({} in all). {ALTERNATIVES}",
                    gigabytes(need),
                    gigabytes(memory.available as f64),
                    gigabytes(memory.total as f64)
                ),
            ));
        }
        Ok(())
    }
}

/// What a user can do instead.
const ALTERNATIVES: &str = "Alternatives: crop the terrain (\"fit\": \"crop\" keeps at most a \
     32769² window; or cut it smaller with another tool), or fly it with chunked LOD from a \
     source read from disk on demand (planned: issue #33; not available yet)";

/// Bytes per sample a synthetic terrain holds while it is generated.
const GENERATING_BYTES_PER_SAMPLE: f64 = 6.0;

/// The least a run holds while flying a terrain of `side`²: heights, Wu's node table when an
/// entry reads it, and the largest entry's own state.
pub(super) fn flying_bytes(side: usize, entries: &[AlgorithmSpec]) -> f64 {
    let node_table = if entries.iter().any(|e| e.config.reads_node_table()) {
        1.0
    } else {
        0.0
    };
    let own = entries
        .iter()
        .map(|e| own_bytes_per_sample(&e.config))
        .fold(0.0, f64::max);
    (4.0 + node_table + own) * (side * side) as f64
}

/// An entry's own state, bytes per sample, as measured at 16385² (`study-scaling`, the
/// entries' *bytes per sample* less the shared 5; the stitching strips' at 1025², from
/// `study-circle`, as the study does not run them larger); for Lindstrom's and ROAM's, the
/// larger peak of their preprocessing, measured at 8193² (docs/performance.md).
fn own_bytes_per_sample(config: &AlgorithmConfig) -> f64 {
    match config {
        AlgorithmConfig::Lindstrom(_) => 17.0,
        AlgorithmConfig::Roam(_) | AlgorithmConfig::RoamRebuild(_) => 11.4,
        AlgorithmConfig::Stitching(_) => 3.2,
        AlgorithmConfig::Wu(_) => 1.5,
        AlgorithmConfig::Rottger(_) => 1.3,
        AlgorithmConfig::Geomipmap(_) => 0.5,
        AlgorithmConfig::Reference(_) => 0.3,
        AlgorithmConfig::Chunked(_) | AlgorithmConfig::Vanek(_) => 0.15,
    }
}

/// A terrain file's grid size and its bytes on disk.
struct SourceSize {
    columns: usize,
    rows: usize,
    file_bytes: u64,
}

/// The file's grid size from the experiment's declared layout (raw), its length (`.hgt`) or its
/// header (PNG, GeoTIFF, ASCII grid); `None` where that cannot be read cheaply (the reader
/// then says why).
fn source_size(experiment: &Path, path: &Path, file: &TerrainFileEntry) -> Option<SourceSize> {
    let file_bytes = std::fs::metadata(path).ok()?.len();
    let format = terrain_format(experiment, path, file).ok()?;
    let (columns, rows) = match format {
        TerrainFormat::Raw(layout) => (layout.columns, layout.rows),
        TerrainFormat::Hgt => {
            let side = ((file_bytes / 2) as f64).sqrt() as usize;
            (side, side)
        }
        TerrainFormat::Png => {
            let reader = png::Decoder::new(BufReader::new(std::fs::File::open(path).ok()?))
                .read_info()
                .ok()?;
            let info = reader.info();
            (info.width as usize, info.height as usize)
        }
        TerrainFormat::GeoTiff => {
            let mut decoder =
                tiff::decoder::Decoder::new(BufReader::new(std::fs::File::open(path).ok()?))
                    .ok()?;
            let (width, height) = decoder.dimensions().ok()?;
            (width as usize, height as usize)
        }
        TerrainFormat::AsciiGrid => ascii_grid_size(path)?,
        // GDAL's rasters are sized by their reader.
        #[cfg(feature = "gdal")]
        TerrainFormat::Gdal => return None,
    };
    (columns >= 3 && rows >= 3).then_some(SourceSize {
        columns,
        rows,
        file_bytes,
    })
}

/// `ncols` and `nrows` from the first 4 KiB of an ESRI ASCII grid.
fn ascii_grid_size(path: &Path) -> Option<(usize, usize)> {
    let mut head = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take(4096)
        .read_to_end(&mut head)
        .ok()?;
    let head = String::from_utf8_lossy(&head);
    let value = |key: &str| {
        head.lines().find_map(|line| {
            let mut words = line.split_whitespace();
            let found = words.next()?.eq_ignore_ascii_case(key);
            found.then(|| words.next()?.parse::<usize>().ok())?
        })
    };
    Some((value("ncols")?, value("nrows")?))
}

/// The machine's memory, bytes.
struct MachineMemory {
    available: u64,
    total: u64,
}

/// `MemAvailable` and `MemTotal` of `/proc/meminfo`; `None` where the system does not say.
fn machine_memory() -> Option<MachineMemory> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib = |key: &str| -> Option<u64> {
        let line = meminfo.lines().find(|line| line.starts_with(key))?;
        line[key.len()..]
            .trim()
            .trim_end_matches("kB")
            .trim()
            .parse()
            .ok()
    };
    Some(MachineMemory {
        available: kib("MemAvailable:")? * 1024,
        total: kib("MemTotal:")? * 1024,
    })
}

/// Bytes as gigabytes, for the user.
fn gigabytes(bytes: f64) -> String {
    format!("{:.1} GB", bytes / 1e9)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_ascii_grid_says_its_size_in_its_header() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("grid.asc");
        std::fs::write(
            &path,
            "NCOLS 40000\nnrows 30000\nxllcorner 0\nyllcorner 0\ncellsize 30\n1 2 3\n",
        )
        .unwrap();
        assert_eq!(ascii_grid_size(&path), Some((40_000, 30_000)));
    }

    #[test]
    fn a_synthetic_terrain_needing_more_than_the_machine_has_is_refused_naming_both() {
        let terrain: TerrainEntry = serde_json::from_str(
            r#"{"synthetic": {"level": 14, "seed": 1, "amplitude_m": 300, "roughness": 0.5,
                "spacing_m": {"dx": 30, "dy": 30}}}"#,
        )
        .unwrap();
        let run = RunToSize {
            experiment: Path::new("big.json"),
            folder: Path::new("."),
            terrain: &terrain,
            mosaic: None,
            entries: &[],
        };
        let small = MachineMemory {
            available: 1_000_000_000,
            total: 2_000_000_000,
        };
        let error = run.check(Some(small)).unwrap_err().to_string();
        // Generating 16385² holds 6 bytes a sample: 1.6 GB.
        for part in [
            "terrain.synthetic",
            "16385²",
            "about 1.6 GB",
            "1.0 GB available",
            "2.0 GB in all",
            "crop",
        ] {
            assert!(error.contains(part), "{error} lacks {part}");
        }
        let large = MachineMemory {
            available: 2_000_000_000,
            total: 2_000_000_000,
        };
        assert!(run.check(Some(large)).is_ok());
        assert!(run.check(None).is_ok());
    }

    #[test]
    fn a_run_of_entries_that_read_no_node_table_needs_none() {
        assert_eq!(flying_bytes(3, &[]), 4.0 * 9.0);
    }
}
