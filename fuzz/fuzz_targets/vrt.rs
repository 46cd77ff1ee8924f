//! Fuzz target: the GDAL VRT parser (the XML of a mosaic: its size, GeoTransform, band, sources
//! and their windows). The source files it names are not opened: their readers have their own
//! targets. What it accepts must be a raster of at least one sample with at least one source.
#![no_main]

use libfuzzer_sys::fuzz_target;
use roamsim::edge::terrain_readers::parse_vrt_bytes;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mosaic) = parse_vrt_bytes(Path::new("fuzz.vrt"), data) {
        let (columns, rows) = mosaic.size();
        assert!(columns >= 1 && rows >= 1 && mosaic.n_sources() >= 1);
    }
});
