//! Tuning an entry to a target (`"tune"`, documented in `docs/experiment-format.md`): the probe
//! runs of a tuned entry's search, run before its real run. Not the search (which values to
//! probe, which probe wins, and why a search rather than a controller: `sim::tuning`), nor the
//! checking of `tune` and the entry with a value set (`edge::experiment`), nor the record's
//! outputs (`edge::output::tuning`).
//!
//! **Probes keep the guarantees.** Each probe flies a strided subset of the flight
//! (`tune.probe_frames` frames, 200 by default: frames 0, s, 2s, …) with the speed bounds scaled
//! by the stride s, so incremental algorithms keep their guarantees over s frames of motion. A
//! probe flies with the experiment's culling, and with the audit (without popping) only for an
//! error target; no mesh checks, exports nor timing passes.
//!
//! **A probe's error stops the run.** A probe whose mesh goes over `limits.max_triangles` stops
//! the run (its frame given as the flight's), rather than being treated as a side of the target.
//!
//! **A plateau comes with its reason.** The frames of the last probes are kept, so that when the
//! search stops on a plateau (`sim::tuning`) the reason is found in their counters
//! (`edge::output::tuning::plateau_reason`), recorded, and told by the end-of-run warning.
//!
//! **The record travels with the result.** The search's record (value found, probes, whether the
//! target was reached) goes with the entry's result, and into `shard.json` for a shard; the full
//! run's mean is filled in after the real run, beside the probes' mean, so that the probes'
//! sampling error is visible.

use super::progress_sink::ProgressSink;
use crate::edge::experiment::{AlgorithmSpec, Experiment, Tune, TuneTarget, tuned_spec};
use crate::edge::output::tuning::{
    PlateauRecord, TuningRecord, mean_of_target, plateau_reason, probe_line,
};
use crate::sim::audit::AuditSettings;
use crate::sim::flight::{Flight, speed_violations};
use crate::sim::hierarchy::Hierarchy;
use crate::sim::run::{CheckError, Effects, RunError, RunInputs, run_algorithm};
use crate::sim::stats::FrameStats;
use crate::sim::tuning::{PLATEAU_PROBES, SearchResult, probe_speed, probe_stride, search};
use std::collections::VecDeque;

/// Runs a tuned entry's search (`sim::tuning`) over probe runs of the point's flight: each probe
/// flies `tune.probe_frames` frames spread over the flight, frames 0, s, 2s, … (s from
/// [`probe_stride`]), with the speed bounds multiplied by s, the experiment's culling, the audit
/// (without popping) only for an error target, no mesh checks, exports nor timing passes.
/// Returns the entry with the value found and the record of the search (its `full_run_mean` is
/// filled after the real run).
pub(super) fn tune_entry(
    experiment: &Experiment,
    hierarchy: &Hierarchy,
    spec: &AlgorithmSpec,
    tune: &Tune,
    progress: &dyn ProgressSink,
) -> Result<(AlgorithmSpec, TuningRecord), RunError> {
    let failed = |problem: String| RunError {
        algorithm: spec.label.clone(),
        frame: 0,
        error: CheckError::Tuning(problem),
    };
    let flight = &experiment.flight;
    let (stride, count) = probe_stride(flight.n_frames(), tune.probe_frames);
    let poses = (0..count).map(|i| *flight.pose(i * stride)).collect();
    let probe_flight = Flight::from_poses(poses).map_err(|e| failed(e.to_string()))?;
    let speed = probe_speed(experiment.speed, stride);
    let violations = speed_violations(&probe_flight, speed);
    let inputs = RunInputs {
        hierarchy,
        view: &experiment.view,
        flight: &probe_flight,
        violations: &violations,
        effects: probe_effects(experiment, tune),
        max_triangles: Some(experiment.max_triangles),
        detail_truth: None,
    };
    // The frames of the last probes, for the reason of a plateau the search may stop on.
    let mut recent: VecDeque<Vec<FrameStats>> = VecDeque::with_capacity(PLATEAU_PROBES);
    let mut extra_columns: &'static [&'static str] = &[];
    let found = search(&tune.search_settings(), |k, value| {
        let probe = tuned_spec(spec, tune, value).map_err(failed)?;
        let mut algorithm = probe.config.build(hierarchy, &experiment.view, speed);
        let label = format!(
            "{} (tuning probe {k}: {}={value})",
            spec.label, tune.parameter
        );
        let frames = run_algorithm(&inputs, &label, algorithm.as_mut(), &mut |_| {}).map_err(
            // The probe's frame k is the flight's frame k·s.
            |error| RunError {
                frame: error.frame * stride,
                ..error
            },
        )?;
        let mean = mean_of_target(&frames, tune.target);
        progress.tuning(&probe_line(&spec.label, tune, k, value, mean));
        extra_columns = algorithm.extra_columns();
        if recent.len() == PLATEAU_PROBES {
            recent.pop_front();
        }
        recent.push_back(frames);
        Ok(mean)
    })?;
    let tuned = tuned_spec(spec, tune, found.value).map_err(failed)?;
    let plateau = found.plateau.map(|plateau| {
        let n_probes = found.probes.len() - plateau.first_probe;
        let frames: Vec<Vec<FrameStats>> = recent.into_iter().rev().take(n_probes).rev().collect();
        PlateauRecord {
            values: plateau.values,
            means: plateau.means,
            probes: n_probes,
            reason: plateau_reason(&frames, extra_columns, tune.target, plateau.values),
        }
    });
    // Told at the end of the run, with the warning that the target was not reached (a plateau
    // is never within the tolerance: a probe within it ends the search first).
    let mut record = search_record(tune, found, (count, stride));
    record.plateau = plateau;
    Ok((tuned, record))
}

/// The effects a probe flies with: the experiment's culling, and its audit without popping only
/// for an error target; no mesh checks.
fn probe_effects(experiment: &Experiment, tune: &Tune) -> Effects {
    let audit = match tune.target {
        TuneTarget::AuditP95Px(_) => experiment.effects.audit.map(|a| AuditSettings {
            popping: false,
            ..a
        }),
        TuneTarget::RenderedTriangles(_) => None,
    };
    Effects {
        audit,
        culling: experiment.effects.culling,
        check_meshes: false,
    }
}

/// The record of a search that `found` a value over probes of `count` frames `stride` apart;
/// its `full_run_mean` is left for the real run.
fn search_record(tune: &Tune, found: SearchResult, (count, stride): (u64, u64)) -> TuningRecord {
    TuningRecord {
        target: tune.target,
        parameter: tune.parameter,
        value: found.value,
        probe_mean: found.mean,
        reached: found.reached,
        tolerance: tune.tolerance,
        probe_frames: count,
        probe_stride: stride,
        probes: found.probes,
        full_run_mean: f64::NAN,
        plateau: None,
    }
}
