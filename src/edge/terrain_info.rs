//! What `roamsim info` prints about a terrain: one plain report, the same for a terrain file and
//! for an experiment's terrain, written for a person (no debug notation; README, "Commands"; the
//! fitting, void filling and spacing it reports are `docs/experiment-format.md`, "Terrain"). It
//! reads no file and fits nothing: the readers and `sim::terrain` have done both before.
//!
//! [`describe_terrain`] lays out what was read and how it was fitted into the (2^n + 1)² grid;
//! [`describe_preprocessing`] times Wu's preprocessing on it and gives its memory. The caller
//! (the CLI) prints both; nothing here reads files.

use crate::edge::experiment::TerrainReport;
use crate::sim::hierarchy::Hierarchy;
use crate::sim::terrain::Heightfield;
use std::fmt::Write;
use std::sync::Arc;
use std::time::Instant;

/// The width of the label column.
const LABEL: usize = 16;

fn line(out: &mut String, label: &str, text: impl std::fmt::Display) {
    let _ = writeln!(out, "{label:<LABEL$}{text}");
}

/// The terrain's source, size, fit, voids, spacing and heights.
pub fn describe_terrain(report: &TerrainReport) -> String {
    let mut out = String::new();
    line(
        &mut out,
        "terrain",
        format!("{} ({})", report.source, report.format),
    );
    line(
        &mut out,
        "source size",
        format!(
            "{} columns × {} rows",
            report.source_columns, report.source_rows
        ),
    );
    let fit = match report.crop_origin {
        Some((column, row)) => format!("cropped from column {column}, row {row} of the source"),
        None if report.padded_columns == 0 && report.padded_rows == 0 => {
            "the source as it is".to_string()
        }
        None => format!(
            "padded with {} columns and {} rows copying the border",
            report.padded_columns, report.padded_rows
        ),
    };
    line(
        &mut out,
        "grid",
        format!("{0} × {0} samples, {fit}", report.side),
    );
    line(&mut out, "voids filled", report.voids_filled);
    line(
        &mut out,
        "spacing",
        format!(
            "dx {:.3} m, dy {:.3} m (from the {})",
            report.spacing.dx, report.spacing.dy, report.spacing_from
        ),
    );
    line(
        &mut out,
        "heights",
        format!("{} m to {} m", report.height_min_m, report.height_max_m),
    );
    out
}

/// Builds Wu's hierarchy on the field, timing it: preprocessing time, memory, the root's error.
pub fn describe_preprocessing(field: impl Into<Arc<Heightfield>>) -> String {
    let field: Arc<Heightfield> = field.into();
    let mut out = String::new();
    if field.paged_samples().is_some() {
        line(
            &mut out,
            "preprocessing",
            "none: a chunk pyramid is read on demand (Wu's node table, which this line would \
             time, needs the whole terrain; chunked LOD builds its tree from the pyramid's \
             records)"
                .to_string(),
        );
        return out;
    }
    let n_samples = field.n_samples();
    let start = Instant::now();
    let hierarchy = Hierarchy::new(field);
    hierarchy.build_node_table();
    let seconds = start.elapsed().as_secs_f64();
    line(
        &mut out,
        "preprocessing",
        format!(
            "{seconds:.3} s ({:.1} ns per sample, one pass over the samples)",
            seconds * 1e9 / n_samples as f64
        ),
    );
    line(
        &mut out,
        "memory",
        format!(
            "{:.2} bytes per sample (heights, Wu's node errors and height ranges)",
            hierarchy.bytes_per_sample()
        ),
    );
    let root = hierarchy.lattice().root();
    line(
        &mut out,
        "root error",
        format!(
            "{} m",
            hierarchy.node_error(root, hierarchy.lattice().cells() / 2)
        ),
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::Spacing;

    fn report(crop_origin: Option<(usize, usize)>, padded: usize) -> TerrainReport {
        TerrainReport {
            source: "data/tile.hgt".to_string(),
            format: "hgt".to_string(),
            source_columns: 1201,
            source_rows: 1201,
            side: 1025,
            padded_columns: padded,
            padded_rows: padded,
            crop_origin,
            voids_filled: 3,
            spacing: Spacing { dx: 61.9, dy: 92.6 },
            spacing_from: "file".to_string(),
            height_min_m: 200.0,
            height_max_m: 1000.0,
        }
    }

    #[test]
    fn the_report_reads_as_words_with_no_debug_notation() {
        for text in [
            describe_terrain(&report(Some((88, 88)), 0)),
            describe_terrain(&report(None, 848)),
            describe_terrain(&report(None, 0)),
        ] {
            assert!(!text.contains("Some("), "{text}");
            assert!(!text.contains("None"), "{text}");
            let labels: Vec<&str> = text.lines().map(|l| l[..LABEL].trim_end()).collect();
            assert_eq!(
                labels,
                [
                    "terrain",
                    "source size",
                    "grid",
                    "voids filled",
                    "spacing",
                    "heights"
                ]
            );
        }
        let cropped = describe_terrain(&report(Some((88, 88)), 0));
        assert!(
            cropped.contains("cropped from column 88, row 88"),
            "{cropped}"
        );
        let padded = describe_terrain(&report(None, 848));
        assert!(
            padded.contains("padded with 848 columns and 848 rows"),
            "{padded}"
        );
    }
}
