//! Runtime detail below the source resolution (the `chunked` entry's `detail` effect,
//! Lauritsen–Nielsen §3.3–3.4): every frame of a low flight through the `--check` validators
//! and the chunked frame validator; the creation limit (chunks requested and not finished) and
//! the cache's cap in every frame; the velocity-based limit; every box enclosing its
//! synthesised descendants'; the synthesised chunks equal to the synthesised surface computed
//! for the whole terrain at once; the same synthesised chunks on every thread count; the two
//! audits, against the source and against the detail-extended surface.

mod common;

use common::algorithms::{chunked, chunked_with_everything};
use common::scenes::{DiagonalFlight, diagonal_flight};
use common::{bumpy_terrain, extra, fly_checked, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::chunked::detail::DetailField;
use roamsim::sim::algorithm::chunked::{ChunkId, DetailConfig};
use roamsim::sim::algorithm::columns::chunked::{
    CHUNKS_COARSER, DETAIL_CACHED, DETAIL_DEEPEST_DRAWN, DETAIL_EVICTED, DETAIL_REFUSED,
    DETAIL_SYNTHESISED,
};
use roamsim::sim::algorithm::{AlgorithmConfig, Chunked, ChunkedConfig};
use roamsim::sim::audit::AuditSettings;
use roamsim::sim::flight::Flight;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::run::{Effects, RunInputs, run_algorithm};
use roamsim::sim::view::ViewSettings;
use roamsim::sim::view::{Camera, Pose};
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};

fn detail(levels: u32, max_queued_chunks: u32, cache_chunks: u32) -> DetailConfig {
    DetailConfig {
        levels,
        seed: 2005,
        amplitude_m: 4.0,
        roughness: 0.5,
        max_queued_chunks,
        max_speed_per_spacing: None,
        cache_chunks,
    }
}

/// A flight 5 m above the ground along the terrain's diagonal, looking ahead and down, its yaw
/// swinging.
fn low_flight(hierarchy: &Hierarchy, frames: u32) -> Vec<Camera> {
    let flight = DiagonalFlight {
        frames,
        above_ground_m: 5.0,
        start: 0.1,
        span: 0.8,
        pitch: -0.35,
        yaw_swing: 0.3,
    };
    diagonal_flight(hierarchy, flight)
}

/// What one frame left: the detail columns and a hash of every cached chunk (ids and height
/// bits, in id order).
#[derive(Clone, Debug, PartialEq)]
struct DetailFrame {
    synthesised: f64,
    evicted: f64,
    cached: f64,
    refused: f64,
    coarser: f64,
    deepest_drawn: f64,
    cache_hash: u64,
}

fn cache_hash(algorithm: &Chunked) -> u64 {
    let mut hasher = DefaultHasher::new();
    for (id, heights) in algorithm.synthesised_chunks() {
        id.hash(&mut hasher);
        for z in heights {
            z.to_bits().hash(&mut hasher);
        }
    }
    hasher.finish()
}

/// Flies `config` over `cameras`, every frame checked; the frames' detail records.
fn fly(hierarchy: &Hierarchy, config: ChunkedConfig, cameras: &[Camera]) -> Vec<DetailFrame> {
    let mut algorithm = Chunked::new(hierarchy, config, &view_600());
    algorithm.validate_tree().unwrap();
    fly_checked(
        hierarchy,
        &mut algorithm,
        cameras,
        "detail",
        |frame, camera, stats, algorithm| {
            algorithm
                .validate_frame(camera)
                .unwrap_or_else(|e| panic!("frame {frame}: {e}"));
            let column = |name| extra(algorithm, &stats, name);
            DetailFrame {
                synthesised: column(DETAIL_SYNTHESISED),
                evicted: column(DETAIL_EVICTED),
                cached: column(DETAIL_CACHED),
                refused: column(DETAIL_REFUSED),
                coarser: column(CHUNKS_COARSER),
                deepest_drawn: column(DETAIL_DEEPEST_DRAWN),
                cache_hash: cache_hash(algorithm),
            }
        },
    )
}

#[test]
fn every_frame_keeps_the_creation_limit_and_the_cache_cap_and_draws_below_the_source() {
    // 65², chunks of 9²: source leaves at level 3; two synthesised levels below.
    let hierarchy = bumpy_terrain(6);
    let cameras = low_flight(&hierarchy, 60);
    for (name, base) in [
        ("plain", chunked(20.0, 3)),
        ("every effect", chunked_with_everything(20.0, 3)),
    ] {
        for (limit, cap) in [(8, 48), (4, 16), (64, 400)] {
            let config = ChunkedConfig {
                detail: Some(detail(2, limit, cap)),
                ..base
            };
            let frames = fly(&hierarchy, config, &cameras);
            for (k, frame) in frames.iter().enumerate() {
                assert!(
                    frame.synthesised <= f64::from(limit) && frame.cached <= f64::from(cap),
                    "{name}, limit {limit}, cap {cap}, frame {k}: {frame:?}"
                );
                assert_eq!(frame.synthesised % 4.0, 0.0, "{name}, frame {k}");
            }
            let deepest = frames.iter().map(|f| f.deepest_drawn).fold(0.0, f64::max);
            assert_eq!(deepest, 5.0, "{name}, limit {limit}, cap {cap}");
            let total = |f: fn(&DetailFrame) -> f64| frames.iter().map(f).sum::<f64>();
            assert!(
                total(|f| f.coarser) > 0.0,
                "{name}: a parent drawn while children wait"
            );
            if cap < 400 {
                assert!(
                    total(|f| f.evicted) > 0.0,
                    "{name}, cap {cap}: nothing evicted"
                );
                assert!(
                    total(|f| f.refused) > 0.0,
                    "{name}, cap {cap}: nothing refused"
                );
            }
            // The cache's count moves by what was made and evicted.
            for pair in frames.windows(2) {
                assert_eq!(
                    pair[1].cached,
                    pair[0].cached + pair[1].synthesised - pair[1].evicted
                );
            }
        }
    }
}

#[test]
fn the_synthesised_chunks_are_the_synthesised_surface_of_the_whole_terrain() {
    let hierarchy = bumpy_terrain(6);
    let cameras = low_flight(&hierarchy, 30);
    let config = ChunkedConfig {
        detail: Some(detail(2, 16, 400)),
        ..chunked(1.0, 3)
    };
    let mut algorithm = Chunked::new(&hierarchy, config, &view_600());
    fly_checked(
        &hierarchy,
        &mut algorithm,
        &cameras,
        "detail",
        |_, _, _, _| (),
    );
    let fields = [1, 2].map(|depth| DetailField::new(&hierarchy, &detail(2, 16, 400), depth));
    let chunks = algorithm.synthesised_chunks();
    assert!(chunks.len() >= 16, "{}", chunks.len());
    let cells = 8;
    for (id, heights) in chunks {
        let field = &fields[(id.level - 4) as usize];
        for b in 0..=cells {
            for a in 0..=cells {
                assert_eq!(
                    heights[(b * (cells + 1) + a) as usize].to_bits(),
                    field.height(id.x * cells + a, id.y * cells + b).to_bits(),
                    "{id:?} vertex ({a}, {b})"
                );
            }
        }
        // A synthesised chunk's error is half its parent's (§3.4.1).
        let parent = id.parent().unwrap();
        assert_eq!(
            algorithm.chunk(id).unwrap().error,
            algorithm.chunk(parent).unwrap().error * 0.5
        );
    }
    // The source leaves carry the estimated ε instead of 0.
    let leaf = ChunkId {
        level: 3,
        x: 0,
        y: 0,
    };
    assert!(algorithm.chunk(leaf).unwrap().error > 0.0);
}

#[test]
fn synthesis_is_the_same_on_every_thread_count() {
    let hierarchy = bumpy_terrain(6);
    let cameras = low_flight(&hierarchy, 40);
    let config = ChunkedConfig {
        detail: Some(detail(2, 8, 64)),
        ..chunked_with_everything(1.0, 3)
    };
    let alone = fly(&hierarchy, config, &cameras);
    assert!(alone.iter().any(|f| f.synthesised > 0.0));
    for threads in [2, 4] {
        let runs: Vec<Vec<DetailFrame>> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads)
                .map(|_| scope.spawn(|| fly(&hierarchy, config, &cameras)))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (thread, run) in runs.iter().enumerate() {
            if let Some(frame) = (0..alone.len()).find(|&k| run[k] != alone[k]) {
                panic!(
                    "{threads} threads, thread {thread}: divergence at frame {frame}: {:?} vs {:?}",
                    run[frame], alone[frame]
                );
            }
        }
    }
}

#[test]
fn the_detail_audit_measures_against_the_synthesised_surface_and_the_source_audit_against_the_source()
 {
    // 17², chunks of 5²: source leaves at level 2, one synthesised level. τ = 0 refines every
    // chunk with an error, so once the children are made the finest level is drawn everywhere.
    let hierarchy = bumpy_terrain(4);
    let config = ChunkedConfig {
        detail: Some(detail(1, 64, 64)),
        ..chunked(0.0, 2)
    };
    let pose = Pose {
        position: DVec3::new(80.0, 80.0, 400.0),
        yaw: 0.0,
        pitch: -std::f64::consts::FRAC_PI_2 + 0.01,
    };
    let flight = Flight::from_poses(vec![pose; 3]).unwrap();
    let truth = AlgorithmConfig::Chunked(config)
        .detail_truth(&hierarchy)
        .unwrap();
    assert_eq!(truth.depth(), 1);
    let view = ViewSettings {
        fovy: 120f64.to_radians(),
        ..view_600()
    };
    let inputs = RunInputs {
        hierarchy: &hierarchy,
        view: &view,
        flight: &flight,
        violations: &[],
        effects: Effects {
            audit: Some(AuditSettings {
                stride: 1,
                popping: false,
                detail_stride: None,
            }),
            culling: false,
            check_meshes: true,
        },
        max_triangles: None,
        detail_truth: Some(&truth),
    };
    let mut algorithm = Chunked::new(&hierarchy, config, &view);
    let frames = run_algorithm(&inputs, "detail", &mut algorithm, &mut |_| {}).unwrap();
    // Frame 0 draws the source leaves: exact at the source's samples, not at the synthesised
    // ones (4 times as many in each direction, less one).
    let (source0, detail0) = (frames[0].audit.unwrap(), frames[0].audit_detail.unwrap());
    assert_eq!(source0.samples_in_view, 17 * 17);
    assert_eq!(detail0.samples_in_view, 33 * 33);
    assert_eq!(source0.projected.unwrap().max, 0.0);
    assert!(detail0.projected.unwrap().max > 0.1, "{detail0:?}");
    // Frame 1 draws the synthesised level everywhere: exact against both (the synthesised
    // surface keeps the source samples).
    let (source1, detail1) = (frames[1].audit.unwrap(), frames[1].audit_detail.unwrap());
    assert_eq!(source1.projected.unwrap().max, 0.0);
    assert_eq!(detail1.projected.unwrap().max, 0.0, "{detail1:?}");
    assert_eq!(detail1.coverage.unwrap().holes, 0);
}

#[test]
fn every_box_encloses_its_synthesised_childrens_so_culling_opens_no_hole() {
    // Culling on, detail with a large amplitude (it rises well above the source leaves' boxes).
    let hierarchy = bumpy_terrain(6);
    let cameras = low_flight(&hierarchy, 60);
    let config = ChunkedConfig {
        detail: Some(DetailConfig {
            amplitude_m: 40.0,
            ..detail(2, 8, 400)
        }),
        ..chunked_with_everything(20.0, 3)
    };
    let mut algorithm = Chunked::new(&hierarchy, config, &view_600());
    let mut checked = 0;
    fly_checked(
        &hierarchy,
        &mut algorithm,
        &cameras,
        "boxes",
        |frame, _, _, algorithm| {
            for (id, _) in algorithm.synthesised_chunks() {
                let inner = *algorithm.chunk(id).expect("a held chunk is available");
                let mut child = id;
                while let Some(parent) = child.parent() {
                    let outer = algorithm
                        .chunk(parent)
                        .expect("an ancestor of a held chunk");
                    assert!(
                        outer.z_min <= inner.z_min && outer.z_max >= inner.z_max,
                        "frame {frame}: {parent:?}'s box {}..{} does not enclose {id:?}'s {}..{}",
                        outer.z_min,
                        outer.z_max,
                        inner.z_min,
                        inner.z_max
                    );
                    child = parent;
                    checked += 1;
                }
            }
        },
    );
    assert!(checked > 100, "{checked}");
}

#[test]
fn the_velocity_limit_refuses_detail_to_a_fast_eye_and_grants_it_to_a_still_one() {
    let hierarchy = bumpy_terrain(6);
    let moving = low_flight(&hierarchy, 30);
    let still = vec![moving[0]; 30];
    let synthesised = |cameras: &[Camera], k: f64| {
        let config = ChunkedConfig {
            detail: Some(DetailConfig {
                max_speed_per_spacing: Some(k),
                ..detail(2, 8, 400)
            }),
            ..chunked(20.0, 3)
        };
        fly(&hierarchy, config, cameras)[1..]
            .iter()
            .map(|f| f.synthesised)
            .sum::<f64>()
    };
    // The flight moves about 19 m a frame; the synthesised chunks' spacings are 5 m and 2.5 m.
    assert_eq!(synthesised(&moving, 0.1), 0.0, "a fast eye gets no detail");
    assert!(
        synthesised(&moving, 100.0) > 0.0,
        "a generous limit refuses nothing"
    );
    assert!(
        synthesised(&still, 0.1) > 0.0,
        "a still eye gets its detail"
    );
}
