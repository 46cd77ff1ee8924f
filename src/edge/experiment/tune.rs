//! An algorithm entry's `"tune"` checked (stage 2, no IO): the target (mean rendered triangles,
//! or mean audited p95 error, over probe runs), the parameter it sets, its start, range and
//! sense, and the search's settings. Not the search (`sim::tuning`, where the choice of a search
//! over probe runs is recorded), not the entry with a value set (`tuned_spec`, in `entries.rs`),
//! not the probe runs (`edge::session`). Documented in `docs/experiment-format.md` ("Tuning to a
//! target").
//!
//! **One count target per entry.** `tune` sets the entry's triangle count through its parameter,
//! so an entry that also gives a count target of its own (`budget_triangles`,
//! `target_triangles`, `target_fan_vertices`) is refused; so is a sweep of the tuned parameter
//! (`entries.rs`), whose label would name a value the run does not use.
//!
//! **Checked at the start value.** When the entry does not write the tuned parameter, the
//! search's start is put there, so that the entry is checked, and listed, with the value the
//! search starts from.

use super::problems::{Problems, decode};
use crate::sim::tuning::{SearchSettings, Sense};
use serde::Deserialize;
use serde_json::{Map, Value};

/// Probe frames when the entry gives none (capped at the flight's frames).
pub const DEFAULT_PROBE_FRAMES: u64 = 200;
/// Relative tolerance when the entry gives none.
pub const DEFAULT_TOLERANCE: f64 = 0.02;
/// Most probes when the entry gives none.
pub const DEFAULT_MAX_PROBES: u32 = 24;

/// `"tune": {...}` as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TuneEntry {
    #[serde(default)]
    rendered_triangles: Option<f64>,
    #[serde(default)]
    audit_p95_px: Option<f64>,
    #[serde(default)]
    parameter: Option<String>,
    #[serde(default)]
    probe_frames: Option<u64>,
    #[serde(default)]
    tolerance: Option<f64>,
    #[serde(default)]
    max_probes: Option<u32>,
}

/// What a tuned entry's probes measure, and the mean sought.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TuneTarget {
    /// The mean over the probe frames of `triangles_rendered`.
    RenderedTriangles(f64),
    /// The mean over the probe frames of each frame's audited projected p95 error, px.
    AuditP95Px(f64),
}

impl TuneTarget {
    /// The field's name in the experiment file (and in `summary.json`'s record).
    pub fn field(&self) -> &'static str {
        match self {
            TuneTarget::RenderedTriangles(_) => "rendered_triangles",
            TuneTarget::AuditP95Px(_) => "audit_p95_px",
        }
    }

    pub fn value(&self) -> f64 {
        match *self {
            TuneTarget::RenderedTriangles(v) | TuneTarget::AuditP95Px(v) => v,
        }
    }

    /// What the mean counts, for the progress lines.
    pub fn unit(&self) -> &'static str {
        match self {
            TuneTarget::RenderedTriangles(_) => "rendered triangles",
            TuneTarget::AuditP95Px(_) => "px audited p95",
        }
    }
}

/// A checked `tune`.
#[derive(Clone, Debug, PartialEq)]
pub struct Tune {
    pub target: TuneTarget,
    /// The parameter set: an entry parameter's name, or `distance_scale` (vanek).
    pub parameter: &'static str,
    /// The search's first value: the entry's written value of the parameter, else the default.
    pub start: f64,
    pub probe_frames: u64,
    pub tolerance: f64,
    pub max_probes: u32,
    /// The values the search may probe.
    pub range: (f64, f64),
    /// How the rendered triangles move as the parameter grows.
    pub triangles_sense: Sense,
    /// Where the entry came from (`algorithms[k]`), for errors.
    pub(super) origin: String,
    /// The algorithm's name as the file writes it.
    pub(super) name: String,
}

impl Tune {
    /// The search's settings.
    pub fn search_settings(&self) -> SearchSettings {
        SearchSettings {
            start: self.start,
            target: self.target.value(),
            tolerance: self.tolerance,
            max_probes: self.max_probes,
            range: self.range,
            sense: match self.target {
                TuneTarget::RenderedTriangles(_) => self.triangles_sense,
                // Audited error falls as triangles grow.
                TuneTarget::AuditP95Px(_) => self.triangles_sense.reversed(),
            },
        }
    }
}

/// A tunable parameter: its name, default start, range and sense.
struct Tunable {
    parameter: &'static str,
    start: f64,
    range: (f64, f64),
    sense: Sense,
}

const TAU: Tunable = Tunable {
    parameter: "tau_px",
    start: 2.0,
    range: (1e-4, 1e4),
    sense: Sense::Decreasing,
};

/// The parameters `tune` may set for algorithm `name`, the default first.
fn tunables(name: &str) -> &'static [Tunable] {
    match name {
        "reference" | "wu" | "lindstrom" | "roam" | "roam-rebuild" | "geomipmap" | "chunked" => {
            &[TAU]
        }
        "stitching-strips" => &[Tunable {
            parameter: "rho_threshold_px",
            start: 1.0,
            range: (1e-4, 1e4),
            sense: Sense::Decreasing,
        }],
        "rottger" => &[
            Tunable {
                parameter: "desired_resolution",
                start: 30.0,
                range: (1e-4, 1e6),
                sense: Sense::Increasing,
            },
            Tunable {
                parameter: "minimum_resolution",
                start: 8.0,
                range: (2.0, 1e6),
                sense: Sense::Increasing,
            },
        ],
        "vanek" => &[Tunable {
            parameter: "distance_scale",
            start: 1.0,
            range: (1e-4, 1e4),
            sense: Sense::Increasing,
        }],
        _ => &[],
    }
}

/// The parameter an entry's (unchecked) `tune` sets: its `parameter`, else the algorithm's
/// default; `None` when neither names one `tune` can set.
pub(super) fn tuned_parameter(name: &str, tune: &Value) -> Option<&'static str> {
    let options = tunables(name);
    match tune.get("parameter").and_then(Value::as_str) {
        Some(wanted) => options.iter().find(|t| t.parameter == wanted),
        None => options.first(),
    }
    .map(|t| t.parameter)
}

/// Parameters that set an entry's triangle count themselves: none may be given with `tune`.
const COUNT_TARGETS: [&str; 3] = [
    "budget_triangles",
    "target_triangles",
    "target_fan_vertices",
];

/// Checks the entry's `tune` (`origin` is `algorithms[k]`); when the tuned parameter is an entry
/// parameter the entry does not write, puts the start there, so that the entry is checked (and
/// listed) with the value the search starts from.
pub(super) fn check_tune(
    origin: &str,
    name: &str,
    tune: &Value,
    parameters: &mut Map<String, Value>,
    audited: bool,
    problems: &mut Problems,
) -> Option<Tune> {
    // The start goes in first, so that a `tune` with its own problems adds no second one (an
    // entry without its τ).
    if let Some(tunable) =
        tuned_parameter(name, tune).and_then(|p| tunables(name).iter().find(|t| t.parameter == p))
        && tunable.parameter != "distance_scale"
        && !parameters.contains_key(tunable.parameter)
    {
        parameters.insert(tunable.parameter.to_string(), Value::from(tunable.start));
    }
    let entry: TuneEntry = decode(&format!("{origin}.tune"), tune, problems)?;
    let n_problems = problems.list.len();
    let clashing: Vec<&str> = COUNT_TARGETS
        .into_iter()
        .filter(|field| parameters.contains_key(*field))
        .collect();
    if !clashing.is_empty() {
        problems.add(
            format!("{origin}.tune"),
            format!(
                "tune and {} both set the entry's triangle count: expected one of them",
                clashing.join(" and ")
            ),
        );
    }
    let target = tune_target(origin, &entry, audited, problems);
    let tunable = tunable_of(origin, name, &entry, problems);
    check_search_limits(origin, &entry, problems);
    let tunable = tunable?;
    // The start: the written value (its own check reports a bad one), else the default.
    let start = match parameters.get(tunable.parameter) {
        Some(written) => written.as_f64().unwrap_or(tunable.start),
        None => {
            if tunable.parameter != "distance_scale" {
                parameters.insert(tunable.parameter.to_string(), Value::from(tunable.start));
            }
            tunable.start
        }
    };
    if problems.list.len() > n_problems {
        return None;
    }
    Some(Tune {
        target: target?,
        parameter: tunable.parameter,
        start: start.clamp(tunable.range.0, tunable.range.1),
        probe_frames: entry.probe_frames.unwrap_or(DEFAULT_PROBE_FRAMES),
        tolerance: entry.tolerance.unwrap_or(DEFAULT_TOLERANCE),
        max_probes: entry.max_probes.unwrap_or(DEFAULT_MAX_PROBES),
        range: tunable.range,
        triangles_sense: tunable.sense,
        origin: origin.to_string(),
        name: name.to_string(),
    })
}

/// The target: exactly one of `rendered_triangles` and `audit_p95_px`, finite and above 0; an
/// audited error only with the audit on.
fn tune_target(
    origin: &str,
    entry: &TuneEntry,
    audited: bool,
    problems: &mut Problems,
) -> Option<TuneTarget> {
    let at = |field: &str| format!("{origin}.tune.{field}");
    let target = match (entry.rendered_triangles, entry.audit_p95_px) {
        (Some(triangles), None) => Some(TuneTarget::RenderedTriangles(triangles)),
        (None, Some(p95)) => Some(TuneTarget::AuditP95Px(p95)),
        _ => {
            problems.add(
                format!("{origin}.tune"),
                "expected exactly one target: \"rendered_triangles\" or \"audit_p95_px\"",
            );
            None
        }
    };
    if let Some(target) = target {
        let value = target.value();
        if !(value > 0.0 && value.is_finite()) {
            problems.add(
                at(target.field()),
                format!("{value}: expected a finite target above 0"),
            );
        }
        if matches!(target, TuneTarget::AuditP95Px(_)) && !audited {
            problems.add(
                at("audit_p95_px"),
                "a target of audited error needs the audit: expected \"effects\": {\"audit\": \
                 {...}} in the experiment",
            );
        }
    }
    target
}

/// The parameter tuned: the entry's `parameter`, else the algorithm's default.
fn tunable_of(
    origin: &str,
    name: &str,
    entry: &TuneEntry,
    problems: &mut Problems,
) -> Option<&'static Tunable> {
    let at = |field: &str| format!("{origin}.tune.{field}");
    let options = tunables(name);
    match &entry.parameter {
        None => options.first(),
        Some(wanted) => {
            let found = options.iter().find(|t| t.parameter == wanted);
            if found.is_none() {
                let names: Vec<&str> = options.iter().map(|t| t.parameter).collect();
                problems.add(
                    at("parameter"),
                    format!(
                        "{wanted:?} is not a parameter tune can set for {name}: expected {}",
                        names.join(" or ")
                    ),
                );
            }
            found
        }
    }
}

/// The search's limits: at least 2 probe frames and 2 probes, a finite tolerance above 0.
fn check_search_limits(origin: &str, entry: &TuneEntry, problems: &mut Problems) {
    let at = |field: &str| format!("{origin}.tune.{field}");
    if let Some(frames) = entry.probe_frames
        && frames < 2
    {
        problems.add(at("probe_frames"), format!("{frames}: expected at least 2"));
    }
    if let Some(tolerance) = entry.tolerance
        && !(tolerance > 0.0 && tolerance.is_finite())
    {
        problems.add(
            at("tolerance"),
            format!("{tolerance}: expected a finite relative tolerance above 0"),
        );
    }
    if let Some(probes) = entry.max_probes
        && probes < 2
    {
        problems.add(at("max_probes"), format!("{probes}: expected at least 2"));
    }
}
