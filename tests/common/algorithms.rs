//! Algorithm configurations, written once: each algorithm with its plainest options (a pure
//! function of the view where the algorithm allows it), for tests to vary with struct update
//! syntax (`WuConfig { depth_limit: Some(2), ..wu(6.0, ZoneVariant::Conservative) }`), and every
//! algorithm at one tolerance for the hard-case and invariance tests. `rottger` has no τ: its
//! configurations come separately ([`every_rottger`]).

use roamsim::sim::algorithm::rottger::DistanceNorm;
use roamsim::sim::algorithm::{
    AlgorithmConfig, BlockGoal, BudgetConfig, ChunkedConfig, GeomipmapConfig, LevelDifference,
    LindstromConfig, LodCurve, LodRounding, PatchDistance, Projection, ReferenceConfig, Refinement,
    RoamConfig, RoamGoal, RottgerConfig, SkirtDepth, SplitThreshold, VanekConfig, ViewThreshold,
    WuConfig,
};
use roamsim::sim::algorithm::{
    BlockDistance, PBlockShape, StitchingConfig, StitchingMethod, ViewDirection,
};
use roamsim::sim::hierarchy::NestingRule;
use roamsim::sim::zone::ZoneVariant;

/// Wu's criterion from scratch: split iff ℓ ≤ 0 wherever the node is, Wu's max nesting.
pub fn reference(tau_px: f64, zone: ZoneVariant) -> ReferenceConfig {
    ReferenceConfig {
        nesting: NestingRule::Max,
        tau_px,
        zone,
        threshold: SplitThreshold::LifeAtMost(0.0),
        refine: Refinement::Everywhere,
        view_threshold: ViewThreshold::InView,
    }
}

/// [`reference`] splitting only nodes whose bounding sphere meets the view cone (the reference
/// of [`wu_in_view`]).
pub fn reference_in_view(tau_px: f64, zone: ZoneVariant) -> ReferenceConfig {
    ReferenceConfig {
        refine: Refinement::InView,
        ..reference(tau_px, zone)
    }
}

/// Wu at a fixed τ: no budget, no traversal options, refining everywhere without the view cone,
/// 64 links per wheel.
pub fn wu(tau_px: f64, zone: ZoneVariant) -> WuConfig {
    WuConfig {
        nesting: NestingRule::Max,
        tau_px: Some(tau_px),
        budget: None,
        zone,
        block_priority: false,
        depth_limit: None,
        cone_culling: false,
        wheel_links: 64,
        refine: Refinement::Everywhere,
        morph_frames: None,
        strips: false,
    }
}

/// [`wu`] refining only in the view cone and keeping the in-view count (the paper's way).
pub fn wu_in_view(tau_px: f64, zone: ZoneVariant) -> WuConfig {
    WuConfig {
        cone_culling: true,
        refine: Refinement::InView,
        ..wu(tau_px, zone)
    }
}

/// Wu held at `triangles` by base shifting (the paper's rule: no dead band, k = 1.5), starting
/// from τ = `tau_px`, b within ±`base_limit`.
pub fn wu_budget(tau_px: f64, triangles: u64, base_limit: i64) -> WuConfig {
    WuConfig {
        budget: Some(BudgetConfig {
            triangles,
            dead_band: 0,
            base_limit,
            initial_tau_k: 1.5,
            tau_recentring: None,
        }),
        ..wu(tau_px, ZoneVariant::Conservative)
    }
}

/// Lindstrom'96 with blocks of (2^block_level + 1)² samples, its max nesting.
pub fn lindstrom(tau_px: f64, block_level: u32) -> LindstromConfig {
    LindstromConfig {
        nesting: NestingRule::Max,
        tau_px,
        block_level,
    }
}

/// ROAM splitting while a priority exceeds τ, the paper's max-plus-own nesting, no effects.
pub fn roam_tolerance(tau_px: f64) -> RoamConfig {
    RoamConfig {
        nesting: NestingRule::MaxPlusOwn,
        thickness: roamsim::sim::algorithm::ThicknessScope::PerTriangle,
        queue: roamsim::sim::algorithm::QueueKind::Buckets,
        goal: RoamGoal::TolerancePx(tau_px),
        deferral: false,
        culling_flags: false,
        strips: false,
    }
}

/// ROAM held at `triangles` by its dual-queue loop, no effects.
pub fn roam_target(triangles: u64) -> RoamConfig {
    RoamConfig {
        goal: RoamGoal::TargetTriangles(triangles),
        ..roam_tolerance(0.0)
    }
}

/// Every algorithm at tolerance `tau_px`, with the options that make it a pure function of the
/// view (no budget).
pub fn every_algorithm(tau_px: f64) -> Vec<AlgorithmConfig> {
    let mut configs = Vec::new();
    for zone in [ZoneVariant::Conservative, ZoneVariant::Paper] {
        configs.push(AlgorithmConfig::Reference(reference(tau_px, zone)));
        configs.push(AlgorithmConfig::Wu(wu(tau_px, zone)));
        // Refining only in view: its reference is the in-view reference.
        configs.push(AlgorithmConfig::Reference(reference_in_view(tau_px, zone)));
        configs.push(AlgorithmConfig::Wu(wu_in_view(tau_px, zone)));
    }
    for block_level in [1, 3] {
        configs.push(AlgorithmConfig::Lindstrom(lindstrom(tau_px, block_level)));
    }
    let roam = roam_tolerance(tau_px);
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

/// Geomipmapping at τ with patches of (2^patch_level + 1)² samples: the survey's one-level
/// limit, no morphing, the horizontal-view projection.
pub fn geomipmap(tau_px: f64, patch_level: u32) -> GeomipmapConfig {
    GeomipmapConfig {
        patch_level,
        goal: BlockGoal::TolerancePx(tau_px),
        level_difference: LevelDifference::AtMostOne,
        morph: false,
        projection: Projection::HorizontalView,
        box_culling: false,
    }
}

/// The chunked quadtree at τ with chunks of (2^chunk_level + 1)² vertices: the paper's skirts,
/// the horizontal-view projection, no effects.
pub fn chunked(tau_px: f64, chunk_level: u32) -> ChunkedConfig {
    ChunkedConfig {
        chunk_level,
        goal: BlockGoal::TolerancePx(tau_px),
        projection: Projection::HorizontalView,
        skirts: SkirtDepth::ChunkError,
        morph: false,
        culling: false,
        front_to_back: false,
        detail: None,
        loading: None,
    }
}

/// The chunked quadtree with every effect and option that is not the default: morphing, box
/// culling, front-to-back order, covering skirts, the exact projection.
pub fn chunked_with_everything(tau_px: f64, chunk_level: u32) -> ChunkedConfig {
    ChunkedConfig {
        projection: Projection::Exact,
        skirts: SkirtDepth::Covering,
        morph: true,
        culling: true,
        front_to_back: true,
        ..chunked(tau_px, chunk_level)
    }
}

/// Every block-based configuration at tolerance `tau_px`, with the options that make it a pure
/// function of the view: geomipmap with both level limits, morphing and the exact projection;
/// chunked plain and with everything (culling: its mesh depends on the frustum).
pub fn every_block_algorithm(tau_px: f64) -> Vec<AlgorithmConfig> {
    vec![
        AlgorithmConfig::Geomipmap(geomipmap(tau_px, 2)),
        AlgorithmConfig::Geomipmap(GeomipmapConfig {
            level_difference: LevelDifference::Any,
            morph: true,
            projection: Projection::Exact,
            ..geomipmap(tau_px, 3)
        }),
        AlgorithmConfig::Chunked(chunked(tau_px, 2)),
        AlgorithmConfig::Chunked(chunked_with_everything(tau_px, 1)),
    ]
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

/// Vaněk–Ježek patches of (2^n + 1)² samples with the paper's linear curve from `min_m` to
/// `max_m`, the default rounding and distance, no target, no culling.
pub fn vanek(patch_level: u32, min_m: f64, max_m: f64) -> VanekConfig {
    VanekConfig {
        patch_level,
        curve: LodCurve {
            min_dist_m: min_m,
            max_dist_m: max_m,
            exponent: 1.0,
            rounding: LodRounding::Down,
        },
        distance: PatchDistance::Box,
        target_triangles: None,
        box_culling: false,
    }
}

/// Every `vanek` configuration the hard cases and invariance properties run, distances scaled
/// by `scale`: the defaults; a bent curve rounded up, distances to the centres, with culling;
/// a triangle target (2000).
pub fn every_vanek(scale: f64) -> Vec<AlgorithmConfig> {
    let plain = vanek(2, 20.0 * scale, 300.0 * scale);
    vec![
        AlgorithmConfig::Vanek(plain),
        AlgorithmConfig::Vanek(VanekConfig {
            patch_level: 3,
            curve: LodCurve {
                exponent: 0.5,
                rounding: LodRounding::Up,
                ..plain.curve
            },
            distance: PatchDistance::Centre,
            box_culling: true,
            ..plain
        }),
        AlgorithmConfig::Vanek(VanekConfig {
            target_triangles: Some(2000),
            ..plain
        }),
    ]
}

/// The stitching strips at ρ_thr `threshold_px` over blocks down to 2^`block_level` cells,
/// with the paper's defaults (strips of 1 cell, d and θ to the block's centre, two-triangle
/// P-blocks, no culling).
pub fn stitching(threshold_px: f64, block_level: u32) -> StitchingConfig {
    StitchingConfig {
        threshold_px,
        block_level,
        strip_width_cells: 1.0,
        method: StitchingMethod::Strips,
        distance: BlockDistance::Centre,
        view_direction: ViewDirection::ToBlock,
        p_block: PBlockShape::TwoTriangles,
        culling: false,
    }
}

/// Every `stitching-strips` configuration the hard cases and invariance properties run: the
/// defaults; the strips with every other option and culling; Method I with the box distance and
/// culling; Method II with the look direction.
pub fn every_stitching() -> Vec<AlgorithmConfig> {
    let plain = stitching(1.0, 2);
    vec![
        AlgorithmConfig::Stitching(plain),
        AlgorithmConfig::Stitching(StitchingConfig {
            strip_width_cells: 0.5,
            distance: BlockDistance::Box,
            view_direction: ViewDirection::Look,
            p_block: PBlockShape::Fan,
            culling: true,
            ..plain
        }),
        AlgorithmConfig::Stitching(StitchingConfig {
            method: StitchingMethod::PowerOfTwo,
            distance: BlockDistance::Box,
            culling: true,
            ..plain
        }),
        AlgorithmConfig::Stitching(StitchingConfig {
            method: StitchingMethod::Uniform,
            view_direction: ViewDirection::Look,
            ..plain
        }),
    ]
}
