//! `vanek` (Vaněk–Ježek 2004) against its definition: every frame's mesh through the `--check`
//! validator (crack policy `collapsed`: the surface tiles the domain, borders closed) and the
//! algorithm's own validator (levels and culling against a brute-force recomputation, counts,
//! collapsed borders lining up), for every eye over 9×9 and 17×17 terrains and every option;
//! every combination of neighbouring levels on small patch grids (exhaustive); the strip's
//! counts per frame; the triangle target; culling; the counters.

mod common;

use common::algorithms::vanek;
use common::scenes::{extended_terrain, short_sighted_camera};
use common::{bumpy_terrain, checked_step, extra, view_600};
use glam::DVec3;
use roamsim::sim::algorithm::columns::vanek::{
    COLLAPSED_TRIANGLES, DEGENERATE_TRIANGLES, DISTANCE_MULTIPLIER, PATCHES_CULLED,
    QUADTREE_NODES_VISITED, STRIP_INDICES, TARGET_UNREACHABLE,
};
use roamsim::sim::algorithm::vanek::lods_from_scratch;
use roamsim::sim::algorithm::{
    LodAlgorithm, LodCurve, LodRounding, PatchDistance, Vanek, VanekConfig,
};
use roamsim::sim::draw::check::check_buffers_draw_mesh;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::TriangleRole;
use roamsim::sim::mesh::check::MeshChecker;
use roamsim::sim::stats::FrameStats;
use roamsim::sim::view::{Camera, Pose, ViewSettings};

/// Eyes over the terrain: above every sample, 4 m and 70 m over the highest ground, turning.
fn eyes_over(hierarchy: &Hierarchy) -> Vec<Camera> {
    let field = hierarchy.field();
    let (_, top) = field.height_range();
    let side = field.side();
    let mut cameras = Vec::new();
    for j in 0..side {
        for i in 0..side {
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

fn every_option(patch_level: u32) -> Vec<VanekConfig> {
    let mut configs = Vec::new();
    for rounding in [LodRounding::Down, LodRounding::Nearest, LodRounding::Up] {
        for distance in [PatchDistance::Box, PatchDistance::Centre] {
            for (exponent, box_culling) in [(1.0, false), (0.5, true), (2.5, false)] {
                let plain = vanek(patch_level, 15.0, 160.0);
                configs.push(VanekConfig {
                    curve: LodCurve {
                        exponent,
                        rounding,
                        ..plain.curve
                    },
                    distance,
                    box_culling,
                    ..plain
                });
            }
        }
    }
    configs
}

/// One checked frame: `--check`'s validator, then the algorithm's own.
fn checked(
    hierarchy: &Hierarchy,
    vanek: &mut Vanek,
    frame: u64,
    camera: &Camera,
    context: &str,
) -> FrameStats {
    let stats = checked_step(hierarchy, vanek, frame, camera, frame == 0, context);
    if let Err(error) = vanek.validate(camera) {
        panic!("{context}, frame {frame}: {error}");
    }
    stats
}

#[test]
fn every_eye_and_option_over_small_terrains_passes_check_and_the_brute_force_selection() {
    for (level, patch_levels) in [(3, &[1, 2, 3][..]), (4, &[2, 3][..])] {
        let hierarchy = bumpy_terrain(level);
        let cameras = eyes_over(&hierarchy);
        for &n in patch_levels {
            let mut levels_seen = [false; 4];
            for config in every_option(n) {
                let mut vanek = Vanek::new(&hierarchy, config);
                for (frame, camera) in cameras.iter().enumerate() {
                    let context = format!("{config:?} on {level}");
                    checked(&hierarchy, &mut vanek, frame as u64, camera, &context);
                    for k in vanek.lods().into_iter().flatten() {
                        levels_seen[k as usize] = true;
                    }
                }
            }
            // Over all the options, the eyes reach every level.
            assert!(
                levels_seen[..=n as usize].iter().all(|&s| s),
                "n = {n}: {levels_seen:?}"
            );
        }
    }
}

#[test]
fn every_combination_of_neighbouring_levels_collapses_into_a_closed_surface() {
    // 2 × 2 patches of n = 1, 2, 3 (every level of each: 16, 81, 256 combinations), and 4 × 4
    // patches of n = 1 (2^16).
    let mut cases = 0;
    for (level, n) in [(2, 1), (3, 2), (4, 3), (3, 1)] {
        let hierarchy = bumpy_terrain(level);
        let mut vanek = Vanek::new(&hierarchy, vanek(n, 10.0, 100.0));
        let patches = vanek.lods().len();
        let choices = n + 1;
        let combinations = u64::from(choices).pow(patches as u32);
        let mut checker = MeshChecker::new();
        for code in 0..combinations {
            let lods: Vec<u32> = (0..patches)
                .map(|p| ((code / u64::from(choices).pow(p as u32)) % u64::from(choices)) as u32)
                .collect();
            vanek.draw_with_lods(&lods);
            if let Err(error) = checker.check(&hierarchy, vanek.mesh(), vanek.triangle_count()) {
                panic!("n = {n}, levels {lods:?}: {error}");
            }
            if let Err(error) = vanek.validate_mesh() {
                panic!("n = {n}, levels {lods:?}: {error}");
            }
            cases += 1;
        }
    }
    assert_eq!(cases, 16 + 81 + 256 + 65_536);
}

#[test]
fn a_coarser_neighbour_flattens_the_finer_patch_border_and_the_strip_counts_add_up() {
    // 2 × 2 patches of 5 × 5 samples on a 9 × 9 terrain: patch 0 at full resolution (k = 2),
    // the other three at k = 0.
    let hierarchy = bumpy_terrain(3);
    let mut vanek = Vanek::new(&hierarchy, vanek(2, 10.0, 100.0));
    vanek.draw_with_lods(&[2, 0, 0, 0]);
    // Patch 0: m = 5, (2·5 + 2)·4 − 2 = 46 triangles, 14 of them joins; the others m = 2:
    // 6 − 2 = 4 each, 2 joins.
    assert_eq!(vanek.triangle_count(), 46 + 3 * 4);
    let roamsim::sim::mesh::MeshOutput::Triangles(list) = vanek.mesh() else {
        panic!("vanek draws a triangle list")
    };
    let degenerate = list.role_count(TriangleRole::Degenerate);
    let joins = 14 + 3 * 2;
    // Each of patch 0's two collapsed sides (4 cells) loses 3 of its vertices to the corners:
    // the triangles over the 4 border cells that touch only one kept vertex flatten. The
    // surface is what the two levels tile: 2·16 − (flattened) + 3·2.
    let surface = list.role_count(TriangleRole::Surface);
    assert_eq!(surface + degenerate, 58);
    assert!(degenerate > joins, "{degenerate} degenerate, {joins} joins");
    assert_eq!(surface, 32 - (degenerate - joins) + 6);
    vanek.validate_mesh().unwrap();
}

#[test]
fn strip_columns_count_the_paper_s_indices_and_degenerate_triangles_every_frame() {
    let hierarchy = bumpy_terrain(5);
    let config = vanek(3, 20.0, 250.0);
    let mut vanek = Vanek::new(&hierarchy, config);
    for (frame, x) in [0.0, 90.0, 200.0, 310.0].into_iter().enumerate() {
        let camera = Camera::new(
            &Pose {
                position: DVec3::new(x, 100.0, 80.0),
                yaw: 0.3,
                pitch: -0.3,
            },
            view_600(),
        );
        let stats = checked(&hierarchy, &mut vanek, frame as u64, &camera, "strip");
        let lods = lods_from_scratch(&hierarchy, &config, 1.0, camera.eye);
        let per_patch = |k: u32| {
            let m = (1u64 << k) + 1;
            ((2 * m + 2) * (m - 1), 4 * (m - 1) - 2)
        };
        let indices: u64 = lods.iter().map(|&k| per_patch(k).0).sum();
        let joins: u64 = lods.iter().map(|&k| per_patch(k).1).sum();
        assert_eq!(extra(&vanek, &stats, STRIP_INDICES), indices as f64);
        assert_eq!(stats.triangles, indices - 2 * lods.len() as u64);
        let collapsed = extra(&vanek, &stats, COLLAPSED_TRIANGLES);
        assert_eq!(
            extra(&vanek, &stats, DEGENERATE_TRIANGLES),
            joins as f64 + collapsed
        );
        let roamsim::sim::mesh::MeshOutput::Triangles(list) = vanek.mesh() else {
            panic!("vanek draws a triangle list")
        };
        assert_eq!(list.draw_batches(), lods.len() as u64);
    }
}

#[test]
fn the_target_holds_the_finest_mesh_within_it_and_reports_the_unreachable() {
    let hierarchy = bumpy_terrain(5);
    let camera = Camera::new(
        &Pose {
            position: DVec3::new(60.0, 90.0, 70.0),
            yaw: 0.4,
            pitch: -0.3,
        },
        view_600(),
    );
    let plain = vanek(3, 20.0, 250.0);
    // 16 patches: coarsest 16·4 triangles, finest 16·(18·8 − 2).
    for (target, unreachable) in [(2000, false), (900, false), (10, true), (1_000_000, false)] {
        let config = VanekConfig {
            target_triangles: Some(target),
            ..plain
        };
        let mut vanek = Vanek::new(&hierarchy, config);
        let stats = checked(&hierarchy, &mut vanek, 0, &camera, "target");
        let mu = extra(&vanek, &stats, DISTANCE_MULTIPLIER);
        assert_eq!(
            extra(&vanek, &stats, TARGET_UNREACHABLE),
            f64::from(u8::from(unreachable)),
            "target {target}"
        );
        if unreachable {
            // Every patch at k = 0 (the eye is above every box): 16 · 4 triangles.
            assert!(stats.triangles > target);
            assert_eq!(stats.triangles, 16 * 4);
            assert!(vanek.lods().iter().all(|&k| k == Some(0)));
            continue;
        }
        assert!(stats.triangles <= target, "target {target}");
        if target == 1_000_000 {
            assert_eq!(mu, 0.0);
            assert!(vanek.lods().iter().all(|&k| k == Some(3)));
            continue;
        }
        // One search step finer (μ smaller by 1/64 octave) is over the target.
        let finer = mu * (-1.0f64 / 64.0).exp2();
        let lods = lods_from_scratch(&hierarchy, &config, finer, camera.eye);
        let count: u64 = lods
            .iter()
            .map(|&k| {
                let m = (1u64 << k) + 1;
                (2 * m + 2) * (m - 1) - 2
            })
            .sum();
        assert!(count > target, "target {target}: μ {mu}, finer {count}");
    }
}

#[test]
fn culling_drops_only_patches_outside_the_view_and_changes_no_level() {
    let hierarchy = bumpy_terrain(5);
    let plain = vanek(2, 20.0, 250.0);
    let culling = VanekConfig {
        box_culling: true,
        ..plain
    };
    let mut without = Vanek::new(&hierarchy, plain);
    let mut with = Vanek::new(&hierarchy, culling);
    let camera = Camera::new(
        &Pose {
            position: DVec3::new(20.0, 160.0, 60.0),
            yaw: 0.0,
            pitch: -0.2,
        },
        view_600(),
    );
    let a = checked(&hierarchy, &mut without, 0, &camera, "no culling");
    let b = checked(&hierarchy, &mut with, 0, &camera, "culling");
    // The patches drawn have the levels they have without culling; the others none.
    for (patch, (all, drawn)) in without.lods().into_iter().zip(with.lods()).enumerate() {
        assert!(drawn.is_none() || drawn == all, "patch {patch}");
    }
    let culled = extra(&with, &b, PATCHES_CULLED);
    assert!(culled > 0.0 && culled < 64.0, "{culled}");
    assert_eq!(extra(&without, &a, PATCHES_CULLED), 0.0);
    assert!(b.triangles < a.triangles);
    // Looking east from near the west edge: a patch ahead (px 3, py 4) is kept, the far
    // corners north-west and south-west of the eye, beside and behind it, are culled.
    let lods = with.lods();
    assert!(lods[4 * 8 + 3].is_some());
    assert!(lods[0].is_none() && lods[7 * 8].is_none());
}

#[test]
fn splits_merges_and_vertices_count_the_patches_that_changed() {
    let hierarchy = bumpy_terrain(4);
    let mut vanek = Vanek::new(&hierarchy, vanek(2, 10.0, 200.0));
    let at = |x: f64| {
        Camera::new(
            &Pose {
                position: DVec3::new(x, 80.0, 40.0),
                yaw: 0.0,
                pitch: -0.3,
            },
            view_600(),
        )
    };
    let first = checked(&hierarchy, &mut vanek, 0, &at(0.0), "counters");
    let vertices: u64 = vanek
        .lods()
        .into_iter()
        .flatten()
        .map(|k| ((1u64 << k) + 1).pow(2))
        .sum();
    assert_eq!(first.vertices_inserted, vertices);
    let before = vanek.lods().to_vec();
    let same = checked(&hierarchy, &mut vanek, 1, &at(0.0), "counters");
    assert_eq!(
        (same.splits, same.merges, same.vertices_inserted),
        (0, 0, 0)
    );
    let moved = checked(&hierarchy, &mut vanek, 2, &at(160.0), "counters");
    let after = vanek.lods();
    let finer = before.iter().zip(&after).filter(|(b, a)| a > b).count() as u64;
    let coarser = before.iter().zip(&after).filter(|(b, a)| a < b).count() as u64;
    assert!(finer > 0 && coarser > 0, "{before:?} → {after:?}");
    assert_eq!((moved.splits, moved.merges), (finer, coarser));
    assert!(moved.vertices_inserted > 0 && moved.vertices_deleted > 0);
}

/// A flight over a 129² terrain: a low pass that turns (levels change, patches leave and
/// enter the view), a hover (the same camera twice), then a teleport and a hover there.
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
fn the_buffers_are_the_mesh_and_a_patch_whose_level_and_neighbours_hold_is_not_rewritten() {
    let hierarchy = bumpy_terrain(7);
    for config in [
        vanek(3, 100.0, 900.0),
        VanekConfig {
            box_culling: true,
            ..vanek(3, 100.0, 900.0)
        },
        VanekConfig {
            target_triangles: Some(3000),
            box_culling: true,
            ..vanek(2, 50.0, 700.0)
        },
    ] {
        let context = format!("{config:?}");
        let mut algorithm = Vanek::new(&hierarchy, config);
        let mut previous: Option<Vec<Option<u32>>> = None;
        let mut level_changes = 0;
        for (frame, camera) in patch_flight().iter().enumerate() {
            let stats = checked_step(
                &hierarchy,
                &mut algorithm,
                frame as u64,
                camera,
                frame == 0,
                &context,
            );
            let counts = common::draw_counts(&stats);
            if let Err(error) =
                check_buffers_draw_mesh(algorithm.buffers(), algorithm.mesh(), &hierarchy)
            {
                panic!("{context}, frame {frame}: {error}");
            }
            let culled = extra(&algorithm, &stats, PATCHES_CULLED) as u64;
            let drawn = algorithm.lods().len() as u64 - culled;
            assert_eq!(
                counts.draw_calls, drawn,
                "{context}, frame {frame}: a draw per patch"
            );
            assert_eq!(
                counts.triangles_submitted,
                stats.triangles + drawn,
                "{context}, frame {frame}: the strips, one parity index each"
            );
            let lods = algorithm.lods();
            if let Some(before) = &previous {
                level_changes += u64::from(*before != lods);
                if *before == lods && frame > 0 && (frame == 24 || frame == 26) {
                    assert_eq!(
                        counts.upload_bytes, 0,
                        "{context}, frame {frame}: nothing changed, nothing is written"
                    );
                }
                if frame > 0 && frame != 25 {
                    // Only patches whose level or a neighbour's changed are rewritten: at most
                    // every drawn patch whose own or a neighbour's level moved, or which it
                    // culls or draws anew (a side beside a culled patch is not collapsed).
                    let per_side = algorithm.patches_per_side() as usize;
                    let changed = |p: usize| before[p] != lods[p];
                    let touched = (0..lods.len())
                        .filter(|&p| lods[p].is_some())
                        .filter(|&p| {
                            let (x, y) = (p % per_side, p / per_side);
                            changed(p)
                                || (x > 0 && changed(p - 1))
                                || (x + 1 < per_side && changed(p + 1))
                                || (y > 0 && changed(p - per_side))
                                || (y + 1 < per_side && changed(p + per_side))
                        })
                        .map(|p| ((1u64 << lods[p].expect("drawn")) + 1).pow(2) * 12)
                        .sum::<u64>();
                    assert!(
                        counts.upload_bytes <= touched + 4 * 4 * 300,
                        "{context}, frame {frame}: {} bytes written, {touched} for the patches \
                         whose level or neighbours changed",
                        counts.upload_bytes
                    );
                }
            }
            previous = Some(lods);
        }
        assert!(level_changes > 3, "{context}: the flight changes levels");
    }
}

#[test]
fn with_culling_a_patch_outside_the_view_is_neither_drawn_nor_given_a_level() {
    // The same view over a terrain 16 times larger: the quadtree visits a few more nodes (its
    // depth), the level computations stay those of the patches in view, one per patch drawn
    // and per pass of the target's search.
    let camera = short_sighted_camera();
    for target_triangles in [None, Some(2000)] {
        let config = VanekConfig {
            box_culling: true,
            target_triangles,
            ..vanek(3, 50.0, 500.0)
        };
        let run = |hierarchy: &Hierarchy| {
            let mut algorithm = Vanek::new(hierarchy, config);
            let stats = checked(hierarchy, &mut algorithm, 0, &camera, "culled");
            let drawn = algorithm.drawn_patches().len() as u64;
            let lods = algorithm.lods();
            assert_eq!(lods.iter().flatten().count() as u64, drawn);
            assert_eq!(common::draw_counts(&stats).draw_calls, drawn);
            assert_eq!(
                extra(&algorithm, &stats, PATCHES_CULLED) as u64,
                lods.len() as u64 - drawn
            );
            // Every level computed is a drawn patch's.
            assert_eq!(stats.metric_evaluations % drawn, 0, "{config:?}");
            if target_triangles.is_none() {
                assert_eq!(stats.metric_evaluations, drawn, "{config:?}");
            }
            (
                lods,
                stats.metric_evaluations,
                extra(&algorithm, &stats, QUADTREE_NODES_VISITED),
            )
        };
        let (small, large) = (extended_terrain(7), extended_terrain(9));
        let (small_lods, small_evaluations, small_nodes) = run(&small);
        let (large_lods, large_evaluations, large_nodes) = run(&large);
        let drawn = |lods: &[Option<u32>], per_side: usize| -> Vec<(usize, usize, u32)> {
            (0..lods.len())
                .filter_map(|p| lods[p].map(|k| (p % per_side, p / per_side, k)))
                .collect()
        };
        assert!(large_lods.len() == 16 * small_lods.len());
        assert!(
            drawn(&small_lods, 16).len() < small_lods.len(),
            "the view culls"
        );
        assert_eq!(
            drawn(&small_lods, 16),
            drawn(&large_lods, 64),
            "{config:?}: the same patches drawn at the same levels"
        );
        assert_eq!(small_evaluations, large_evaluations, "{config:?}");
        assert!(
            large_nodes <= small_nodes + 16.0,
            "{large_nodes} nodes visited over the large terrain, {small_nodes} over the small one"
        );
    }
}

#[test]
fn culling_changes_no_mesh_when_every_patch_is_in_view() {
    // From high above, looking straight down with a wide view: nothing to cull, and the
    // meshes, the multiplier and the buffers drawn are those without culling, frame by frame.
    let hierarchy = bumpy_terrain(6);
    let cameras: Vec<Camera> = [(320.0, 320.0, 900.0), (250.0, 380.0, 700.0)]
        .iter()
        .map(|&(x, y, z)| {
            Camera::new(
                &Pose {
                    position: DVec3::new(x, y, z),
                    yaw: 0.3,
                    pitch: -std::f64::consts::FRAC_PI_2 + 1e-3,
                },
                ViewSettings {
                    fovy: 120f64.to_radians(),
                    ..view_600()
                },
            )
        })
        .collect();
    for plain in [
        vanek(3, 100.0, 1500.0),
        VanekConfig {
            target_triangles: Some(1500),
            ..vanek(3, 100.0, 1500.0)
        },
    ] {
        let culling = VanekConfig {
            box_culling: true,
            ..plain
        };
        let mut without = Vanek::new(&hierarchy, plain);
        let mut with = Vanek::new(&hierarchy, culling);
        for (frame, camera) in cameras.iter().enumerate() {
            let a = checked(&hierarchy, &mut without, frame as u64, camera, "no culling");
            let b = checked(&hierarchy, &mut with, frame as u64, camera, "culling");
            assert_eq!(extra(&with, &b, PATCHES_CULLED), 0.0, "{plain:?}");
            assert_eq!(without.lods(), with.lods(), "{plain:?}");
            assert_eq!(
                without.distance_multiplier(),
                with.distance_multiplier(),
                "{plain:?}"
            );
            let triangles = |v: &Vanek| {
                let mut all = Vec::new();
                v.mesh().for_each_triangle(&hierarchy, |t| {
                    all.push((t.corners.map(|c| (c.position.raw(), c.z.to_bits())), t.info));
                });
                all
            };
            assert_eq!(triangles(&without), triangles(&with), "{plain:?}");
            assert_eq!(
                (a.triangles, a.metric_evaluations),
                (b.triangles, b.metric_evaluations)
            );
            assert_eq!(common::draw_counts(&a), common::draw_counts(&b));
        }
    }
}
