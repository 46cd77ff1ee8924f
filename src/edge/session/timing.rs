//! Timing passes: how an entry's update times are measured (`--repeat N`,
//! `--time-with-effects`; documented in `docs/output-formats.md`). Not the frame loop's timed span
//! (`sim::run::FrameRunner` times only the algorithm's update) and not the summaries of the times
//! (`sim::stats`).
//!
//! **Times from a clean pass.** When any effect is on (the audit above all, also culling, mesh
//! checks and exports), an entry's reported update times come from its flight flown again from a
//! fresh algorithm with every effect off, a *timing pass*, because the effects between two
//! updates evict the algorithm's data from the caches and inflate its next update. The counts and
//! meshes come from the measured pass. The alternative is kept behind a flag: the measured pass's
//! own times (`--time-with-effects`, no timing pass).
//!
//! **A free determinism check.** A timing pass must draw the measured pass's triangle count
//! every frame, else the run stops (`same_counts_timed`): the same experiment gives the same
//! counts every time (SPEC §8), so an algorithm decides alike on every pass.
//!
//! **Several passes give a spread.** With `--repeat N`, each frame's time is the median over the
//! passes (nearest rank, the lower of two), and the entry's facts give the spread of the passes'
//! medians (their median, least and greatest). The algorithms' own timing columns
//! (`strip_construction_ns`, `detail_synthesis_ms`: `TIMING_COLUMNS`) come from the passes too,
//! so that a part is never measured with the effects on while the whole is measured without;
//! not the reads from disk (`read_latency_*_us`, `read_wait_us`), which stay the measured pass's:
//! a pass flown again rereads what the page cache now holds.
//!
//! **One algorithm alive at a time.** The measured pass's algorithm is dropped before a pass
//! builds its own, and each pass's before the next, so a run's peak memory is one algorithm's
//! (per entry running).

use super::progress_sink::{FrameProgress, ProgressSink};
use crate::edge::experiment::{AlgorithmSpec, Experiment};
use crate::edge::output::columns::{MEASURED_PASS_TIMING_COLUMNS, TIMING_COLUMNS};
use crate::sim::run::{CheckError, Effects, RunError, RunInputs, run_algorithm_with};
use crate::sim::stats::{FrameStats, nearest_rank, summarise};

/// How update times are measured (`--repeat N`, `--time-with-effects`).
///
/// The effects between two updates (the audit above all, also culling, mesh checks and
/// exports) evict the algorithm's data from the caches and inflate its next update by up to
/// 1.5–2×. So by default, when any effect is on, each entry's flight is flown again from a
/// fresh algorithm with every effect off — a **timing pass** — and its update times replace
/// the measured pass's (the counts and meshes come from the measured pass; the timing pass
/// must draw the same triangle counts, else the run stops). `repeat` = N runs N timing
/// passes (even with no effect on): frames.csv's `update_ns` is each frame's median over the
/// passes, and summary.json's facts give the passes' medians (their median, least and
/// greatest): the spread of the figure a paper would quote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timing {
    /// Timing passes (at least 1).
    pub repeat: u32,
    /// Keep the measured pass's times (no timing pass; `repeat` must be 1).
    pub with_effects: bool,
}

impl Default for Timing {
    fn default() -> Timing {
        Timing {
            repeat: 1,
            with_effects: false,
        }
    }
}

impl Timing {
    /// The timing passes an entry needs: none when its measured pass is already clean (no
    /// effect on) and one pass is asked for, or when the effects' times are kept.
    pub(super) fn passes(&self, effects_on: bool) -> u32 {
        if self.with_effects || (!effects_on && self.repeat == 1) {
            0
        } else {
            self.repeat
        }
    }
}

/// One entry's timing passes: the entry as it ran (a tuned entry with its value found) and the
/// inputs of its measured pass, whose effects the passes turn off.
pub(super) struct TimingPasses<'a> {
    pub(super) experiment: &'a Experiment,
    pub(super) spec: &'a AlgorithmSpec,
    pub(super) inputs: RunInputs<'a>,
    pub(super) progress: &'a dyn ProgressSink,
}

impl TimingPasses<'_> {
    /// Flies `passes` timing passes, each from a fresh algorithm, and puts their update times
    /// (and the algorithm's own timing columns among `extra_columns`) into the measured pass's
    /// `frames`; returns the facts of the passes' spread.
    pub(super) fn retime(
        &self,
        passes: u32,
        frames: &mut [FrameStats],
        extra_columns: &[&str],
    ) -> Result<Vec<(&'static str, f64)>, RunError> {
        let experiment = self.experiment;
        let spec = self.spec;
        let clean = RunInputs {
            effects: Effects {
                audit: None,
                culling: false,
                check_meshes: false,
            },
            ..self.inputs
        };
        let n_frames = experiment.flight.n_frames();
        let mut pass_times = Vec::new();
        let mut pass_frames = Vec::new();
        for _ in 0..passes {
            let mut fresh = spec
                .config
                .build(clean.hierarchy, &experiment.view, experiment.speed);
            let mut progress = FrameProgress::new(self.progress, n_frames);
            let timed =
                run_algorithm_with(&clean, &spec.label, fresh.as_mut(), &mut |outcome, _| {
                    progress.frame_done(outcome.stats.frame);
                })?;
            same_counts(&spec.label, frames, &timed)?;
            pass_times.push(timed.iter().map(|f| (f.update_ns, f.frame_ns)).collect());
            pass_frames.push(timed);
        }
        let facts = take_pass_times(frames, &pass_times, experiment.warm_up_frames);
        take_pass_sub_timings(frames, &pass_frames, extra_columns);
        Ok(facts)
    }
}

/// Whether a timing pass drew the measured pass's triangle counts frame by frame (else the run
/// stops: an algorithm must decide alike on every pass).
fn same_counts(label: &str, measured: &[FrameStats], timed: &[FrameStats]) -> Result<(), RunError> {
    for (m, t) in measured.iter().zip(timed) {
        if m.triangles != t.triangles {
            return Err(RunError {
                algorithm: label.to_string(),
                frame: m.frame,
                error: CheckError::TimingPassDiverged {
                    measured: m.triangles,
                    timed: t.triangles,
                },
            });
        }
    }
    Ok(())
}

/// Puts each frame's median (nearest rank) over the timing passes into `frames` (`update_ns`
/// and `frame_ns`, each pass's pair per frame), and returns the facts of the spread: the median
/// update and frame time of each pass over the summarised frames (after `warm_up_frames`), and
/// those medians' median, least and greatest, in µs.
fn take_pass_times(
    frames: &mut [FrameStats],
    pass_times: &[Vec<(u64, u64)>],
    warm_up_frames: u64,
) -> Vec<(&'static str, f64)> {
    let mut at_frame = Vec::with_capacity(pass_times.len());
    let median = |at_frame: &mut Vec<u64>| {
        at_frame.sort_unstable();
        at_frame[at_frame.len().div_ceil(2) - 1]
    };
    for (k, frame) in frames.iter_mut().enumerate() {
        at_frame.clear();
        at_frame.extend(pass_times.iter().map(|pass| pass[k].0));
        frame.update_ns = median(&mut at_frame);
        at_frame.clear();
        at_frame.extend(pass_times.iter().map(|pass| pass[k].1));
        frame.frame_ns = median(&mut at_frame);
    }
    let skip = usize::try_from(warm_up_frames).unwrap_or(usize::MAX);
    let medians = |which: fn(&(u64, u64)) -> u64| -> Vec<f64> {
        pass_times
            .iter()
            .filter_map(|pass| {
                let summarised: Vec<f64> =
                    pass.iter().skip(skip).map(|t| which(t) as f64).collect();
                summarise(&summarised).map(|s| s.p50 / 1e3)
            })
            .collect()
    };
    let mut facts = Vec::new();
    let names = [
        (
            [
                "update_p50_us_median_of_passes",
                "update_p50_us_least_of_passes",
                "update_p50_us_greatest_of_passes",
            ],
            medians(|t| t.0),
        ),
        (
            [
                "frame_p50_us_median_of_passes",
                "frame_p50_us_least_of_passes",
                "frame_p50_us_greatest_of_passes",
            ],
            medians(|t| t.1),
        ),
    ];
    for ([median_name, least_name, greatest_name], medians) in names {
        if let Some(spread) = summarise(&medians) {
            facts.extend([
                (median_name, spread.p50),
                (least_name, least(&medians)),
                (greatest_name, spread.max),
            ]);
        }
    }
    facts
}

/// The algorithm's own timing columns (parts of its update, such as the stitching strips'
/// construction or chunked's synthesis: [`TIMING_COLUMNS`]) taken from the timing passes too,
/// each frame's median over them, so that a part is never measured with the effects on while
/// the whole is measured without. Not the reads from disk
/// ([`MEASURED_PASS_TIMING_COLUMNS`]): they stay the measured pass's, the first to read each
/// chunk.
fn take_pass_sub_timings(
    frames: &mut [FrameStats],
    pass_frames: &[Vec<FrameStats>],
    extra_columns: &[&str],
) {
    let timing: Vec<usize> = extra_columns
        .iter()
        .enumerate()
        .filter(|(_, name)| {
            TIMING_COLUMNS.contains(name) && !MEASURED_PASS_TIMING_COLUMNS.contains(name)
        })
        .map(|(k, _)| k)
        .collect();
    let mut at_frame: Vec<f64> = Vec::with_capacity(pass_frames.len());
    for column in timing {
        for (k, frame) in frames.iter_mut().enumerate() {
            at_frame.clear();
            at_frame.extend(
                pass_frames
                    .iter()
                    .filter_map(|pass| pass[k].extra.get(column)),
            );
            at_frame.sort_unstable_by(|a, b| a.total_cmp(b));
            if let Some(slot) = frame.extra.get_mut(column)
                && !at_frame.is_empty()
            {
                *slot = nearest_rank(&at_frame, 0.5);
            }
        }
    }
}

/// The least value of a non-empty slice.
fn least(values: &[f64]) -> f64 {
    values.iter().copied().fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames_with(triangles: &[u64], update_ns: &[u64]) -> Vec<FrameStats> {
        triangles
            .iter()
            .zip(update_ns)
            .enumerate()
            .map(|(frame, (&triangles, &update_ns))| FrameStats {
                frame: frame as u64,
                triangles,
                update_ns,
                ..FrameStats::default()
            })
            .collect()
    }

    #[test]
    fn each_frame_gets_its_median_over_the_passes_and_the_facts_their_spread() {
        let mut frames = frames_with(&[10, 20, 30], &[999, 999, 999]);
        // Three passes; frame 0's times 5, 9, 7 → 7; the passes' medians over frames 1.. (one
        // warm-up frame): pass 0 {2000, 4000} → 2 µs, pass 1 {1000, 1000} → 1, pass 2
        // {3000, 5000} → 3.
        // Each frame's time to drawable buffers is its update time plus 100 ns here.
        let pass = |times: [u64; 3]| times.map(|t| (t, t + 100)).to_vec();
        let passes = [
            pass([5, 2000, 4000]),
            pass([9, 1000, 1000]),
            pass([7, 3000, 5000]),
        ];
        let facts = take_pass_times(&mut frames, &passes, 1);
        let times: Vec<u64> = frames.iter().map(|f| f.update_ns).collect();
        assert_eq!(times, [7, 2000, 4000]);
        let frame_times: Vec<u64> = frames.iter().map(|f| f.frame_ns).collect();
        assert_eq!(frame_times, [107, 2100, 4100]);
        assert_eq!(
            facts,
            [
                ("update_p50_us_median_of_passes", 2.0),
                ("update_p50_us_least_of_passes", 1.0),
                ("update_p50_us_greatest_of_passes", 3.0),
                ("frame_p50_us_median_of_passes", 2.1),
                ("frame_p50_us_least_of_passes", 1.1),
                ("frame_p50_us_greatest_of_passes", 3.1),
            ]
        );
    }

    #[test]
    fn an_algorithms_own_timing_columns_come_from_the_passes_too() {
        let with_extra = |update_ns: u64, extra: [f64; 2]| FrameStats {
            update_ns,
            extra: extra.to_vec(),
            ..FrameStats::default()
        };
        // Column 0 is a count, column 1 a part of the update (strip_construction_ns).
        let mut frames = vec![with_extra(100, [7.0, 90.0])];
        let passes = [
            vec![with_extra(40, [7.0, 30.0])],
            vec![with_extra(50, [7.0, 10.0])],
            vec![with_extra(60, [7.0, 20.0])],
        ];
        take_pass_sub_timings(&mut frames, &passes, &["m_blocks", "strip_construction_ns"]);
        assert_eq!(frames[0].extra, [7.0, 20.0]);
    }

    #[test]
    fn the_reads_from_disk_stay_the_measured_passes() {
        let with_extra = |extra: [f64; 3]| FrameStats {
            extra: extra.to_vec(),
            ..FrameStats::default()
        };
        // A pass flown again reads from the page cache: its latencies say nothing of the disk.
        let mut frames = vec![with_extra([4.0, 900.0, 850.0])];
        let passes = [vec![with_extra([4.0, 3.0, 2.0])]];
        let columns = ["chunks_read", "read_latency_max_us", "read_latency_mean_us"];
        take_pass_sub_timings(&mut frames, &passes, &columns);
        assert_eq!(frames[0].extra, [4.0, 900.0, 850.0]);
    }

    #[test]
    fn a_timing_pass_that_draws_other_counts_stops_the_run() {
        let measured = frames_with(&[10, 20, 30], &[1, 1, 1]);
        let same = frames_with(&[10, 20, 30], &[4, 5, 6]);
        assert_eq!(same_counts("a", &measured, &same), Ok(()));
        let other = frames_with(&[10, 21, 30], &[4, 5, 6]);
        let error = same_counts("a", &measured, &other).expect_err("diverged");
        assert_eq!(error.frame, 1);
        assert!(
            error
                .to_string()
                .contains("drew 21 triangles where the measured pass drew 20"),
            "{error}"
        );
    }

    #[test]
    fn timing_passes_run_when_an_effect_is_on_or_more_than_one_is_asked_for() {
        let default = Timing::default();
        assert_eq!(default.passes(true), 1);
        assert_eq!(default.passes(false), 0);
        let three = Timing {
            repeat: 3,
            with_effects: false,
        };
        assert_eq!((three.passes(true), three.passes(false)), (3, 3));
        let kept = Timing {
            repeat: 1,
            with_effects: true,
        };
        assert_eq!(kept.passes(true), 0);
    }
}
