//! Every algorithm configuration the hard-case and invariance tests run, with the options that
//! make each a pure function of the view (no budget). `rottger` has no τ: its configurations
//! come separately ([`every_rottger`]).

use roamsim::sim::algorithm::rottger::DistanceNorm;
use roamsim::sim::algorithm::{
    AlgorithmConfig, LindstromConfig, ReferenceConfig, RoamConfig, RoamGoal, RottgerConfig,
    SplitThreshold, WuConfig,
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

/// Röttger's algorithm with a fixed c (no load target), at minimum resolution C and desired
/// resolution c, the paper's options: L1 distance, propagation, no clipping, geomorphing on.
pub fn rottger(minimum_resolution: f64, desired_resolution: f64) -> RottgerConfig {
    RottgerConfig {
        minimum_resolution,
        desired_resolution,
        load: None,
        distance: DistanceNorm::L1,
        d2_propagation: true,
        clipping: false,
        geomorphing: true,
    }
}

/// Every Röttger configuration the generic hard cases and invariance properties run: the
/// paper's options at C = 8, the Euclidean distance with clipping, local d2 at C = 2.
pub fn every_rottger() -> Vec<AlgorithmConfig> {
    vec![
        AlgorithmConfig::Rottger(rottger(8.0, 20.0)),
        AlgorithmConfig::Rottger(RottgerConfig {
            distance: DistanceNorm::Euclidean,
            clipping: true,
            ..rottger(4.0, 60.0)
        }),
        AlgorithmConfig::Rottger(RottgerConfig {
            d2_propagation: false,
            ..rottger(2.0, 5.0)
        }),
    ]
}
