//! The map (`docs/output-formats.md`, "plots/map"): a terrain seen from above as a hillshade in
//! height colours, with a colour bar of the heights, a scale bar in metres, a north arrow and
//! world coordinates along two edges; over it, when there is a flight, the eye's path with frame
//! numbers along it, the view frustum's footprint at some frames, and the frames that broke a
//! motion bound. Written as a PNG (1200×1000) and an SVG of the same drawing, or one of them.
//!
//! The caller ([`MapChart`]) hands over heights already sampled on a grid of at most
//! [`MAP_SIDE_PX`] cells a side ([`map_raster_size`] says how many for an extent) and everything
//! else in world metres; this file shades, colours and lays out, and decides nothing about which
//! frames are labelled. For a terrain read on demand the caller samples the coarsest level of
//! its pyramid whose sample spacing is at most the map's pixel footprint, not the
//! full-resolution samples (`edge::output::flight_map`), so the raster of any pyramid costs
//! about as many samples as it has cells. North (+y) is up. The terrain is drawn once as an image: in the PNG its
//! pixels, in the SVG an embedded PNG at half the resolution (`<image>`, so that the SVG stays
//! small), under vector lines and text.
//!
//! Shading: Lambertian light from the north-west, 45° above the horizon, with the heights as
//! they are (no vertical exaggeration), so a steep slope looks steep; colours go from green
//! (lowest) through tan and brown to white (highest) over the sampled height range.

use super::{
    AXIS_COLOR, BYTES_PER_RGB_PIXEL, FONT_FAMILY, PlotError, RenderTarget, TEXT_COLOR,
    embedded_font_registered, encode_rgb_png,
};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::ops::Range;
use std::path::Path;

/// The image's size in pixels.
pub const MAP_IMAGE_SIZE: (u32, u32) = (1200, 1000);

/// The map's largest side in pixels: the raster has at most this many cells a side.
pub const MAP_SIDE_PX: usize = 860;

/// Heights sampled on a regular grid over a world rectangle, row 0 the north edge; NaN where
/// there is no terrain.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightRaster {
    pub columns: usize,
    pub rows: usize,
    pub heights: Vec<f64>,
    /// The world rectangle the raster covers, metres (cell centres are inside it).
    pub x_range: Range<f64>,
    pub y_range: Range<f64>,
}

/// What a map shows, in world metres (x east, y north).
#[derive(Debug, Clone, PartialEq)]
pub struct MapChart {
    pub title: String,
    pub raster: HeightRaster,
    /// The terrain's rectangle (south-west and north-east corners), outlined.
    pub terrain: [(f64, f64); 2],
    /// The part of it that holds the file's data (the rest, north and east of it, is padding,
    /// drawn paler).
    pub data: [(f64, f64); 2],
    /// The eye's position at every frame, in order (empty without a flight).
    pub path: Vec<(f64, f64)>,
    /// Frames labelled along the path, with the eye's position there.
    pub frame_labels: Vec<(u64, (f64, f64))>,
    /// The view frustum's footprint at some frames, already clipped to what is shown.
    pub footprints: Vec<Vec<(f64, f64)>>,
    /// The eye's position at every frame that broke a motion bound.
    pub broken: Vec<(f64, f64)>,
    /// The legend's line for the footprints (`view frustum every 50 frames`).
    pub footprint_label: String,
    /// The legend's line for the frames that broke a bound.
    pub broken_label: String,
}

/// Which file [`write_map_file`] writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapFormat {
    Png,
    Svg,
}

/// The raster size for a world extent of `x_span` × `y_span` metres: one cell per pixel of the
/// map, at most [`MAP_SIDE_PX`] a side, at least 1.
pub fn map_raster_size(x_span: f64, y_span: f64) -> (usize, usize) {
    let scale = MAP_SIDE_PX as f64 / x_span.max(y_span).max(f64::MIN_POSITIVE);
    let cells = |span: f64| ((span * scale).round() as usize).clamp(1, MAP_SIDE_PX);
    (cells(x_span), cells(y_span))
}

/// Writes `<dir>/<stem>.png` and `<dir>/<stem>.svg`; `dir` must exist.
pub fn write_map(dir: &Path, stem: &str, chart: &MapChart) -> Result<(), PlotError> {
    write_map_file(&dir.join(format!("{stem}.png")), MapFormat::Png, chart)?;
    write_map_file(&dir.join(format!("{stem}.svg")), MapFormat::Svg, chart)
}

/// Writes the map to `path` as `format`; the whole picture is made in memory first, so a
/// failure leaves no half-written file.
pub fn write_map_file(path: &Path, format: MapFormat, chart: &MapChart) -> Result<(), PlotError> {
    if !embedded_font_registered() {
        return Err(PlotError::new(
            path,
            "the embedded font assets/fonts/DejaVuSans.ttf could not be loaded",
        ));
    }
    let layout = Layout::new(chart);
    let colours = shaded_colours(&chart.raster);
    let bytes = match format {
        MapFormat::Png => map_png(chart, &layout, &colours),
        MapFormat::Svg => map_svg(chart, &layout, &colours).map(String::into_bytes),
    }
    .map_err(|problem| PlotError::new(path, problem))?;
    std::fs::write(path, bytes).map_err(|error| PlotError::new(path, error.to_string()))
}

const TITLE_BAND: i32 = 52;
const MAP_LEFT: i32 = 90;
const MAP_TOP: i32 = 64;
/// The gap between the map and the panel right of it (colour bar, legend).
const PANEL_GAP: i32 = 40;
const COLOUR_BAR_WIDTH: i32 = 24;
const COLOUR_BAR_HEIGHT: i32 = 380;
const FONT_SIZE: f64 = 15.0;
const LABEL_FONT_SIZE: f64 = 13.0;
/// Outside the terrain.
const NO_TERRAIN: RGBColor = RGBColor(0xe4, 0xe4, 0xe4);
const PATH_COLOR: RGBColor = RGBColor(0x11, 0x11, 0x11);
const FOOTPRINT_COLOR: RGBColor = RGBColor(0x1f, 0x5f, 0xd0);
const BROKEN_COLOR: RGBColor = RGBColor(0xe0, 0x10, 0x10);
const START_COLOR: RGBColor = RGBColor(0x10, 0xa0, 0x30);
/// Height colours, from the lowest (0) to the highest (1).
const HEIGHT_RAMP: [(f64, (f64, f64, f64)); 5] = [
    (0.0, (46.0, 125.0, 50.0)),
    (0.25, (139.0, 176.0, 84.0)),
    (0.5, (222.0, 204.0, 129.0)),
    (0.75, (156.0, 110.0, 70.0)),
    (1.0, (245.0, 245.0, 245.0)),
];

/// Where the world goes on the image.
struct Layout {
    x0: f64,
    y1: f64,
    px_per_m: f64,
    /// The map's pixel rectangle.
    left: i32,
    top: i32,
    width: i32,
    height: i32,
    height_range: (f64, f64),
}

impl Layout {
    fn new(chart: &MapChart) -> Layout {
        let raster = &chart.raster;
        let x_span = raster.x_range.end - raster.x_range.start;
        let y_span = raster.y_range.end - raster.y_range.start;
        let px_per_m = raster.columns as f64 / x_span.max(f64::MIN_POSITIVE);
        let height_range = raster
            .heights
            .iter()
            .filter(|h| h.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
                (lo.min(h), hi.max(h))
            });
        let height_range = if height_range.0 <= height_range.1 {
            height_range
        } else {
            (0.0, 0.0)
        };
        Layout {
            x0: raster.x_range.start,
            y1: raster.y_range.end,
            px_per_m,
            left: MAP_LEFT,
            top: MAP_TOP,
            width: raster.columns as i32,
            height: ((y_span * px_per_m).round() as i32).max(1),
            height_range,
        }
    }

    fn to_px(&self, (x, y): (f64, f64)) -> (i32, i32) {
        let px = (x - self.x0) * self.px_per_m;
        let py = (self.y1 - y) * self.px_per_m;
        let clamp = |v: f64| v.round().clamp(-1e6, 1e6) as i32;
        (self.left + clamp(px), self.top + clamp(py))
    }
}

/// The raster's colours: height colour times hillshade, RGB bytes row by row.
fn shaded_colours(raster: &HeightRaster) -> Vec<u8> {
    let (columns, rows) = (raster.columns, raster.rows);
    let cell_x = (raster.x_range.end - raster.x_range.start) / columns as f64;
    let cell_y = (raster.y_range.end - raster.y_range.start) / rows as f64;
    let (lo, hi) = raster
        .heights
        .iter()
        .filter(|h| h.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
            (lo.min(h), hi.max(h))
        });
    let at = |c: usize, r: usize| raster.heights[r * columns + c];
    // Towards the light: azimuth 315° (north-west), 45° up.
    let light = glam::DVec3::new(-0.5, 0.5, std::f64::consts::FRAC_1_SQRT_2);
    let flat = light.z;
    let mut out = Vec::with_capacity(columns * rows * BYTES_PER_RGB_PIXEL);
    for r in 0..rows {
        for c in 0..columns {
            let h = at(c, r);
            if !h.is_finite() {
                let RGBColor(red, green, blue) = NO_TERRAIN;
                out.extend_from_slice(&[red, green, blue]);
                continue;
            }
            // Central differences where both neighbours are terrain, else one-sided.
            let neighbour = |c: usize, r: usize| Some(at(c, r)).filter(|v| v.is_finite());
            let west = c.checked_sub(1).and_then(|c| neighbour(c, r));
            let east = (c + 1 < columns).then(|| neighbour(c + 1, r)).flatten();
            let north = r.checked_sub(1).and_then(|r| neighbour(c, r));
            let south = (r + 1 < rows).then(|| neighbour(c, r + 1)).flatten();
            let slope = |low: Option<f64>, high: Option<f64>, cell: f64| match (low, high) {
                (Some(a), Some(b)) => (b - a) / (2.0 * cell),
                (None, Some(b)) => (b - h) / cell,
                (Some(a), None) => (h - a) / cell,
                (None, None) => 0.0,
            };
            let dz_dx = slope(west, east, cell_x);
            let dz_dy = slope(south, north, cell_y);
            let normal = glam::DVec3::new(-dz_dx, -dz_dy, 1.0).normalize();
            let shade = (normal.dot(light).max(0.0) / flat).clamp(0.0, 1.3);
            let t = if hi > lo { (h - lo) / (hi - lo) } else { 0.5 };
            let (red, green, blue) = ramp(t);
            let lit =
                |channel: f64| (channel * (0.35 + 0.65 * shade)).round().clamp(0.0, 255.0) as u8;
            out.extend_from_slice(&[lit(red), lit(green), lit(blue)]);
        }
    }
    out
}

/// The height colour at `t` in [0, 1].
fn ramp(t: f64) -> (f64, f64, f64) {
    let t = t.clamp(0.0, 1.0);
    for pair in HEIGHT_RAMP.windows(2) {
        let ((t0, a), (t1, b)) = (pair[0], pair[1]);
        if t <= t1 {
            let f = (t - t0) / (t1 - t0);
            return (
                a.0 + (b.0 - a.0) * f,
                a.1 + (b.1 - a.1) * f,
                a.2 + (b.2 - a.2) * f,
            );
        }
    }
    HEIGHT_RAMP[HEIGHT_RAMP.len() - 1].1
}

fn ramp_colour(t: f64) -> RGBColor {
    let (r, g, b) = ramp(t);
    RGBColor(r.round() as u8, g.round() as u8, b.round() as u8)
}

/// The PNG: the raster's pixels put into the image, then the drawing over them.
fn map_png(chart: &MapChart, layout: &Layout, colours: &[u8]) -> Result<Vec<u8>, String> {
    let (width, height) = MAP_IMAGE_SIZE;
    let mut pixels = vec![255u8; width as usize * height as usize * BYTES_PER_RGB_PIXEL];
    let raster = &chart.raster;
    for r in 0..raster.rows.min(layout.height as usize) {
        let y = layout.top as usize + r;
        if y >= height as usize {
            break;
        }
        for c in 0..raster.columns {
            let x = layout.left as usize + c;
            if x >= width as usize {
                break;
            }
            let from = (r * raster.columns + c) * BYTES_PER_RGB_PIXEL;
            let to = (y * width as usize + x) * BYTES_PER_RGB_PIXEL;
            pixels[to..to + BYTES_PER_RGB_PIXEL]
                .copy_from_slice(&colours[from..from + BYTES_PER_RGB_PIXEL]);
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut pixels, MAP_IMAGE_SIZE).into_drawing_area();
        draw_over(&root, chart, layout, RenderTarget::Raster)
            .and_then(|()| root.present())
            .map_err(|e| e.to_string())?;
    }
    encode_rgb_png(&pixels, MAP_IMAGE_SIZE).map_err(|e| e.to_string())
}

/// The SVG: the drawing, with the raster embedded as a PNG under it.
fn map_svg(chart: &MapChart, layout: &Layout, colours: &[u8]) -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, MAP_IMAGE_SIZE).into_drawing_area();
        draw_over(&root, chart, layout, RenderTarget::Vector)
            .and_then(|()| root.present())
            .map_err(|e| e.to_string())?;
    }
    let raster = &chart.raster;
    let (half, half_size) = halved(colours, raster.columns, raster.rows);
    let png = encode_rgb_png(&half, half_size).map_err(|e| e.to_string())?;
    let (width, height) = MAP_IMAGE_SIZE;
    let under = format!(
        "<rect x=\"0\" y=\"0\" width=\"{width}\" height=\"{height}\" fill=\"#FFFFFF\"/>\n\
         <image x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" preserveAspectRatio=\"none\" \
         href=\"data:image/png;base64,{}\"/>\n",
        layout.left,
        layout.top,
        layout.width,
        layout.height,
        base64(&png)
    );
    let open_end = svg
        .find("<svg")
        .and_then(|start| svg[start..].find('>').map(|end| start + end + 1))
        .ok_or("plotters wrote no <svg> element")?;
    let after_newline = if svg[open_end..].starts_with('\n') {
        open_end + 1
    } else {
        open_end
    };
    svg.insert_str(after_newline, &under);
    Ok(svg)
}

/// The colours averaged over 2×2 cells (a last odd row or column kept as it is).
fn halved(colours: &[u8], columns: usize, rows: usize) -> (Vec<u8>, (u32, u32)) {
    let (half_columns, half_rows) = (columns.div_ceil(2), rows.div_ceil(2));
    let mut out = Vec::with_capacity(half_columns * half_rows * BYTES_PER_RGB_PIXEL);
    for hr in 0..half_rows {
        for hc in 0..half_columns {
            for channel in 0..BYTES_PER_RGB_PIXEL {
                let mut sum = 0u32;
                let mut n = 0u32;
                for r in (2 * hr)..(2 * hr + 2).min(rows) {
                    for c in (2 * hc)..(2 * hc + 2).min(columns) {
                        sum +=
                            u32::from(colours[(r * columns + c) * BYTES_PER_RGB_PIXEL + channel]);
                        n += 1;
                    }
                }
                out.push(((sum + n / 2) / n) as u8);
            }
        }
    }
    (out, (half_columns as u32, half_rows as u32))
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

fn style<'a>(size: f64) -> TextStyle<'a> {
    TextStyle::from((FONT_FAMILY, size).into_font()).color(&TEXT_COLOR)
}

/// Everything drawn over the terrain image, the same on both backends.
fn draw_over<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &MapChart,
    layout: &Layout,
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (width, _) = MAP_IMAGE_SIZE;
    let title = style(24.0).pos(Pos::new(HPos::Center, VPos::Center));
    root.draw(&Text::new(
        chart.title.as_str(),
        (
            width as i32 / 2,
            TITLE_BAND / 2 + target.text_center_nudge(24.0),
        ),
        title,
    ))?;
    let map = root.clone().shrink(
        (layout.left, layout.top),
        (layout.width as u32, layout.height as u32),
    );
    // The map area clips what reaches beyond it; its coordinates start at its corner.
    let local = |p: (f64, f64)| {
        let (x, y) = layout.to_px(p);
        (x - layout.left, y - layout.top)
    };
    for footprint in &chart.footprints {
        let pixels: Vec<(i32, i32)> = footprint.iter().map(|&p| local(p)).collect();
        if pixels.len() >= 3 {
            map.draw(&Polygon::new(
                pixels.clone(),
                FOOTPRINT_COLOR.mix(0.08).filled(),
            ))?;
            let mut closed = pixels;
            closed.push(closed[0]);
            map.draw(&PathElement::new(
                closed,
                FOOTPRINT_COLOR.mix(0.7).stroke_width(1),
            ))?;
        }
    }
    let [(x0, y0), (x1, y1)] = chart.terrain;
    let [_, (data_x1, data_y1)] = chart.data;
    let pale = WHITE.mix(0.6).filled();
    if data_x1 < x1 {
        map.draw(&Rectangle::new(
            [local((data_x1, y1)), local((x1, y0))],
            pale,
        ))?;
    }
    if data_y1 < y1 {
        map.draw(&Rectangle::new(
            [local((x0, y1)), local((data_x1.min(x1), data_y1))],
            pale,
        ))?;
    }
    if data_x1 < x1 || data_y1 < y1 {
        let (px, py) = local((x1, y1));
        map.draw(&Text::new(
            "padding (pale)",
            (px - 60, py + 80 + target.text_center_nudge(FONT_SIZE)),
            style(FONT_SIZE).pos(Pos::new(HPos::Right, VPos::Center)),
        ))?;
    }
    let (a, b) = (local((x0, y1)), local((x1, y0)));
    map.draw(&Rectangle::new([a, b], AXIS_COLOR.stroke_width(1)))?;
    let mut path: Vec<(i32, i32)> = Vec::new();
    for &p in &chart.path {
        let px = local(p);
        if path.last() != Some(&px) {
            path.push(px);
        }
    }
    if path.len() >= 2 {
        target.draw_wide_line(&map, &path, PATH_COLOR)?;
    }
    if let Some(&start) = path.first() {
        map.draw(&Circle::new(start, 6, START_COLOR.filled()))?;
        map.draw(&Circle::new(start, 6, WHITE.stroke_width(1)))?;
    }
    for &p in &chart.broken {
        map.draw(&Cross::new(local(p), 5, BROKEN_COLOR.stroke_width(2)))?;
    }
    let label_style = style(LABEL_FONT_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    for (frame, p) in &chart.frame_labels {
        let (x, y) = local(*p);
        map.draw(&Circle::new((x, y), 3, PATH_COLOR.filled()))?;
        let text = frame.to_string();
        let (w, h) = map.estimate_text_size(&text, &label_style)?;
        let (tx, ty) = (x + 6, y - 10);
        map.draw(&Rectangle::new(
            [
                (tx - 2, ty - h as i32 / 2 - 2),
                (tx + w as i32 + 2, ty + h as i32 / 2 + 2),
            ],
            WHITE.mix(0.8).filled(),
        ))?;
        map.draw(&Text::new(
            text,
            (tx, ty + target.text_center_nudge(LABEL_FONT_SIZE)),
            label_style.clone(),
        ))?;
    }
    draw_scale_bar(&map, layout, target)?;
    draw_north_arrow(&map, layout, target)?;
    draw_coordinates(root, layout, target)?;
    let panel_left = layout.left + layout.width + PANEL_GAP;
    let below_bar = draw_colour_bar(root, layout, panel_left, target)?;
    draw_legend(root, chart, (panel_left, below_bar), target)
}

/// 1, 2 or 5 times a power of ten, the smallest at least `value`.
fn nice_at_least(value: f64) -> f64 {
    let value = value.max(f64::MIN_POSITIVE);
    let power = 10f64.powf(value.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * power)
        .find(|&v| v >= value * (1.0 - 1e-12))
        .unwrap_or(10.0 * power)
}

/// `1234 m` or `12.5 km`.
fn metres(value: f64) -> String {
    if value.abs() >= 10_000.0 {
        format!(
            "{} km",
            super::ticks::trim_fraction_zeros(&format!("{:.3}", value / 1000.0))
        )
    } else {
        format!(
            "{} m",
            super::ticks::trim_fraction_zeros(&format!("{value:.2}"))
        )
    }
}

fn draw_scale_bar<DB: DrawingBackend>(
    map: &DrawingArea<DB, Shift>,
    layout: &Layout,
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    // About a fifth of the map's width, rounded down to 1, 2 or 5 × 10^k metres.
    let wanted = layout.width as f64 / layout.px_per_m / 5.0;
    let mut length = nice_at_least(wanted);
    if length > wanted * 1.001 {
        length = nice_at_least(length / 2.6);
    }
    let bar = (length * layout.px_per_m).round() as i32;
    let (x, y) = (14, layout.height - 20);
    let text = metres(length);
    let text_style = style(FONT_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    let (w, _) = map.estimate_text_size(&text, &text_style)?;
    map.draw(&Rectangle::new(
        [(x - 8, y - 24), (x + bar + w as i32 + 22, y + 12)],
        WHITE.mix(0.85).filled(),
    ))?;
    map.draw(&Rectangle::new(
        [(x, y - 4), (x + bar, y + 4)],
        BLACK.filled(),
    ))?;
    map.draw(&Rectangle::new(
        [(x + bar / 2, y - 4), (x + bar, y + 4)],
        WHITE.filled(),
    ))?;
    map.draw(&Rectangle::new(
        [(x, y - 4), (x + bar, y + 4)],
        BLACK.stroke_width(1),
    ))?;
    map.draw(&Text::new(
        text,
        (x + bar + 10, y + target.text_center_nudge(FONT_SIZE)),
        text_style,
    ))?;
    map.draw(&Text::new(
        "0",
        (x - 3, y - 14 + target.text_center_nudge(LABEL_FONT_SIZE)),
        style(LABEL_FONT_SIZE).pos(Pos::new(HPos::Left, VPos::Center)),
    ))
}

fn draw_north_arrow<DB: DrawingBackend>(
    map: &DrawingArea<DB, Shift>,
    layout: &Layout,
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (x, y) = (layout.width - 28, 16);
    map.draw(&Rectangle::new(
        [(x - 16, y - 10), (x + 16, y + 54)],
        WHITE.mix(0.85).filled(),
    ))?;
    map.draw(&Polygon::new(
        vec![(x, y), (x - 8, y + 22), (x + 8, y + 22)],
        BLACK.filled(),
    ))?;
    map.draw(&Text::new(
        "N",
        (x, y + 36 + target.text_center_nudge(FONT_SIZE)),
        style(FONT_SIZE).pos(Pos::new(HPos::Center, VPos::Center)),
    ))
}

/// World x below the map and y left of it, at round numbers.
fn draw_coordinates<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    layout: &Layout,
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let span_x = layout.width as f64 / layout.px_per_m;
    let span_y = layout.height as f64 / layout.px_per_m;
    let step = nice_at_least(span_x.max(span_y) / 6.0);
    let tick_style = style(LABEL_FONT_SIZE);
    // `+ 0.0` turns −0 into 0.
    let number = |v: f64| super::ticks::trim_fraction_zeros(&format!("{:.2}", v + 0.0)).to_string();
    let bottom = layout.top + layout.height;
    let mut x = (layout.x0 / step).ceil() * step;
    while x <= layout.x0 + span_x {
        let (px, _) = layout.to_px((x, 0.0));
        root.draw(&PathElement::new(
            vec![(px, bottom), (px, bottom + 5)],
            AXIS_COLOR.stroke_width(1),
        ))?;
        root.draw(&Text::new(
            number(x),
            (px, bottom + 14 + target.text_center_nudge(LABEL_FONT_SIZE)),
            tick_style.pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
        x += step;
    }
    let y0 = layout.y1 - span_y;
    let mut y = (y0 / step).ceil() * step;
    while y <= layout.y1 {
        let (_, py) = layout.to_px((0.0, y));
        root.draw(&PathElement::new(
            vec![(layout.left - 5, py), (layout.left, py)],
            AXIS_COLOR.stroke_width(1),
        ))?;
        root.draw(&Text::new(
            number(y),
            (
                layout.left - 8,
                py + target.text_center_nudge(LABEL_FONT_SIZE),
            ),
            tick_style.pos(Pos::new(HPos::Right, VPos::Center)),
        ))?;
        y += step;
    }
    root.draw(&Text::new(
        "x (m, east)",
        (
            layout.left + layout.width / 2,
            bottom + 36 + target.text_center_nudge(FONT_SIZE),
        ),
        style(FONT_SIZE).pos(Pos::new(HPos::Center, VPos::Center)),
    ))?;
    root.draw(&Text::new(
        "y (m, north)",
        (8, layout.top - 14 + target.text_center_nudge(FONT_SIZE)),
        style(FONT_SIZE).pos(Pos::new(HPos::Left, VPos::Center)),
    ))
}

/// The colour bar of heights; returns the pixel row below it.
fn draw_colour_bar<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    layout: &Layout,
    x: i32,
    target: RenderTarget,
) -> Result<i32, DrawingAreaErrorKind<DB::ErrorType>> {
    let top = MAP_TOP + 30;
    root.draw(&Text::new(
        "height (m)",
        (x, MAP_TOP + 8 + target.text_center_nudge(FONT_SIZE)),
        style(FONT_SIZE).pos(Pos::new(HPos::Left, VPos::Center)),
    ))?;
    // Bands of 4 pixels: a smooth bar with a hundred rectangles in the SVG.
    const BAND: i32 = 4;
    let mut row = 0;
    while row < COLOUR_BAR_HEIGHT {
        let t = 1.0 - (row as f64 + BAND as f64 / 2.0) / COLOUR_BAR_HEIGHT as f64;
        root.draw(&Rectangle::new(
            [(x, top + row), (x + COLOUR_BAR_WIDTH, top + row + BAND)],
            ramp_colour(t).filled(),
        ))?;
        row += BAND;
    }
    root.draw(&Rectangle::new(
        [(x, top), (x + COLOUR_BAR_WIDTH, top + COLOUR_BAR_HEIGHT)],
        AXIS_COLOR.stroke_width(1),
    ))?;
    let (lo, hi) = layout.height_range;
    let tick_style = style(LABEL_FONT_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    let number = |v: f64| super::ticks::trim_fraction_zeros(&format!("{v:.2}")).to_string();
    let at = |h: f64| {
        let t = if hi > lo { (h - lo) / (hi - lo) } else { 0.5 };
        top + ((1.0 - t) * COLOUR_BAR_HEIGHT as f64).round() as i32
    };
    let mut ticks = vec![lo, hi];
    if hi > lo {
        let step = nice_at_least((hi - lo) / 6.0);
        let mut h = (lo / step).ceil() * step;
        while h < hi {
            // Keep clear of the end labels.
            if (at(h) - at(lo)).abs() > 16 && (at(h) - at(hi)).abs() > 16 {
                ticks.push(h);
            }
            h += step;
        }
    }
    for h in ticks {
        let y = at(h);
        root.draw(&PathElement::new(
            vec![(x + COLOUR_BAR_WIDTH, y), (x + COLOUR_BAR_WIDTH + 5, y)],
            AXIS_COLOR.stroke_width(1),
        ))?;
        root.draw(&Text::new(
            number(h),
            (
                x + COLOUR_BAR_WIDTH + 8,
                y + target.text_center_nudge(LABEL_FONT_SIZE),
            ),
            tick_style.clone(),
        ))?;
    }
    Ok(top + COLOUR_BAR_HEIGHT + 30)
}

/// The little picture before a legend line.
#[derive(Clone, Copy)]
enum Swatch {
    Path,
    Start,
    Footprint,
    Broken,
}

fn draw_swatch<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    swatch: Swatch,
    (x, y): (i32, i32),
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    match swatch {
        Swatch::Path => target.draw_wide_line(root, &[(x - 10, y), (x + 10, y)], PATH_COLOR),
        Swatch::Start => root.draw(&Circle::new((x, y), 6, START_COLOR.filled())),
        Swatch::Footprint => {
            let corners = [(x - 9, y - 6), (x + 9, y + 6)];
            root.draw(&Rectangle::new(corners, FOOTPRINT_COLOR.mix(0.25).filled()))?;
            root.draw(&Rectangle::new(corners, FOOTPRINT_COLOR.stroke_width(1)))
        }
        Swatch::Broken => root.draw(&Cross::new((x, y), 5, BROKEN_COLOR.stroke_width(2))),
    }
}

/// The legend of the flight's marks, below the colour bar (nothing without a flight).
fn draw_legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &MapChart,
    (x, top): (i32, i32),
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    if chart.path.is_empty() {
        return Ok(());
    }
    let mut rows = vec![
        (Swatch::Path, "the eye's path, frame numbers along it"),
        (Swatch::Start, "frame 0"),
    ];
    if !chart.footprints.is_empty() {
        rows.push((Swatch::Footprint, chart.footprint_label.as_str()));
    }
    if !chart.broken.is_empty() {
        rows.push((Swatch::Broken, chart.broken_label.as_str()));
    }
    let text_style = style(LABEL_FONT_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    let max_width = (MAP_IMAGE_SIZE.0 as i32 - x - 28 - 8).max(100) as u32;
    let mut y = top;
    for (swatch, text) in rows {
        draw_swatch(root, swatch, (x + 10, y), target)?;
        for line in super::legend::wrap_text(root, text, &text_style, max_width)? {
            root.draw(&Text::new(
                line,
                (x + 28, y + target.text_center_nudge(LABEL_FONT_SIZE)),
                text_style.clone(),
            ))?;
            y += 18;
        }
        y += 8;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_pads_as_the_standard_says() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn the_raster_of_a_wide_extent_fills_the_map_width() {
        assert_eq!(
            map_raster_size(2000.0, 1000.0),
            (MAP_SIDE_PX, MAP_SIDE_PX / 2)
        );
        assert_eq!(map_raster_size(1.0, 1e9), (1, MAP_SIDE_PX));
    }

    #[test]
    fn a_scale_bar_length_is_one_two_or_five_times_a_power_of_ten() {
        assert_eq!(nice_at_least(0.7), 1.0);
        assert_eq!(nice_at_least(130.0), 200.0);
        assert_eq!(nice_at_least(4000.0), 5000.0);
        assert_eq!(nice_at_least(5000.0), 5000.0);
    }
}
