//! The block-based algorithms, `geomipmap` (de Boer 2000, as Lauritsen–Nielsen 2005 §2.5 survey
//! it) and `chunked` (Lauritsen–Nielsen 2005 §3.2), against their definitions: every frame's
//! mesh through the `--check` validators and the algorithm's own structure validator; the
//! selection against a from-scratch evaluation of the same criterion, for every eye over
//! 9×9 and 17×17 terrains; the skirts against the cracks the audit finds without them; the
//! triangle target; culling, front-to-back order and morphing.

mod common;

use common::algorithms::{chunked, chunked_with_everything, geomipmap};
use common::scenes::{extended_terrain, short_sighted_camera};
use common::{bumpy_terrain, checked_step, fly_checked, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::chunked::{ChunkId, chunks_from_scratch};
use roamsim::sim::algorithm::columns::chunked::{
    CHUNKS_CULLED, ORDER_INVERSIONS, TARGET_UNREACHABLE,
};
use roamsim::sim::algorithm::columns::geomipmap::{PATCHES_CULLED, QUADTREE_NODES_VISITED};
use roamsim::sim::algorithm::geomipmap::levels_from_scratch;
use roamsim::sim::algorithm::{
    BlockGoal, Chunked, ChunkedConfig, Geomipmap, GeomipmapConfig, LevelDifference, LodAlgorithm,
    Projection, SkirtDepth,
};
use roamsim::sim::audit::{AuditSettings, Auditor};
use roamsim::sim::draw::DrawCounts;
use roamsim::sim::draw::check::check_buffers_draw_mesh;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::{CrackPolicy, MeshOutput, TriangleList, TriangleRole};
use roamsim::sim::stats::{FrameStats, SurfaceCoverage};
use roamsim::sim::terrain::{Heightfield, Spacing};
use roamsim::sim::view::{Camera, Pose};

/// Eyes over a terrain of side `side` with 10 m posts: above every sample, at 4 m and 70 m
/// over the highest ground, looking along +x and 25° down.
fn eyes_over(hierarchy: &Hierarchy) -> Vec<Camera> {
    let field = hierarchy.field();
    let (_, top) = field.height_range();
    let side = field.side();
    let mut cameras = Vec::new();
    for j in 0..side {
        for i in 0..side {
            for above in [4.0, 70.0] {
                let eye = field.position(i, j) + DVec3::new(0.0, 0.0, 0.0);
                let eye = DVec3::new(eye.x, eye.y, f64::from(top) + above);
                let yaw = 0.37 * (i + 3 * j) as f64;
                cameras.push(Camera::new(
                    &Pose {
                        position: eye,
                        yaw,
                        pitch: -0.45,
                    },
                    view_600(),
                ));
            }
        }
    }
    cameras
}

/// The ids of the chunks drawn, sorted.
fn drawn_ids(algorithm: &Chunked) -> Vec<ChunkId> {
    let mut ids: Vec<ChunkId> = algorithm.drawn().iter().map(|c| c.id).collect();
    ids.sort_unstable();
    ids
}

fn chunked_configs(tau_px: f64) -> Vec<ChunkedConfig> {
    vec![
        chunked(tau_px, 2),
        chunked_with_everything(tau_px, 1),
        ChunkedConfig {
            skirts: SkirtDepth::Covering,
            front_to_back: true,
            ..chunked(tau_px, 1)
        },
        ChunkedConfig {
            culling: true,
            morph: true,
            ..chunked(tau_px, 3)
        },
    ]
}

fn geomipmap_configs(tau_px: f64) -> Vec<GeomipmapConfig> {
    vec![
        geomipmap(tau_px, 1),
        GeomipmapConfig {
            morph: true,
            ..geomipmap(tau_px, 2)
        },
        GeomipmapConfig {
            level_difference: LevelDifference::Any,
            projection: Projection::Exact,
            morph: true,
            ..geomipmap(tau_px, 1)
        },
        GeomipmapConfig {
            level_difference: LevelDifference::Any,
            ..geomipmap(tau_px, 3)
        },
    ]
}

#[test]
fn every_eye_over_9_by_9_and_17_by_17_terrains_draws_the_from_scratch_chunks_in_valid_meshes() {
    for level in [3, 4] {
        let hierarchy = bumpy_terrain(level);
        for tau_px in [0.5, 4.0] {
            for config in chunked_configs(tau_px) {
                let mut algorithm = Chunked::new(&hierarchy, config, &view_600());
                algorithm.validate_tree().unwrap();
                for (frame, camera) in eyes_over(&hierarchy).iter().enumerate() {
                    let context = format!("{config:?} at {:?}", camera.eye);
                    checked_step(
                        &hierarchy,
                        &mut algorithm,
                        frame as u64,
                        camera,
                        false,
                        &context,
                    );
                    if let Err(error) = algorithm.validate_frame(camera) {
                        panic!("{context}: {error}");
                    }
                    let expected = chunks_from_scratch(&hierarchy, &config, camera, tau_px);
                    assert_eq!(drawn_ids(&algorithm), expected, "{context}");
                }
            }
        }
    }
}

#[test]
fn every_eye_over_9_by_9_and_17_by_17_terrains_gives_the_from_scratch_patch_levels_in_closed_meshes()
 {
    for level in [3, 4] {
        let hierarchy = bumpy_terrain(level);
        for tau_px in [0.5, 4.0] {
            for config in geomipmap_configs(tau_px) {
                let mut algorithm = Geomipmap::new(&hierarchy, config, &view_600());
                for (frame, camera) in eyes_over(&hierarchy).iter().enumerate() {
                    let context = format!("{config:?} at {:?}", camera.eye);
                    checked_step(
                        &hierarchy,
                        &mut algorithm,
                        frame as u64,
                        camera,
                        false,
                        &context,
                    );
                    if let Err(error) = algorithm.validate(camera) {
                        panic!("{context}: {error}");
                    }
                    let expected = levels_from_scratch(&hierarchy, &config, camera, tau_px);
                    assert_eq!(algorithm.levels(), expected.as_slice(), "{context}");
                }
            }
        }
    }
}

#[test]
fn neighbouring_patches_differ_by_more_than_one_level_only_when_allowed() {
    // Rough ground west of x = 80 m, a flat plain east of it: the criterion puts the rough
    // patches at full resolution and the flat ones at their coarsest level, side by side.
    let side = 33;
    let heights = (0..side * side)
        .map(|k| {
            let (i, j) = (k % side, k / side);
            if i <= 8 {
                ((i * 7 + j * 13) % 5) as f32
            } else {
                0.0
            }
        })
        .collect();
    let field = Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap();
    let hierarchy = Hierarchy::new(field);
    let camera = Camera::new(
        &Pose {
            position: DVec3::new(5.0, 5.0, 40.0),
            yaw: 0.8,
            pitch: -0.2,
        },
        view_600(),
    );
    let largest_jump = |config: GeomipmapConfig| {
        let mut algorithm = Geomipmap::new(&hierarchy, config, &view_600());
        checked_step(&hierarchy, &mut algorithm, 0, &camera, true, "jump");
        algorithm.validate(&camera).unwrap();
        let stitches =
            algorithm.mesh().counts(0).unwrap().triangles_by_role[TriangleRole::Stitch.index()];
        let n = algorithm.patches_per_side() as usize;
        let levels = algorithm.levels();
        let mut jump = 0;
        for p in 0..n * n {
            if p % n + 1 < n {
                jump = jump.max(levels[p].abs_diff(levels[p + 1]));
            }
            if p + n < n * n {
                jump = jump.max(levels[p].abs_diff(levels[p + n]));
            }
        }
        (jump, stitches)
    };
    let (limited, limited_stitches) = largest_jump(geomipmap(2.0, 2));
    let (free, free_stitches) = largest_jump(GeomipmapConfig {
        level_difference: LevelDifference::Any,
        ..geomipmap(2.0, 2)
    });
    assert_eq!(limited, 1);
    assert!(
        free >= 2,
        "the scene should need a jump of two levels, got {free}"
    );
    assert!(limited_stitches > 0 && free_stitches > 0);
}

/// The audit of `mesh` from `camera`, every sample.
fn audit(hierarchy: &Hierarchy, mesh: MeshOutput, camera: &Camera) -> SurfaceCoverage {
    let settings = AuditSettings {
        stride: 1,
        popping: false,
        detail_stride: None,
    };
    let frame = Auditor::new(hierarchy, settings).audit(hierarchy, mesh, camera);
    frame
        .coverage
        .expect("a triangle list has coverage figures")
}

/// `list` without its skirts.
fn without_skirts(list: &TriangleList, hierarchy: &Hierarchy) -> TriangleList {
    let mut bare = TriangleList::new(hierarchy.lattice(), CrackPolicy::Skirted);
    MeshOutput::triangles(list).for_each_triangle(hierarchy, |t| {
        if t.info.role != TriangleRole::Skirt {
            let corners = t.corners.map(|c| bare.add_vertex(c.position, c.z));
            bare.add_triangle(corners, t.info);
        }
    });
    bare
}

/// A flight low over a 65² terrain, turning: chunks of several levels side by side, morphing.
fn low_flight() -> Vec<Camera> {
    (0..40)
        .map(|k| {
            let angle = 0.07 * f64::from(k);
            Camera::new(
                &Pose {
                    position: DVec3::new(
                        320.0 + 180.0 * angle.cos(),
                        320.0 + 180.0 * angle.sin(),
                        60.0,
                    ),
                    yaw: angle + 2.0,
                    pitch: -0.35,
                },
                view_600(),
            )
        })
        .collect()
}

/// Rolling hills 30 m high with half a metre of roughness, 10 m posts: chunks and patches of
/// every level are drawn side by side from a low eye.
fn rolling_hills(level: u32) -> Hierarchy {
    let side = (1usize << level) + 1;
    let heights = (0..side * side)
        .map(|k| {
            let (i, j) = ((k % side) as f32, (k / side) as f32);
            30.0 * (0.11 * i).sin() * (0.07 * j).cos() + ((k * 2654435761) % 11) as f32 * 0.05
        })
        .collect();
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

#[test]
fn without_skirts_the_audit_finds_the_cracks_the_skirts_cover() {
    let hierarchy = rolling_hills(6);
    for skirts in [SkirtDepth::Covering, SkirtDepth::ChunkError] {
        let config = ChunkedConfig {
            skirts,
            morph: true,
            ..chunked(4.0, 2)
        };
        let mut algorithm = Chunked::new(&hierarchy, config, &view_600());
        let (mut cracks, mut open_with, mut open_without) = (0, 0, 0);
        let cameras = low_flight();
        fly_checked(
            &hierarchy,
            &mut algorithm,
            &cameras,
            "skirts",
            |_, camera, _, algorithm| {
                let Some(list) = (match algorithm.mesh() {
                    MeshOutput::Triangles(list) => Some(list),
                    MeshOutput::Lattice(_) => None,
                }) else {
                    panic!("chunked draws a triangle list");
                };
                let with = audit(&hierarchy, algorithm.mesh(), camera);
                let bare = without_skirts(list, &hierarchy);
                let without = audit(&hierarchy, MeshOutput::triangles(&bare), camera);
                // The surface is the same: the same cracks; only what covers them differs.
                assert_eq!(with.crack_samples, without.crack_samples);
                assert_eq!(without.cracks_uncovered, without.crack_samples);
                assert_eq!(without.crack_uncovered_max_m, without.crack_gap_max_m);
                cracks += with.crack_samples;
                open_with += with.cracks_uncovered;
                open_without += without.cracks_uncovered;
            },
        );
        assert!(
            cracks > 100,
            "{skirts:?}: the flight should tear borders ({cracks})"
        );
        assert_eq!(open_without, cracks);
        match skirts {
            // Deep enough for every crack.
            SkirtDepth::Covering => assert_eq!(open_with, 0, "covering skirts left cracks open"),
            // The paper's: zero at the leaves, so some cracks stay open; the others' cover.
            SkirtDepth::ChunkError => assert!(
                open_with > 0 && open_with < cracks,
                "paper skirts: {open_with} of {cracks} crack samples open"
            ),
        }
    }
}

#[test]
fn a_triangle_target_is_held_by_the_finest_tau_that_fits() {
    let hierarchy = bumpy_terrain(6);
    let cameras = low_flight();
    let target = 6_000;
    let chunked_target = ChunkedConfig {
        goal: BlockGoal::TargetTriangles(target),
        morph: true,
        ..chunked(1.0, 2)
    };
    let geomipmap_target = GeomipmapConfig {
        goal: BlockGoal::TargetTriangles(target),
        ..geomipmap(1.0, 2)
    };
    let mut chunked_algorithm = Chunked::new(&hierarchy, chunked_target, &view_600());
    let mut geomipmap_algorithm = Geomipmap::new(&hierarchy, geomipmap_target, &view_600());
    let finer = (-1.0f64 / 64.0).exp2();
    for (frame, camera) in cameras.iter().enumerate() {
        let frame = frame as u64;
        let stats = checked_step(
            &hierarchy,
            &mut chunked_algorithm,
            frame,
            camera,
            false,
            "ch",
        );
        chunked_algorithm.validate_frame(camera).unwrap();
        assert!(
            stats.triangles <= target,
            "frame {frame}: {}",
            stats.triangles
        );
        let tau = chunked_algorithm.tau_px();
        assert!(
            tau > 0.0,
            "frame {frame}: the whole terrain cannot fit 6000 triangles"
        );
        let one_step_finer = ChunkedConfig {
            goal: BlockGoal::TolerancePx(tau * finer),
            ..chunked_target
        };
        let mut fixed = Chunked::new(&hierarchy, one_step_finer, &view_600());
        let finer_stats = checked_step(&hierarchy, &mut fixed, 0, camera, true, "finer");
        assert!(
            finer_stats.triangles > target,
            "frame {frame}: τ {tau} is not the finest"
        );

        let stats = checked_step(
            &hierarchy,
            &mut geomipmap_algorithm,
            frame,
            camera,
            false,
            "gm",
        );
        geomipmap_algorithm.validate(camera).unwrap();
        assert!(
            stats.triangles <= target,
            "frame {frame}: {}",
            stats.triangles
        );
        let tau = geomipmap_algorithm.tau_px();
        assert!(
            tau > 0.0,
            "frame {frame}: the whole terrain cannot fit 6000 triangles"
        );
        let one_step_finer = GeomipmapConfig {
            goal: BlockGoal::TolerancePx(tau * finer),
            ..geomipmap_target
        };
        let mut fixed = Geomipmap::new(&hierarchy, one_step_finer, &view_600());
        let finer_stats = checked_step(&hierarchy, &mut fixed, 0, camera, true, "finer");
        assert!(
            finer_stats.triangles > target,
            "frame {frame}: τ {tau} is not the finest"
        );
    }
}

#[test]
fn an_unreachable_target_draws_the_coarsest_mesh_and_says_so() {
    let hierarchy = bumpy_terrain(5);
    // High above the terrain's box: nothing but the root's own error can ask for detail.
    let camera = Camera::new(
        &Pose {
            position: DVec3::new(160.0, 160.0, 900.0),
            yaw: 0.0,
            pitch: -1.2,
        },
        view_600(),
    );
    let config = ChunkedConfig {
        goal: BlockGoal::TargetTriangles(10),
        ..chunked(1.0, 2)
    };
    let mut algorithm = Chunked::new(&hierarchy, config, &view_600());
    let stats = checked_step(&hierarchy, &mut algorithm, 0, &camera, true, "unreachable");
    assert_eq!(drawn_ids(&algorithm), [ChunkId::ROOT]);
    assert_eq!(common::extra(&algorithm, &stats, TARGET_UNREACHABLE), 1.0);
}

/// Runs `config` over the flight; returns every frame's statistics.
fn fly_chunked(
    hierarchy: &Hierarchy,
    config: ChunkedConfig,
    cameras: &[Camera],
) -> Vec<FrameStats> {
    let mut algorithm = Chunked::new(hierarchy, config, &view_600());
    fly_checked(
        hierarchy,
        &mut algorithm,
        cameras,
        "fly",
        |_, camera, stats, algorithm| {
            algorithm.validate_frame(camera).unwrap();
            stats
        },
    )
}

#[test]
fn culling_drops_chunks_outside_the_view_and_leaves_no_hole_in_it() {
    let hierarchy = bumpy_terrain(6);
    let cameras = low_flight();
    let culled = fly_chunked(
        &hierarchy,
        ChunkedConfig {
            culling: true,
            ..chunked(1.0, 2)
        },
        &cameras,
    );
    let whole = fly_chunked(&hierarchy, chunked(1.0, 2), &cameras);
    let algorithm = Chunked::new(&hierarchy, chunked(1.0, 2), &view_600());
    let mut n_culled = 0.0;
    for ((with, without), camera) in culled.iter().zip(&whole).zip(&cameras) {
        assert!(with.triangles <= without.triangles);
        n_culled += common::extra(&algorithm, with, CHUNKS_CULLED);
        let _ = camera;
    }
    assert!(
        n_culled > 0.0,
        "the flight looks away from most of the terrain"
    );
    // No sample the camera sees is left uncovered.
    let mut algorithm = Chunked::new(
        &hierarchy,
        ChunkedConfig {
            culling: true,
            ..chunked(1.0, 2)
        },
        &view_600(),
    );
    fly_checked(
        &hierarchy,
        &mut algorithm,
        &cameras,
        "holes",
        |frame, camera, _, algorithm| {
            assert_eq!(
                audit(&hierarchy, algorithm.mesh(), camera).holes,
                0,
                "frame {frame}"
            );
        },
    );
}

#[test]
fn front_to_back_order_leaves_fewer_nearer_chunks_behind_farther_ones() {
    let hierarchy = bumpy_terrain(6);
    let cameras = low_flight();
    let ordered = fly_chunked(
        &hierarchy,
        ChunkedConfig {
            front_to_back: true,
            ..chunked(0.5, 1)
        },
        &cameras,
    );
    let plain = fly_chunked(&hierarchy, chunked(0.5, 1), &cameras);
    let algorithm = Chunked::new(&hierarchy, chunked(0.5, 1), &view_600());
    let inversions = |frames: &[FrameStats]| -> f64 {
        frames
            .iter()
            .map(|f| common::extra(&algorithm, f, ORDER_INVERSIONS))
            .sum()
    };
    let (with, without) = (inversions(&ordered), inversions(&plain));
    assert!(
        with < without / 2.0,
        "{with} inversions in order, {without} without"
    );
    // The same chunks, in another order.
    for (a, b) in ordered.iter().zip(&plain) {
        assert_eq!(a.triangles, b.triangles);
    }
}

#[test]
fn the_exact_projection_never_draws_more_than_the_horizontal_view_assumption() {
    let hierarchy = bumpy_terrain(5);
    for camera in eyes_over(&hierarchy).iter().step_by(7) {
        let mut horizontal = Chunked::new(&hierarchy, chunked(1.0, 2), &view_600());
        let exact_config = ChunkedConfig {
            projection: Projection::Exact,
            ..chunked(1.0, 2)
        };
        let mut exact = Chunked::new(&hierarchy, exact_config, &view_600());
        let a = checked_step(&hierarchy, &mut horizontal, 0, camera, true, "h");
        let b = checked_step(&hierarchy, &mut exact, 0, camera, true, "e");
        assert!(b.triangles <= a.triangles, "{:?}", camera.eye);
        // Every chunk the exact projection draws is one the assumption draws or an ancestor.
        for chunk in exact.drawn() {
            assert!(
                horizontal.drawn().iter().any(|h| chunk.id.contains(h.id)),
                "{:?} at {:?}",
                chunk.id,
                camera.eye
            );
        }
    }
}

/// A terrain of side 2^level + 1 shaped as a smooth dome: every level's error four times the
/// finer one's, so that each level has its own distance and morphs into the next.
fn dome(level: u32) -> Hierarchy {
    let side = (1usize << level) + 1;
    let centre = (side / 2) as f32;
    let heights = (0..side * side)
        .map(|k| {
            let (i, j) = ((k % side) as f32, (k / side) as f32);
            let r2 = (i - centre).powi(2) + (j - centre).powi(2);
            80.0 - r2 * 0.05
        })
        .collect();
    Hierarchy::new(Heightfield::new(side, heights, Spacing { dx: 10.0, dy: 10.0 }).unwrap())
}

#[test]
fn morphing_makes_level_changes_continuous() {
    // The eye descends slowly towards the dome: level changes happen every few frames. With
    // morphing the surface moves by a fraction of what it jumps without.
    let hierarchy = dome(6);
    let cameras: Vec<Camera> = (0..120)
        .map(|k| {
            Camera::new(
                &Pose {
                    position: DVec3::new(-200.0 + 3.0 * f64::from(k), 320.0, 300.0 - f64::from(k)),
                    yaw: 0.0,
                    pitch: -0.5,
                },
                view_600(),
            )
        })
        .collect();
    let popping_max = |algorithm: &mut dyn LodAlgorithm| -> f64 {
        let mut auditor = Auditor::new(
            &hierarchy,
            AuditSettings {
                stride: 1,
                popping: true,
                detail_stride: None,
            },
        );
        let mut largest: f64 = 0.0;
        for (frame, camera) in cameras.iter().enumerate() {
            checked_step(&hierarchy, algorithm, frame as u64, camera, false, "morph");
            let frame = auditor.audit(&hierarchy, algorithm.mesh(), camera);
            if let Some(popping) = frame.popping {
                largest = largest.max(popping.max_m);
            }
        }
        largest
    };
    let plain = popping_max(&mut Chunked::new(&hierarchy, chunked(2.0, 2), &view_600()));
    let morphed = popping_max(&mut Chunked::new(
        &hierarchy,
        ChunkedConfig {
            morph: true,
            ..chunked(2.0, 2)
        },
        &view_600(),
    ));
    assert!(
        plain > 0.5,
        "the flight should pop without morphing ({plain} m)"
    );
    assert!(
        morphed < plain / 3.0,
        "chunked: {morphed} m with morphing, {plain} m without"
    );
    let plain = popping_max(&mut Geomipmap::new(
        &hierarchy,
        geomipmap(2.0, 3),
        &view_600(),
    ));
    let morphed = popping_max(&mut Geomipmap::new(
        &hierarchy,
        GeomipmapConfig {
            morph: true,
            ..geomipmap(2.0, 3)
        },
        &view_600(),
    ));
    assert!(
        plain > 0.5,
        "the flight should pop without morphing ({plain} m)"
    );
    assert!(
        morphed < plain / 3.0,
        "geomipmap: {morphed} m with morphing, {plain} m without"
    );
}

/// [`checked_step`], then the buffers made drawable (what the runner times as `frame_ns`) and
/// checked against the mesh as `--check` does; what the frame uploaded and issued.
fn drawn_step(
    hierarchy: &Hierarchy,
    algorithm: &mut dyn LodAlgorithm,
    frame: u64,
    camera: &Camera,
    context: &str,
) -> (FrameStats, DrawCounts) {
    let stats = checked_step(hierarchy, algorithm, frame, camera, frame == 0, context);
    let counts = common::draw_counts(&stats);
    if let Err(error) = check_buffers_draw_mesh(algorithm.buffers(), algorithm.mesh(), hierarchy) {
        panic!("{context}, frame {frame}: {error}");
    }
    assert_eq!(
        counts.triangles_submitted, stats.triangles,
        "{context}, frame {frame}: a patch's list submits its triangles"
    );
    (stats, counts)
}

/// A flight over a 129² terrain: a low pass that turns (levels change, patches leave and
/// enter the view), a hover (the same camera twice), then a teleport to the far corner.
fn patch_flight() -> Vec<Camera> {
    let mut cameras: Vec<Camera> = (0..24)
        .map(|t| {
            let t = f64::from(t);
            Camera::new(
                &Pose {
                    position: DVec3::new(60.0 + 25.0 * t, 100.0 + 12.0 * t, 60.0 - 1.5 * t),
                    yaw: 0.12 * t,
                    pitch: -0.35,
                },
                view_600(),
            )
        })
        .collect();
    cameras.push(cameras[23]);
    cameras.push(Camera::new(
        &Pose {
            position: DVec3::new(1200.0, 1150.0, 45.0),
            yaw: 3.5,
            pitch: -0.4,
        },
        view_600(),
    ));
    cameras.push(cameras[25]);
    cameras
}

#[test]
fn geomipmap_buffers_are_the_mesh_and_only_a_level_or_morph_change_writes_a_vertex() {
    let hierarchy = bumpy_terrain(7);
    for box_culling in [false, true] {
        for config in [
            GeomipmapConfig {
                box_culling,
                ..geomipmap(8.0, 3)
            },
            GeomipmapConfig {
                morph: true,
                box_culling,
                ..geomipmap(5.0, 3)
            },
            GeomipmapConfig {
                morph: true,
                level_difference: LevelDifference::Any,
                box_culling,
                goal: BlockGoal::TargetTriangles(4000),
                ..geomipmap(1.0, 2)
            },
        ] {
            let context = format!("{config:?}");
            let mut algorithm = Geomipmap::new(&hierarchy, config, &view_600());
            let n_patches = algorithm.patches_per_side().pow(2) as u64;
            let mut previous: Option<(Vec<u32>, Vec<f64>)> = None;
            let mut level_changes = 0;
            let mut uploaded_after_the_first_frame = 0;
            for (frame, camera) in patch_flight().iter().enumerate() {
                let (stats, counts) =
                    drawn_step(&hierarchy, &mut algorithm, frame as u64, camera, &context);
                algorithm
                    .validate(camera)
                    .unwrap_or_else(|e| panic!("{context}, frame {frame}: {e}"));
                let culled = if box_culling {
                    common::extra(&algorithm, &stats, PATCHES_CULLED) as u64
                } else {
                    0
                };
                assert_eq!(
                    counts.draw_calls,
                    n_patches - culled,
                    "{context}, frame {frame}: one draw per patch drawn"
                );
                let now = (
                    algorithm.levels().to_vec(),
                    algorithm.morph_factors().to_vec(),
                );
                if let Some(before) = &previous {
                    level_changes += u64::from(*before != now);
                    if *before == now && stats.splits + stats.merges == 0 {
                        // The camera hovered (or the levels and factors did not move): nothing
                        // is written, whatever the culling did (buffers are kept).
                        if frame == 24 || frame == 26 {
                            assert_eq!(counts.upload_bytes, 0, "{context}, frame {frame}");
                        }
                    }
                }
                if !config.morph && frame > 0 && !box_culling {
                    // Every vertex buffer exists from the first frame on: a later frame writes
                    // only index buffers for a (level, sides) not drawn before, never a vertex.
                    uploaded_after_the_first_frame += counts.upload_bytes;
                }
                previous = Some(now);
            }
            let k = algorithm.patch_level();
            let largest_index_buffer = 2 * 4u64.pow(k) * 3 * 4;
            assert!(
                uploaded_after_the_first_frame <= u64::from(k + 1) * 16 * largest_index_buffer,
                "{context}: {uploaded_after_the_first_frame} bytes after the first frame: more \
                 than one index buffer per (level, stitched sides)"
            );
            assert!(
                level_changes > 3,
                "{context}: the flight changes levels or factors ({level_changes} times)"
            );
        }
    }
}

#[test]
fn geomipmap_with_box_culling_visits_the_patches_in_view_not_the_terrain() {
    // The same view over a terrain 16 times larger: the quadtree visits a few more nodes (its
    // depth), the level tests stay those of the patches in view.
    let (small, large) = (extended_terrain(7), extended_terrain(9));
    let camera = short_sighted_camera();
    let run = |hierarchy: &Hierarchy| {
        let config = GeomipmapConfig {
            box_culling: true,
            ..geomipmap(1.0, 3)
        };
        let mut algorithm = Geomipmap::new(hierarchy, config, &view_600());
        let (stats, counts) = drawn_step(hierarchy, &mut algorithm, 0, &camera, "culled");
        (
            stats.metric_evaluations,
            common::extra(&algorithm, &stats, QUADTREE_NODES_VISITED),
            counts.draw_calls,
        )
    };
    let (small_tests, small_nodes, small_draws) = run(&small);
    let (large_tests, large_nodes, large_draws) = run(&large);
    assert_eq!(small_draws, large_draws, "the same patches are in view");
    assert_eq!(small_tests, large_tests);
    assert!(
        // Two more quadtree levels above the same patches: at most four nodes each, twice.
        large_nodes <= small_nodes + 16.0,
        "{large_nodes} nodes visited over the large terrain, {small_nodes} over the small one"
    );
}
