//! `plots/map.png` and `plots/map.svg` (`docs/output-formats.md`, "plots/map"), and the map
//! `roamsim info --map` draws: the terrain from above and, for a run, its flight. This file
//! chooses what the map shows — the heights sampled on the map's grid, which frames are numbered
//! along the path, at which frames the view frustum's footprint is drawn, which frames broke a
//! bound — and `plots` draws it.
//!
//! **Sampled, never visited whole.** The terrain is read at one point per map pixel (at most
//! [`MAP_SIDE_PX`] a side, the bilinear ground height at the pixel's centre), so a 16385²
//! terrain costs as much as a 1025² one; the colour bar spans the sampled heights.
//!
//! **A pyramid is read at a coarse level.** A terrain read on demand (a chunk pyramid,
//! `edge::pyramid`) is not sampled through its full-resolution cache, which on a 65 537²
//! pyramid would read most of the file: the map reads the coarsest level L of the pyramid whose
//! sample spacing, 2^(D − L) times the terrain's (a level's chunks hold every 2^(D − L)-th
//! sample, D the leaves' level), is at most the map's pixel footprint in x and in y, whole, with
//! the pyramid's loader, and samples that level's grid as it samples a terrain in memory
//! (`coarse_level`). That level has at most about twice as many samples a side as the map has
//! pixels, so the map of any pyramid reads about as many samples as it has pixels (at most about
//! 4× them, and at most 1025², 4 MB of `f32`, since the level has fewer than 2 × 860 cells a
//! side); where the pixels are finer than the samples (L = D) it is the full-resolution grid
//! and the map is the one the same terrain in memory draws. A read that fails is the map's
//! error, naming the pyramid and the chunk.
//!
//! **Labels that do not crowd.** Frame numbers go every N frames, N the smallest of 1, 2, 5 × 10^k
//! that puts them at least [`LABEL_SPACING_PX`] apart along the path on average and gives at most
//! [`MAX_LABELS`] of them; a label closer than [`LABEL_CLEARANCE_PX`] to one already placed (a
//! flight that passes the same place again) is left out, and the last frame is labelled when
//! there is room. Footprints go every M frames, M the same kind of number, the smallest giving
//! at most [`MAX_FOOTPRINTS`] of them. All of it is a function of the flight: the same run
//! draws the same map.

use crate::edge::output::plots::{
    HeightRaster, MAP_SIDE_PX, MapChart, MapFormat, PlotError, map_raster_size, write_map,
    write_map_file,
};
use crate::sim::algorithm::chunked::ChunkId;
use crate::sim::flight::{Flight, SpeedViolation};
use crate::sim::terrain::paged::PagedSamples;
use crate::sim::terrain::{Heightfield, Spacing};
use crate::sim::view::{Camera, ViewSettings};
use glam::DVec2;
use std::path::Path;

/// Frame labels are at least this far apart along the path on average, pixels.
pub const LABEL_SPACING_PX: f64 = 70.0;
/// At most this many frame labels.
pub const MAX_LABELS: u64 = 24;
/// A label this close to one already placed is left out, pixels.
pub const LABEL_CLEARANCE_PX: f64 = 30.0;
/// At most this many footprints.
pub const MAX_FOOTPRINTS: u64 = 8;

/// A flight to draw over the terrain.
#[derive(Clone, Copy)]
pub struct FlightOnMap<'a> {
    pub flight: &'a Flight,
    pub view: ViewSettings,
    pub violations: &'a [SpeedViolation],
}

/// Writes `<dir>/map.png` and `<dir>/map.svg`: the terrain and, when given, the flight.
pub fn write_flight_map(
    dir: &Path,
    field: &Heightfield,
    title: &str,
    flight: Option<FlightOnMap>,
) -> Result<(), PlotError> {
    let chart = map_chart(field, title, flight).map_err(|problem| PlotError {
        path: dir.join("map.png"),
        problem,
    })?;
    write_map(dir, "map", &chart)
}

/// Writes the map to `path`, a PNG or an SVG by its extension (`.png`, `.svg`); anything else is
/// refused before anything is drawn.
pub fn write_map_to(
    path: &Path,
    field: &Heightfield,
    title: &str,
    flight: Option<FlightOnMap>,
) -> Result<(), PlotError> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let format = match extension.as_deref() {
        Some("png") => MapFormat::Png,
        Some("svg") => MapFormat::Svg,
        _ => {
            return Err(PlotError {
                path: path.to_path_buf(),
                problem: "expected a file name ending in .png or .svg".to_string(),
            });
        }
    };
    let chart = map_chart(field, title, flight).map_err(|problem| PlotError {
        path: path.to_path_buf(),
        problem,
    })?;
    write_map_file(path, format, &chart)
}

/// What the map shows: the terrain sampled on the map's grid, the flight's path with its labels,
/// footprints and broken frames. The error of a terrain read on demand whose pyramid could not
/// be read, a sentence naming the file and the chunk.
pub fn map_chart(
    field: &Heightfield,
    title: &str,
    flight: Option<FlightOnMap>,
) -> Result<MapChart, String> {
    let origin = field.origin().truncate();
    let (width, depth) = field.extent();
    let terrain_low = origin;
    let terrain_high = origin + DVec2::new(width, depth);
    let spacing = field.spacing();
    let data_high = origin
        + DVec2::new(
            (field.data_columns() - 1) as f64 * spacing.dx,
            (field.data_rows() - 1) as f64 * spacing.dy,
        );
    let (mut low, mut high) = (terrain_low, terrain_high);
    let path: Vec<DVec2> = flight
        .map(|f| {
            f.flight
                .poses()
                .iter()
                .map(|p| p.position.truncate())
                .collect()
        })
        .unwrap_or_default();
    if !path.is_empty() {
        for &p in &path {
            low = low.min(p);
            high = high.max(p);
        }
        let margin = 0.03 * (high - low).max_element();
        low -= DVec2::splat(margin);
        high += DVec2::splat(margin);
    }
    let span = (high - low).max(DVec2::splat(f64::MIN_POSITIVE));
    let raster = match field.paged_samples() {
        None => sample_heights(field, low, span),
        Some(paged) => {
            let (columns, rows) = map_raster_size(span.x, span.y);
            let footprint = DVec2::new(span.x / columns as f64, span.y / rows as f64);
            sample_heights(&coarse_level(field, paged.as_ref(), footprint)?, low, span)
        }
    };
    let px_per_m = MAP_SIDE_PX as f64 / span.max_element();
    let mut chart = MapChart {
        title: title.to_string(),
        raster,
        terrain: [pair(terrain_low), pair(terrain_high)],
        data: [pair(terrain_low), pair(data_high)],
        path: path.iter().map(|&p| pair(p)).collect(),
        frame_labels: Vec::new(),
        footprints: Vec::new(),
        broken: Vec::new(),
        footprint_label: String::new(),
        broken_label: String::new(),
    };
    let Some(flight) = flight else {
        return Ok(chart);
    };
    let n_frames = path.len() as u64;
    let label_step = label_step(&path, px_per_m);
    chart.frame_labels = frame_labels(&path, label_step, px_per_m);
    let footprint_step = footprint_step(n_frames);
    chart.footprints = (0..n_frames)
        .step_by(footprint_step as usize)
        .map(|frame| {
            let camera = Camera::new(flight.flight.pose(frame), flight.view);
            clip_to_rectangle(&camera.footprint(), terrain_low, terrain_high)
                .into_iter()
                .map(pair)
                .collect::<Vec<_>>()
        })
        .filter(|polygon| polygon.len() >= 3)
        .collect();
    chart.footprint_label = format!(
        "the view frustum out to the far plane, every {footprint_step} frame(s) (over the terrain)"
    );
    chart.broken = flight
        .violations
        .iter()
        .filter_map(|v| path.get(v.frame as usize).map(|&p| pair(p)))
        .collect();
    let count =
        |which: fn(&SpeedViolation) -> bool| flight.violations.iter().filter(|v| which(v)).count();
    let by_bound: Vec<String> = [
        ("horizontal", count(|v| v.broken.horizontal)),
        ("vertical", count(|v| v.broken.vertical)),
        ("rotation", count(|v| v.broken.rotation)),
    ]
    .iter()
    .filter(|(_, n)| *n > 0)
    .map(|(name, n)| format!("{name} {n}"))
    .collect();
    chart.broken_label = format!(
        "{} frame(s) breaking a motion bound ({})",
        flight.violations.len(),
        by_bound.join(", ")
    );
    Ok(chart)
}

/// The coarsest level of the pyramid behind the paged `field` whose sample spacing is at most
/// `footprint` (metres a map pixel, x and y), read whole through the pyramid's chunk reader, as
/// a field in memory over the same rectangle (see the module doc). The level is the finest
/// (the leaves') when the pixels are finer than the samples.
fn coarse_level(
    field: &Heightfield,
    paged: &dyn PagedSamples,
    footprint: DVec2,
) -> Result<Heightfield, String> {
    let chunk_level = paged.chunk_level();
    let leaf_level = field.level() - chunk_level;
    let spacing = field.spacing();
    // s = D − L: the level's samples are 2^s of the terrain's apart.
    let coarser = (0..=leaf_level)
        .take_while(|&s| {
            let stride = f64::from(1u32 << s);
            stride * spacing.dx <= footprint.x && stride * spacing.dy <= footprint.y
        })
        .last()
        .unwrap_or(0);
    let level = leaf_level - coarser;
    let cells = 1usize << chunk_level;
    let per_side = 1u32 << level;
    let side = per_side as usize * cells + 1;
    let mut heights = vec![0.0f32; side * side];
    let mut reader = paged.chunk_reader()?;
    // A row of chunks at a time: the reads in flight hold at most a row's heights.
    for y in 0..per_side {
        for x in 0..per_side {
            reader.request(ChunkId { level, x, y });
        }
        for x in 0..per_side {
            let read = reader.take(ChunkId { level, x, y })?;
            for b in 0..=cells {
                let start = (y as usize * cells + b) * side + x as usize * cells;
                heights[start..=start + cells]
                    .copy_from_slice(&read.heights[b * (cells + 1)..(b + 1) * (cells + 1)]);
            }
        }
    }
    let stride = f64::from(1u32 << coarser);
    let coarse_spacing = Spacing {
        dx: spacing.dx * stride,
        dy: spacing.dy * stride,
    };
    Heightfield::new(side, heights, coarse_spacing)
        .map(|coarse| coarse.with_origin(field.origin()))
        .map_err(|error| format!("the map's level {level} of the pyramid: {error}"))
}

fn pair(p: DVec2) -> (f64, f64) {
    (p.x, p.y)
}

/// The ground height at the centre of each map pixel over `[low, low + span]`, NaN off the
/// terrain; row 0 the north edge.
fn sample_heights(field: &Heightfield, low: DVec2, span: DVec2) -> HeightRaster {
    let (columns, rows) = map_raster_size(span.x, span.y);
    let cell = DVec2::new(span.x / columns as f64, span.y / rows as f64);
    let high_y = low.y + span.y;
    let mut heights = Vec::with_capacity(columns * rows);
    for r in 0..rows {
        let y = high_y - (r as f64 + 0.5) * cell.y;
        for c in 0..columns {
            let xy = DVec2::new(low.x + (c as f64 + 0.5) * cell.x, y);
            heights.push(if field.covers(xy) {
                field.ground_height(xy)
            } else {
                f64::NAN
            });
        }
    }
    HeightRaster {
        columns,
        rows,
        heights,
        x_range: low.x..low.x + span.x,
        y_range: low.y..high_y,
    }
}

/// 1, 2 or 5 × 10^k, the smallest at least `value` (and at least 1).
fn nice_frames(value: f64) -> u64 {
    let mut power = 1u64;
    loop {
        for m in [1, 2, 5] {
            if (m * power) as f64 >= value {
                return m * power;
            }
        }
        power = power.saturating_mul(10);
        if power > u64::MAX / 10 {
            return power;
        }
    }
}

/// Frames between two labels (see the module doc).
fn label_step(path: &[DVec2], px_per_m: f64) -> u64 {
    let n_frames = path.len() as u64;
    let length_px: f64 = path
        .windows(2)
        .map(|pair| (pair[1] - pair[0]).length() * px_per_m)
        .sum();
    let px_per_frame = length_px / n_frames.max(1) as f64;
    let for_spacing = if px_per_frame > 0.0 {
        LABEL_SPACING_PX / px_per_frame
    } else {
        n_frames as f64
    };
    let for_count = n_frames as f64 / MAX_LABELS as f64;
    nice_frames(for_spacing.max(for_count).max(1.0))
}

/// Frames between two footprints.
fn footprint_step(n_frames: u64) -> u64 {
    nice_frames((n_frames as f64 / MAX_FOOTPRINTS as f64).max(1.0))
}

/// Frames 0, N, 2N, … and the last, each left out when too close to one already placed.
fn frame_labels(path: &[DVec2], step: u64, px_per_m: f64) -> Vec<(u64, (f64, f64))> {
    let n_frames = path.len() as u64;
    let mut wanted: Vec<u64> = (0..n_frames).step_by(step as usize).collect();
    if n_frames > 0 && wanted.last() != Some(&(n_frames - 1)) {
        wanted.push(n_frames - 1);
    }
    let clearance_m = LABEL_CLEARANCE_PX / px_per_m;
    let mut placed: Vec<(u64, (f64, f64))> = Vec::new();
    for frame in wanted {
        let p = path[frame as usize];
        let clear = placed
            .iter()
            .all(|(_, q)| p.distance(DVec2::new(q.0, q.1)) >= clearance_m);
        if clear {
            placed.push((frame, pair(p)));
        }
    }
    placed
}

/// The part of the convex polygon `polygon` inside the rectangle `[low, high]`
/// (Sutherland–Hodgman); empty when none is.
fn clip_to_rectangle(polygon: &[DVec2], low: DVec2, high: DVec2) -> Vec<DVec2> {
    // Each edge of the rectangle: a point is inside when `inside` ≥ 0.
    let edges: [fn(DVec2, DVec2, DVec2) -> f64; 4] = [
        |p, low, _| p.x - low.x,
        |p, _, high| high.x - p.x,
        |p, low, _| p.y - low.y,
        |p, _, high| high.y - p.y,
    ];
    let mut points = polygon.to_vec();
    for inside in edges {
        if points.is_empty() {
            break;
        }
        let mut kept = Vec::with_capacity(points.len() + 2);
        for k in 0..points.len() {
            let (a, b) = (points[k], points[(k + 1) % points.len()]);
            let (da, db) = (inside(a, low, high), inside(b, low, high));
            if da >= 0.0 {
                kept.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                kept.push(a + (b - a) * (da / (da - db)));
            }
        }
        points = kept;
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::terrain::Spacing;
    use crate::sim::view::Pose;
    use glam::DVec3;

    #[test]
    fn a_footprint_reaching_beyond_the_terrain_is_clipped_to_it() {
        let square = [
            DVec2::new(-5.0, -5.0),
            DVec2::new(5.0, -5.0),
            DVec2::new(5.0, 5.0),
            DVec2::new(-5.0, 5.0),
        ];
        let clipped = clip_to_rectangle(&square, DVec2::ZERO, DVec2::new(10.0, 10.0));
        let area: f64 = (0..clipped.len())
            .map(|k| clipped[k].perp_dot(clipped[(k + 1) % clipped.len()]))
            .sum::<f64>()
            / 2.0;
        assert!((area - 25.0).abs() < 1e-9, "{clipped:?}");
        let outside = clip_to_rectangle(&square, DVec2::splat(20.0), DVec2::splat(30.0));
        assert!(outside.is_empty());
    }

    #[test]
    fn labels_of_a_long_slow_flight_are_few_and_round() {
        // 10 000 frames along 1 km (860 px): a label every 1000 frames, 0 and the last among
        // them; a footprint every 2000 (at most 8).
        let path: Vec<DVec2> = (0..10_000)
            .map(|f| DVec2::new(f as f64 * 0.1, 0.0))
            .collect();
        let px_per_m = MAP_SIDE_PX as f64 / 1000.0;
        let step = label_step(&path, px_per_m);
        assert_eq!(step, 1000);
        let labels = frame_labels(&path, step, px_per_m);
        assert_eq!(labels.first().map(|l| l.0), Some(0));
        assert_eq!(labels.last().map(|l| l.0), Some(9_999));
        assert!(labels.len() as u64 <= MAX_LABELS + 1);
        assert_eq!(footprint_step(10_000), 2000);
    }

    #[test]
    fn a_circling_flight_is_not_labelled_twice_in_one_place() {
        // Two laps of one circle: the second lap's labels fall on the first's.
        let path: Vec<DVec2> = (0..200)
            .map(|f| {
                let a = f as f64 / 100.0 * std::f64::consts::TAU;
                DVec2::new(500.0 * a.cos(), 500.0 * a.sin())
            })
            .collect();
        let px_per_m = MAP_SIDE_PX as f64 / 1000.0;
        let step = label_step(&path, px_per_m);
        let labels = frame_labels(&path, step, px_per_m);
        assert!(labels.len() > 3, "{labels:?}");
        assert!(labels.iter().all(|(frame, _)| *frame < 100), "{labels:?}");
    }

    #[test]
    fn the_map_of_a_flight_samples_the_terrain_and_marks_its_broken_frames() {
        let field = Heightfield::new(
            5,
            (0..25).map(|k| k as f32).collect(),
            Spacing { dx: 10.0, dy: 10.0 },
        )
        .unwrap();
        let poses: Vec<Pose> = (0..5)
            .map(|f| Pose {
                position: DVec3::new(5.0 + f as f64 * 7.0, 20.0, 60.0),
                yaw: 0.0,
                pitch: -0.5,
            })
            .collect();
        let flight = Flight::from_poses(poses).unwrap();
        let violation = SpeedViolation {
            frame: 3,
            horizontal: 7.0,
            vertical: 0.0,
            rotation: 0.0,
            broken: crate::sim::flight::BrokenBounds {
                horizontal: true,
                vertical: false,
                rotation: false,
            },
        };
        let view = ViewSettings {
            width_px: 100,
            height_px: 100,
            fovy: 1.0,
            near: 1.0,
            far: 1000.0,
        };
        let chart = map_chart(
            &field,
            "test",
            Some(FlightOnMap {
                flight: &flight,
                view,
                violations: &[violation],
            }),
        )
        .unwrap();
        assert_eq!(chart.path.len(), 5);
        assert_eq!(chart.broken, vec![(26.0, 20.0)]);
        assert!(chart.broken_label.contains("horizontal 1"));
        assert!(!chart.footprints.is_empty());
        let raster = &chart.raster;
        assert!(raster.columns <= MAP_SIDE_PX && raster.rows <= MAP_SIDE_PX);
        let finite: Vec<f64> = raster
            .heights
            .iter()
            .copied()
            .filter(|h| h.is_finite())
            .collect();
        assert!(finite.len() > raster.heights.len() / 2);
        assert!(finite.iter().all(|h| (0.0..=24.0).contains(h)));
    }
}
