//! Fuzz target: the recorded camera log (CSV) parser, then building a flight from the poses it
//! accepted (which must all be finite).
#![no_main]

use libfuzzer_sys::fuzz_target;
use roamsim::edge::flight_log::parse_flight_log_bytes;
use roamsim::sim::flight::Flight;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(poses) = parse_flight_log_bytes(Path::new("fuzz.csv"), data) {
        assert!(
            Flight::from_poses(poses).is_ok(),
            "the parser accepted a pose the flight refuses"
        );
    }
});
