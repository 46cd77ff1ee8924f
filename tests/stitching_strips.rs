//! `stitching-strips` (the 2019 dynamic stitching strips) against its definition: every frame's
//! mesh through the `--check` validator (crack policy `stitched` for the strips: the surface
//! tiles the domain, no holes, every edge closed, so every strip vertex is a vertex of both
//! neighbours' edges; `closed` for Methods I and II) and the algorithm's own validator (the
//! selection against a brute-force recomputation, the triangle counts, strip vertices on the
//! blocks' edges), for every eye over 9×9 and 17×17 terrains and every option; every quadtree
//! shape of a small tree with many factors (exhaustive); the statistics; the methods' shapes.

mod common;

use common::{bumpy_terrain, checked_step, extra, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::columns::stitching::{
    M_BLOCKS, M_BLOCKS_CULLED, P_BLOCKS, STRIPS, STRIPS_CULLED, TESSELLATION_FACTOR_2_4,
    TESSELLATION_FACTOR_4_8, TESSELLATION_FACTOR_8_16, TESSELLATION_FACTOR_16_32,
    TESSELLATION_FACTOR_32_64, TESSELLATION_FACTOR_MEAN,
};
use roamsim::sim::algorithm::stitching::NodeId;
use roamsim::sim::algorithm::{
    BlockDistance, LodAlgorithm, PBlockShape, Stitching, StitchingConfig, StitchingMethod,
    ViewDirection,
};
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::check::MeshChecker;
use roamsim::sim::mesh::{MeshOutput, TriangleList, TriangleRole};
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::{Camera, Pose};

fn plain(block_level: u32, threshold_px: f64) -> StitchingConfig {
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

fn every_option(block_level: u32) -> Vec<StitchingConfig> {
    let mut configs = Vec::new();
    for method in [
        StitchingMethod::Strips,
        StitchingMethod::PowerOfTwo,
        StitchingMethod::Uniform,
    ] {
        for (distance, view_direction, p_block, culling, width, threshold) in [
            (
                BlockDistance::Centre,
                ViewDirection::ToBlock,
                PBlockShape::TwoTriangles,
                false,
                1.0,
                1.0,
            ),
            (
                BlockDistance::Box,
                ViewDirection::Look,
                PBlockShape::Fan,
                true,
                0.3,
                0.2,
            ),
            (
                BlockDistance::Centre,
                ViewDirection::Look,
                PBlockShape::Fan,
                false,
                0.5,
                4.0,
            ),
        ] {
            configs.push(StitchingConfig {
                method,
                distance,
                view_direction,
                p_block,
                culling,
                strip_width_cells: width,
                threshold_px: threshold,
                ..plain(block_level, 1.0)
            });
        }
    }
    configs
}

/// Eyes over the terrain: above every `stride`-th sample, 4 m and 70 m over the highest ground,
/// turning.
fn eyes_over(hierarchy: &Hierarchy, stride: usize) -> Vec<Camera> {
    let field = hierarchy.field();
    let (_, top) = field.height_range();
    let side = field.side();
    let mut cameras = Vec::new();
    for j in (0..side).step_by(stride) {
        for i in (0..side).step_by(stride) {
            for above in [4.0, 70.0] {
                let p = field.position(i, j);
                cameras.push(Camera::new(
                    &Pose {
                        position: DVec3::new(p.x, p.y, f64::from(top) + above),
                        yaw: 0.37 * (i + 3 * j) as f64,
                        pitch: -0.45,
                    },
                    view_600(),
                ));
            }
        }
    }
    cameras
}

/// One checked frame: `--check`'s validator, then the algorithm's own.
fn checked(
    hierarchy: &Hierarchy,
    stitching: &mut Stitching,
    frame: u64,
    camera: &Camera,
    context: &str,
) -> FrameStats {
    let stats = checked_step(hierarchy, stitching, frame, camera, frame == 0, context);
    if let Err(error) = stitching.validate(camera) {
        panic!("{context}, frame {frame}: {error}");
    }
    stats
}

/// A block of at most 64 cells has no error at F = 64 (every sample is a vertex), so only larger
/// blocks ever split: these terrains are 129² and 257², the eyes over every 64th and 128th sample.
#[test]
fn every_eye_and_option_passes_check_and_the_brute_force_selection() {
    for (level, block_levels, stride) in [(7, &[5, 6][..], 64), (8, &[6][..], 128)] {
        let hierarchy = bumpy_terrain(level);
        let cameras = eyes_over(&hierarchy, stride);
        for &block_level in block_levels {
            let (mut depths_seen, mut fractional, mut stitched) = ([false; 4], false, false);
            for config in every_option(block_level) {
                let mut stitching = Stitching::new(&hierarchy, config);
                for (frame, camera) in cameras.iter().enumerate() {
                    let context = format!("{config:?} on {level}");
                    checked(&hierarchy, &mut stitching, frame as u64, camera, &context);
                    for (id, f) in stitching.leaves() {
                        depths_seen[id.depth as usize] = true;
                        fractional |= f.fract() != 0.0;
                    }
                    let stitches = stats_role(&stitching, TriangleRole::Stitch);
                    if config.method == StitchingMethod::Strips {
                        stitched |= stitches > 0;
                    } else {
                        assert_eq!(stitches, 0, "{context}: no strips in Methods I and II");
                    }
                }
            }
            let depth_max = level - block_level;
            assert!(
                depths_seen[..=depth_max as usize].iter().all(|&s| s),
                "level {level}, block level {block_level}: {depths_seen:?}"
            );
            assert!(
                fractional && stitched,
                "fractional factors and strips were drawn"
            );
        }
    }
}

fn stats_role(stitching: &Stitching, role: TriangleRole) -> u64 {
    list(stitching).role_count(role)
}

fn list<'a>(stitching: &'a Stitching) -> &'a TriangleList {
    match stitching.mesh() {
        MeshOutput::Triangles(list) => list,
        MeshOutput::Lattice(_) => panic!("stitching-strips draws a triangle list"),
    }
}

/// Every subset of the root's children splitting (with the root split or not: a tree three deep
/// over a 17² terrain, blocks down to 4 cells), every method and
/// P-block shape, with factors from a list of awkward values assigned in turn: the surface tiles
/// the domain and closes (strips included), and the counts are the factors'.
#[test]
fn every_quadtree_shape_and_awkward_factors_close_the_surface() {
    let hierarchy = bumpy_terrain(4);
    let awkward = [2.0, 2.0 + 1e-7, 3.0, 3.999_999, 4.0, 5.5, 9.3, 63.9];
    let mut cases = 0;
    for method in [
        StitchingMethod::Strips,
        StitchingMethod::PowerOfTwo,
        StitchingMethod::Uniform,
    ] {
        for (p_block, width) in [(PBlockShape::TwoTriangles, 1.0), (PBlockShape::Fan, 0.25)] {
            let config = StitchingConfig {
                method,
                p_block,
                strip_width_cells: width,
                ..plain(2, 1.0)
            };
            let mut stitching = Stitching::new(&hierarchy, config);
            for shape in 0..32u32 {
                for offset in 0..awkward.len() {
                    // Bit 4: the root splits; bits 0..3: which of its children split too.
                    let split = |id: NodeId| match id.depth {
                        0 => shape & 16 != 0,
                        1 => shape & (1 << (id.ix + 2 * id.iy)) != 0,
                        _ => false,
                    };
                    let factor = |id: NodeId| {
                        awkward
                            [(offset + (id.ix * 7 + id.iy * 3 + id.depth) as usize) % awkward.len()]
                    };
                    stitching.draw_with(split, factor);
                    let context = format!("{method:?} {p_block:?}, shape {shape}, offset {offset}");
                    let mesh = stitching.mesh();
                    if let Err(error) =
                        MeshChecker::new().check(&hierarchy, mesh, stitching.triangle_count())
                    {
                        panic!("{context}: {error}");
                    }
                    if let Err(error) = stitching.validate_mesh() {
                        panic!("{context}: {error}");
                    }
                    cases += 1;
                }
            }
        }
    }
    assert_eq!(cases, 3 * 2 * 32 * 8);
}

#[test]
fn a_lone_block_at_an_even_factor_draws_the_full_grid_and_strips_join_rows() {
    let hierarchy = bumpy_terrain(4);
    let mut stitching = Stitching::new(&hierarchy, plain(2, 1.0));
    for f in [2.0, 4.0, 8.0, 64.0] {
        stitching.draw_with(|_| false, |_| f);
        assert_eq!(stitching.triangle_count(), 2 * (f * f) as u64, "F = {f}");
    }
    // The root split once, all four children at F = 2: 4 × 8 block triangles, 4 strips of
    // (3 + 3 − 2) triangles (each row one child's edge at F = 2), a P-block of 2.
    stitching.draw_with(|id| id.depth == 0, |_| 2.0);
    let drawn = list(&stitching);
    assert_eq!(drawn.role_count(TriangleRole::Surface), 4 * 8 + 2);
    assert_eq!(drawn.role_count(TriangleRole::Stitch), 4 * 4);
    // Children at F = 2 and F = 6: the strip between them has 3 + 7 vertices, 8 triangles.
    stitching.draw_with(|id| id.depth == 0, |id| if id.ix == 0 { 2.0 } else { 6.0 });
    let drawn = list(&stitching);
    // South and north strips join F = 2 and F = 6 rows (8 each), west and east join equals
    // (4 and 12).
    assert_eq!(drawn.role_count(TriangleRole::Stitch), 8 + 8 + 4 + 12);
}

#[test]
fn statistics_count_blocks_strips_p_blocks_and_the_factors() {
    let hierarchy = bumpy_terrain(7);
    // Past the centre, looking north-east: the south-west quarter lies behind.
    let eye = DVec3::new(700.0, 700.0, 60.0);
    let camera = Camera::new(
        &Pose {
            position: eye,
            yaw: 0.8,
            pitch: -0.3,
        },
        view_600(),
    );
    for culling in [false, true] {
        let config = StitchingConfig {
            culling,
            ..plain(5, 0.5)
        };
        let mut stitching = Stitching::new(&hierarchy, config);
        let stats = checked(&hierarchy, &mut stitching, 0, &camera, "statistics");
        let leaves: Vec<(NodeId, f64)> = stitching.leaves().collect();
        let column = |name| extra(&stitching, &stats, name);
        assert_eq!(column(M_BLOCKS), leaves.len() as f64);
        let splits = (leaves.len() - 1) / 3;
        assert!(splits > 0, "the eye splits the root");
        assert_eq!(
            column(STRIPS) + column(STRIPS_CULLED),
            4.0 * splits as f64,
            "four strips per split"
        );
        let histogram: f64 = [
            TESSELLATION_FACTOR_2_4,
            TESSELLATION_FACTOR_4_8,
            TESSELLATION_FACTOR_8_16,
            TESSELLATION_FACTOR_16_32,
            TESSELLATION_FACTOR_32_64,
        ]
        .iter()
        .map(|&name| column(name))
        .sum();
        assert_eq!(histogram, leaves.len() as f64);
        let mean = leaves.iter().map(|(_, f)| f).sum::<f64>() / leaves.len() as f64;
        assert!((column(TESSELLATION_FACTOR_MEAN) - mean).abs() < 1e-9);
        if culling {
            assert!(
                column(M_BLOCKS_CULLED) + column(STRIPS_CULLED) > 0.0,
                "the eye looks away from part of the terrain"
            );
        } else {
            assert_eq!(column(P_BLOCKS), splits as f64);
            assert_eq!(column(M_BLOCKS_CULLED), 0.0);
        }
    }
}

#[test]
fn method_one_uses_powers_of_two_and_method_two_uniform_blocks() {
    let hierarchy = bumpy_terrain(7);
    let camera = common::camera_at(DVec3::new(50.0, 700.0, 80.0));
    let mut one = Stitching::new(
        &hierarchy,
        StitchingConfig {
            method: StitchingMethod::PowerOfTwo,
            ..plain(5, 0.5)
        },
    );
    checked(&hierarchy, &mut one, 0, &camera, "Method I");
    assert!(one.leaves().count() > 1, "the quadtree split");
    assert!(one.leaves().all(|(_, f)| f.log2().fract() == 0.0));
    let mut two = Stitching::new(
        &hierarchy,
        StitchingConfig {
            method: StitchingMethod::Uniform,
            ..plain(5, 0.5)
        },
    );
    checked(&hierarchy, &mut two, 0, &camera, "Method II");
    assert_eq!(two.leaves().count(), 16);
    assert!(two.leaves().all(|(id, _)| id.depth == 2));
    // The strips' own selection at the same threshold: the same quadtree as Method I, with
    // the factors before rounding (at most Method I's).
    let mut strips = Stitching::new(&hierarchy, plain(5, 0.5));
    checked(&hierarchy, &mut strips, 0, &camera, "strips");
    let ids = |s: &Stitching| s.leaves().map(|(id, _)| id).collect::<Vec<_>>();
    assert_eq!(ids(&strips), ids(&one));
    for ((_, f), (_, g)) in strips.leaves().zip(one.leaves()) {
        assert!(f <= g && g < 2.0 * f.max(2.0) + 1e-9, "{f} → {g}");
    }
}

#[test]
fn an_approach_moves_the_strips_factors_continuously_and_method_one_s_by_doublings() {
    // The eye slides towards a 16-cell terrain (one block) in 1 m steps: the strips' factor
    // takes many values, Method I's only powers of two.
    let hierarchy = bumpy_terrain(4);
    let mut distinct = [0usize; 2];
    for (k, method) in [StitchingMethod::Strips, StitchingMethod::PowerOfTwo]
        .into_iter()
        .enumerate()
    {
        let config = StitchingConfig {
            method,
            ..plain(4, 2.0)
        };
        let mut stitching = Stitching::new(&hierarchy, config);
        let mut factors = Vec::new();
        for step in 0..400 {
            let eye = DVec3::new(80.0, -400.0 + step as f64, 300.0 - 0.5 * step as f64);
            checked(
                &hierarchy,
                &mut stitching,
                step,
                &common::camera_at(eye),
                "approach",
            );
            let (_, f) = stitching.leaves().next().expect("the root");
            factors.push(f.to_bits());
        }
        factors.sort_unstable();
        factors.dedup();
        distinct[k] = factors.len();
    }
    assert!(distinct[0] > 50, "strips: {distinct:?}");
    assert!((2..=6).contains(&distinct[1]), "Method I: {distinct:?}");
}
