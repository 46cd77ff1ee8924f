//! Warm-up: the first frames of a run left out of its summaries, and whether an entry holding a
//! count target had reached it (`docs/experiment-format.md`, "Outputs", `warm_up_frames`). It
//! changes no frame and no file's frame rows; whether an entry held its count over the run is
//! `goal_check.rs`'s.
//!
//! An entry that starts far from its target (Wu's budget from the paper's initial τ, ROAM's or
//! Röttger's controller from their first guess) takes frames to get there, and averaging those
//! frames in makes its summary describe the start-up, not the algorithm. An experiment's
//! `outputs.warm_up_frames` (default 0: every frame counts, as before) leaves its first frames
//! out of `summary.json`'s column summaries, `report.md`'s tables and figures, the sweep's
//! figures and the end-of-run printout. `frames.csv` and the per-frame plots keep every frame,
//! and `summary.json` records the warm-up (`flight.warm_up_frames`) and each entry's
//! `frames_summarised`.
//!
//! Settling (decided here; the issue left it open): an entry with a count target — `wu`'s
//! `budget_triangles` (the triangles of its in-view blocks when it reports them, else the whole
//! mesh), `roam`'s, `roam-rebuild`'s, `geomipmap`'s, `chunked`'s and `vanek`'s `target_triangles`,
//! `rottger`'s `target_triangles` (its fan triangles) or `target_fan_vertices` — has *settled* at
//! the first frame whose held count is within [`SETTLED_WITHIN`] of the target. `report.md` names
//! every entry that settled only after more than [`NEGLIGIBLE_APPROACH`] of the summarised frames,
//! or never, so a reader knows which summaries still contain the approach to the target. Entries
//! without a target (a fixed τ) have nothing to settle to and are not judged.

use super::columns::{RunColumns, value};
use crate::sim::algorithm::CountGoal;

/// The relative distance from its target at which an entry counts as settled: 10 %.
pub const SETTLED_WITHIN: f64 = 0.10;

/// The share of the summarised frames an approach to the target may take before `report.md`
/// names the entry as not settled: 2 % (a controller's first two frames of a 400-frame flight
/// move its means by little).
pub const NEGLIGIBLE_APPROACH: f64 = 0.02;

/// The runs as their summaries see them: each without its first `warm_up_frames` frames.
pub fn summarised_runs<'a>(runs: &[RunColumns<'a>], warm_up_frames: u64) -> Vec<RunColumns<'a>> {
    runs.iter()
        .map(|run| {
            let skip = (warm_up_frames as usize).min(run.frames.len());
            RunColumns {
                label: run.label,
                extra_columns: run.extra_columns,
                frames: &run.frames[skip..],
            }
        })
        .collect()
}

/// An entry's count target and when its held count first came near it.
#[derive(Clone, Debug, PartialEq)]
pub struct Settling {
    /// The target as written.
    pub target: f64,
    /// The `frames.csv` column the target holds.
    pub column: &'static str,
    /// The first frame whose held count is within [`SETTLED_WITHIN`] of the target; `None`:
    /// never.
    pub first_frame: Option<u64>,
}

/// The entry's settling, when it holds a count target (its [`CountGoal`]; see the module doc).
pub fn settling(goal: Option<CountGoal>, run: &RunColumns) -> Option<Settling> {
    let CountGoal { column, target } = goal?;
    let target = target as f64;
    let first_frame = run
        .frames
        .iter()
        .find(|f| {
            value(run, f, column)
                .is_some_and(|held| (held - target).abs() <= SETTLED_WITHIN * target)
        })
        .map(|f| f.frame);
    Some(Settling {
        target,
        column,
        first_frame,
    })
}

/// `report.md`'s paragraph on the warm-up and on entries that had not settled; empty when there
/// is neither a warm-up nor an unsettled entry.
pub fn warm_up_paragraph(
    labels: &[&str],
    settling: &[Option<Settling>],
    warm_up_frames: u64,
    n_frames: u64,
) -> String {
    let summarised = n_frames.saturating_sub(warm_up_frames);
    let mut sentences = Vec::new();
    if warm_up_frames > 0 {
        sentences.push(format!(
            "**Warm-up.** The first {warm_up_frames} frames (0 to {}) are left out of every figure \
             of this report and of summary.json's column summaries; frames.csv and the plots keep them.",
            warm_up_frames - 1
        ));
    }
    for (label, settled) in labels.iter().zip(settling) {
        let Some(settled) = settled else { continue };
        let within = format!("{:.0} %", SETTLED_WITHIN * 100.0);
        match settled.first_frame {
            // Settled inside the warm-up, or after a negligible part of the summarised frames.
            Some(frame)
                if frame.saturating_sub(warm_up_frames) as f64
                    <= NEGLIGIBLE_APPROACH * summarised as f64 => {}
            Some(frame) => sentences.push(format!(
                "**Not settled:** {} first came within {within} of its target ({:.0} {}) at \
                 frame {frame}, so the summarised frames {} include its approach to the target{}.",
                label.replace('|', "\\|"),
                settled.target,
                settled.column,
                if warm_up_frames > 0 {
                    format!("from {warm_up_frames} on")
                } else {
                    "from 0 on".to_string()
                },
                if warm_up_frames > 0 {
                    ""
                } else {
                    " (`outputs.warm_up_frames` leaves such frames out)"
                }
            )),
            None => sentences.push(format!(
                "**Not settled:** {} never came within {within} of its target ({:.0} {}).",
                label.replace('|', "\\|"),
                settled.target,
                settled.column
            )),
        }
    }
    sentences.join("\n\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::stats::FrameStats;

    fn frames(triangles: &[u64]) -> Vec<FrameStats> {
        triangles
            .iter()
            .enumerate()
            .map(|(k, &t)| FrameStats {
                frame: k as u64,
                triangles: t,
                ..FrameStats::default()
            })
            .collect()
    }

    fn run<'a>(frames: &'a [FrameStats]) -> RunColumns<'a> {
        RunColumns {
            label: "roam",
            extra_columns: &[],
            frames,
        }
    }

    #[test]
    fn summarised_runs_leave_out_the_warm_up_frames_and_never_more_than_there_are() {
        let frames = frames(&[1, 2, 3, 4]);
        let runs = [run(&frames)];
        let kept = summarised_runs(&runs, 3);
        assert_eq!(kept[0].frames.len(), 1);
        assert_eq!(kept[0].frames[0].frame, 3);
        assert!(summarised_runs(&runs, 9)[0].frames.is_empty());
        assert_eq!(summarised_runs(&runs, 0)[0].frames.len(), 4);
    }

    fn goal(column: &'static str, target: u64) -> CountGoal {
        CountGoal { column, target }
    }

    #[test]
    fn an_entry_settles_at_the_first_frame_within_ten_percent_of_its_target() {
        let frames = frames(&[100, 500, 880, 910, 1010]);
        let settled = settling(Some(goal("triangles", 1000)), &run(&frames));
        assert_eq!(
            settled,
            Some(Settling {
                target: 1000.0,
                column: "triangles",
                first_frame: Some(3),
            })
        );
        assert_eq!(
            settling(None, &run(&frames)),
            None,
            "a fixed τ has no target to settle to"
        );
        let never = settling(Some(goal("triangles", 5000)), &run(&frames));
        assert_eq!(never.unwrap().first_frame, None);
    }

    #[test]
    fn the_report_names_entries_that_settled_inside_the_summarised_frames_or_never() {
        let late = Some(Settling {
            target: 1000.0,
            column: "triangles",
            first_frame: Some(200),
        });
        let early = Some(Settling {
            target: 1000.0,
            column: "triangles",
            first_frame: Some(3),
        });
        let never = Some(Settling {
            target: 50.0,
            column: "fan_vertices",
            first_frame: None,
        });
        let text = warm_up_paragraph(
            &["wu budget", "roam", "rottger", "wu τ=2px"],
            &[late.clone(), early, never, None],
            50,
            1000,
        );
        assert!(text.contains("The first 50 frames (0 to 49)"), "{text}");
        assert!(
            text.contains(
                "wu budget first came within 10 % of its target (1000 triangles) at frame 200"
            ),
            "{text}"
        );
        assert!(!text.contains("roam"), "settled inside the warm-up: {text}");
        assert!(text.contains("rottger never came within 10 %"), "{text}");
        assert!(!text.contains("wu τ=2px"), "{text}");
        let no_warm_up = warm_up_paragraph(&["wu budget"], &[late], 0, 1000);
        assert!(
            no_warm_up.contains("`outputs.warm_up_frames`"),
            "{no_warm_up}"
        );
        assert!(warm_up_paragraph(&["x"], &[None], 0, 1000).is_empty());
        // Two frames of approach in a 400-frame flight are negligible; forty are not.
        let at = |frame| {
            Some(Settling {
                target: 1000.0,
                column: "triangles",
                first_frame: Some(frame),
            })
        };
        assert!(warm_up_paragraph(&["rottger"], &[at(2)], 0, 400).is_empty());
        assert!(!warm_up_paragraph(&["rottger"], &[at(40)], 0, 400).is_empty());
    }
}
