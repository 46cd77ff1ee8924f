//! Every algorithm configuration the hard-case and invariance tests run, with the options that
//! make each a pure function of the view (no budget).

use roamsim::sim::algorithm::{
    AlgorithmConfig, LindstromConfig, ReferenceConfig, RoamConfig, RoamGoal, SplitThreshold,
    WuConfig,
};
use roamsim::sim::zone::ZoneVariant;

/// Every algorithm at tolerance `tau_px`, with the options that make it a pure function of the
/// view (no budget).
pub fn every_algorithm(tau_px: f64) -> Vec<AlgorithmConfig> {
    let mut configs = Vec::new();
    for zone in [ZoneVariant::Conservative, ZoneVariant::Paper] {
        configs.push(AlgorithmConfig::Reference(ReferenceConfig {
            nesting: roamsim::sim::hierarchy::NestingRule::Max,
            tau_px,
            zone,
            threshold: SplitThreshold::LifeAtMost(0.0),
        }));
        configs.push(AlgorithmConfig::Wu(WuConfig {
            nesting: roamsim::sim::hierarchy::NestingRule::Max,
            tau_px: Some(tau_px),
            budget: None,
            zone,
            block_priority: false,
            depth_limit: None,
            cone_culling: false,
            wheel_links: 64,
        }));
    }
    for block_level in [1, 3] {
        configs.push(AlgorithmConfig::Lindstrom(LindstromConfig {
            nesting: roamsim::sim::hierarchy::NestingRule::Max,
            tau_px,
            block_level,
        }));
    }
    let roam = RoamConfig {
        nesting: roamsim::sim::hierarchy::NestingRule::MaxPlusOwn,
        thickness: roamsim::sim::algorithm::ThicknessScope::PerTriangle,
        queue: roamsim::sim::algorithm::QueueKind::Buckets,
        goal: RoamGoal::TolerancePx(tau_px),
        deferral: false,
        culling_flags: false,
        strips: false,
    };
    configs.push(AlgorithmConfig::Roam(roam));
    configs.push(AlgorithmConfig::Roam(RoamConfig {
        deferral: true,
        culling_flags: true,
        strips: true,
        ..roam
    }));
    configs.push(AlgorithmConfig::RoamRebuild(roam));
    configs
}
