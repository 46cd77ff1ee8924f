//! Röttger'98 (§2) against its own criterion evaluated from scratch on every block.
//!
//! Exhaustive small cases: every eye position on a grid over 9×9 and 17×17 terrains, at heights
//! below, inside and above the relief, for both distance norms, with and without clipping, at
//! several C and c, one frame each in sequence: the mesh, the subdivided and forced blocks, the
//! blend bytes, the fans, the morphing vertices and the heights the mesh output draws them at
//! equal the brute force's, and the mesh and matrix validators pass. Then the paper's 2D
//! guarantee (§2.2, eq. 4–5: no forced split wherever every block averages to the same
//! elevation), what propagation buys on rough terrain, the constant-load controller, and the
//! experiment file.

mod common;

use common::algorithms::rottger;
use common::{bumpy_terrain, checked_step, extra, step, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::columns::rottger::{
    C_CLAMPED, CLIPPED_NODES, DESIRED_RESOLUTION_C, FAN_TRIANGLES, FAN_VERTICES, FANS,
    FORCED_SPLITS, MESH_VERTICES, MORPHING_VERTICES, NODES_VISITED, SUBDIVIDED,
};
use roamsim::sim::algorithm::rottger::{
    Criterion, DESIRED_RESOLUTION_MAX, DESIRED_RESOLUTION_MIN, DistanceNorm, FromScratchView,
    LoadCount, LoadTarget, frame_from_scratch,
};
use roamsim::sim::algorithm::{AlgorithmConfig, LodAlgorithm, Rottger, RottgerConfig};
use roamsim::sim::hierarchy::{Hierarchy, VertexClass};
use roamsim::sim::mesh::{LatticeMesh, MeshOutput, MorphedHeights};
use roamsim::sim::stats::FrameStats;
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose};

/// A pose at `eye` whose heading turns with `k`, looking slightly down: over a sweep of eyes the
/// view points every way, so clipping sees everything from nothing to all.
fn pose(eye: DVec3, k: usize) -> Pose {
    Pose {
        position: eye,
        yaw: 0.9 * k as f64,
        pitch: -0.35,
    }
}

/// One Röttger instance on a terrain, checked against the brute force every frame.
struct Scene<'h> {
    hierarchy: &'h Hierarchy,
    config: RottgerConfig,
    algorithm: Rottger<'h>,
    frame: u64,
}

impl<'h> Scene<'h> {
    fn new(hierarchy: &'h Hierarchy, config: RottgerConfig) -> Scene<'h> {
        let algorithm = Rottger::new(hierarchy, config);
        algorithm.validate_roughness().unwrap();
        Scene {
            hierarchy,
            config,
            algorithm,
            frame: 0,
        }
    }

    /// Runs one frame, checks it against the brute force and the validators, checks that the
    /// counters add up, and returns the frame's statistics.
    fn frame_matches_brute_force(&mut self, pose: &Pose) -> FrameStats {
        let camera = Camera::new(pose, view_600());
        let context = format!("eye {:?}, {:?}", pose.position, self.config);
        let stats = checked_step(
            self.hierarchy,
            &mut self.algorithm,
            self.frame,
            &camera,
            false,
            &context,
        );
        self.frame += 1;
        let lattice = self.hierarchy.lattice();
        if let Err(error) = self.algorithm.validate_frame() {
            panic!("{context}: {error}");
        }
        let expected = frame_from_scratch(&FromScratchView {
            hierarchy: self.hierarchy,
            matrix: self.algorithm.matrix(),
            criterion: Criterion {
                minimum_resolution: self.config.minimum_resolution,
                desired_resolution: self.config.desired_resolution,
                norm: self.config.distance,
            },
            camera: &camera,
            clipping: self.config.clipping,
        });
        assert!(
            self.algorithm.vertex_set() == &expected.mesh,
            "{context}: {} vertices, brute force {}",
            self.algorithm.vertex_set().len(),
            expected.mesh.len()
        );
        for id in 0..lattice.n_vertices() as u32 {
            if matches!(
                lattice.classify(lattice.point(id)),
                VertexClass::Square { .. }
            ) {
                assert_eq!(
                    self.algorithm.matrix().blend_byte(id),
                    expected.blend_bytes[id as usize],
                    "{context}: blend byte of {:?}",
                    lattice.point(id)
                );
            }
        }
        let morphed = output_morphs(&self.algorithm);
        if self.config.geomorphing {
            assert_morphed_heights_match(
                morphed.expect("geomorphing on: the output carries morphed heights"),
                &expected.morphed,
                &context,
            );
        } else {
            assert!(
                morphed.is_none(),
                "{context}: morphed heights without geomorphing"
            );
        }
        let column = |name: &str| extra(&self.algorithm, &stats, name);
        assert_eq!(
            column(SUBDIVIDED),
            expected.subdivided_by_criterion as f64,
            "{context}"
        );
        assert_eq!(column(FORCED_SPLITS), expected.forced as f64, "{context}");
        assert_eq!(column(FANS), expected.fans.fans as f64, "{context}");
        assert_eq!(
            column(FAN_VERTICES),
            expected.fans.vertices as f64,
            "{context}"
        );
        assert_eq!(
            column(FAN_TRIANGLES),
            expected.fans.triangles as f64,
            "{context}"
        );
        assert_eq!(
            column(MORPHING_VERTICES),
            expected.morphing as f64,
            "{context}"
        );
        assert_eq!(
            column(MESH_VERTICES),
            self.algorithm.vertex_set().len() as f64
        );
        assert_eq!(
            column(NODES_VISITED),
            stats.metric_evaluations as f64 + column(CLIPPED_NODES),
            "{context}: every block reached is evaluated or clipped"
        );
        assert_eq!(
            column(FAN_VERTICES),
            column(FAN_TRIANGLES) + 2.0 * column(FANS)
        );
        if !self.config.clipping {
            assert_eq!(column(FAN_TRIANGLES), stats.triangles as f64, "{context}");
            assert_eq!(column(CLIPPED_NODES), 0.0);
        }
        assert_eq!(column(DESIRED_RESOLUTION_C), self.config.desired_resolution);
        assert_eq!(column(C_CLAMPED), 0.0);
        stats
    }
}

/// The morphed heights of Röttger's mesh output (`None`: drawn at the samples' heights).
fn output_morphs<'a>(algorithm: &'a Rottger) -> Option<&'a MorphedHeights> {
    match algorithm.mesh() {
        MeshOutput::Lattice(LatticeMesh { morphed, .. }) => morphed,
        MeshOutput::Triangles(_) => panic!("rottger draws a 4-8 mesh"),
    }
}

/// The output's morphed heights are the brute force's: the same vertices, each at the height
/// z̄ + b·(z − z̄) the brute force computes (in `f64`; the output holds `f32`).
fn assert_morphed_heights_match(
    morphed: &MorphedHeights,
    expected: &std::collections::BTreeMap<u32, f64>,
    context: &str,
) {
    assert_eq!(
        morphed.sorted_ids(),
        expected.keys().copied().collect::<Vec<u32>>(),
        "{context}: the morphing vertices"
    );
    for (&id, &z) in expected {
        let drawn = f64::from(morphed.get(id).unwrap());
        assert!(
            (drawn - z).abs() <= 1e-6 * z.abs().max(1.0),
            "{context}: vertex {id} drawn at {drawn}, the brute force's {z}"
        );
    }
}

/// Every eye position on the terrain's grid (10 m posts), at the given heights, with its pose.
fn poses_over(hierarchy: &Hierarchy, heights: &[f64]) -> Vec<Pose> {
    let side = hierarchy.field().side();
    let mut poses = Vec::new();
    for j in 0..side {
        for i in 0..side {
            for &z in heights {
                let k = poses.len();
                poses.push(pose(DVec3::new(i as f64 * 10.0, j as f64 * 10.0, z), k));
            }
        }
    }
    poses
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
        600.0,
    ]
}

/// Columns an exhaustive run must see counted at least once.
const SEEN_COLUMNS: [&str; 5] = [
    FANS,
    SUBDIVIDED,
    FORCED_SPLITS,
    CLIPPED_NODES,
    MORPHING_VERTICES,
];

/// What the exhaustive runs saw, summed over every frame.
#[derive(Debug, Default)]
struct Seen {
    frames: u64,
    base_meshes: u64,
    full_meshes: u64,
    /// Sums of [`SEEN_COLUMNS`], in order.
    sums: [f64; SEEN_COLUMNS.len()],
}

impl Seen {
    fn add(&mut self, hierarchy: &Hierarchy, algorithm: &dyn LodAlgorithm, stats: &FrameStats) {
        self.frames += 1;
        self.base_meshes += u64::from(stats.triangles == 2);
        let cells = hierarchy.lattice().cells() as u64;
        self.full_meshes += u64::from(stats.triangles == 2 * cells * cells);
        for (sum, name) in self.sums.iter_mut().zip(SEEN_COLUMNS) {
            *sum += extra(algorithm, stats, name);
        }
    }

    /// Panics naming the first of [`SEEN_COLUMNS`] never counted.
    fn assert_every_column_counted(&self) {
        for (sum, name) in self.sums.iter().zip(SEEN_COLUMNS) {
            assert!(*sum > 0.0, "{name} never counted: {self:?}");
        }
    }
}

fn check_every_eye(level: u32, configs: &[RottgerConfig]) -> Seen {
    let hierarchy = bumpy_terrain(level);
    let poses = poses_over(&hierarchy, &eye_heights(&hierarchy));
    let mut seen = Seen::default();
    for config in configs {
        let mut scene = Scene::new(&hierarchy, *config);
        for pose in &poses {
            let stats = scene.frame_matches_brute_force(pose);
            seen.add(&hierarchy, &scene.algorithm, &stats);
        }
    }
    seen
}

/// Both norms, with and without clipping, at each (C, c).
fn configs(pairs: &[(f64, f64)]) -> Vec<RottgerConfig> {
    let mut configs = Vec::new();
    for &(minimum_resolution, desired_resolution) in pairs {
        for distance in [DistanceNorm::L1, DistanceNorm::Euclidean] {
            for clipping in [false, true] {
                configs.push(RottgerConfig {
                    distance,
                    clipping,
                    ..rottger(minimum_resolution, desired_resolution)
                });
            }
        }
    }
    configs
}

#[test]
fn every_eye_over_a_9_by_9_terrain_gives_the_brute_force_frame() {
    let mut all = configs(&[(2.0, 0.0), (2.0, 40.0), (8.0, 5.0), (8.0, 1e4)]);
    all.push(RottgerConfig {
        d2_propagation: false,
        ..rottger(4.0, 60.0)
    });
    let seen = check_every_eye(3, &all);
    seen.assert_every_column_counted();
    assert!(seen.base_meshes > 0 && seen.full_meshes > 0, "{seen:?}");
}

#[test]
fn every_eye_over_a_17_by_17_terrain_gives_the_brute_force_frame() {
    let mut all = configs(&[(2.0, 0.5), (2.0, 5.0), (8.0, 2.0), (16.0, 0.0)]);
    all.push(RottgerConfig {
        d2_propagation: false,
        ..rottger(2.0, 2.0)
    });
    check_every_eye(4, &all).assert_every_column_counted();
}

/// A rough terrain whose every block averages to exactly 100 m: heights repeat with period 3
/// (a 3 × 3 table summing to 0, plus 100), and the nine samples of any block (spaced by a power
/// of two) take every residue modulo 3 once in each direction.
fn equal_average_terrain(side: usize) -> Hierarchy {
    const TABLE: [[f32; 3]; 3] = [[3.0, -1.0, -2.0], [0.0, 4.0, -4.0], [-5.0, 2.0, 3.0]];
    let heights = (0..side * side)
        .map(|k| 100.0 + TABLE[(k / side) % 3][(k % side) % 3])
        .collect();
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

#[test]
fn where_every_block_averages_alike_propagation_alone_keeps_the_mesh_conforming() {
    // The paper's 2D argument (§2.2, eq. 4–5) applies exactly when the eye's height is measured
    // against the same elevation for every block: no forced split, for any eye, C ≥ 2, c, and
    // both norms.
    for level in [3, 4] {
        let hierarchy = equal_average_terrain((1 << level) + 1);
        let heights = [40.0, 99.0, 100.0, 103.5, 250.0];
        let poses = poses_over(&hierarchy, &heights);
        for minimum_resolution in [2.0, 3.0, 8.0, 64.0] {
            for desired_resolution in [0.0, 7.0, 90.0, 3e3] {
                for distance in [DistanceNorm::L1, DistanceNorm::Euclidean] {
                    let config = RottgerConfig {
                        distance,
                        ..rottger(minimum_resolution, desired_resolution)
                    };
                    let mut scene = Scene::new(&hierarchy, config);
                    let mut subdivided = 0.0;
                    for pose in &poses {
                        let stats = scene.frame_matches_brute_force(pose);
                        let column = |name| extra(&scene.algorithm, &stats, name);
                        assert_eq!(column(FORCED_SPLITS), 0.0, "{config:?} at {pose:?}");
                        subdivided += column(SUBDIVIDED);
                    }
                    assert!(subdivided > 0.0);
                }
            }
        }
    }
}

#[test]
fn on_rough_terrain_propagation_leaves_fewer_forced_splits_than_local_d2() {
    let hierarchy = bumpy_terrain(4);
    let poses = poses_over(&hierarchy, &eye_heights(&hierarchy));
    // Where c·d2 matters (c·d2 > 1 for some blocks, < 1 for others); at c·d2 < 1 everywhere the
    // mesh is C's alone and propagation changes nothing.
    for (minimum_resolution, desired_resolution) in [(2.0, 2.0), (2.0, 5.0), (4.0, 4.0), (8.0, 2.0)]
    {
        let forced = |d2_propagation: bool| {
            let mut scene = Scene::new(
                &hierarchy,
                RottgerConfig {
                    d2_propagation,
                    ..rottger(minimum_resolution, desired_resolution)
                },
            );
            poses
                .iter()
                .map(|pose| {
                    let stats = scene.frame_matches_brute_force(pose);
                    extra(&scene.algorithm, &stats, FORCED_SPLITS)
                })
                .sum::<f64>()
        };
        let (with, without) = (forced(true), forced(false));
        assert!(
            with < without,
            "C = {minimum_resolution}, c = {desired_resolution}: {with} forced with \
             propagation, {without} without"
        );
    }
}

#[test]
fn on_flat_terrain_the_mesh_depends_on_c_not_at_all_and_needs_no_forced_split() {
    let flat = Hierarchy::new(
        Heightfield::new(33, vec![250.0; 33 * 33], Spacing { dx: 10.0, dy: 10.0 }).unwrap(),
    );
    let poses = poses_over(&flat, &[250.0, 300.0, 1000.0]);
    for minimum_resolution in [2.0, 8.0] {
        let mut coarse = Scene::new(&flat, rottger(minimum_resolution, 0.0));
        let mut rough = Scene::new(&flat, rottger(minimum_resolution, 1e6));
        for pose in &poses {
            let a = coarse.frame_matches_brute_force(pose);
            let b = rough.frame_matches_brute_force(pose);
            assert!(coarse.algorithm.vertex_set() == rough.algorithm.vertex_set());
            assert_eq!(extra(&coarse.algorithm, &a, FORCED_SPLITS), 0.0);
            assert_eq!(
                extra(&rough.algorithm, &b, MORPHING_VERTICES),
                0.0,
                "a flat vertex never moves"
            );
        }
    }
}

#[test]
fn fan_vertices_grow_with_the_minimum_resolution_c_about_quadratically() {
    // The paper: "as C increases, the total number of vertices per frame grows quadratically".
    let hierarchy = bumpy_terrain(7);
    let eye = DVec3::new(640.0, 640.0, 80.0);
    let vertices_at = |minimum_resolution: f64| {
        let mut algorithm = Rottger::new(&hierarchy, rottger(minimum_resolution, 0.0));
        let camera = Camera::new(&pose(eye, 0), view_600());
        let stats = step(&mut algorithm, 0, &camera, false);
        extra(&algorithm, &stats, FAN_VERTICES)
    };
    let counts: Vec<f64> = [2.0, 4.0, 8.0, 16.0].map(vertices_at).to_vec();
    for pair in counts.windows(2) {
        assert!(pair[1] > pair[0], "{counts:?}");
    }
    // From C = 4 to 8 the load is far from both the coarsest and the full mesh: about ×4.
    let ratio = counts[2] / counts[1];
    assert!((2.5..6.0).contains(&ratio), "{counts:?}");
}

/// Runs `config` over a circle around a 129 × 129 bumpy terrain, checking every frame; returns
/// every frame's stats and the algorithm (for its column names).
fn fly_circle(
    hierarchy: &Hierarchy,
    config: RottgerConfig,
    frames: u64,
) -> (Vec<FrameStats>, Rottger<'_>) {
    let mut rottger = Rottger::new(hierarchy, config);
    let stats = (0..frames)
        .map(|frame| {
            let angle = frame as f64 * 0.01;
            let eye = DVec3::new(
                640.0 + 300.0 * angle.cos(),
                640.0 + 300.0 * angle.sin(),
                90.0,
            );
            let camera = Camera::new(
                &Pose {
                    position: eye,
                    yaw: angle + std::f64::consts::FRAC_PI_2,
                    pitch: -0.3,
                },
                view_600(),
            );
            checked_step(
                hierarchy,
                &mut rottger,
                frame,
                &camera,
                false,
                config_name(&config),
            )
        })
        .collect();
    (stats, rottger)
}

fn config_name(config: &RottgerConfig) -> String {
    format!("{config:?}")
}

#[test]
fn the_controller_holds_a_fan_vertex_target_and_records_c_every_frame() {
    let hierarchy = bumpy_terrain(7);
    for (count, count_column) in [
        (LoadCount::FanVertices, FAN_VERTICES),
        (LoadCount::Triangles, FAN_TRIANGLES),
    ] {
        for clipping in [false, true] {
            let target = 3000;
            let (frames, algorithm) = fly_circle(
                &hierarchy,
                RottgerConfig {
                    load: Some(LoadTarget { count, target }),
                    clipping,
                    ..rottger(4.0, 1.0)
                },
                300,
            );
            let column = |stats: &FrameStats, name| extra(&algorithm, stats, name);
            let settled = &frames[40..];
            let mean =
                settled.iter().map(|s| column(s, count_column)).sum::<f64>() / settled.len() as f64;
            assert!(
                (mean / target as f64 - 1.0).abs() < 0.05,
                "{count:?}, clipping {clipping}: mean {mean}"
            );
            for stats in settled {
                let ratio = column(stats, count_column) / target as f64;
                assert!(
                    (0.75..1.33).contains(&ratio),
                    "{count:?} frame {}: {ratio}",
                    stats.frame
                );
                assert_eq!(column(stats, C_CLAMPED), 0.0);
            }
            let c: Vec<f64> = frames
                .iter()
                .map(|s| column(s, DESIRED_RESOLUTION_C))
                .collect();
            assert_eq!(c[0], 1.0, "the first frame uses the starting c");
            assert!(c.windows(2).any(|w| w[0] != w[1]));
        }
    }
}

#[test]
fn an_unreachable_target_drives_c_to_its_bound_and_reports_the_clamp() {
    let hierarchy = bumpy_terrain(5);
    let lattice = hierarchy.lattice();
    for (target, bound) in [
        (1, DESIRED_RESOLUTION_MIN),
        (1_000_000, DESIRED_RESOLUTION_MAX),
    ] {
        let (frames, algorithm) = fly_circle(
            &hierarchy,
            RottgerConfig {
                load: Some(LoadTarget {
                    count: LoadCount::Triangles,
                    target,
                }),
                ..rottger(2.0, 1.0)
            },
            120,
        );
        let last = frames.last().unwrap();
        assert_eq!(
            extra(&algorithm, last, DESIRED_RESOLUTION_C),
            bound,
            "target {target}"
        );
        assert_eq!(extra(&algorithm, last, C_CLAMPED), 1.0, "target {target}");
        if target > 1 {
            // Every block with any roughness subdivides at c = 2^40: the full grid.
            assert_eq!(last.triangles, 2 * u64::from(lattice.cells()).pow(2));
        }
    }
}

#[test]
fn an_experiment_names_rottger_with_its_resolutions_target_and_options() {
    let configs = common::experiment::load_with_algorithms(serde_json::json!([
        { "name": "rottger", "label": "a", "minimum_resolution": 8, "desired_resolution": 25 },
        { "name": "rottger", "label": "b", "minimum_resolution": 8, "target_fan_vertices": 15000,
          "distance": "euclidean", "clipping": true, "geomorphing": true, "d2_propagation": false }
    ]));
    assert_eq!(
        configs,
        Ok(vec![
            AlgorithmConfig::Rottger(config_without_morphing(8.0, 25.0)),
            AlgorithmConfig::Rottger(RottgerConfig {
                load: Some(LoadTarget {
                    count: LoadCount::FanVertices,
                    target: 15000
                }),
                distance: DistanceNorm::Euclidean,
                d2_propagation: false,
                clipping: true,
                geomorphing: true,
                ..rottger(8.0, 1.0)
            })
        ])
    );
}

fn config_without_morphing(minimum_resolution: f64, desired_resolution: f64) -> RottgerConfig {
    RottgerConfig {
        geomorphing: false,
        ..rottger(minimum_resolution, desired_resolution)
    }
}

#[test]
fn an_experiment_with_bad_rottger_entries_names_each_field() {
    let problems = common::experiment::load_with_algorithms(serde_json::json!([
        { "name": "rottger", "label": "a", "minimum_resolution": 1.5, "desired_resolution": 1 },
        { "name": "rottger", "label": "b", "minimum_resolution": 8, "desired_resolution": -1 },
        { "name": "rottger", "label": "c", "minimum_resolution": 8 },
        { "name": "rottger", "label": "d", "minimum_resolution": 8, "target_triangles": 10,
          "target_fan_vertices": 10 },
        { "name": "rottger", "label": "e", "minimum_resolution": 8, "target_triangles": 0 },
        { "name": "rottger", "label": "f", "minimum_resolution": 8, "target_triangles": 10,
          "desired_resolution": 0 },
        { "name": "rottger", "label": "g", "minimum_resolution": 8, "desired_resolution": 1,
          "distance": "manhattan" }
    ]))
    .unwrap_err();
    assert_eq!(problems.len(), 7, "{problems:#?}");
    assert!(
        problems[0].starts_with(
            "algorithms[0].minimum_resolution: 1.5: expected a finite C of at least 2"
        )
    );
    assert!(problems[1].starts_with("algorithms[1].desired_resolution: -1: expected a finite c"));
    assert!(problems[2].starts_with("algorithms[2]: neither desired_resolution nor a load target"));
    assert!(
        problems[3].starts_with("algorithms[3]: both target_triangles and target_fan_vertices")
    );
    assert!(problems[4].starts_with("algorithms[4].target_triangles: 0: expected a target"));
    assert!(
        problems[5]
            .starts_with("algorithms[5].desired_resolution: 0: expected a finite starting c")
    );
    assert!(problems[6].starts_with("algorithms[6].distance: unknown variant `manhattan`"));
}

#[test]
fn a_checked_run_of_the_real_tile_writes_the_rottger_columns_and_facts() {
    let dir = tempfile::tempdir().unwrap();
    let mut experiment = common::experiment::short_quickstart(3);
    experiment["algorithms"] = serde_json::json!([
        { "name": "rottger", "label": "rottger", "minimum_resolution": 8,
          "target_fan_vertices": 15000, "clipping": true, "geomorphing": true }
    ]);
    let path = common::experiment::save(dir.path(), "rottger", &experiment);
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
    let c: Vec<f64> = rows
        .iter()
        .map(|row| row[column(DESIRED_RESOLUTION_C)].parse().unwrap())
        .collect();
    assert_eq!(c[0], 1.0);
    assert_eq!(c[1], 2.0, "far below the target, c doubles");
    for row in &rows {
        let value = |name: &str| row[column(name)].parse::<f64>().unwrap();
        assert_eq!(
            value(FAN_VERTICES),
            value(FAN_TRIANGLES) + 2.0 * value(FANS)
        );
        assert!(
            value(CLIPPED_NODES) > 0.0,
            "the flight sees part of the tile"
        );
        assert!(value(FAN_TRIANGLES) < value("triangles"));
    }
    for extension in ["png", "svg"] {
        assert!(
            out.join(format!("plots/{DESIRED_RESOLUTION_C}.{extension}"))
                .is_file()
        );
    }
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
    let facts = &summary["algorithms"][0]["facts"];
    assert_eq!(facts["matrix_bytes_per_sample"], 1.0);
    assert_eq!(facts["propagation_k"], 8.0 / 14.0);
}

/// A flight of `frames` around and over the middle of a 33 × 33 terrain (320 m), low enough that
/// the blocks' f cross ½ and 1 as it goes (so blocks morph in and out).
fn low_flight(frames: u64) -> Vec<Camera> {
    (0..frames)
        .map(|frame| {
            let angle = 0.05 * frame as f64;
            let eye = DVec3::new(
                160.0 + 130.0 * angle.cos(),
                160.0 + 130.0 * angle.sin(),
                45.0,
            );
            let to_middle = DVec3::new(160.0, 160.0, 0.0) - eye;
            Camera::new(
                &Pose {
                    position: eye,
                    yaw: to_middle.y.atan2(to_middle.x),
                    pitch: -0.4,
                },
                view_600(),
            )
        })
        .collect()
}

#[test]
fn the_mesh_output_draws_every_vertex_at_rottgers_drawn_height_over_a_flight() {
    let hierarchy = bumpy_terrain(5);
    let lattice = hierarchy.lattice();
    for clipping in [false, true] {
        let config = RottgerConfig {
            clipping,
            ..rottger(4.0, 20.0)
        };
        let mut algorithm = Rottger::new(&hierarchy, config);
        let mut morphing = 0;
        for (frame, camera) in low_flight(40).iter().enumerate() {
            let context = format!("clipping {clipping}, frame {frame}");
            let stats = checked_step(
                &hierarchy,
                &mut algorithm,
                frame as u64,
                camera,
                false,
                &context,
            );
            algorithm.validate_frame().unwrap();
            let morphed = output_morphs(&algorithm).expect("geomorphing on");
            for id in algorithm.vertex_set().iter() {
                let p = lattice.point(id);
                let drawn = morphed.get(id).unwrap_or_else(|| hierarchy.height(p));
                assert_eq!(
                    drawn,
                    algorithm.drawn_height(p) as f32,
                    "{context}: vertex {p:?}"
                );
            }
            assert_eq!(
                extra(&algorithm, &stats, MORPHING_VERTICES),
                morphed.len() as f64,
                "{context}"
            );
            let counts = algorithm.mesh().counts(stats.triangles).unwrap();
            assert_eq!(counts.morphing_vertices, morphed.len() as u64);
            assert_eq!(counts.triangles_by_role, [stats.triangles, 0, 0, 0]);
            morphing += morphed.len();
        }
        // The flight morphs vertices.
        assert!(morphing > 0, "{morphing}");
    }
}

#[test]
fn without_geomorphing_the_mesh_output_has_no_morphed_heights() {
    let hierarchy = bumpy_terrain(5);
    let mut algorithm = Rottger::new(&hierarchy, config_without_morphing(4.0, 20.0));
    for (frame, camera) in low_flight(20).iter().enumerate() {
        let stats = checked_step(&hierarchy, &mut algorithm, frame as u64, camera, false, "");
        algorithm.validate_frame().unwrap();
        assert!(output_morphs(&algorithm).is_none(), "frame {frame}");
        assert_eq!(algorithm.mesh().counts(stats.triangles), None);
        assert_eq!(extra(&algorithm, &stats, MORPHING_VERTICES), 0.0);
    }
}

#[test]
fn the_fans_drawn_are_the_mesh_at_its_morphed_heights_every_frame_one_draw_per_fan() {
    let hierarchy = bumpy_terrain(5);
    let mut cameras: Vec<(Camera, bool)> = low_flight(40).into_iter().map(|c| (c, false)).collect();
    // A teleport back to the start, then a frame standing still.
    let start = cameras[0].0;
    cameras.extend([(start, true), (start, false)]);
    for geomorphing in [false, true] {
        for clipping in [false, true] {
            let config = RottgerConfig {
                clipping,
                geomorphing,
                ..rottger(4.0, 20.0)
            };
            let mut algorithm = Rottger::new(&hierarchy, config);
            let (mut morphing, mut fans_seen) = (0.0, 0.0);
            for (frame, (camera, teleport)) in cameras.iter().enumerate() {
                let context =
                    format!("geomorphing {geomorphing}, clipping {clipping}, frame {frame}");
                let stats = checked_step(
                    &hierarchy,
                    &mut algorithm,
                    frame as u64,
                    camera,
                    *teleport,
                    &context,
                );
                let counts = common::draw_counts(&stats);
                if let Err(error) = roamsim::sim::draw::check::check_buffers_draw_mesh(
                    algorithm.buffers(),
                    algorithm.mesh(),
                    &hierarchy,
                ) {
                    panic!("{context}: {error}");
                }
                assert_eq!(counts.triangles_submitted, stats.triangles, "{context}");
                if !clipping {
                    // The paper's fans and vertices: one draw per fan, its vertices sent once each.
                    assert_eq!(
                        counts.draw_calls as f64,
                        extra(&algorithm, &stats, FANS),
                        "{context}"
                    );
                    let vertex_bytes = 12.0 * extra(&algorithm, &stats, FAN_VERTICES);
                    assert!(counts.upload_bytes as f64 >= vertex_bytes, "{context}");
                    fans_seen += extra(&algorithm, &stats, FANS);
                }
                morphing += extra(&algorithm, &stats, MORPHING_VERTICES);
            }
            assert_eq!(
                morphing > 0.0,
                geomorphing,
                "the flight morphs vertices iff geomorphing"
            );
            assert!(clipping || fans_seen > 40.0, "{fans_seen} fans");
        }
    }
}
