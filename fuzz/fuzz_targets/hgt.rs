//! Fuzz target: the SRTM `.hgt` reader. The first byte chooses between the input as the whole
//! file (the length check) and the input repeated to the size of an SRTM3 tile (the samples and
//! voids); the next eight bytes name the tile (the spacing comes from the name).
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use roamsim::edge::terrain_readers::{ReadOptions, TerrainFormat, read_terrain_bytes};
use std::path::PathBuf;

const SRTM3_BYTES: usize = 1201 * 1201 * 2;

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let (name, samples) = rest.split_at(rest.len().min(8));
    let path = PathBuf::from(format!("{}.hgt", String::from_utf8_lossy(name)));
    let bytes: Vec<u8> = if mode & 1 == 0 || samples.is_empty() {
        data.to_vec()
    } else {
        samples.iter().copied().cycle().take(SRTM3_BYTES).collect()
    };
    common::exercise(read_terrain_bytes(
        &path,
        &bytes,
        TerrainFormat::Hgt,
        &ReadOptions::AS_STORED,
    ));
});
