//! What every terrain fuzz target does with a grid a reader accepted: fill its voids and embed
//! it, as an experiment would, so that a reader's `Ok` is also checked downstream. Not a target.
//!
//! The fuzz crate is its own workspace, outside the package's build, with one target per parser
//! over the parsers' byte entry points (`read_terrain_bytes`, `parse_flight_log_bytes`,
//! `experiment::check_bytes`), which do no IO. CI builds every target without running it, so
//! that none can rot. The targets, their seeds, how to run them and the runs so far:
//! `docs/robustness.md`, "Fuzzing".

use roamsim::edge::terrain_readers::{LoadedTerrain, TerrainReadError};
use roamsim::sim::terrain::Spacing;
use roamsim::sim::terrain::embed::{Fit, embed};
use roamsim::sim::terrain::fill::fill_voids;

/// Grids larger than this are not embedded (padding a 3×4000 grid gives 4097² samples: slow,
/// not interesting).
const MAX_EMBEDDED_SAMPLES: usize = 1 << 20;

/// Fills and embeds an accepted grid; errors are values, panics are the bugs being looked for.
pub fn exercise(result: Result<LoadedTerrain, TerrainReadError>) {
    let Ok(loaded) = result else { return };
    let Ok((filled, _)) = fill_voids(loaded.grid) else {
        return;
    };
    let side = filled.width().max(filled.height()).next_power_of_two() + 1;
    if side.saturating_mul(side) > MAX_EMBEDDED_SAMPLES {
        return;
    }
    let spacing = loaded.spacing.unwrap_or(Spacing { dx: 1.0, dy: 1.0 });
    let _ = embed(&filled, Fit::Pad, spacing);
    let _ = embed(&filled, Fit::Crop { origin: None }, spacing);
}
