//! One algorithm entry's parameters checked into its `AlgorithmConfig` (stage 2, no IO): each
//! algorithm's own rules and defaults, every problem with its field path. Here are the 4-8
//! family's entries (SPEC §5 and §6: reference, wu, lindstrom, roam, roam-rebuild, rottger); the
//! block-based algorithms' are in `block_lod.rs` and `block_strips.rs`, dispatched to by name.
//! Not the entry's label, sweep or `tune` (`entries.rs`, `tune.rs`). The parameters are
//! documented in `docs/experiment-format.md`.
//!
//! **One check for a written entry and a tuned one.** `tuned_spec` (`entries.rs`) sets a tuned
//! parameter's value and checks the entry again through [`entry_config`], so that every probe's
//! entry, and the real run's, is checked like a written one.

use super::block_lod::{chunked_config, geomipmap_config};
use super::block_strips::{stitching_config, vanek_config};
use super::format::{
    DistanceEntry, LindstromParameters, NestingEntry, QueueEntry, ReferenceParameters, RefineEntry,
    RoamParameters, RottgerParameters, ThicknessEntry, WuParameters, ZoneEntry,
};
use super::problems::{Problems, decode};
use crate::sim::algorithm::rottger::{DistanceNorm, LoadCount, LoadTarget};
use crate::sim::algorithm::{
    AlgorithmConfig, BudgetConfig, LindstromConfig, QueueKind, ReferenceConfig, Refinement,
    RoamConfig, RoamGoal, RottgerConfig, SplitThreshold, TauRecentring, ThicknessScope,
    ViewThreshold, WuConfig,
};
use crate::sim::hierarchy::NestingRule;
use crate::sim::zone::ZoneVariant;
use serde_json::Value;

/// Algorithms this build knows, as the experiment file names them.
pub const KNOWN_ALGORITHMS: &[&str] = &[
    "reference",
    "wu",
    "lindstrom",
    "roam",
    "roam-rebuild",
    "geomipmap",
    "chunked",
    "rottger",
    "vanek",
    "stitching-strips",
];

/// The configuration of the entry at `origin` for algorithm `name` with `parameters` (as
/// written, `tune` taken out), or `None` with its problems added.
pub(super) fn entry_config(
    k: &str,
    name: &str,
    parameters: &Value,
    problems: &mut Problems,
) -> Option<AlgorithmConfig> {
    match name {
        "reference" => decode::<ReferenceParameters>(k, parameters, problems).and_then(|p| {
            check_tau(k, p.tau_px, problems)?;
            Some(AlgorithmConfig::Reference(ReferenceConfig {
                nesting: nesting_rule(p.nesting, NestingRule::Max),
                tau_px: p.tau_px,
                zone: zone_variant(p.zone),
                threshold: SplitThreshold::LifeAtMost(0.0),
                refine: refinement(p.refine.unwrap_or(RefineEntry::Everywhere)),
                view_threshold: ViewThreshold::InView,
            }))
        }),
        "wu" => {
            decode::<WuParameters>(k, parameters, problems).and_then(|p| check_wu(k, &p, problems))
        }
        "lindstrom" => decode::<LindstromParameters>(k, parameters, problems).and_then(|p| {
            check_tau(k, p.tau_px, problems)?;
            check_block_level(k, p.block_level, problems)?;
            Some(AlgorithmConfig::Lindstrom(LindstromConfig {
                nesting: nesting_rule(p.nesting, NestingRule::Max),
                tau_px: p.tau_px,
                block_level: p.block_level,
            }))
        }),
        name @ ("roam" | "roam-rebuild") => decode::<RoamParameters>(k, parameters, problems)
            .and_then(|p| {
                let config = roam_config(k, &p, problems)?;
                if name == "roam" {
                    Some(AlgorithmConfig::Roam(config))
                } else if config.deferral {
                    problems.add(
                        format!("{k}.deferral"),
                        "true: roam-rebuild starts from scratch every frame, expected false \
                             or absent",
                    );
                    None
                } else {
                    Some(AlgorithmConfig::RoamRebuild(config))
                }
            }),
        "geomipmap" => geomipmap_config(k, parameters)
            .map_err(|list| problems.list.extend(list))
            .ok(),
        "chunked" => chunked_config(k, parameters)
            .map_err(|list| problems.list.extend(list))
            .ok(),
        "vanek" => vanek_config(k, parameters)
            .map_err(|list| problems.list.extend(list))
            .ok(),
        "stitching-strips" => stitching_config(k, parameters)
            .map_err(|list| problems.list.extend(list))
            .ok(),
        "rottger" => decode::<RottgerParameters>(k, parameters, problems)
            .and_then(|p| check_rottger(k, &p, problems)),
        other => {
            problems.add(
                format!("{k}.name"),
                format!(
                    "{other:?} is not an algorithm this build knows: expected one of {}",
                    KNOWN_ALGORITHMS.join(", ")
                ),
            );
            None
        }
    }
}

fn roam_config(origin: &str, p: &RoamParameters, problems: &mut Problems) -> Option<RoamConfig> {
    let goal = match (p.target_triangles, p.tau_px) {
        (Some(0), None) => {
            problems.add(
                format!("{origin}.target_triangles"),
                "0: expected at least 1 triangle",
            );
            return None;
        }
        (Some(target), None) => RoamGoal::TargetTriangles(target),
        (None, Some(tau)) => {
            check_tau(origin, tau, problems)?;
            RoamGoal::TolerancePx(tau)
        }
        _ => {
            problems.add(
                origin.to_string(),
                "expected exactly one of \"target_triangles\" and \"tau_px\"",
            );
            return None;
        }
    };
    Some(RoamConfig {
        nesting: nesting_rule(p.nesting, NestingRule::MaxPlusOwn),
        thickness: roam_thickness(p.thickness),
        queue: roam_queue(p.queue),
        goal,
        deferral: p.deferral,
        culling_flags: p.culling_flags,
        strips: p.strips,
    })
}

/// ROAM's thickness scope: per triangle (eq. 1) unless the entry says otherwise.
fn roam_thickness(entry: Option<ThicknessEntry>) -> ThicknessScope {
    match entry {
        None | Some(ThicknessEntry::PerTriangle) => ThicknessScope::PerTriangle,
        Some(ThicknessEntry::PerVertex) => ThicknessScope::PerVertex,
    }
}

/// ROAM's queues: Duchaineau's buckets unless the entry says otherwise.
fn roam_queue(entry: Option<QueueEntry>) -> QueueKind {
    match entry {
        None | Some(QueueEntry::Buckets) => QueueKind::Buckets,
        Some(QueueEntry::Heap) => QueueKind::Heap,
    }
}

fn nesting_rule(entry: Option<NestingEntry>, default: NestingRule) -> NestingRule {
    match entry {
        None => default,
        Some(NestingEntry::Max) => NestingRule::Max,
        Some(NestingEntry::MaxPlusOwn) => NestingRule::MaxPlusOwn,
    }
}

fn check_tau(origin: &str, tau_px: f64, problems: &mut Problems) -> Option<()> {
    if tau_px >= 0.0 && tau_px.is_finite() {
        Some(())
    } else {
        problems.add(
            format!("{origin}.tau_px"),
            format!("{tau_px}: expected a finite tolerance of at least 0 pixels"),
        );
        None
    }
}

/// Defaults of Wu's optional parameters (documented in docs/experiment-format.md).
const WU_DEFAULT_BASE_LIMIT: i64 = 1000;
const WU_DEFAULT_INITIAL_TAU_K: f64 = 1.5;
const WU_DEFAULT_WHEEL_LINKS: u32 = 256;
const WU_DEFAULT_RECENTRE_TAU_WINDOW_FRAMES: u32 = 16;
const WU_MAX_WHEEL_LINKS: u32 = 1 << 20;

/// Wu's goal: τ, the budget, or both; the budget's own fields only with a budget.
fn check_wu_goal(origin: &str, p: &WuParameters, problems: &mut Problems) {
    let field = |name: &str| format!("{origin}.{name}");
    if p.tau_px.is_none() && p.budget_triangles.is_none() {
        problems.add(
            origin.to_string(),
            "neither tau_px nor budget_triangles: expected a fixed τ, a triangle budget, or both",
        );
    }
    if let Some(tau) = p.tau_px {
        check_tau(origin, tau, problems);
    }
    if p.budget_triangles == Some(0) {
        problems.add(field("budget_triangles"), "0: expected at least 1 triangle");
    }
    if p.budget_triangles.is_none() {
        for (name, given) in [
            ("dead_band_triangles", p.dead_band_triangles.is_some()),
            ("base_limit", p.base_limit.is_some()),
            ("initial_tau_k", p.initial_tau_k.is_some()),
        ] {
            if given {
                problems.add(
                    field(name),
                    "only applies with a budget: expected budget_triangles as well",
                );
            }
        }
    }
    if let Some(limit) = p.base_limit
        && limit < 0
    {
        problems.add(field("base_limit"), format!("{limit}: expected at least 0"));
    }
    if let Some(k) = p.initial_tau_k
        && !(k > 0.0 && k.is_finite())
    {
        problems.add(
            field("initial_tau_k"),
            format!("{k}: expected a finite number above 0"),
        );
    }
}

/// Wu's entry: a fixed τ, a triangle budget or both ([`check_wu_goal`]), and the options of the
/// queues, the culling and the budget's τ re-centring.
fn check_wu(origin: &str, p: &WuParameters, problems: &mut Problems) -> Option<AlgorithmConfig> {
    let field = |name: &str| format!("{origin}.{name}");
    let n_problems = problems.list.len();
    check_wu_goal(origin, p, problems);
    // `refine` defaults to the paper's in-view refinement when the entry culls by the cone, and
    // `cone_culling` to on when the entry refines in view (the paper's budget counts what is in
    // view; `cone_culling: false` with `in_view` counts the whole mesh).
    let refine = p.refine.unwrap_or(if p.cone_culling == Some(true) {
        RefineEntry::InView
    } else {
        RefineEntry::Everywhere
    });
    let cone_culling = p.cone_culling.unwrap_or(refine == RefineEntry::InView);
    let recentre_tau = p.recentre_tau.unwrap_or(false);
    if recentre_tau && p.budget_triangles.is_none() {
        problems.add(
            field("recentre_tau"),
            "true without a budget: re-centring moves τ to keep b near 0, expected \
             budget_triangles as well",
        );
    }
    if let Some(window) = p.recentre_tau_window_frames {
        if !recentre_tau {
            problems.add(
                field("recentre_tau_window_frames"),
                "only applies with recentre_tau: expected \"recentre_tau\": true as well",
            );
        } else if window == 0 {
            problems.add(
                field("recentre_tau_window_frames"),
                "0: expected at least 1",
            );
        }
    }
    let wheel_links = p.wheel_links.unwrap_or(WU_DEFAULT_WHEEL_LINKS);
    if !(2..=WU_MAX_WHEEL_LINKS).contains(&wheel_links) {
        problems.add(
            field("wheel_links"),
            format!("{wheel_links}: expected 2 to {WU_MAX_WHEEL_LINKS}"),
        );
    }
    if p.morph_frames == Some(0) {
        problems.add(
            field("morph_frames"),
            "0: expected at least 1 (leave the key out for no morphing)",
        );
    }
    if problems.list.len() > n_problems {
        return None;
    }
    Some(AlgorithmConfig::Wu(WuConfig {
        nesting: nesting_rule(p.nesting, NestingRule::Max),
        tau_px: p.tau_px,
        budget: p.budget_triangles.map(|triangles| BudgetConfig {
            triangles,
            dead_band: p.dead_band_triangles.unwrap_or(0),
            base_limit: p.base_limit.unwrap_or(WU_DEFAULT_BASE_LIMIT),
            initial_tau_k: p.initial_tau_k.unwrap_or(WU_DEFAULT_INITIAL_TAU_K),
            tau_recentring: recentre_tau.then(|| TauRecentring {
                window_frames: p
                    .recentre_tau_window_frames
                    .unwrap_or(WU_DEFAULT_RECENTRE_TAU_WINDOW_FRAMES),
            }),
        }),
        zone: zone_variant(p.zone),
        block_priority: p.block_priority.unwrap_or(false),
        depth_limit: p.depth_limit,
        cone_culling,
        refine: refinement(refine),
        wheel_links,
        morph_frames: p.morph_frames,
        strips: p.strips.unwrap_or(false),
    }))
}

/// Lindstrom's blocks have (2^k + 1)² samples; the largest grid has level 15.
fn check_block_level(origin: &str, block_level: u32, problems: &mut Problems) -> Option<()> {
    if (1..=15).contains(&block_level) {
        Some(())
    } else {
        problems.add(
            format!("{origin}.block_level"),
            format!(
                "{block_level}: expected a block level k from 1 to 15 (blocks of (2^k+1)² samples)"
            ),
        );
        None
    }
}

fn refinement(refine: RefineEntry) -> Refinement {
    match refine {
        RefineEntry::InView => Refinement::InView,
        RefineEntry::Everywhere => Refinement::Everywhere,
    }
}

/// Röttger's parameters: C ≥ 2 (the paper's K bound), c ≥ 0 fixed or > 0 as a load target's
/// start (default 1), at most one target of at least 1.
fn check_rottger(
    origin: &str,
    p: &RottgerParameters,
    problems: &mut Problems,
) -> Option<AlgorithmConfig> {
    let field = |name: &str| format!("{origin}.{name}");
    let n_problems = problems.list.len();
    let minimum = p.minimum_resolution;
    if !(minimum >= 2.0 && minimum.is_finite()) {
        problems.add(
            field("minimum_resolution"),
            format!(
                "{minimum}: expected a finite C of at least 2 (the paper's K = C/(2(C-1)) needs it)"
            ),
        );
    }
    let both_targets = p.target_triangles.is_some() && p.target_fan_vertices.is_some();
    let load = rottger_load(origin, p, problems);
    let desired = match (p.desired_resolution, load) {
        (Some(c), None) if !(c >= 0.0 && c.is_finite()) => {
            problems.add(
                field("desired_resolution"),
                format!("{c}: expected a finite c of at least 0"),
            );
            c
        }
        (Some(c), Some(_)) if !(c > 0.0 && c.is_finite()) => {
            problems.add(
                field("desired_resolution"),
                format!("{c}: expected a finite starting c above 0 for the load target"),
            );
            c
        }
        (Some(c), _) => c,
        (None, Some(_)) => ROTTGER_DEFAULT_START_C,
        (None, None) if both_targets => 0.0,
        (None, None) => {
            problems.add(
                origin.to_string(),
                "neither desired_resolution nor a load target: expected a fixed c, \
                 target_triangles or target_fan_vertices",
            );
            0.0
        }
    };
    if problems.list.len() > n_problems {
        return None;
    }
    Some(AlgorithmConfig::Rottger(RottgerConfig {
        minimum_resolution: minimum,
        desired_resolution: desired,
        load,
        distance: match p.distance {
            None | Some(DistanceEntry::L1) => DistanceNorm::L1,
            Some(DistanceEntry::Euclidean) => DistanceNorm::Euclidean,
        },
        d2_propagation: p.d2_propagation,
        clipping: p.clipping,
        geomorphing: p.geomorphing,
    }))
}

/// Röttger's load target: at most one of `target_triangles` and `target_fan_vertices`, of at
/// least 1.
fn rottger_load(
    origin: &str,
    p: &RottgerParameters,
    problems: &mut Problems,
) -> Option<LoadTarget> {
    let field = |name: &str| format!("{origin}.{name}");
    let load = match (p.target_triangles, p.target_fan_vertices) {
        (Some(_), Some(_)) => {
            problems.add(
                origin.to_string(),
                "both target_triangles and target_fan_vertices: expected at most one load target",
            );
            None
        }
        (Some(target), None) => Some(LoadTarget {
            count: LoadCount::Triangles,
            target,
        }),
        (None, Some(target)) => Some(LoadTarget {
            count: LoadCount::FanVertices,
            target,
        }),
        (None, None) => None,
    };
    if let Some(load) = load
        && load.target == 0
    {
        let name = match load.count {
            LoadCount::Triangles => "target_triangles",
            LoadCount::FanVertices => "target_fan_vertices",
        };
        problems.add(field(name), "0: expected a target of at least 1");
    }
    load
}

/// The c a load target starts from when the entry gives none (documented in
/// docs/experiment-format.md).
const ROTTGER_DEFAULT_START_C: f64 = 1.0;

fn zone_variant(zone: Option<ZoneEntry>) -> ZoneVariant {
    match zone {
        Some(ZoneEntry::Paper) => ZoneVariant::Paper,
        Some(ZoneEntry::Conservative) | None => ZoneVariant::Conservative,
    }
}
