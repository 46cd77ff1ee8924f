//! `roamsim prepare`'s command: the source read ([`PrepareSource`]: a raw file streamed, or any
//! terrain read whole, `source.rs`), the pyramid written with its progress on stderr and its
//! summary line on stdout. Not the format or the build (`prepare.rs`); not argument parsing
//! (`main.rs`).

use super::source::{TerrainInMemory, read_experiment_terrain, read_terrain_file};
use super::{PrepareSummary, RawSource, prepare_from_field, prepare_from_raw};
use crate::edge::info_command::TerrainFileKeys;
use crate::edge::terrain_readers::{RawLayout, RawSample};
use crate::sim::terrain::Spacing;
use std::path::{Path, PathBuf};

/// What `roamsim prepare` reads.
#[derive(Clone, Debug)]
pub enum PrepareSource {
    /// A raw file of (2^n + 1)² samples, streamed in bounded memory.
    Raw(RawSource),
    /// A terrain file read whole as `terrain.file` with these keys (`.hgt`, GeoTIFF, PNG, ASCII
    /// grid, a raw file of another layout, a GDAL raster).
    File {
        path: PathBuf,
        keys: TerrainFileKeys,
    },
    /// The terrain of an experiment file (a mosaic or a folder of tiles among others).
    Experiment(PathBuf),
}

impl PrepareSource {
    /// The source the command line names: `raw` (side and sample) makes `terrain` a raw file
    /// streamed (its spacing from `keys.spacing_m`, no other key applies); otherwise an
    /// experiment (`.json`, no key applies) or a terrain file read with `keys`.
    pub fn from_arguments(
        terrain: PathBuf,
        raw: Option<(usize, RawSample)>,
        raw_south_first: bool,
        keys: TerrainFileKeys,
    ) -> Result<PrepareSource, String> {
        let is_experiment = terrain
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let others: Vec<&str> = keys
            .given()
            .into_iter()
            .filter(|name| *name != "--spacing-m")
            .collect();
        if let Some((side, sample)) = raw {
            if !others.is_empty() {
                return Err(format!(
                    "{}: {} do not apply to a raw file streamed with --raw-side: its heights are \
                     taken as stored (to scale, fill or fit it, read it whole: name it in an \
                     experiment's terrain.file with `format.raw` and prepare the experiment)",
                    terrain.display(),
                    others.join(", ")
                ));
            }
            let spacing = match keys.spacing_m[..] {
                [d] => Spacing { dx: d, dy: d },
                [dx, dy] => Spacing { dx, dy },
                _ => {
                    return Err(format!(
                        "{}: a raw file declares no spacing: give --spacing-m DX[,DY]",
                        terrain.display()
                    ));
                }
            };
            return Ok(PrepareSource::Raw(RawSource {
                path: terrain,
                layout: RawLayout {
                    columns: side,
                    rows: side,
                    sample,
                    north_first: !raw_south_first,
                },
                spacing,
            }));
        }
        if is_experiment {
            let given = keys.given();
            if !given.is_empty() {
                return Err(format!(
                    "{}: {} describe a terrain file; an experiment declares its terrain's in \
                     its terrain object",
                    terrain.display(),
                    given.join(", ")
                ));
            }
            return Ok(PrepareSource::Experiment(terrain));
        }
        Ok(PrepareSource::File {
            path: terrain,
            keys,
        })
    }
}

/// `roamsim prepare`: writes the pyramid, progress on stderr every 5 % of the rows.
pub fn prepare_command(source: PrepareSource, chunk_level: u32, out: &Path) -> Result<(), String> {
    let start = std::time::Instant::now();
    let mut last_percent = 0;
    let mut progress = |done: u64, rows: u64| {
        let percent = done * 100 / rows;
        if percent >= last_percent + 5 || done == rows {
            last_percent = percent;
            eprintln!(
                "prepare: {done}/{rows} rows ({percent}%), {:.0} s elapsed",
                start.elapsed().as_secs_f64()
            );
        }
    };
    let (summary, read) = match &source {
        PrepareSource::Raw(raw) => (prepare_from_raw(raw, chunk_level, out, &mut progress), None),
        PrepareSource::File { path, keys } => {
            let terrain = read_terrain_file(path, keys, &mut |notice| eprintln!("{notice}"))?;
            (
                prepare_from_field(&terrain.field, path, chunk_level, out, &mut progress),
                Some(terrain),
            )
        }
        PrepareSource::Experiment(path) => {
            let terrain = read_experiment_terrain(path)?;
            (
                prepare_from_field(&terrain.field, path, chunk_level, out, &mut progress),
                Some(terrain),
            )
        }
    };
    let summary = summary.map_err(|error| error.to_string())?;
    println!("{}", summary_line(out, &summary, read.as_ref()));
    Ok(())
}

/// The line printed when the pyramid is written.
fn summary_line(out: &Path, summary: &PrepareSummary, read: Option<&TerrainInMemory>) -> String {
    let header = summary.header;
    let source = match read {
        None => String::new(),
        Some(terrain) => {
            let report = &terrain.report;
            format!(
                "; from {} ({}, {}×{} samples, {}² as read, {} voids filled, spacing {} × {} m \
                 from {})",
                report.source,
                report.format,
                report.source_columns,
                report.source_rows,
                report.side,
                report.voids_filled,
                report.spacing.dx,
                report.spacing.dy,
                report.spacing_from
            )
        }
    };
    format!(
        "{}: {} × {} samples, chunks of {}² ({} levels, {} chunks), {:?} heights, {} bytes; \
         row bands held at most {} bytes{source}",
        out.display(),
        header.side(),
        header.side(),
        header.cells() + 1,
        header.leaf_level() + 1,
        header.n_chunks(),
        header.sample,
        summary.file_bytes,
        summary.band_bytes
    )
}
