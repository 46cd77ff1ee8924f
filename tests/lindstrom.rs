//! Lindstrom'96 against its own criterion evaluated from scratch with no blocks.
//!
//! Exhaustive small cases: every eye position on a grid over 9×9 and 17×17 terrains, at a few
//! heights, tolerances and block levels, one frame each in sequence (so the inserted/deleted
//! bookkeeping is exercised too): the block-based mesh equals the brute-force mesh and passes the
//! mesh validator. Plus the limits: τ = 0 keeps every vertex with an error, a far eye gives the
//! base mesh, flat terrain gives the base mesh, and the experiment file accepts and checks it.

mod common;

use common::algorithms::lindstrom;
use common::{bumpy_terrain, camera_at, checked_step, extra, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::columns::lindstrom::{
    BLOCKS_COARSEST, BLOCKS_FINEST, BLOCKS_PARTIAL, FORCED_ACTIVATIONS, VERTICES_BY_INTERVAL,
    VERTICES_EVALUATED,
};
use roamsim::sim::algorithm::lindstrom::{FromScratchView, mesh_from_scratch};
use roamsim::sim::algorithm::{Lindstrom, LindstromConfig};
use roamsim::sim::hierarchy::{Hierarchy, NestingRule};
use roamsim::sim::mesh::VertexSet;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::terrain::{Heightfield, Spacing};

/// Lindstrom's own columns, in the order it declares them.
const COLUMNS: [&str; 6] = [
    BLOCKS_COARSEST,
    BLOCKS_FINEST,
    BLOCKS_PARTIAL,
    VERTICES_EVALUATED,
    VERTICES_BY_INTERVAL,
    FORCED_ACTIVATIONS,
];

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
        let config = lindstrom(tau_px, block_level);
        Scene {
            hierarchy,
            nested_errors: hierarchy.nested_vertex_errors(NestingRule::Max),
            config,
            algorithm: Lindstrom::new(hierarchy, config, &view_600()),
            frame: 0,
        }
    }

    /// Runs one frame from `eye`, checks the mesh against the brute force and the validator,
    /// checks that the counters add up, and returns the frame's statistics.
    fn frame_matches_brute_force(&mut self, eye: DVec3) -> FrameStats {
        let context = format!("eye {eye:?}, {:?}", self.config);
        let camera = camera_at(eye);
        let (hierarchy, frame) = (self.hierarchy, self.frame);
        let stats = checked_step(
            hierarchy,
            &mut self.algorithm,
            frame,
            &camera,
            false,
            &context,
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
        let mesh = self.algorithm.vertex_set();
        assert!(
            mesh == &expected,
            "{context}: {} vertices, brute force {}",
            mesh.len(),
            expected.len()
        );
        let column = |name| extra(&self.algorithm, &stats, name);
        let non_corner = (lattice.n_vertices() - 4) as f64;
        assert_eq!(
            column(VERTICES_EVALUATED) + column(VERTICES_BY_INTERVAL),
            non_corner,
            "{context}: every vertex is evaluated or decided by interval"
        );
        assert_eq!(stats.metric_evaluations as f64, column(VERTICES_EVALUATED));
        assert_eq!(
            column(BLOCKS_COARSEST) + column(BLOCKS_FINEST) + column(BLOCKS_PARTIAL),
            self.algorithm.n_blocks() as f64,
            "{context}: every block is classified"
        );
        assert!(column(FORCED_ACTIVATIONS) <= (mesh.len() - 4) as f64);
        stats
    }
}

/// Every eye position on the terrain's grid (10 m posts), at the given heights.
fn eyes_over(hierarchy: &Hierarchy, heights: &[f64]) -> Vec<DVec3> {
    let side = hierarchy.field().side();
    let mut eyes = Vec::new();
    for j in 0..side {
        for i in 0..side {
            for &z in heights {
                eyes.push(DVec3::new(i as f64 * 10.0, j as f64 * 10.0, z));
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
        for (k, column) in COLUMNS.iter().enumerate() {
            assert!(
                self.extra[k] > 0.0,
                "column {column} never counted: {self:?}"
            );
        }
    }
}

fn check_every_eye(level: u32, taus: &[f64], block_levels: &[u32]) -> Seen {
    let hierarchy = bumpy_terrain(level);
    let eyes = eyes_over(&hierarchy, &eye_heights(&hierarchy));
    let mut seen = Seen {
        fewest_triangles: u64::MAX,
        ..Seen::default()
    };
    for &tau_px in taus {
        for &block_level in block_levels {
            let mut scene = Scene::new(&hierarchy, tau_px, block_level);
            for &eye in &eyes {
                let stats = scene.frame_matches_brute_force(eye);
                seen.fewest_triangles = seen.fewest_triangles.min(stats.triangles);
                seen.most_triangles = seen.most_triangles.max(stats.triangles);
                for (sum, column) in seen.extra.iter_mut().zip(COLUMNS) {
                    *sum += extra(&scene.algorithm, &stats, column);
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
fn an_eye_exactly_on_a_vertex_keeps_that_vertex() {
    let hierarchy = bumpy_terrain(4);
    let nested = hierarchy.nested_vertex_errors(NestingRule::Max);
    let lattice = hierarchy.lattice();
    let vertex = roamsim::sim::hierarchy::GridPoint::new(5, 7);
    assert!(nested[lattice.id(vertex) as usize] > 0.0);
    let eye = hierarchy.field().position(5, 7);
    let mut scene = Scene::new(&hierarchy, 1e6, 2);
    scene.frame_matches_brute_force(eye);
    assert!(scene.algorithm.vertex_set().contains_point(lattice, vertex));
}

#[test]
fn tau_zero_keeps_exactly_the_vertices_with_an_error() {
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
        for eye in [DVec3::new(80.0, 80.0, 30.0), DVec3::new(-500.0, 20.0, 1e5)] {
            let stats = scene.frame_matches_brute_force(eye);
            assert!(
                scene.algorithm.vertex_set() == &with_error,
                "k = {block_level}"
            );
            assert_eq!(extra(&scene.algorithm, &stats, FORCED_ACTIVATIONS), 0.0);
            assert_eq!(
                stats.metric_evaluations, 0,
                "τ = 0 is decided by intervals alone"
            );
        }
    }
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
        extra(&scene.algorithm, &stats, BLOCKS_COARSEST),
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
        let algorithm = Lindstrom::new(&hierarchy, lindstrom(1.0, block_level), &view_600());
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
            lindstrom(1.0, 4)
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
    let bumpy = bumpy_terrain(level);
    let field = bumpy.field();
    let heights = field.heights().iter().map(|&z| height(z)).collect();
    let spacing = Spacing {
        dx: post_m,
        dy: post_m,
    };
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
            value(VERTICES_EVALUATED) + value(VERTICES_BY_INTERVAL),
            (1025.0 * 1025.0) - 4.0
        );
        assert_eq!(
            value(BLOCKS_COARSEST) + value(BLOCKS_FINEST) + value(BLOCKS_PARTIAL),
            5461.0,
            "1 + 4 + … + 4^6 blocks of 17² samples on a 1025² grid"
        );
        assert!(
            value(FORCED_ACTIVATIONS) > 0.0,
            "closure forces parents on a real tile"
        );
    }
}
