//! Fuzz target: the raw sample reader. The first four bytes declare the layout (columns and rows
//! of 1 to 64, the sample type, the row order), the rest is the file; then void filling and
//! embedding of what it accepted. A nodata value is declared so that voids occur.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;
use roamsim::edge::terrain_readers::{
    RawLayout, RawSample, ReadOptions, TerrainFormat, read_terrain_bytes,
};
use std::path::Path;

const SAMPLES: [RawSample; 6] = [
    RawSample::I16Le,
    RawSample::I16Be,
    RawSample::U16Le,
    RawSample::U16Be,
    RawSample::F32Le,
    RawSample::F32Be,
];

fuzz_target!(|data: &[u8]| {
    let Some((header, file)) = data.split_first_chunk::<4>() else {
        return;
    };
    let layout = RawLayout {
        columns: 1 + usize::from(header[0] % 64),
        rows: 1 + usize::from(header[1] % 64),
        sample: SAMPLES[usize::from(header[2]) % SAMPLES.len()],
        north_first: header[3] & 1 == 1,
    };
    let options = ReadOptions {
        nodata: Some(0.0),
        ..ReadOptions::AS_STORED
    };
    common::exercise(read_terrain_bytes(
        Path::new("fuzz.raw"),
        file,
        TerrainFormat::Raw(layout),
        &options,
    ));
});
