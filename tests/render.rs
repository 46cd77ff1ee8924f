//! The preview's drawing, checked on what must be in the images (built with `--features
//! preview`; CI runs it on Mesa's software Vulkan driver).
//!
//! A small synthetic experiment is replayed; its meshes are drawn offscreen as flat triangle
//! ids and the ids read back: seen from straight above every triangle of the frame's mesh
//! shows, so the distinct ids count the triangles drawn, which must equal the frame's
//! statistic; seen from the flight camera every covered pixel must lie on the triangle the
//! simulation's own camera projects there, the sky above the horizon stays empty, and the
//! ground below is covered. A triangle list with skirts, degenerate strip joins and morphed
//! heights (the test-only `Patches` of `tests/common/patches.rs`) is drawn the same way: from
//! above exactly its surface triangles show (skirts and degenerate triangles have no area seen
//! from there), from the flight camera every pixel lies on its triangle, from the side the
//! skirts show, and with roles on they (and the degenerate triangles' edges) are told apart by
//! colour. Without a graphics adapter the GPU tests say so and pass, unless `CI` is set: then a
//! missing adapter fails them.

#![cfg(feature = "preview")]

mod common;

use common::experiment::{quickstart, save};
use common::patches::{Borders, PatchConfig, Patches};
use glam::{DVec2, DVec3};
use roamsim::edge::preview::geometry::{
    LineVertex, MeshGeometry, ViewChoice, Viewport, flight_view_projection,
    overview_view_projection,
};
use roamsim::edge::preview::headless::{
    HeadlessError, Offscreen, RenderRequest, TriangleIdImage, pane_camera, render_experiment,
};
use roamsim::edge::preview::renderer::{DrawOptions, Pane};
use roamsim::edge::preview::replay::{Replay, Scene};
use roamsim::sim::algorithm::LodAlgorithm;
use roamsim::sim::draw::GpuBuffers;
use roamsim::sim::hierarchy::Hierarchy;
use roamsim::sim::mesh::TriangleRole;
use roamsim::sim::mesh::triangles::count_triangles;
use roamsim::sim::run::{Effects, FrameOutcome, FrameRunner, RunInputs};
use roamsim::sim::view::{Camera, Pose};
use serde_json::json;
use std::collections::BTreeSet;
use std::path::Path;

/// Drawing options of the id checks: no wireframe, no tint, no roles.
const PLAIN: DrawOptions = DrawOptions {
    wireframe: false,
    tint_culled: false,
    roles: false,
};

/// Frames of the small flight that the tests look at.
const FRAMES: [u64; 3] = [0, 4, 9];
/// The flight camera's image (the experiment's window).
const FLIGHT_SIZE: (u32, u32) = (320, 240);
/// The overview's image: 512 px over a 64-cell terrain (plus margins) leaves the finest
/// triangles (legs of one cell) about 7 px wide, so each covers pixel centres.
const OVERVIEW_SIZE: u32 = 512;

/// A 65² synthetic terrain, 30 m posts, flown over on a circle looking 25° down, with Wu and
/// the from-scratch reference at a tolerance that refines near the camera.
fn small_experiment(dir: &Path) -> std::path::PathBuf {
    let mut experiment = quickstart();
    experiment["name"] = json!("render-small");
    experiment["terrain"] = json!({"synthetic": {"level": 6, "seed": 11, "amplitude_m": 120,
        "roughness": 0.7, "spacing_m": {"dx": 30, "dy": 30}}});
    experiment["view"] = json!({"width_px": FLIGHT_SIZE.0, "height_px": FLIGHT_SIZE.1,
        "fovy_deg": 60, "near_m": 1, "far_m": 20000});
    experiment["flight"] = json!({
        "frames": 10,
        "look": { "along_path": { "pitch_deg": -25 } },
        "path": { "circle": { "centre_m": [960, 960], "radius_m": 300, "altitude_m": 400,
                              "frames_per_lap": 400 } }
    });
    experiment["algorithms"] = json!([
        { "name": "wu", "label": "wu τ=2px", "tau_px": 2 },
        { "name": "reference", "label": "reference τ=2px", "tau_px": 2, "zone": "conservative" }
    ]);
    experiment["effects"] = json!({"culling": true});
    save(dir, "render-small", &experiment)
}

/// An offscreen target, or `None` (after saying why) when the machine has no adapter and this
/// is not CI. Under `CI` a missing adapter is a failure.
fn offscreen(width: u32, height: u32) -> Option<Offscreen> {
    match Offscreen::new(width, height) {
        Ok(offscreen) => {
            eprintln!("rendering on {}", offscreen.adapter_description());
            Some(offscreen)
        }
        Err(HeadlessError::NoAdapter(why)) if std::env::var_os("CI").is_none() => {
            // Written to the process's stderr, not through `eprintln!`, so that the test
            // harness does not swallow it: a skipped check must be seen. (A failed write to
            // stderr has nowhere left to be reported.)
            let message = format!(
                "SKIPPED: no graphics adapter ({why}); install Mesa's software Vulkan driver \
                 (mesa-vulkan-drivers) to run the render tests. Under CI this fails.\n"
            );
            let _ = std::io::Write::write_all(&mut std::io::stderr(), message.as_bytes());
            None
        }
        Err(error) => panic!("cannot render offscreen: {error}"),
    }
}

/// Replays both entries of the small experiment and calls `check` at every frame of [`FRAMES`]
/// with the scene, the replay and the frame.
fn at_each_checked_frame(check: &mut dyn FnMut(&Scene, &Replay, u64)) {
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::load(&small_experiment(dir.path())).unwrap();
    let mut replay = Replay::new(&scene, &[0, 1]);
    for frame in FRAMES {
        replay.run_to(frame).unwrap();
        check(&scene, &replay, frame);
    }
}

fn distinct_triangles(image: &TriangleIdImage) -> BTreeSet<u32> {
    image
        .ids
        .iter()
        .filter(|&&id| id != 0)
        .map(|&id| id - 1)
        .collect()
}

fn covered_fraction(ids: &[u32]) -> f64 {
    ids.iter().filter(|&&id| id != 0).count() as f64 / ids.len() as f64
}

#[test]
fn the_triangle_list_holds_every_triangle_of_the_mesh_once_with_the_runs_culling() {
    at_each_checked_frame(&mut |scene, replay, frame| {
        for k in 0..replay.n_lanes() {
            let lane = replay.lane(k).unwrap();
            let mut geometry = MeshGeometry::default();
            geometry.rebuild(&scene.hierarchy, lane.buffers, lane.mesh, lane.camera);
            let lattice = scene.hierarchy.lattice();
            assert_eq!(lane.stats.frame, frame);
            assert_eq!(
                geometry.n_triangles(),
                lane.stats.triangles,
                "{}",
                lane.label
            );
            assert_eq!(
                geometry.n_triangles(),
                lane.triangle_count,
                "{}",
                lane.label
            );
            let vertices = lane.mesh.lattice_vertices().unwrap();
            assert_eq!(geometry.n_triangles(), count_triangles(lattice, vertices));
            let in_view = geometry
                .vertices()
                .chunks_exact(3)
                .filter(|t| t[0].in_view == 1.0)
                .count() as u64;
            assert_eq!(in_view, lane.stats.triangles_rendered, "{}", lane.label);
            assert!(
                lane.stats.triangles > 100 && geometry.max_level() > 6,
                "{}: the flight should refine the mesh near the camera (T = {}, deepest level {})",
                lane.label,
                lane.stats.triangles,
                geometry.max_level()
            );
        }
    });
}

#[test]
fn seen_from_above_the_drawn_triangles_are_exactly_the_frames_triangles() {
    let Some(offscreen) = offscreen(OVERVIEW_SIZE, OVERVIEW_SIZE) else {
        return;
    };
    at_each_checked_frame(&mut |scene, replay, frame| {
        for k in 0..replay.n_lanes() {
            let lane = replay.lane(k).unwrap();
            let mut geometry = MeshGeometry::default();
            geometry.rebuild(&scene.hierarchy, lane.buffers, lane.mesh, lane.camera);
            let (viewport, view_projection) = pane_camera(
                &scene.hierarchy,
                &lane,
                offscreen.viewport(),
                ViewChoice::Overview,
            );
            let image = offscreen
                .render_triangle_ids(&Pane {
                    viewport,
                    view_projection,
                    mesh: &geometry,
                    lines: &[],
                    options: PLAIN,
                })
                .unwrap();
            let drawn = distinct_triangles(&image);
            assert_eq!(
                drawn.len() as u64,
                lane.stats.triangles,
                "{}, frame {frame}: distinct triangles drawn vs the frame's triangle count",
                lane.label
            );
            assert!(
                drawn
                    .iter()
                    .all(|&id| u64::from(id) < geometry.n_triangles())
            );
            // The square terrain fills the square image but for the 5% margin on each side.
            let expected = (1.0 / 1.1f64).powi(2);
            let covered = covered_fraction(&image.ids);
            assert!(
                (covered - expected).abs() < 0.01,
                "{}, frame {frame}: the terrain covers {covered:.4} of the overview, expected \
                 {expected:.4}",
                lane.label
            );
            eprintln!(
                "{} frame {frame}: {} triangles drawn = frame statistic {}; overview coverage \
                 {covered:.4} (expected {expected:.4})",
                lane.label,
                drawn.len(),
                lane.stats.triangles
            );
        }
    });
}

#[test]
fn from_the_flight_camera_each_pixel_shows_the_triangle_the_camera_projects_there() {
    let Some(offscreen) = offscreen(FLIGHT_SIZE.0, FLIGHT_SIZE.1) else {
        return;
    };
    at_each_checked_frame(&mut |scene, replay, frame| {
        for k in 0..replay.n_lanes() {
            let lane = replay.lane(k).unwrap();
            let mut geometry = MeshGeometry::default();
            geometry.rebuild(&scene.hierarchy, lane.buffers, lane.mesh, lane.camera);
            let (viewport, view_projection) = pane_camera(
                &scene.hierarchy,
                &lane,
                offscreen.viewport(),
                ViewChoice::Flight,
            );
            assert_eq!(
                viewport,
                offscreen.viewport(),
                "the image has the view's aspect"
            );
            let image = offscreen
                .render_triangle_ids(&Pane {
                    viewport,
                    view_projection,
                    mesh: &geometry,
                    lines: &[],
                    options: PLAIN,
                })
                .unwrap();
            let (width, height) = (image.width as usize, image.height as usize);
            let row = |y: usize| &image.ids[y * width..(y + 1) * width];
            // Looking 25° down with a 60° field of view from above the highest terrain: the top
            // edge of the image looks 5° up, into the sky; the bottom edge 55° down, onto the
            // terrain under the circle.
            assert_eq!(
                covered_fraction(row(0)),
                0.0,
                "{}: sky at the top",
                lane.label
            );
            assert_eq!(
                covered_fraction(row(height - 1)),
                1.0,
                "{}: ground at the bottom",
                lane.label
            );
            let drawn = distinct_triangles(&image);
            assert!(
                drawn.len() > 50,
                "{}: {} triangles seen",
                lane.label,
                drawn.len()
            );
            let in_view: Vec<bool> = geometry
                .vertices()
                .chunks_exact(3)
                .map(|t| t[0].in_view == 1.0)
                .collect();
            assert!(
                drawn.iter().all(|&id| in_view[id as usize]),
                "{}: a triangle the run counts as culled was drawn",
                lane.label
            );
            let (agreeing, checked) = pixels_on_their_projected_triangle(
                &scene.hierarchy,
                lane.buffers,
                lane.camera,
                &image,
            );
            assert!(
                agreeing as f64 >= 0.995 * checked as f64 && checked > width * height / 4,
                "{}, frame {frame}: {agreeing} of {checked} covered pixels lie on the triangle \
                 the simulation's camera projects there",
                lane.label
            );
            eprintln!(
                "{} frame {frame}: {} triangles visible of {} in view; {agreeing}/{checked} \
                 covered pixels on their projected triangle; coverage {:.3}",
                lane.label,
                drawn.len(),
                lane.stats.triangles_rendered,
                covered_fraction(&image.ids)
            );
        }
    });
}

/// Of the covered pixels whose triangle lies wholly in front of the near plane, how many have
/// their centre within one pixel of that triangle as `Camera::project_camera` places it. The
/// triangles are the mesh visitor's, in its order (the order the geometry was built in).
fn pixels_on_their_projected_triangle(
    hierarchy: &Hierarchy,
    buffers: &GpuBuffers,
    camera: &Camera,
    image: &TriangleIdImage,
) -> (usize, usize) {
    let spacing = hierarchy.field().spacing();
    // The preview draws the buffers' triangles in their order: triangle k of the image is the
    // buffers' k-th.
    let mut projected: Vec<Option<[DVec2; 3]>> = Vec::new();
    buffers.for_each_triangle(|drawn| {
        let corners = drawn.map(|c| camera.project_camera(camera.to_camera(c.local(spacing))));
        projected.push(match corners {
            [Some(a), Some(b), Some(c)] => Some([a, b, c]),
            _ => None,
        });
    });
    let (width, height) = (image.width as usize, image.height as usize);
    let (mut agreeing, mut checked) = (0, 0);
    for (index, &id) in image.ids.iter().enumerate() {
        let Some(corners) = id.checked_sub(1).and_then(|t| projected[t as usize]) else {
            continue;
        };
        let (x, y) = (index % width, index / width);
        // Pixel centres from the image centre, y up: the frame of `project_camera`.
        let centre = DVec2::new(
            x as f64 + 0.5 - width as f64 / 2.0,
            height as f64 / 2.0 - (y as f64 + 0.5),
        );
        checked += 1;
        agreeing += usize::from(within_one_pixel(corners, centre));
    }
    (agreeing, checked)
}

/// Whether `point` is inside the triangle or less than one pixel outside one of its edges.
fn within_one_pixel(corners: [DVec2; 3], point: DVec2) -> bool {
    let area = (corners[1] - corners[0]).perp_dot(corners[2] - corners[0]);
    if area.abs() < 1e-9 {
        return false;
    }
    (0..3).all(|k| {
        let (a, b) = (corners[k], corners[(k + 1) % 3]);
        let edge = b - a;
        let signed_distance = edge.perp_dot(point - a) * area.signum() / edge.length();
        signed_distance > -1.0
    })
}

#[test]
fn roamsim_render_writes_the_asked_frames_with_ground_below_and_sky_above() {
    if offscreen(8, 8).is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("frames");
    let written = render_experiment(&RenderRequest {
        experiment: small_experiment(dir.path()),
        frames: vec![9, 0],
        out_dir: out.clone(),
        algorithms: vec!["wu".into(), "reference τ=2px".into()],
        view: ViewChoice::Flight,
        wireframe: true,
        size: None,
        // The pixel checks below look at the top row, where the captions would be.
        captions: false,
        roles: false,
    })
    .unwrap();
    let names: Vec<_> = written
        .iter()
        .map(|f| f.path.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["frame-000000.png", "frame-000009.png"]);
    assert!(written[1].captions[0].starts_with("wu τ=2px · frame 9 · "));
    assert!(written[1].captions[1].starts_with("reference τ=2px · frame 9 · "));
    for frame in &written {
        let (width, height, rgba) = read_png(&frame.path);
        // Two panes of the view's 320×240, side by side.
        assert_eq!((width, height), (2 * FLIGHT_SIZE.0, FLIGHT_SIZE.1));
        let pixel = |x: u32, y: u32| {
            let at = ((y * width + x) * 4) as usize;
            [rgba[at], rgba[at + 1], rgba[at + 2]]
        };
        let sky = pixel(0, 0);
        for pane in 0..2 {
            let x0 = pane * FLIGHT_SIZE.0;
            let top_is_sky = (x0..x0 + FLIGHT_SIZE.0).all(|x| pixel(x, 0) == sky);
            let bottom_is_ground = (x0..x0 + FLIGHT_SIZE.0).all(|x| pixel(x, height - 1) != sky);
            assert!(
                top_is_sky && bottom_is_ground,
                "{}: pane {pane}",
                frame.path.display()
            );
        }
    }
}

#[test]
fn captions_write_the_frames_statistics_in_the_panes_corner_and_nowhere_else() {
    if offscreen(8, 8).is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let experiment = small_experiment(dir.path());
    let render = |captions: bool, out: &str| {
        let written = render_experiment(&RenderRequest {
            experiment: experiment.clone(),
            frames: vec![3],
            out_dir: dir.path().join(out),
            algorithms: vec![],
            view: ViewChoice::Overview,
            wireframe: true,
            size: None,
            captions,
            roles: false,
        })
        .unwrap();
        assert_eq!(written.len(), 1);
        assert!(written[0].captions[0].contains("frame 3 · "));
        read_png(&written[0].path)
    };
    let (width, height, plain) = render(false, "plain");
    let (_, _, captioned) = render(true, "captioned");
    let differs = |x: u32, y: u32| {
        let at = ((y * width + x) * 4) as usize;
        plain[at..at + 4] != captioned[at..at + 4]
    };
    let changed_in_corner = (0..40)
        .flat_map(|y| (0..200).map(move |x| (x, y)))
        .filter(|&(x, y)| differs(x, y))
        .count();
    assert!(
        changed_in_corner > 500,
        "{changed_in_corner} caption pixels"
    );
    let changed_below = (height / 2..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| differs(x, y))
        .count();
    assert_eq!(changed_below, 0);
}

fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buffer).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    buffer.truncate(info.buffer_size());
    (info.width, info.height, buffer)
}

#[test]
fn panes_split_the_window_and_keep_the_views_aspect() {
    let window = Viewport {
        x: 0,
        y: 0,
        width: 1200,
        height: 600,
    };
    let panes = window.split_horizontally(2);
    assert_eq!(panes[1].x, 600);
    let fitted = panes[1].fitted(4.0 / 3.0);
    assert_eq!(
        (fitted.x, fitted.y, fitted.width, fitted.height),
        (600, 75, 600, 450)
    );
}

/// The test-only triangle-list algorithm as the render tests draw it: 8×8-cell patches with
/// deep skirts (so that they show from the side), strip joins and geomorphing.
fn patches_config() -> PatchConfig {
    PatchConfig {
        patch_level: 3,
        borders: Borders::Skirts { depth_m: 200.0 },
        morph: true,
        strip_joins: true,
        detail_distance_m: 100.0,
    }
}

/// Runs the test-only patches over the small experiment's flight through the simulation's own
/// runner (culling on, every mesh checked) and calls `check` at every frame of [`FRAMES`].
fn patches_at_each_checked_frame(check: &mut dyn FnMut(&Hierarchy, &Patches, &FrameOutcome)) {
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::load(&small_experiment(dir.path())).unwrap();
    let hierarchy = &scene.hierarchy;
    let inputs = RunInputs {
        hierarchy,
        view: &scene.experiment.view,
        flight: &scene.experiment.flight,
        violations: &[],
        effects: Effects {
            audit: None,
            culling: true,
            check_meshes: true,
        },
        max_triangles: None,
        detail_truth: None,
    };
    let mut patches = Patches::new(hierarchy, patches_config());
    let mut runner = FrameRunner::new(&inputs);
    while let Some(outcome) = runner.step("patches", &mut patches) {
        let outcome = outcome.unwrap();
        if FRAMES.contains(&outcome.stats.frame) {
            check(hierarchy, &patches, &outcome);
        }
    }
}

fn pane_of<'a>(
    viewport: Viewport,
    view_projection: glam::Mat4,
    mesh: &'a MeshGeometry,
    lines: &'a [LineVertex],
    options: DrawOptions,
) -> Pane<'a> {
    Pane {
        viewport,
        view_projection,
        mesh,
        lines,
        options,
    }
}

/// The overview's matrix over the whole image (the render's 5 % margin).
fn overview(hierarchy: &Hierarchy, viewport: Viewport) -> glam::Mat4 {
    overview_view_projection(hierarchy.field().extent(), 0.05, viewport.aspect())
}

#[test]
fn a_triangle_list_seen_from_above_shows_exactly_its_surface_triangles() {
    let Some(offscreen) = offscreen(OVERVIEW_SIZE, OVERVIEW_SIZE) else {
        return;
    };
    patches_at_each_checked_frame(&mut |hierarchy, patches, outcome| {
        let mut geometry = MeshGeometry::default();
        geometry.rebuild(
            hierarchy,
            patches.buffers(),
            patches.mesh(),
            &outcome.camera,
        );
        let stats = &outcome.stats;
        let counts = stats.mesh.unwrap();
        assert_eq!(geometry.n_triangles(), stats.triangles);
        let [surface, skirt, degenerate, _] = counts.triangles_by_role;
        assert!(skirt > 0 && degenerate > 0 && counts.morphing_vertices > 0);
        let in_view = geometry
            .vertices()
            .chunks_exact(3)
            .filter(|t| t[0].in_view == 1.0)
            .count() as u64;
        assert_eq!(in_view, stats.triangles_rendered);
        let image = offscreen
            .render_triangle_ids(&Pane {
                viewport: offscreen.viewport(),
                view_projection: overview(hierarchy, offscreen.viewport()),
                mesh: &geometry,
                lines: &[],
                options: PLAIN,
            })
            .unwrap();
        let drawn = distinct_triangles(&image);
        let roles: Vec<f32> = geometry
            .vertices()
            .chunks_exact(3)
            .map(|t| t[0].role)
            .collect();
        let surface_role = TriangleRole::Surface.index() as f32;
        assert!(
            drawn.iter().all(|&id| roles[id as usize] == surface_role),
            "frame {}: a skirt or degenerate triangle showed from straight above",
            stats.frame
        );
        assert_eq!(
            drawn.len() as u64,
            surface,
            "frame {}: distinct triangles drawn vs the frame's surface triangles",
            stats.frame
        );
        let expected = (1.0 / 1.1f64).powi(2);
        let covered = covered_fraction(&image.ids);
        assert!((covered - expected).abs() < 0.01, "coverage {covered:.4}");
        eprintln!(
            "patches frame {}: {} surface triangles drawn of {} ({skirt} skirt, {degenerate} \
             degenerate); coverage {covered:.4}",
            stats.frame,
            drawn.len(),
            stats.triangles
        );
    });
}

#[test]
fn from_the_flight_camera_each_pixel_of_a_triangle_list_lies_on_its_triangle() {
    let Some(offscreen) = offscreen(FLIGHT_SIZE.0, FLIGHT_SIZE.1) else {
        return;
    };
    patches_at_each_checked_frame(&mut |hierarchy, patches, outcome| {
        let camera = &outcome.camera;
        let mut geometry = MeshGeometry::default();
        geometry.rebuild(hierarchy, patches.buffers(), patches.mesh(), camera);
        let image = offscreen
            .render_triangle_ids(&Pane {
                viewport: offscreen.viewport(),
                view_projection: flight_view_projection(camera, camera.settings.aspect()),
                mesh: &geometry,
                lines: &[],
                options: PLAIN,
            })
            .unwrap();
        let (width, height) = (image.width as usize, image.height as usize);
        assert_eq!(covered_fraction(&image.ids[..width]), 0.0, "sky at the top");
        let bottom = &image.ids[(height - 1) * width..];
        assert_eq!(covered_fraction(bottom), 1.0, "ground at the bottom");
        let (agreeing, checked) =
            pixels_on_their_projected_triangle(hierarchy, patches.buffers(), camera, &image);
        assert!(
            agreeing as f64 >= 0.995 * checked as f64 && checked > width * height / 4,
            "frame {}: {agreeing} of {checked} covered pixels on their projected triangle",
            outcome.stats.frame
        );
    });
}

#[test]
fn roles_tell_skirts_and_degenerate_triangles_apart_by_colour() {
    let Some(offscreen) = offscreen(FLIGHT_SIZE.0, FLIGHT_SIZE.1) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::load(&small_experiment(dir.path())).unwrap();
    let hierarchy = &scene.hierarchy;
    let field = hierarchy.field();
    // From the south, looking north along the ground, level with the lowest point of the
    // south border: the skirts hung below that border face the camera.
    let lowest = (0..field.side())
        .map(|i| f64::from(field.height(i, 0)))
        .fold(f64::INFINITY, f64::min);
    let (width_m, _) = field.extent();
    let camera = Camera::new(
        &Pose {
            position: DVec3::new(0.5 * width_m, -400.0, lowest - 20.0),
            yaw: std::f64::consts::FRAC_PI_2,
            pitch: 0.0,
        },
        scene.experiment.view,
    );
    let mut patches = Patches::new(hierarchy, patches_config());
    common::step(&mut patches, 0, &camera, true);
    let mut geometry = MeshGeometry::default();
    geometry.rebuild(hierarchy, patches.buffers(), patches.mesh(), &camera);
    let viewport = offscreen.viewport();
    let side_view = flight_view_projection(&camera, camera.settings.aspect());
    let pane = |options, lines| pane_of(viewport, side_view, &geometry, lines, options);
    let ids = offscreen.render_triangle_ids(&pane(PLAIN, &[])).unwrap();
    let roles: Vec<f32> = geometry
        .vertices()
        .chunks_exact(3)
        .map(|t| t[0].role)
        .collect();
    let skirt = TriangleRole::Skirt.index() as f32;
    let skirt_pixels: Vec<usize> = (0..ids.ids.len())
        .filter(|&k| ids.ids[k] != 0 && roles[ids.ids[k] as usize - 1] == skirt)
        .collect();
    assert!(
        skirt_pixels.len() > 1000,
        "{} skirt pixels seen from the side",
        skirt_pixels.len()
    );
    let plain = offscreen.render_colour(&[pane(PLAIN, &[])]).unwrap();
    let with_roles = DrawOptions {
        roles: true,
        ..PLAIN
    };
    let coloured = offscreen.render_colour(&[pane(with_roles, &[])]).unwrap();
    let rgb = |image: &roamsim::edge::preview::headless::RgbaImage, k: usize| {
        [
            image.pixels[4 * k],
            image.pixels[4 * k + 1],
            image.pixels[4 * k + 2],
        ]
    };
    // Skirts: grey terrain shading without roles, cyan (blue and green well above red) with.
    for &k in &skirt_pixels {
        let [r, g, b] = rgb(&coloured, k);
        assert!(
            b > r.saturating_add(60) && g > r.saturating_add(40),
            "pixel {k}: {r} {g} {b}"
        );
        let [r, _, b] = rgb(&plain, k);
        assert!(r >= b, "pixel {k} is not terrain-grey without roles");
    }
    // Surface pixels look the same either way.
    let surface = TriangleRole::Surface.index() as f32;
    let surface_pixels = (0..ids.ids.len())
        .filter(|&k| ids.ids[k] != 0 && roles[ids.ids[k] as usize - 1] == surface);
    assert!(surface_pixels.clone().count() > 0);
    for k in surface_pixels {
        assert_eq!(rgb(&plain, k), rgb(&coloured, k), "surface pixel {k}");
    }

    // Degenerate triangles have no area: with roles on their edges are drawn as magenta lines.
    let from_above = overview(hierarchy, viewport);
    let overview_pane = |options, lines| pane_of(viewport, from_above, &geometry, lines, options);
    let magenta = |image: &roamsim::edge::preview::headless::RgbaImage| {
        (0..image.pixels.len() / 4)
            .filter(|&k| {
                let [r, g, b] = rgb(image, k);
                r > 200 && g < 140 && b > 190
            })
            .count()
    };
    let lines = geometry.degenerate_lines();
    assert!(!lines.is_empty());
    let without = offscreen
        .render_colour(&[overview_pane(PLAIN, &[])])
        .unwrap();
    let with = offscreen
        .render_colour(&[overview_pane(with_roles, lines)])
        .unwrap();
    assert_eq!(magenta(&without), 0);
    assert!(magenta(&with) > 100, "{} magenta pixels", magenta(&with));
}
