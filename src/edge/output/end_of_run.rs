//! What `roamsim run` prints when it has finished: per entry the figures a person looks at
//! first (triangles, the audited error, time to a drawn frame, as `report.md`'s table has them), then
//! where the files are (README, "Commands"). A sweep prints one block per point. It returns
//! the text and computes no figure; printing it is `main.rs`'s.
//!
//! The figures are the report's own ([`Row`](super::report_md::Row)), warm-up frames left out
//! as there; this module only lays them out as fixed-width text for a terminal or a log.

use super::report_md::REPORT_FILE;
use super::sweep_outputs::EntryFigures;
use std::fmt::Write;
use std::path::Path;

/// One point's figures for the end-of-run printout.
#[derive(Clone, Debug)]
pub struct PointFigures {
    /// The swept values (`None` without a sweep).
    pub choice: Option<String>,
    /// The point's folder inside the output folder (empty without a sweep).
    pub folder: String,
    pub entries: Vec<EntryFigures>,
    /// The frames whose eye was below the ground.
    pub below_ground_frames: Vec<u64>,
}

/// The lines printed after a run: a table per point, then the output files: `written`, what the
/// output folder holds at its top (folders with a `/`), listed as they are, `report.md` first.
pub fn end_of_run_text(out_dir: &Path, points: &[PointFigures], written: &[String]) -> String {
    let mut text = String::new();
    let label_width = points
        .iter()
        .flat_map(|p| &p.entries)
        .map(|e| e.label.chars().count())
        .max()
        .unwrap_or(0)
        .max("entry".len());
    for point in points {
        if let Some(choice) = &point.choice {
            let _ = writeln!(text, "\n{choice} ({}/):", point.folder);
        }
        let _ = writeln!(
            text,
            "  {:<label_width$}  {:>9}  {:>9}  {:>35}  {:>21}",
            "entry",
            "triangles",
            "rendered",
            "error max / mean / mean of p95 (px)",
            "frame p50 / p95 (µs)"
        );
        if let Some(first) = point.below_ground_frames.first() {
            let _ = writeln!(
                text,
                "  warning: the eye is below the ground in {} frame(s) (first: frame {first}; \
                 summary.json lists them)",
                point.below_ground_frames.len()
            );
        }
        for entry in &point.entries {
            let row = &entry.row;
            let error = row.error.map_or("—".to_string(), |(max, mean, p95)| {
                format!("{max:.2} / {mean:.3} / {p95:.2}")
            });
            let update = format!("{:.1} / {:.1}", row.frame_p50_us, row.frame_p95_us);
            let _ = writeln!(
                text,
                "  {:<label_width$}  {:>9.0}  {:>9.0}  {:>35}  {:>21}",
                entry.label, row.triangles, row.rendered, error, update
            );
        }
    }
    let mut listed: Vec<String> = written
        .iter()
        .filter(|name| name.as_str() != REPORT_FILE)
        .cloned()
        .collect();
    if written.iter().any(|name| name == REPORT_FILE) {
        listed.insert(0, format!("{REPORT_FILE} (the full comparison)"));
    }
    let _ = writeln!(
        text,
        "\nwrote {dir}/: {}",
        listed.join(", "),
        dir = out_dir.display()
    );
    if points.iter().any(|p| p.choice.is_some()) {
        let _ = writeln!(
            text,
            "(each sweep point has its own folder with the same files; the top ones compare the points)"
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edge::output::report_md::Row;

    fn entry(label: &str, error: Option<(f64, f64, f64)>) -> EntryFigures {
        EntryFigures {
            label: label.to_string(),
            name: "wu".to_string(),
            row: Row {
                triangles: 10_240.4,
                rendered: 5_120.0,
                error,
                frame_p50_us: 81.25,
                frame_p95_us: 140.0,
                update_p50_us: 20.0,
                update_p95_us: 30.0,
                upload_bytes: 1200.0,
                draw_calls: 1.0,
                triangles_submitted: 10_240.0,
                operations_per_frame: 3.0,
                evaluations_per_operation: None,
            },
            bytes_per_sample: 6.8,
            counters: Vec::new(),
        }
    }

    #[test]
    fn the_printout_has_each_entrys_triangles_error_and_frame_time_and_the_files() {
        let points = [PointFigures {
            choice: None,
            folder: String::new(),
            entries: vec![
                entry("wu τ=2px", Some((3.5, 0.125, 1.75))),
                entry("roam", None),
            ],
            below_ground_frames: Vec::new(),
        }];
        let written = ["frames.csv", "plots/", "report.md", "summary.json"].map(String::from);
        let text = end_of_run_text(Path::new("out/qs"), &points, &written);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].contains("triangles") && lines[0].contains("frame p50 / p95 (µs)"));
        assert!(lines[1].starts_with("  wu τ=2px"), "{}", lines[1]);
        for figure in ["10240", "5120", "3.50 / 0.125 / 1.75", "81.2 / 140.0"] {
            assert!(
                lines[1].contains(figure),
                "{figure} missing from {}",
                lines[1]
            );
        }
        assert!(lines[2].contains("—"), "{}", lines[2]);
        assert!(
            text.contains(
                "wrote out/qs/: report.md (the full comparison), frames.csv, plots/, summary.json"
            ),
            "{text}"
        );
    }

    #[test]
    fn a_sweep_prints_one_block_per_point_with_its_folder() {
        let point = |choice: &str, folder: &str| PointFigures {
            choice: Some(choice.to_string()),
            folder: folder.to_string(),
            entries: vec![entry("wu", None)],
            below_ground_frames: vec![4, 5],
        };
        let text = end_of_run_text(
            Path::new("out/s"),
            &[point("level = 6", "level=6"), point("level = 7", "level=7")],
            &["report.md".to_string(), "summary.json".to_string()],
        );
        assert!(
            text.contains("wrote out/s/: report.md (the full comparison), summary.json\n"),
            "plots/ only where written: {text}"
        );
        assert!(text.contains("level = 6 (level=6/):"), "{text}");
        assert!(text.contains("level = 7 (level=7/):"), "{text}");
        assert_eq!(text.matches("  wu ").count(), 2, "{text}");
        assert!(
            text.contains("warning: the eye is below the ground in 2 frame(s) (first: frame 4"),
            "{text}"
        );
    }
}
