//! What a tuned entry's search found (`"tune"` in the experiment): the record `summary.json`
//! carries under `"tuning"`, the "Tuned entries" table of `report.md` and the progress line of
//! each probe. Documented in `docs/output-formats.md` ("summary.json", "report.md") and
//! `docs/experiment-format.md`, "Tuning to a target". It only reports: the search is
//! `sim::tuning`'s.

use super::report_md::section;
use crate::edge::experiment::{Tune, TuneTarget};
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
            } else {
                format!("no (tolerance {})", r.tolerance)
            },
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_print_with_three_significant_digits() {
        assert_eq!(significant(2.828_427), "2.83");
        assert_eq!(significant(30.0), "30");
        assert_eq!(significant(0.000_123_4), "0.000123");
        assert_eq!(significant(1234.6), "1235");
    }
}
