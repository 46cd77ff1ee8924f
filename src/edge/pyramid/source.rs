//! What `roamsim prepare` reads: a raw file, streamed row by row ([`super::prepare_from_raw`]),
//! or any other terrain the experiment format reads, read whole into memory through the
//! experiment's own stages and written from memory ([`super::prepare_from_field`]).
//!
//! **Any terrain, read as a run reads it.** A terrain file (`.hgt`, GeoTIFF, PNG, ASCII grid, a
//! raw file of any layout, a GDAL raster under the `gdal` feature) is read by
//! `experiment::load_terrain_file` with the `terrain.file` keys given as options (`--fit`,
//! `--spacing-m`, `--nodata`, …, as `roamsim info` takes them): voids filled, fitted to
//! (2^n + 1)² samples by `fit` (`pad`, the default, or `crop`), spacing from the file's geography
//! or `--spacing-m`. An experiment file gives its terrain (a mosaic of files or a folder among
//! others), read by the experiment's plan and loader, whose up-front size check applies. A file
//! that declares no spacing needs `--spacing-m` (a pyramid never holds an assumed spacing).
//!
//! **Memory, stated before reading.** Reading whole holds the file's bytes and its `f32` grid,
//! then the grid and the fitted terrain (4 B a sample each), as the experiment's own estimate
//! (`experiment/terrain_size.rs`) counts it. For a terrain file whose size a header or its
//! length gives (`.hgt`, GeoTIFF, PNG, ASCII grid), the need is printed before reading and a
//! need above the machine's available memory is refused, naming the need and the alternative: a
//! raw file, which streams in bounded memory whatever its size. Not here: streaming a tiled
//! GeoTIFF by tiles.

use crate::edge::experiment::{self, TerrainReport};
use crate::edge::info_command::TerrainFileKeys;
use crate::sim::terrain::Heightfield;
use crate::sim::terrain::embed::{Fit, fitted_side};
use serde_json::Value;
use std::io::{BufReader, Read};
use std::path::Path;

/// A terrain read whole, with what the experiment's loader reports of it.
pub struct TerrainInMemory {
    pub field: Heightfield,
    pub report: TerrainReport,
}

/// Reads the terrain file `path` with the `terrain.file` keys `keys`, after stating and
/// checking the memory it needs (`notice` gets the statement). Errors name the file.
pub fn read_terrain_file(
    path: &Path,
    keys: &TerrainFileKeys,
    notice: &mut dyn FnMut(&str),
) -> Result<TerrainInMemory, String> {
    let fit = match keys.fit {
        Some("crop") => Fit::Crop { origin: None },
        _ => Fit::Pad,
    };
    if let Some(need) = memory_needed(path, fit) {
        let available = available_memory();
        let what = format!(
            "{}: {}×{} samples, {}² once {}",
            path.display(),
            need.columns,
            need.rows,
            need.side,
            match fit {
                Fit::Pad => "padded",
                Fit::Crop { .. } => "cropped",
            }
        );
        if let Some(available) = available
            && need.bytes > available
        {
            return Err(format!(
                "{what}: reading it whole to prepare it needs about {} of memory, and this \
                 machine has {} available. {ALTERNATIVE}",
                gigabytes(need.bytes),
                gigabytes(available)
            ));
        }
        notice(&format!(
            "prepare: reading {what}, whole: about {} of memory{}",
            gigabytes(need.bytes),
            available.map_or(String::new(), |a| format!(" ({} available)", gigabytes(a)))
        ));
    }
    let file = keys.object(path)?;
    let (field, report) = experiment::load_terrain_file(path, &Value::Object(file))
        .map_err(|error| error.to_string())?;
    if report.spacing_from.contains("assumed") {
        return Err(format!(
            "{}: the file declares no usable grid spacing ({}); give --spacing-m DX[,DY] \
             (a pyramid keeps the spacing it is given)",
            path.display(),
            report.spacing_from
        ));
    }
    Ok(TerrainInMemory { field, report })
}

/// Reads the terrain of the experiment `path` (one point: a sweep over terrains is refused), as
/// a run reads it, after the plan's checks (the size check among them).
pub fn read_experiment_terrain(path: &Path) -> Result<TerrainInMemory, String> {
    let plan = experiment::plan(path).map_err(|error| error.to_string())?;
    if plan.n_points() != 1 {
        return Err(format!(
            "{}: a sweep of {} points; prepare takes one terrain (give the terrain file itself)",
            path.display(),
            plan.n_points()
        ));
    }
    let experiment = plan.load_point(0).map_err(|error| error.to_string())?;
    let report = experiment.terrain.clone();
    let field = std::sync::Arc::try_unwrap(experiment.field)
        .unwrap_or_else(|shared| Heightfield::clone(&shared));
    Ok(TerrainInMemory { field, report })
}

/// What to do instead of reading a terrain whole.
const ALTERNATIVE: &str = "Convert it to a raw file of (2^n + 1)² samples (e.g. `gdal_translate \
     -of ENVI -ot Int16`), which `roamsim prepare FILE --raw-side N --raw-sample …` streams in \
     bounded memory whatever its size, or crop it (--fit crop --crop-origin …)";

/// The memory reading a file whole needs.
struct MemoryNeed {
    columns: usize,
    rows: usize,
    side: usize,
    bytes: u64,
}

/// The memory reading `path` whole needs, from its size (a header, or its length); `None`
/// where that is not known before reading (the reader then reads it).
fn memory_needed(path: &Path, fit: Fit) -> Option<MemoryNeed> {
    let file_bytes = std::fs::metadata(path).ok()?.len();
    let (columns, rows) = grid_size(path, file_bytes)?;
    let side = fitted_side(columns, rows, fit);
    let grid = 4 * (columns as u64) * (rows as u64);
    let fitted = 4 * (side as u64) * (side as u64);
    Some(MemoryNeed {
        columns,
        rows,
        side,
        bytes: (file_bytes + grid).max(grid + fitted),
    })
}

/// A terrain file's columns and rows from its length (`.hgt`) or its header (PNG, GeoTIFF,
/// ASCII grid), by its extension; `None` for others.
fn grid_size(path: &Path, file_bytes: u64) -> Option<(usize, usize)> {
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    let open = || std::fs::File::open(path).ok().map(BufReader::new);
    let (columns, rows) = match extension.as_str() {
        "hgt" => {
            let side = ((file_bytes / 2) as f64).sqrt() as usize;
            (side, side)
        }
        "png" => {
            let reader = png::Decoder::new(open()?).read_info().ok()?;
            (reader.info().width as usize, reader.info().height as usize)
        }
        "tif" | "tiff" => {
            let (width, height) = tiff::decoder::Decoder::new(open()?)
                .ok()?
                .dimensions()
                .ok()?;
            (width as usize, height as usize)
        }
        "asc" => {
            let mut head = Vec::new();
            open()?.take(4096).read_to_end(&mut head).ok()?;
            let head = String::from_utf8_lossy(&head);
            let value = |key: &str| {
                head.lines().find_map(|line| {
                    let mut words = line.split_whitespace();
                    let found = words.next()?.eq_ignore_ascii_case(key);
                    found.then(|| words.next()?.parse::<usize>().ok())?
                })
            };
            (value("ncols")?, value("nrows")?)
        }
        _ => return None,
    };
    (columns >= 3 && rows >= 3).then_some((columns, rows))
}

/// `MemAvailable` of `/proc/meminfo`, bytes; `None` where the system does not say.
fn available_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = meminfo
        .lines()
        .find(|line| line.starts_with("MemAvailable:"))?;
    let kib: u64 = line["MemAvailable:".len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib * 1024)
}

/// Bytes as gigabytes (megabytes below 1 GB), for the user.
fn gigabytes(bytes: u64) -> String {
    if bytes < 1_000_000_000 {
        format!("{:.0} MB", bytes as f64 / 1e6)
    } else {
        format!("{:.1} GB", bytes as f64 / 1e9)
    }
}
