//! Lindstrom'96 against its own criterion evaluated from scratch with no blocks (SPEC §6: the
//! brute-force reference is the ground truth of the block-based mesh).
//!
//! Exhaustive small cases: every eye position on a grid over 9×9 and 17×17 terrains, at a few
//! heights, tolerances and block levels, under both nesting rules and with anisotropic posts, one
//! frame each in sequence (so the inserted/deleted bookkeeping and the block state kept between
//! frames are exercised too): the block-based mesh equals the brute-force mesh and passes the
//! mesh validator. Then the shipped 1025² tile along the quickstart flight. Plus the limits: the
//! paper's tie rule (an error of exactly τ, an eye on a vertex), τ = 0, a far eye, flat terrain,
//! what the metric does off the view axis, and the experiment file.

mod common;

use common::{bumpy_terrain, camera_at, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::lindstrom::{FromScratchView, mesh_from_scratch};
use roamsim::sim::algorithm::{FrameInput, Lindstrom, LindstromConfig, LodAlgorithm};
use roamsim::sim::hierarchy::{Hierarchy, NestingRule};
use roamsim::sim::mesh::VertexSet;
use roamsim::sim::mesh::validate::validate_reported;
use roamsim::sim::metrics::{projected_error_px, vertical_projection_error_px};
use roamsim::sim::stats::FrameStats;
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose};

/// Names of the extra columns, in the order the algorithm declares them.
const BLOCKS_COARSEST: usize = 0;
const BLOCKS_FINEST: usize = 1;
const BLOCKS_PARTIAL: usize = 2;
const VERTICES_EVALUATED: usize = 3;
const VERTICES_BY_INTERVAL: usize = 4;
const FORCED_ACTIVATIONS: usize = 5;
const BLOCKS_CHANGED: usize = 6;
const INTERVAL_PROBES: usize = 7;

/// One Lindstrom instance on a terrain, with the brute force beside it.
struct Scene<'h> {
    hierarchy: &'h Hierarchy,
    nested_errors: Vec<f32>,
    config: LindstromConfig,
    algorithm: Lindstrom<'h>,
    frame: u64,
}

impl<'h> Scene<'h> {
    fn new(hierarchy: &'h Hierarchy, tau_px: f64, block_level: u32) -> Scene<'h> {
        Scene::with_nesting(hierarchy, tau_px, block_level, NestingRule::Max)
    }

    fn with_nesting(
        hierarchy: &'h Hierarchy,
        tau_px: f64,
        block_level: u32,
        nesting: NestingRule,
    ) -> Scene<'h> {
        let config = LindstromConfig {
            nesting,
            tau_px,
            block_level,
        };
        Scene {
            hierarchy,
            nested_errors: hierarchy.nested_vertex_errors(nesting),
            config,
            algorithm: Lindstrom::new(hierarchy, config, &view_600()),
            frame: 0,
        }
    }

    /// Runs one frame from `eye`, checks the mesh against the brute force and the validator,
    /// checks that the counters add up, and returns the frame's statistics.
    fn frame_matches_brute_force(&mut self, eye: DVec3) -> FrameStats {
        self.frame_matches_brute_force_seen_by(&camera_at(eye))
    }

    /// As [`Self::frame_matches_brute_force`], for any camera.
    fn frame_matches_brute_force_seen_by(&mut self, camera: &Camera) -> FrameStats {
        let eye = camera.eye;
        let mut stats = FrameStats::default();
        self.algorithm.update(
            &FrameInput {
                frame: self.frame,
                camera,
                broken_bounds: roamsim::sim::algorithm::BrokenBounds::NONE,
            },
            &mut stats,
        );
        self.frame += 1;
        let lattice = self.hierarchy.lattice();
        let expected = mesh_from_scratch(&FromScratchView {
            hierarchy: self.hierarchy,
            nested_errors: &self.nested_errors,
            eye,
            lambda: view_600().pixels_per_unit(),
            tau_px: self.config.tau_px,
        });
        let context = format!("eye {eye:?}, {:?}", self.config);
        assert!(
            self.algorithm.vertex_set() == &expected,
            "{context}: {} vertices, brute force {}",
            self.algorithm.vertex_set().len(),
            expected.len()
        );
        if let Err(error) = validate_reported(lattice, self.algorithm.vertex_set(), stats.triangles)
        {
            panic!("{context}: {error}");
        }
        assert_eq!(self.algorithm.triangle_count(), stats.triangles);
        let non_corner = (lattice.n_vertices() - 4) as f64;
        assert_eq!(
            stats.extra[VERTICES_EVALUATED] + stats.extra[VERTICES_BY_INTERVAL],
            non_corner,
            "{context}: every vertex is evaluated or decided by interval"
        );
        assert_eq!(
            stats.metric_evaluations as f64,
            stats.extra[VERTICES_EVALUATED]
        );
        assert_eq!(
            stats.extra[BLOCKS_COARSEST] + stats.extra[BLOCKS_FINEST] + stats.extra[BLOCKS_PARTIAL],
            self.algorithm.n_blocks() as f64,
            "{context}: every block is classified"
        );
        assert!(stats.extra[FORCED_ACTIVATIONS] <= (self.algorithm.vertex_set().len() - 4) as f64);
        assert!(stats.extra[BLOCKS_CHANGED] <= self.algorithm.n_blocks() as f64);
        stats
    }
}

/// Every eye position on the terrain's grid (on every post), at the given heights.
fn eyes_over(hierarchy: &Hierarchy, heights: &[f64]) -> Vec<DVec3> {
    let field = hierarchy.field();
    let side = field.side();
    let mut eyes = Vec::new();
    for j in 0..side {
        for i in 0..side {
            for &z in heights {
                eyes.push(field.position(i, j).truncate().extend(z));
            }
        }
    }
    eyes
}

/// Heights below the terrain, inside its height range, just above it, and high above.
fn eye_heights(hierarchy: &Hierarchy) -> Vec<f64> {
    let (min_z, max_z) = hierarchy.field().height_range();
    let (min_z, max_z) = (f64::from(min_z), f64::from(max_z));
    vec![
        min_z - 5.0,
        0.5 * (min_z + max_z),
        max_z + 1.0,
        max_z + 60.0,
        2_000.0,
    ]
}

/// What the exhaustive runs saw, summed over every frame.
#[derive(Debug, Default)]
struct Seen {
    fewest_triangles: u64,
    most_triangles: u64,
    /// Sums of the extra columns.
    extra: [f64; 6],
}

impl Seen {
    /// The views differed, and every kind of block decision and both kinds of vertex decision
    /// happened, so the comparison exercised every path of the coarse step.
    fn covers_every_decision(&self) {
        assert!(self.fewest_triangles < self.most_triangles, "{self:?}");
        for column in [
            BLOCKS_COARSEST,
            BLOCKS_FINEST,
            BLOCKS_PARTIAL,
            VERTICES_EVALUATED,
            VERTICES_BY_INTERVAL,
            FORCED_ACTIVATIONS,
        ] {
            assert!(
                self.extra[column] > 0.0,
                "column {column} never counted: {self:?}"
            );
        }
    }
}

fn check_every_eye(level: u32, taus: &[f64], block_levels: &[u32]) -> Seen {
    check_every_eye_on(&bumpy_terrain(level), taus, block_levels, NestingRule::Max)
}

fn check_every_eye_on(
    hierarchy: &Hierarchy,
    taus: &[f64],
    block_levels: &[u32],
    nesting: NestingRule,
) -> Seen {
    let eyes = eyes_over(hierarchy, &eye_heights(hierarchy));
    let mut seen = Seen {
        fewest_triangles: u64::MAX,
        ..Seen::default()
    };
    for &tau_px in taus {
        for &block_level in block_levels {
            let mut scene = Scene::with_nesting(hierarchy, tau_px, block_level, nesting);
            for &eye in &eyes {
                let stats = scene.frame_matches_brute_force(eye);
                seen.fewest_triangles = seen.fewest_triangles.min(stats.triangles);
                seen.most_triangles = seen.most_triangles.max(stats.triangles);
                for (sum, value) in seen.extra.iter_mut().zip(&stats.extra) {
                    *sum += value;
                }
            }
        }
    }
    seen
}

#[test]
fn every_eye_over_a_9_by_9_terrain_gives_the_brute_force_mesh() {
    check_every_eye(3, &[0.5, 2.0, 8.0, 40.0], &[1, 2, 3]).covers_every_decision();
}

#[test]
fn every_eye_over_a_17_by_17_terrain_gives_the_brute_force_mesh() {
    check_every_eye(4, &[1.0, 4.0, 16.0], &[1, 2, 4]).covers_every_decision();
}

#[test]
fn every_eye_over_9_by_9_and_17_by_17_terrains_matches_under_the_max_plus_own_rule() {
    check_every_eye_on(
        &bumpy_terrain(3),
        &[0.5, 8.0],
        &[1, 3],
        NestingRule::MaxPlusOwn,
    )
    .covers_every_decision();
    check_every_eye_on(
        &bumpy_terrain(4),
        &[1.0, 16.0],
        &[2, 4],
        NestingRule::MaxPlusOwn,
    )
    .covers_every_decision();
}

#[test]
fn every_eye_over_a_terrain_with_anisotropic_posts_matches_under_both_rules() {
    // 10 m east–west, 37 m north–south, and 2.5 m × 1 m: the blocks' boxes are not square.
    for (dx, dy) in [(10.0, 37.0), (2.5, 1.0)] {
        let hierarchy = reshaped_bumpy_spacing(4, Spacing { dx, dy }, |z| z);
        for nesting in [NestingRule::Max, NestingRule::MaxPlusOwn] {
            check_every_eye_on(&hierarchy, &[1.0, 8.0], &[1, 2], nesting).covers_every_decision();
        }
    }
}

#[test]
fn an_error_of_exactly_tau_is_removed_as_the_paper_says() {
    // One vertex of a flat 3×3 terrain raised by δ: the centre (its only non-corner vertex with
    // an error besides its edge midpoints, which stay flat). Seen side-on from 100 m at λ = 519.6,
    // its error is λ·δ·100/100² px; τ is set to exactly that.
    let side = 3;
    let mut heights = vec![0.0f32; side * side];
    heights[4] = 1.0;
    let field = Heightfield::new(side, heights, Spacing { dx: 1.0, dy: 1.0 }).unwrap();
    let hierarchy = Hierarchy::new(field);
    let centre = hierarchy.field().position(1, 1);
    let eye = centre + DVec3::new(-100.0, 0.0, 0.0);
    let lambda = view_600().pixels_per_unit();
    let delta = f64::from(hierarchy.nested_vertex_errors(NestingRule::Max)[4]);
    let exactly = lambda * delta * 100.0 / (100.0 * 100.0);
    let mut at_tau = Scene::new(&hierarchy, exactly, 1);
    at_tau.frame_matches_brute_force(eye);
    assert!(
        !at_tau.algorithm.vertex_set().contains(4),
        "error = τ: removed"
    );
    let mut below_tau = Scene::new(&hierarchy, exactly * (1.0 - 1e-9), 1);
    below_tau.frame_matches_brute_force(eye);
    assert!(
        below_tau.algorithm.vertex_set().contains(4),
        "error > τ: kept"
    );
}

#[test]
fn an_eye_exactly_on_a_vertex_removes_it_unless_closure_needs_it() {
    let hierarchy = bumpy_terrain(4);
    let nested = hierarchy.nested_vertex_errors(NestingRule::Max);
    let lattice = hierarchy.lattice();
    let vertex = roamsim::sim::hierarchy::GridPoint::new(5, 7);
    assert!(nested[lattice.id(vertex) as usize] > 0.0);
    let eye = hierarchy.field().position(5, 7);
    // A large τ keeps nothing for itself: the vertex under the eye projects its error to 0.
    let mut coarse = Scene::new(&hierarchy, 1e6, 2);
    let stats = coarse.frame_matches_brute_force(eye);
    assert!(
        !coarse
            .algorithm
            .vertex_set()
            .contains_point(lattice, vertex)
    );
    assert_eq!(stats.triangles, 2);
    // A small τ keeps its neighbours, which need it: it is back, as a forced activation.
    let mut fine = Scene::new(&hierarchy, 1.0, 2);
    let stats = fine.frame_matches_brute_force(eye);
    assert!(fine.algorithm.vertex_set().contains_point(lattice, vertex));
    assert!(stats.extra[FORCED_ACTIVATIONS] >= 1.0);
}

#[test]
fn tau_zero_keeps_every_vertex_with_an_error_not_straight_below_the_eye() {
    let hierarchy = bumpy_terrain(4);
    let nested = hierarchy.nested_vertex_errors(NestingRule::Max);
    let lattice = hierarchy.lattice();
    let mut with_error = VertexSet::base_mesh(lattice);
    for (id, &delta) in nested.iter().enumerate() {
        if delta > 0.0 {
            with_error.insert(id as u32);
        }
    }
    for block_level in [1, 2, 4] {
        let mut scene = Scene::new(&hierarchy, 0.0, block_level);
        // Off the grid and far away: every vertex with an error is kept for itself, and the
        // intervals decide them all.
        let stats = scene.frame_matches_brute_force(DVec3::new(-500.0, 20.0, 1e5));
        assert!(
            scene.algorithm.vertex_set() == &with_error,
            "k = {block_level}"
        );
        assert_eq!(stats.extra[FORCED_ACTIVATIONS], 0.0);
        assert_eq!(stats.metric_evaluations, 0);
        // Straight above the vertex (8, 8): its own error projects to 0, but every other vertex
        // depends on it, so closure brings it back as the frame's one forced activation.
        let stats = scene.frame_matches_brute_force(DVec3::new(80.0, 80.0, 30.0));
        assert!(
            scene.algorithm.vertex_set() == &with_error,
            "k = {block_level}"
        );
        assert_eq!(stats.extra[FORCED_ACTIVATIONS], 1.0);
    }
}

/// The true projected length of a short vertical segment, divided by the vertical-projection
/// metric, at a pixel (x right, y up from the image centre) of a camera at pitch −15°.
fn perspective_over_metric(pixel_x: f64, pixel_y: f64) -> f64 {
    let camera = Camera::new(
        &Pose {
            position: DVec3::ZERO,
            yaw: 0.4,
            pitch: (-15f64).to_radians(),
        },
        view_600(),
    );
    let lambda = camera.settings.pixels_per_unit();
    let direction =
        camera.forward + camera.right * (pixel_x / lambda) + camera.up * (pixel_y / lambda);
    let point = direction * 200.0;
    let delta = 1e-4;
    let projected = projected_error_px(&camera, point, delta).unwrap();
    projected / vertical_projection_error_px(DVec3::ZERO, point, delta, lambda)
}

#[test]
fn off_the_view_axis_the_metric_understates_the_projection_by_the_documented_factors() {
    // docs/reproductions/lindstrom.md and lindstrom/mod.rs quote these (600×600, fovy 60°).
    let cases = [
        ("centre", 0.0, 0.0, 1.0),
        ("bottom edge", 0.0, -300.0, 1.333),
        ("bottom corner", 300.0, -300.0, 1.383),
        ("top corner", 300.0, 300.0, 1.493),
    ];
    for (name, x, y, factor) in cases {
        let measured = perspective_over_metric(x, y);
        assert!((measured - factor).abs() < 5e-4, "{name}: {measured}");
    }
}

#[test]
fn the_real_tile_matches_the_brute_force_along_the_quickstart_flight() {
    let experiment = quickstart_experiment();
    let hierarchy = Hierarchy::new(experiment.field.clone());
    for nesting in [NestingRule::Max, NestingRule::MaxPlusOwn] {
        let mut scene = Scene::with_nesting(&hierarchy, 2.0, 4, nesting);
        // Consecutive frames (block state carried over) and a jump (state far off).
        for frame in [0u64, 1, 2, 3, 200, 201] {
            let camera = Camera::new(
                &experiment.field.local_pose(experiment.flight.pose(frame)),
                experiment.view,
            );
            let stats = scene.frame_matches_brute_force_seen_by(&camera);
            if frame == 1 || frame == 3 || frame == 201 {
                assert!(
                    stats.extra[BLOCKS_CHANGED] < 20.0,
                    "frame {frame}: {stats:?}"
                );
            }
            assert!(stats.extra[INTERVAL_PROBES] > 0.0);
        }
    }
}

#[test]
fn keeping_block_state_between_frames_saves_search_probes_and_changes_no_mesh() {
    // The same flight twice: one instance carries its block state from frame to frame, the other
    // is rebuilt every frame (cold state). Same meshes; fewer probes with the state kept.
    let hierarchy = bumpy_terrain(7);
    let mut warm = Scene::new(&hierarchy, 1.0, 3);
    let (mut warm_probes, mut cold_probes) = (0.0, 0.0);
    for frame in 0..30 {
        let eye = DVec3::new(
            100.0 + 9.0 * f64::from(frame),
            300.0 + 4.0 * f64::from(frame),
            90.0,
        );
        let stats = warm.frame_matches_brute_force(eye);
        let mut cold = Scene::new(&hierarchy, 1.0, 3);
        let cold_stats = cold.frame_matches_brute_force(eye);
        assert!(
            cold.algorithm.vertex_set() == warm.algorithm.vertex_set(),
            "frame {frame}"
        );
        if frame > 0 {
            warm_probes += stats.extra[INTERVAL_PROBES];
            cold_probes += cold_stats.extra[INTERVAL_PROBES];
        }
    }
    assert!(
        warm_probes < 0.8 * cold_probes,
        "probes with state {warm_probes}, without {cold_probes}"
    );
}

/// The shipped quickstart experiment, loaded.
fn quickstart_experiment() -> roamsim::edge::experiment::Experiment {
    roamsim::edge::experiment::load(
        &common::experiment::repository().join("experiments/quickstart.json"),
    )
    .unwrap()
}

#[test]
fn a_far_eye_gives_the_base_mesh_without_evaluating_anything() {
    let hierarchy = bumpy_terrain(4);
    let mut scene = Scene::new(&hierarchy, 1.0, 2);
    let stats = scene.frame_matches_brute_force(DVec3::new(1.0e7, -3.0e7, 5.0e6));
    assert!(scene.algorithm.vertex_set() == &VertexSet::base_mesh(hierarchy.lattice()));
    assert_eq!(stats.triangles, 2);
    assert_eq!(stats.metric_evaluations, 0);
    assert_eq!(
        stats.extra[BLOCKS_COARSEST],
        scene.algorithm.n_blocks() as f64
    );
}

#[test]
fn flat_terrain_stays_at_the_base_mesh_even_at_tau_zero() {
    let side = 17;
    let field = Heightfield::new(
        side,
        vec![123.0; side * side],
        Spacing { dx: 10.0, dy: 10.0 },
    )
    .unwrap();
    let hierarchy = Hierarchy::new(field);
    let mut scene = Scene::new(&hierarchy, 0.0, 2);
    let stats = scene.frame_matches_brute_force(DVec3::new(80.0, 80.0, 123.0));
    assert_eq!(stats.triangles, 2);
}

#[test]
fn moving_back_and_forth_reports_what_entered_and_left_the_mesh() {
    let hierarchy = bumpy_terrain(4);
    let mut scene = Scene::new(&hierarchy, 2.0, 2);
    let near = DVec3::new(20.0, 20.0, 30.0);
    let far = DVec3::new(150.0, 150.0, 30.0);
    let first = scene.frame_matches_brute_force(near);
    let mesh_near = scene.algorithm.vertex_set().clone();
    let second = scene.frame_matches_brute_force(far);
    let mesh_far = scene.algorithm.vertex_set().clone();
    let third = scene.frame_matches_brute_force(near);
    assert_eq!(first.vertices_inserted as usize, mesh_near.len() - 4);
    let only_near = mesh_near
        .iter()
        .filter(|&id| !mesh_far.contains(id))
        .count() as u64;
    let only_far = mesh_far
        .iter()
        .filter(|&id| !mesh_near.contains(id))
        .count() as u64;
    assert!(only_near > 0 && only_far > 0, "the two views must differ");
    assert_eq!(
        (second.vertices_deleted, second.vertices_inserted),
        (only_near, only_far)
    );
    assert_eq!(
        (third.vertices_deleted, third.vertices_inserted),
        (only_far, only_near)
    );
    assert_eq!((third.splits, third.merges), (only_near, only_far));
}

#[test]
fn the_block_quadtree_is_valid_for_every_block_level() {
    let hierarchy = bumpy_terrain(5);
    for block_level in 1..=6 {
        let algorithm = Lindstrom::new(
            &hierarchy,
            LindstromConfig {
                nesting: roamsim::sim::hierarchy::NestingRule::Max,
                tau_px: 1.0,
                block_level,
            },
            &view_600(),
        );
        assert_eq!(algorithm.block_level(), block_level.min(5));
        assert_eq!(algorithm.validate_blocks(), Ok(()), "k = {block_level}");
    }
}

#[test]
fn an_experiment_names_lindstrom_with_its_tolerance_and_block_level() {
    let configs = common::experiment::load_with_algorithms(serde_json::json!([
        { "name": "lindstrom", "label": "lindstrom τ=1", "tau_px": 1, "block_level": 4 }
    ]));
    assert_eq!(
        configs,
        Ok(vec![roamsim::sim::algorithm::AlgorithmConfig::Lindstrom(
            LindstromConfig {
                nesting: roamsim::sim::hierarchy::NestingRule::Max,
                tau_px: 1.0,
                block_level: 4
            }
        )])
    );
}

#[test]
fn an_experiment_with_a_bad_lindstrom_entry_names_each_field() {
    let problems = common::experiment::load_with_algorithms(serde_json::json!([
        { "name": "lindstrom", "label": "a", "tau_px": 1, "block_level": 0 },
        { "name": "lindstrom", "label": "b", "tau_px": -2, "block_level": 4 },
        { "name": "lindstrom", "label": "c", "tau_px": 1 },
        { "name": "lindstrom", "label": "d", "tau_px": 1, "block_level": 3, "zone": "paper" }
    ]))
    .unwrap_err();
    assert_eq!(problems.len(), 4, "{problems:#?}");
    assert!(
        problems[0]
            .starts_with("algorithms[0].block_level: 0: expected a block level k from 1 to 15")
    );
    assert!(problems[1].starts_with("algorithms[1].tau_px: "));
    assert!(problems[2].starts_with("algorithms[2]") && problems[2].contains("block_level"));
    assert!(problems[3].starts_with("algorithms[3]") && problems[3].contains("zone"));
}

/// `bumpy_terrain(level)` with its heights mapped by `height` and its posts `post_m` apart.
fn reshaped_bumpy(level: u32, post_m: f64, height: impl Fn(f32) -> f32) -> Hierarchy {
    let spacing = Spacing {
        dx: post_m,
        dy: post_m,
    };
    reshaped_bumpy_spacing(level, spacing, height)
}

/// `bumpy_terrain(level)` with its heights mapped by `height` and the given posts.
fn reshaped_bumpy_spacing(level: u32, spacing: Spacing, height: impl Fn(f32) -> f32) -> Hierarchy {
    let bumpy = bumpy_terrain(level);
    let field = bumpy.field();
    let heights = field.heights().iter().map(|&z| height(z)).collect();
    Hierarchy::new(Heightfield::new(field.side(), heights, spacing).unwrap())
}

#[test]
fn scaling_terrain_and_eye_by_four_changes_no_decision() {
    let small = bumpy_terrain(4);
    let large = reshaped_bumpy(4, 40.0, |z| 4.0 * z);
    for block_level in [1, 3] {
        let mut small_scene = Scene::new(&small, 1.5, block_level);
        let mut large_scene = Scene::new(&large, 1.5, block_level);
        for eye in [DVec3::new(35.0, 60.0, 45.0), DVec3::new(-40.0, 170.0, 12.5)] {
            let small_stats = small_scene.frame_matches_brute_force(eye);
            let large_stats = large_scene.frame_matches_brute_force(4.0 * eye);
            assert!(small_scene.algorithm.vertex_set() == large_scene.algorithm.vertex_set());
            assert_eq!(small_stats.extra, large_stats.extra);
        }
    }
}

#[test]
fn millimetre_relief_and_ten_kilometre_heights_still_match_the_brute_force() {
    let millimetres = reshaped_bumpy(4, 10.0, |z| 1e-4 * z);
    let high = reshaped_bumpy(4, 10.0, |z| 10_000.0 + z);
    let deep = reshaped_bumpy(4, 10.0, |z| z - 10_000.0);
    for (hierarchy, eye_z) in [(&millimetres, 0.3), (&high, 10_050.0), (&deep, -9_950.0)] {
        for tau_px in [0.0, 0.01, 1.0] {
            let mut scene = Scene::new(hierarchy, tau_px, 2);
            for eye in eyes_over(hierarchy, &[eye_z]) {
                scene.frame_matches_brute_force(eye);
            }
        }
    }
}

#[test]
fn a_checked_run_of_the_real_tile_writes_the_lindstrom_columns() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = common::experiment::short_quickstart(3);
    experiment["algorithms"] = serde_json::json!([
        { "name": "lindstrom", "label": "lindstrom τ=2", "tau_px": 2, "block_level": 4 }
    ]);
    let path = common::experiment::save(dir.path(), "lindstrom", &experiment);
    let out = dir.path().join("out");
    let options = roamsim::edge::session::RunOptions {
        out_dir: Some(out.clone()),
        check_meshes: true,
        threads: Some(1),
        command_line: None,
        max_frames: None,
        shard: None,
        timing: Default::default(),
    };
    roamsim::edge::session::run_experiment(&path, &options, &roamsim::edge::session::NoProgress)
        .unwrap();
    let csv = std::fs::read_to_string(out.join("frames.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|line| line.split(',').collect()).collect();
    assert_eq!(rows.len(), 3);
    for row in &rows {
        let value = |name: &str| row[column(name)].parse::<f64>().unwrap();
        assert!(value("triangles") > 2.0);
        assert_eq!(
            value("vertices_evaluated") + value("vertices_by_interval"),
            (1025.0 * 1025.0) - 4.0
        );
        assert_eq!(
            value("blocks_coarsest") + value("blocks_finest") + value("blocks_partial"),
            5461.0,
            "1 + 4 + … + 4^6 blocks of 17² samples on a 1025² grid"
        );
        assert!(
            value("forced_activations") > 0.0,
            "closure forces parents on a real tile"
        );
    }
}
