//! `roamsim prepare`: writes a chunk pyramid from a raw file in bounded memory, bottom-up from
//! bands of rows, never holding the terrain.
//!
//! **How.** The source's rows are read one at a time, south to north. Level L of the tree
//! (leaves at D) sees the terrain every s_L = 2^(D − L)-th sample: each level keeps a band of
//! at most 2·2^c + 1 of its own rows. When a level's band reaches the top of a row of its chunks,
//! those chunks are complete: their heights are written, and their records computed — a leaf's
//! from its samples, an internal chunk's from its four children's records (the two chunk rows
//! just completed one level down) and its δ_m from the finer level's band (its children's union
//! grid), by the functions the in-memory tree uses, so the records are the same bits. Levels are
//! completed finest first, so a parent always finds its children done. Memory: about
//! 2·(2^(c+1) + 1)·side `f32` for the bands, whatever the number of rows; the file is written
//! at each chunk row's place (its layout is fixed by the header), each row of chunks in one
//! write.
//!
//! **All or nothing.** The pyramid is written to `.<name>.partial-<pid>` beside the destination
//! and renamed into place once complete and synced; on an error the partial file is removed. An
//! existing destination is replaced only when it is itself a pyramid (it begins with the magic).
//!
//! Not here: other source formats (a raw file is the one that streams; an `.hgt`, GeoTIFF or
//! mosaic terrain can be converted to raw first), nodata, voids, scaling or fitting (the source
//! must be (2^n + 1)² samples with no voids: its heights are taken as stored).

use super::{MAGIC, MAX_LEAF_LEVEL, MAX_TERRAIN_LEVEL, PyramidError, PyramidHeader, StoredSample};
use crate::edge::terrain_readers::{RawLayout, RawSample, decode_sample};
use crate::sim::algorithm::chunked::{ChunkId, ChunkRecord, chunk_own_error};
use crate::sim::terrain::{Heightfield, Spacing};
use std::fs::{self, File};
use std::io::{Read, Seek, SeekFrom, Write};
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

/// A raw source: the file, its layout (as an experiment's `format.raw` declares it) and its
/// spacing in metres.
#[derive(Clone, Debug)]
pub struct RawSource {
    pub path: PathBuf,
    pub layout: RawLayout,
    pub spacing: Spacing,
}

/// What `prepare` wrote.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrepareSummary {
    pub header: PyramidHeader,
    /// The pyramid's length in bytes.
    pub file_bytes: u64,
    /// The most bytes the row bands held at once (the builder's memory beside its fixed
    /// buffers).
    pub band_bytes: u64,
}

/// Writes the pyramid of `source` with chunks of (2^`chunk_level` + 1)² vertices (clamped to
/// the terrain, as `chunked` clamps it) to `out`; `progress(rows_done, rows)` is called after
/// every source row.
pub fn prepare_from_raw(
    source: &RawSource,
    chunk_level: u32,
    out: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<PrepareSummary, PyramidError> {
    let header = raw_header(source, chunk_level)?;
    let input = File::open(&source.path)
        .map_err(|e| PyramidError::new(&source.path, format!("cannot open the source: {e}")))?;
    let sample_bytes = source.layout.sample.bytes() as u64;
    let expected = header.side() * header.side() * sample_bytes;
    let length = input
        .metadata()
        .map_err(|e| PyramidError::new(&source.path, format!("cannot read its length: {e}")))?
        .len();
    if length != expected {
        return Err(PyramidError::new(
            &source.path,
            format!(
                "the file has {length} bytes; the declared layout ({0} × {0} samples of {1:?}) \
                 needs {expected}",
                header.side(),
                source.layout.sample
            ),
        ));
    }
    let sample = source.layout.sample;
    let row_bytes = header.side() as usize * sample.bytes();
    let mut raw_row = vec![0u8; row_bytes];
    let mut read_row = |j: u64, row: &mut [f32]| {
        let side = header.side();
        let file_row = if source.layout.north_first {
            side - 1 - j
        } else {
            j
        };
        input
            .read_exact_at(&mut raw_row, file_row * row_bytes as u64)
            .map_err(|e| {
                PyramidError::new(&source.path, format!("cannot read row {file_row}: {e}"))
            })?;
        for (z, bytes) in row.iter_mut().zip(raw_row.chunks_exact(sample.bytes())) {
            *z = decode_sample(sample, bytes) as f32;
        }
        Ok(())
    };
    write_all_or_nothing(header, out, &mut read_row, progress)
}

/// Writes the pyramid of the terrain `field` holds in memory (read from `source`, which errors
/// name) with chunks of (2^`chunk_level` + 1)² vertices (clamped to the terrain) to `out`:
/// the same pyramid [`prepare_from_raw`] writes from the same heights. Heights are stored as
/// `i16` when every one is an integer in −32 768..=32 767 (an SRTM tile's), else as `f32`.
pub fn prepare_from_field(
    field: &Heightfield,
    source: &Path,
    chunk_level: u32,
    out: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<PrepareSummary, PyramidError> {
    let side = field.side();
    let integer = |z: f32| {
        z == z.round() && (-32768.0..=32767.0).contains(&z) && z.to_bits() != (-0.0f32).to_bits()
    };
    let all_integer = (0..side).all(|j| (0..side).all(|i| integer(field.height(i, j))));
    let header = header_for(
        source,
        (side, side),
        field.spacing(),
        if all_integer {
            StoredSample::I16
        } else {
            StoredSample::F32
        },
        chunk_level,
    )?;
    let mut read_row = |j: u64, row: &mut [f32]| {
        for (i, z) in row.iter_mut().enumerate() {
            *z = field.height(i, j as usize);
        }
        Ok(())
    };
    write_all_or_nothing(header, out, &mut read_row, progress)
}

/// Terrain row `j` (south = 0) into the slice, `side` heights.
type ReadRow<'a> = dyn FnMut(u64, &mut [f32]) -> Result<(), PyramidError> + 'a;

/// Writes the pyramid of `header` from the rows `read_row` gives to a partial file beside
/// `out`, then renames it into place; on an error the partial file is removed.
fn write_all_or_nothing(
    header: PyramidHeader,
    out: &Path,
    read_row: &mut ReadRow,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<PrepareSummary, PyramidError> {
    check_destination(out)?;
    let partial = partial_path(out)?;
    let written = write_pyramid(read_row, header, &partial, progress);
    let band_bytes = match written {
        Ok(band_bytes) => band_bytes,
        Err(error) => {
            let _ = fs::remove_file(&partial);
            return Err(error);
        }
    };
    if let Err(error) = fs::rename(&partial, out) {
        let _ = fs::remove_file(&partial);
        return Err(PyramidError::new(
            out,
            format!("cannot move the finished pyramid into place: {error}"),
        ));
    }
    Ok(PrepareSummary {
        header,
        file_bytes: header.file_bytes(),
        band_bytes,
    })
}

/// The header of a raw source's pyramid, or why it cannot have one.
fn raw_header(source: &RawSource, chunk_level: u32) -> Result<PyramidHeader, PyramidError> {
    let RawLayout { columns, rows, .. } = source.layout;
    let sample = match source.layout.sample {
        RawSample::I16Le | RawSample::I16Be => StoredSample::I16,
        RawSample::U16Le | RawSample::U16Be | RawSample::F32Le | RawSample::F32Be => {
            StoredSample::F32
        }
    };
    header_for(
        &source.path,
        (columns, rows),
        source.spacing,
        sample,
        chunk_level,
    )
}

/// The header of the pyramid of a `columns` × `rows` terrain read from `source`, or why it
/// cannot have one.
fn header_for(
    source: &Path,
    (columns, rows): (usize, usize),
    spacing: Spacing,
    sample: StoredSample,
    chunk_level: u32,
) -> Result<PyramidHeader, PyramidError> {
    let level = (columns as u64)
        .checked_sub(1)
        .filter(|cells| cells.is_power_of_two())
        .map(u64::trailing_zeros);
    let terrain_level = match level {
        Some(level) if columns == rows && (1..=MAX_TERRAIN_LEVEL).contains(&level) => level,
        _ => {
            return Err(PyramidError::new(
                source,
                format!(
                    "the source is {columns} × {rows} samples; a pyramid needs a square of \
                     2^n + 1 samples a side, 3 to 65 537 (crop or pad it first)"
                ),
            ));
        }
    };
    let chunk_level = chunk_level.clamp(1, terrain_level);
    if terrain_level - chunk_level > MAX_LEAF_LEVEL {
        return Err(PyramidError::new(
            source,
            format!(
                "chunks of level {chunk_level} on a terrain of level {terrain_level} make {} \
                 levels of chunks below the root; at most {MAX_LEAF_LEVEL}: use a larger \
                 --chunk-level",
                terrain_level - chunk_level
            ),
        ));
    }
    let Spacing { dx, dy } = spacing;
    if !(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0) {
        return Err(PyramidError::new(
            source,
            format!("the spacing is {dx} × {dy} m; expected finite spacings above 0"),
        ));
    }
    Ok(PyramidHeader {
        sample,
        terrain_level,
        chunk_level,
        dx,
        dy,
    })
}

/// Refuses a destination that exists and is not a pyramid (roamsim replaces only its own).
fn check_destination(out: &Path) -> Result<(), PyramidError> {
    if !out.exists() {
        return Ok(());
    }
    let mut magic = [0u8; 8];
    let is_pyramid = File::open(out)
        .and_then(|mut file| file.read_exact(&mut magic))
        .is_ok()
        && magic == MAGIC;
    if is_pyramid && out.is_file() {
        Ok(())
    } else {
        Err(PyramidError::new(
            out,
            "something that is not a roamsim chunk pyramid is in the way; roamsim leaves it \
             alone: choose another --out, or move it",
        ))
    }
}

/// `.<name>.partial-<pid>` beside `out`.
fn partial_path(out: &Path) -> Result<PathBuf, PyramidError> {
    let name = out
        .file_name()
        .ok_or_else(|| PyramidError::new(out, "--out must name a file"))?;
    let partial = format!(".{}.partial-{}", name.to_string_lossy(), std::process::id());
    Ok(out.with_file_name(partial))
}

/// Writes the whole pyramid to `partial`; the most bytes the bands held.
fn write_pyramid(
    read_row: &mut ReadRow,
    header: PyramidHeader,
    partial: &Path,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<u64, PyramidError> {
    let write_error = |e: std::io::Error| PyramidError::new(partial, format!("cannot write: {e}"));
    let mut output = File::create(partial).map_err(write_error)?;
    output.set_len(header.file_bytes()).map_err(write_error)?;
    output.write_all(&header.encode()).map_err(write_error)?;
    let mut builder = Builder::new(header);
    let side = header.side();
    let mut row = vec![0f32; side as usize];
    for j in 0..side {
        read_row(j, &mut row)?;
        builder
            .push_row(j, &row, &mut output)
            .map_err(write_error)?;
        progress(j + 1, side);
    }
    output.sync_all().map_err(write_error)?;
    Ok(builder.band_bytes_max)
}

/// One level's band of rows and its last completed chunk rows' records.
struct LevelBand {
    /// Samples per row at this level's stride.
    width: usize,
    /// The band's rows, row after row.
    rows: Vec<f32>,
    /// The level's row number of the band's first row.
    first_row: u64,
    /// The records of the chunk rows completed since the level above last took them.
    pending: Vec<ChunkRecord>,
    /// The chunk row `pending` starts with.
    pending_first: u64,
}

/// The bottom-up builder (see the module docs).
struct Builder {
    header: PyramidHeader,
    levels: Vec<LevelBand>,
    /// Scratch: one chunk row's heights and records, encoded.
    heights_bytes: Vec<u8>,
    records_bytes: Vec<u8>,
    chunk_heights: Vec<f32>,
    band_bytes_max: u64,
}

impl Builder {
    fn new(header: PyramidHeader) -> Builder {
        let cells = header.cells() as usize;
        let levels = (0..=header.leaf_level())
            .map(|level| LevelBand {
                width: (cells << level) + 1,
                rows: Vec::new(),
                first_row: 0,
                pending: Vec::new(),
                pending_first: 0,
            })
            .collect();
        Builder {
            header,
            levels,
            heights_bytes: Vec::new(),
            records_bytes: Vec::new(),
            chunk_heights: Vec::new(),
            band_bytes_max: 0,
        }
    }

    /// The stride of level `level`'s samples.
    fn stride(&self, level: u32) -> u64 {
        1 << (self.header.leaf_level() - level)
    }

    /// Takes terrain row `j` (south = 0), completing and writing the chunk rows it closes.
    fn push_row(&mut self, j: u64, row: &[f32], output: &mut File) -> std::io::Result<()> {
        let cells = u64::from(self.header.cells());
        let leaf_level = self.header.leaf_level();
        for level in 0..=leaf_level {
            let stride = self.stride(level);
            if j.is_multiple_of(stride) {
                let band = &mut self.levels[level as usize];
                band.rows.extend(row.iter().step_by(stride as usize));
            }
        }
        let band_bytes: usize = self.levels.iter().map(|l| l.rows.len() * 4).sum();
        self.band_bytes_max = self.band_bytes_max.max(band_bytes as u64);
        for level in (0..=leaf_level).rev() {
            let stride = self.stride(level);
            let r = j / stride;
            if j.is_multiple_of(stride) && r > 0 && r.is_multiple_of(cells) {
                self.complete_chunk_row(level, r / cells - 1, output)?;
            }
        }
        // Keep what the level above still needs: from the start of its chunk row in progress.
        for level in 0..=leaf_level {
            let stride = self.stride(level);
            let r = j / stride;
            let period = if level == 0 { cells } else { 2 * cells };
            if j.is_multiple_of(stride) && r > 0 && r.is_multiple_of(period) {
                let band = &mut self.levels[level as usize];
                let keep_from = band.rows.len() - band.width;
                band.rows.drain(..keep_from);
                band.first_row = r;
                band.pending.clear();
                band.pending_first = r / cells;
            }
        }
        Ok(())
    }

    /// Writes chunk row `k` of `level` (its heights and records) and keeps its records.
    fn complete_chunk_row(&mut self, level: u32, k: u64, output: &mut File) -> std::io::Result<()> {
        let header = self.header;
        let cells = header.cells() as usize;
        let per_side = 1u32 << level;
        self.heights_bytes.clear();
        self.records_bytes.clear();
        let mut records = Vec::with_capacity(per_side as usize);
        for x in 0..per_side {
            let id = ChunkId {
                level,
                x,
                y: k as u32,
            };
            let band = &self.levels[level as usize];
            let first = (k * cells as u64 - band.first_row) as usize;
            self.chunk_heights.clear();
            for b in 0..=cells {
                let start = (first + b) * band.width + x as usize * cells;
                self.chunk_heights
                    .extend_from_slice(&band.rows[start..=start + cells]);
            }
            for &z in &self.chunk_heights {
                match header.sample {
                    StoredSample::I16 => self
                        .heights_bytes
                        .extend_from_slice(&(z as i16).to_le_bytes()),
                    StoredSample::F32 => self.heights_bytes.extend_from_slice(&z.to_le_bytes()),
                }
            }
            let record = if level == header.leaf_level() {
                ChunkRecord::leaf(self.chunk_heights.iter().copied(), 0.0)
            } else {
                self.internal_record(id)
            };
            for value in [record.error, record.z_min, record.z_max] {
                self.records_bytes.extend_from_slice(&value.to_le_bytes());
            }
            records.push(record);
        }
        let row_start = ChunkId {
            level,
            x: 0,
            y: k as u32,
        };
        output.seek(SeekFrom::Start(header.heights_offset(row_start)))?;
        output.write_all(&self.heights_bytes)?;
        output.seek(SeekFrom::Start(header.record_offset(row_start)))?;
        output.write_all(&self.records_bytes)?;
        self.levels[level as usize].pending.extend(records);
        Ok(())
    }

    /// The record of internal chunk `id`, whose children's chunk rows were just completed.
    fn internal_record(&self, id: ChunkId) -> ChunkRecord {
        let cells = self.header.cells();
        let finer = &self.levels[id.level as usize + 1];
        let finer_per_side = 2usize << id.level;
        let children = id.children().map(|child| {
            let row = (u64::from(child.y) - finer.pending_first) as usize;
            finer.pending[row * finer_per_side + child.x as usize]
        });
        let first = (u64::from(2 * id.y * cells) - finer.first_row) as usize;
        let x0 = (2 * id.x * cells) as usize;
        let own_error = chunk_own_error(cells, |a, b| {
            finer.rows[(first + b as usize) * finer.width + x0 + a as usize]
        });
        ChunkRecord::internal(&children, own_error)
    }
}
