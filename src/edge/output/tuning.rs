//! What a tuned entry's search found (`"tune"` in the experiment): the record `summary.json`
//! carries under `"tuning"`, the "Tuned entries" section of `report.md` and the progress line of
//! each probe; and where the search stopped on a plateau, the reason the probes' counters give
//! for it ([`plateau_reason`]). Documented in `docs/output-formats.md` ("summary.json", "report.md") and
//! `docs/experiment-format.md`, "Tuning to a target". It only reports: the search is
//! `sim::tuning`'s.

use super::columns::{RunColumns, value};
use super::report_md::section;
use crate::edge::experiment::{Tune, TuneTarget};
use crate::sim::algorithm::columns::stitching;
use crate::sim::stats::FrameStats;
use crate::sim::tuning::Probe;
use serde_json::{Value, json};
use std::fmt::Write;

/// A tuned entry's search and what the real run then gave.
#[derive(Clone, Debug, PartialEq)]
pub struct TuningRecord {
    pub target: TuneTarget,
    /// The parameter set (`tau_px`, `desired_resolution`, `distance_scale`, …).
    pub parameter: &'static str,
    /// The value the real run used: the probe closest to the target.
    pub value: f64,
    /// That probe's mean over the probe frames.
    pub probe_mean: f64,
    /// Whether that mean is within the tolerance of the target.
    pub reached: bool,
    pub tolerance: f64,
    /// Frames each probe flew, `probe_stride` apart.
    pub probe_frames: u64,
    pub probe_stride: u64,
    /// Every probe, in order.
    pub probes: Vec<Probe>,
    /// The same mean over every frame of the real run (`NaN` when no frame was audited).
    pub full_run_mean: f64,
    /// Where the search found the parameter had stopped mattering, if it stopped so.
    pub plateau: Option<PlateauRecord>,
}

/// A search's plateau (`sim::tuning::Plateau`) and the reason found for it.
#[derive(Clone, Debug, PartialEq)]
pub struct PlateauRecord {
    /// The smallest and largest value probed on it.
    pub values: (f64, f64),
    /// The smallest and largest mean measured on it.
    pub means: (f64, f64),
    /// Its probes (the last ones of the search).
    pub probes: usize,
    /// Why the mean stopped moving, from the probes' counters ([`plateau_reason`]).
    pub reason: String,
}

impl PlateauRecord {
    /// One sentence: `rho_threshold_px from 0.0313 to 0.25 gave 1.231 to 1.262 px audited p95
    /// over 4 probes: <reason>`.
    pub fn sentence(&self, parameter: &str, target: TuneTarget) -> String {
        format!(
            "{parameter} from {} to {} gave {} to {} {} over {} probes: {}",
            significant(self.values.0),
            significant(self.values.1),
            mean_text(target, self.means.0),
            mean_text(target, self.means.1),
            target.unit(),
            self.probes,
            self.reason
        )
    }
}

/// Why a plateau's probes measured the same mean, from their frames (`probes`, each probe's
/// frames in order, flown over the same probe frames) and the algorithm's columns: the evidence
/// its counters give, or, where none does, the generic "did not change" over the values probed.
///
/// The evidence looked for: every probe drew the same triangles in every frame (the parameter no
/// longer changes the mesh), or the meshes changed and the measured mean did not; for the
/// stitching strips, every M-block in the highest tessellation factor's bin in every frame, and
/// the same M-blocks frame for frame (no block splits further, the eye's included).
pub fn plateau_reason(
    probes: &[Vec<FrameStats>],
    extra_columns: &[&str],
    target: TuneTarget,
    values: (f64, f64),
) -> String {
    let runs: Vec<RunColumns> = probes
        .iter()
        .map(|frames| RunColumns {
            label: "probe",
            extra_columns,
            frames,
        })
        .collect();
    let per_frame = |run: &RunColumns, column: &str| -> Vec<Option<f64>> {
        run.frames.iter().map(|f| value(run, f, column)).collect()
    };
    let same_in_every_probe = |column: &str| {
        let first = per_frame(&runs[0], column);
        runs.iter().all(|run| per_frame(run, column) == first)
    };
    let mut evidence = Vec::new();
    if runs.is_empty() {
        return generic_reason(target, probes.len(), values);
    }
    if same_in_every_probe("triangles") {
        evidence.push(
            "every probe on it drew the same number of triangles in every frame: the parameter no \
             longer changes how many triangles are drawn"
                .to_string(),
        );
    } else if matches!(target, TuneTarget::AuditP95Px(_)) {
        let means: Vec<f64> = runs
            .iter()
            .map(|run| mean_column(run, "triangles"))
            .collect();
        evidence.push(format!(
            "the meshes changed (mean triangles {} to {}) but the error did not: the error left \
             is where the parameter does not reach",
            significant(means.iter().copied().fold(f64::INFINITY, f64::min)),
            significant(means.iter().copied().fold(0.0, f64::max)),
        ));
    }
    if extra_columns.contains(&stitching::M_BLOCKS)
        && extra_columns.contains(&stitching::TESSELLATION_FACTOR_32_64)
    {
        let all_at_top = runs.iter().all(|run| {
            run.frames.iter().all(|f| {
                value(run, f, stitching::TESSELLATION_FACTOR_32_64)
                    == value(run, f, stitching::M_BLOCKS)
            })
        });
        if all_at_top {
            evidence.push(format!(
                "every M-block is in the highest tessellation factor's bin, [32, 64], in every \
                 probe frame ({} = {}; mean factor {})",
                stitching::TESSELLATION_FACTOR_32_64,
                stitching::M_BLOCKS,
                significant(mean_column(
                    &runs[runs.len() - 1],
                    stitching::TESSELLATION_FACTOR_MEAN
                )),
            ));
        }
        if same_in_every_probe(stitching::M_BLOCKS) {
            evidence.push(format!(
                "the block tree is the same at every value ({} equal frame for frame): no block, \
                 the eye's included, splits further",
                stitching::M_BLOCKS
            ));
        }
    }
    if evidence.is_empty() {
        generic_reason(target, probes.len(), values)
    } else {
        evidence.join("; ")
    }
}

/// The reason where the counters give none.
fn generic_reason(target: TuneTarget, probes: usize, values: (f64, f64)) -> String {
    format!(
        "the {} did not change over the last {probes} probes spanning [{}, {}]",
        target.unit(),
        significant(values.0),
        significant(values.1)
    )
}

/// The mean of `column` over a probe's frames (`NaN` without values).
fn mean_column(run: &RunColumns, column: &str) -> f64 {
    let values: Vec<f64> = run
        .frames
        .iter()
        .filter_map(|f| value(run, f, column))
        .collect();
    values.iter().sum::<f64>() / values.len() as f64
}

impl TuningRecord {
    /// The `"tuning"` object of the entry in `summary.json`.
    pub fn to_json(&self) -> Value {
        let number = |v: f64| if v.is_finite() { json!(v) } else { Value::Null };
        json!({
            "target": { self.target.field(): self.target.value() },
            "parameter": self.parameter,
            "value": self.value,
            "probe_mean": number(self.probe_mean),
            "reached": self.reached,
            "tolerance": self.tolerance,
            "probe_frames": self.probe_frames,
            "probe_stride": self.probe_stride,
            "probes": self.probes.iter().map(|p| json!({"value": p.value, "mean": number(p.mean)})).collect::<Vec<_>>(),
            "full_run_mean": number(self.full_run_mean),
            "plateau": self.plateau.as_ref().map(|p| json!({
                "values": [p.values.0, p.values.1],
                "means": [number(p.means.0), number(p.means.1)],
                "probes": p.probes,
                "reason": p.reason,
            })),
        })
    }
}

/// The mean over `frames` of what `target` measures: `triangles_rendered`, or each audited
/// frame's projected p95 error (frames without one left out; `NaN` when none has one).
pub fn mean_of_target(frames: &[FrameStats], target: TuneTarget) -> f64 {
    let values: Vec<f64> = match target {
        TuneTarget::RenderedTriangles(_) => {
            frames.iter().map(|f| f.triangles_rendered as f64).collect()
        }
        TuneTarget::AuditP95Px(_) => frames
            .iter()
            .filter_map(|f| f.audit.as_ref()?.projected.map(|e| e.p95))
            .collect(),
    };
    if values.is_empty() {
        f64::NAN
    } else {
        values.iter().sum::<f64>() / values.len() as f64
    }
}

/// The progress line of probe `k`:
/// `tune 'wu @6000': probe 4: tau_px=2.83 -> 6110 rendered triangles (target 6000)`.
pub fn probe_line(label: &str, tune: &Tune, k: usize, value: f64, mean: f64) -> String {
    format!(
        "tune '{label}': probe {k}: {}={} -> {} {} (target {})",
        tune.parameter,
        significant(value),
        mean_text(tune.target, mean),
        tune.target.unit(),
        mean_text(tune.target, tune.target.value()),
    )
}

/// A triangle mean as a whole number, an error with three decimals.
fn mean_text(target: TuneTarget, mean: f64) -> String {
    match target {
        TuneTarget::RenderedTriangles(_) => format!("{mean:.0}"),
        TuneTarget::AuditP95Px(_) => format!("{mean:.3}"),
    }
}

/// `value` with three significant digits, trailing zeros dropped (2.828 → 2.83, 30 → 30).
pub fn significant(value: f64) -> String {
    if !value.is_finite() || value == 0.0 {
        return format!("{value}");
    }
    let magnitude = value.abs().log10().floor() as i32;
    let decimals = (2 - magnitude).clamp(0, 8) as usize;
    let text = format!("{value:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The "Tuned entries" table of `report.md` (nothing when no entry is tuned).
pub fn write_tuned_entries(out: &mut String, labels: &[&str], records: &[Option<&TuningRecord>]) {
    if records.iter().all(Option::is_none) {
        return;
    }
    let _ = writeln!(
        out,
        "\n## {}\n\nThe parameter set by a search over probe runs (`tune` in the experiment); \
         the probe mean is over the probe frames, the run's over every frame.\n",
        section::TUNED_ENTRIES
    );
    let _ = writeln!(
        out,
        "| entry | parameter | probe mean / target | run mean | probes | reached |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|");
    for (label, record) in labels.iter().zip(records) {
        let Some(r) = record else { continue };
        let _ = writeln!(
            out,
            "| {} | {} = {} | {} / {} {} | {} | {} × {} frames (stride {}) | {} |",
            label.replace('|', "\\|"),
            r.parameter,
            significant(r.value),
            mean_text(r.target, r.probe_mean),
            mean_text(r.target, r.target.value()),
            r.target.unit(),
            mean_text(r.target, r.full_run_mean),
            r.probes.len(),
            r.probe_frames,
            r.probe_stride,
            if r.reached {
                "yes".to_string()
            } else if r.plateau.is_some() {
                format!("no (tolerance {}): plateau", r.tolerance)
            } else {
                format!("no (tolerance {})", r.tolerance)
            },
        );
    }
    for (label, record) in labels.iter().zip(records) {
        let Some(r) = record else { continue };
        if let Some(plateau) = &r.plateau {
            let _ = writeln!(
                out,
                "\n**{}: the search stopped on a plateau**, where the parameter stopped \
                 mattering: {}.",
                label.replace('|', "\\|"),
                plateau.sentence(r.parameter, r.target)
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(triangles: &[u64]) -> Vec<FrameStats> {
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

    #[test]
    fn a_plateau_is_explained_by_the_counters_or_said_plainly() {
        let target = TuneTarget::RenderedTriangles(5000.0);
        let same = [probe(&[10, 20]), probe(&[10, 20]), probe(&[10, 20])];
        let reason = plateau_reason(&same, &[], target, (0.125, 1.0));
        assert!(
            reason
                .starts_with("every probe on it drew the same number of triangles in every frame"),
            "{reason}"
        );
        let moving = [probe(&[10, 20]), probe(&[11, 20]), probe(&[10, 21])];
        assert_eq!(
            plateau_reason(&moving, &[], target, (0.125, 1.0)),
            "the rendered triangles did not change over the last 3 probes spanning [0.125, 1]"
        );
    }

    #[test]
    fn values_print_with_three_significant_digits() {
        assert_eq!(significant(2.828_427), "2.83");
        assert_eq!(significant(30.0), "30");
        assert_eq!(significant(0.000_123_4), "0.000123");
        assert_eq!(significant(1234.6), "1235");
    }
}
