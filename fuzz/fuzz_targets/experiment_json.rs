//! Fuzz target: the experiment file, parsed (JSON into the format types) and checked (every
//! field's meaning, sweeps expanded). The terrain and flight-log files it names are not read:
//! their readers have their own targets.
#![no_main]

use libfuzzer_sys::fuzz_target;
use roamsim::edge::experiment::check_bytes;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let _ = check_bytes(Path::new("fuzz.json"), data);
});
