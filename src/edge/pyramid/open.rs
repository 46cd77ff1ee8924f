//! Reading a chunk pyramid: the header and every chunk record at open, a chunk's heights with
//! one positioned read when asked (`read_heights` takes `&self`, so a loader thread can share the
//! file).
//!
//! **Checked at open** (each failure names the file and the field): the magic, the version, the
//! header's fields, the file's length against the one the header implies (a truncated or
//! unfinished file is refused), and every record: finite, δ_c ≥ 0, z_min ≤ z_max, and nested
//! (a parent's error at least its children's, its height range around theirs, as eq. 3.1 and
//! §3.2.12 make them). **Checked per read**: every height finite and inside its chunk's range.
//! Memory: 16 bytes per chunk for the records, nothing per height beyond the caller's buffer.
//! Reads are positioned (`pread`, Unix's `FileExt`), so they need no seek and no lock.

use super::{HEADER_BYTES, PyramidError, PyramidHeader, RECORD_BYTES, StoredSample, chunk_ids};
use crate::sim::algorithm::chunked::{ChunkId, ChunkRecord};
use std::fs::File;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

/// An open pyramid: its header and records in memory, its heights on disk.
#[derive(Debug)]
pub struct PyramidFile {
    path: PathBuf,
    file: File,
    header: PyramidHeader,
    /// Every chunk's record in breadth-first order, skirt depth 0.
    records: Vec<ChunkRecord>,
}

impl PyramidFile {
    /// Opens and checks the pyramid at `path` (see the module docs).
    pub fn open(path: &Path) -> Result<PyramidFile, PyramidError> {
        let file = File::open(path)
            .map_err(|e| PyramidError::new(path, format!("cannot open the pyramid: {e}")))?;
        let length = file
            .metadata()
            .map_err(|e| PyramidError::new(path, format!("cannot read its length: {e}")))?
            .len();
        let mut header_bytes = [0u8; HEADER_BYTES as usize];
        if length < HEADER_BYTES {
            return Err(PyramidError::new(
                path,
                format!(
                    "the file has {length} bytes, fewer than a pyramid's {HEADER_BYTES}-byte \
                     header: not a pyramid, or truncated"
                ),
            ));
        }
        file.read_exact_at(&mut header_bytes, 0)
            .map_err(|e| PyramidError::new(path, format!("cannot read the header: {e}")))?;
        let header =
            PyramidHeader::decode(&header_bytes).map_err(|e| PyramidError::new(path, e))?;
        if length != header.file_bytes() {
            return Err(PyramidError::new(
                path,
                format!(
                    "the file has {length} bytes; its header (terrain level {}, chunk level {}, \
                     {:?} samples) needs {}: truncated, or not written to the end (prepare it \
                     again)",
                    header.terrain_level,
                    header.chunk_level,
                    header.sample,
                    header.file_bytes()
                ),
            ));
        }
        let mut record_bytes = vec![0u8; (header.n_chunks() * RECORD_BYTES) as usize];
        file.read_exact_at(&mut record_bytes, HEADER_BYTES)
            .map_err(|e| PyramidError::new(path, format!("cannot read the chunk records: {e}")))?;
        let records: Vec<ChunkRecord> = record_bytes
            .chunks_exact(RECORD_BYTES as usize)
            .map(|bytes| {
                let f32_at = |k: usize| f32::from_le_bytes(bytes[k..k + 4].try_into().unwrap());
                ChunkRecord {
                    error: f32_at(0),
                    z_min: f32_at(4),
                    z_max: f32_at(8),
                    skirt_depth: 0.0,
                }
            })
            .collect();
        let pyramid = PyramidFile {
            path: path.to_path_buf(),
            file,
            header,
            records,
        };
        pyramid.check_records()?;
        Ok(pyramid)
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn header(&self) -> &PyramidHeader {
        &self.header
    }

    /// Every chunk's record (skirt depth 0), in breadth-first order: [`ChunkId::breadth_first_index`].
    pub fn records(&self) -> &[ChunkRecord] {
        &self.records
    }

    /// The record of chunk `id`; `None` outside the tree.
    pub fn record(&self, id: ChunkId) -> Option<ChunkRecord> {
        let inside = id.level <= self.header.leaf_level() && id.x >> id.level == 0 && {
            id.y >> id.level == 0
        };
        inside.then(|| self.records[id.breadth_first_index() as usize])
    }

    /// Reads chunk `id`'s (2^c + 1)² heights, row by row from the south, into `heights` with
    /// one read. Refused: a chunk outside the tree, a failed read (the file cut short or changed
    /// after it was opened), a height not finite or outside the chunk's range. Each error names
    /// the file, the chunk (level, position, byte offset) and what was expected there.
    pub fn read_heights(&self, id: ChunkId, heights: &mut Vec<f32>) -> Result<(), PyramidError> {
        let record = self.record(id).ok_or_else(|| {
            PyramidError::new(
                &self.path,
                format!("chunk {id:?} is not in the pyramid's tree"),
            )
        })?;
        let offset = self.header.heights_offset(id);
        let length = self.header.chunk_bytes();
        let chunk = format!(
            "chunk at level {}, x {}, y {} (heights at bytes {offset}..{})",
            id.level,
            id.x,
            id.y,
            offset + length
        );
        let mut bytes = vec![0u8; length as usize];
        self.file.read_exact_at(&mut bytes, offset).map_err(|e| {
            let now = self
                .file
                .metadata()
                .map_or_else(|_| "unknown".to_string(), |m| m.len().to_string());
            PyramidError::new(
                &self.path,
                format!(
                    "{chunk}: cannot read its heights ({e}): expected {length} bytes there, and \
                     the file now has {now} bytes of the {} it had when opened (cut short or \
                     changed during the run; prepare it again)",
                    self.header.file_bytes()
                ),
            )
        })?;
        heights.clear();
        match self.header.sample {
            StoredSample::I16 => heights.extend(
                bytes
                    .chunks_exact(2)
                    .map(|b| f32::from(i16::from_le_bytes([b[0], b[1]]))),
            ),
            StoredSample::F32 => heights.extend(
                bytes
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            ),
        }
        if let Some(k) = heights
            .iter()
            .position(|z| !(record.z_min..=record.z_max).contains(z))
        {
            let side = self.header.cells() as usize + 1;
            return Err(PyramidError::new(
                &self.path,
                format!(
                    "{chunk}: vertex ({}, {}) at byte {} has height {}, outside its record's \
                     range: expected {} to {}; the file is corrupt (prepare it again)",
                    k % side,
                    k / side,
                    offset + k as u64 * self.header.sample.bytes(),
                    heights[k],
                    record.z_min,
                    record.z_max
                ),
            ));
        }
        Ok(())
    }

    /// The records' own invariants and their nesting.
    fn check_records(&self) -> Result<(), PyramidError> {
        for id in chunk_ids(self.header.leaf_level()) {
            let record = self.records[id.breadth_first_index() as usize];
            let sound = record.error.is_finite()
                && record.error >= 0.0
                && record.z_min.is_finite()
                && record.z_max.is_finite()
                && record.z_min <= record.z_max;
            let nested = id.parent().is_none_or(|parent| {
                let outer = self.records[parent.breadth_first_index() as usize];
                outer.error >= record.error
                    && outer.z_min <= record.z_min
                    && outer.z_max >= record.z_max
            });
            if !(sound && nested) {
                return Err(PyramidError::new(
                    &self.path,
                    format!(
                        "chunk {id:?}'s record (error {}, heights {} to {}) is {}: the file is \
                         corrupt (prepare it again)",
                        record.error,
                        record.z_min,
                        record.z_max,
                        if sound {
                            "not inside its parent's"
                        } else {
                            "not finite and ordered"
                        }
                    ),
                ));
            }
        }
        Ok(())
    }
}
