//! Fuzz target: the 16-bit (or 8-bit) grayscale PNG reader, on the input as the whole file, then on
//! what it accepted: void filling and embedding.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use roamsim::edge::terrain_readers::{ReadOptions, TerrainFormat, read_terrain_bytes};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    common::exercise(read_terrain_bytes(
        Path::new("fuzz.png"),
        data,
        TerrainFormat::Png,
        &ReadOptions::AS_STORED,
    ));
});
