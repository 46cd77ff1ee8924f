//! `roamsim prepare`'s command: [`prepare_from_raw`] with its progress on stderr and its summary
//! line on stdout. Not the format or the build (`prepare.rs`); not argument parsing (`main.rs`).

use super::{RawSource, prepare_from_raw};

/// `roamsim prepare`: writes the pyramid, progress on stderr every 5 % of the rows.
pub fn prepare_command(
    source: RawSource,
    chunk_level: u32,
    out: &std::path::Path,
) -> Result<(), String> {
    let start = std::time::Instant::now();
    let mut last_percent = 0;
    let summary = prepare_from_raw(&source, chunk_level, out, &mut |done, rows| {
        let percent = done * 100 / rows;
        if percent >= last_percent + 5 || done == rows {
            last_percent = percent;
            eprintln!(
                "prepare: {done}/{rows} rows ({percent}%), {:.0} s elapsed",
                start.elapsed().as_secs_f64()
            );
        }
    })
    .map_err(|error| error.to_string())?;
    let header = summary.header;
    println!(
        "{}: {} × {} samples, chunks of {}² ({} levels, {} chunks), {:?} heights, {} bytes; \
         row bands held at most {} bytes",
        out.display(),
        header.side(),
        header.side(),
        header.cells() + 1,
        header.leaf_level() + 1,
        header.n_chunks(),
        header.sample,
        summary.file_bytes,
        summary.band_bytes
    );
    Ok(())
}
