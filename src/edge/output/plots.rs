//! Line and scatter charts, each written as a PNG (1200×700) and an SVG of the same drawing.
//!
//! This is the only module that knows plotters. Callers hand over plain data ([`LineChart`],
//! [`ScatterChart`]) and a directory; the module computes the axis ranges, lays out the title,
//! axes, legend and marker labels, renders the whole picture in memory and only then writes
//! `<dir>/<stem>.png` and `<dir>/<stem>.svg`, so a failed drawing never leaves a half-written file.
//!
//! Text never depends on the fonts installed on the machine: the embedded DejaVu Sans
//! (`assets/fonts/DejaVuSans.ttf`) is registered once with plotters' `ab_glyph` support under the
//! family name `sans-serif`, which is the family every plotters default text style and every
//! style in this module looks up. The PNG therefore looks the same everywhere; the SVG keeps its
//! text as `<text>` elements with `font-family="sans-serif"`, so a viewer draws it with its own
//! sans-serif font.
//!
//! Bad data is drawn around, never a panic:
//! - a point whose x or y is NaN, infinite or larger in magnitude than
//!   [`LARGEST_PLOTTABLE_MAGNITUDE`] is skipped, and the line of its series is broken there;
//! - no data at all gives the unit square as axis ranges, all-equal values a small band around
//!   the value, and a lone point (or a run of one point between gaps) is drawn as a dot;
//! - a series of more than [`DECIMATE_ABOVE_POINTS`] points is decimated deterministically for
//!   drawing: the x range is cut into [`DECIMATION_COLUMNS`] columns (about one per pixel) and each
//!   run of consecutive points falling into one column is replaced by its first, lowest, highest
//!   and last point, in their original order. For a series whose x increases (frames, time) this
//!   draws exactly the same min/max envelope as the full series with at most four points per
//!   column, so a run of 10^6 frames plots in a fraction of a second and its SVG stays small.
//!   A gap (skipped point) inside one column is invisible at that resolution and is bridged.
//!   Series whose x jumps back and forth are not reduced much: line charts expect ordered x.
//!
//! What it deliberately does not do: compute statistics, pick which quantities to plot, or
//! decide file names beyond `<stem>.png`/`<stem>.svg`; those belong to the callers. The scatter
//! chart is meant for tens of labelled points (one per algorithm or setting): every point is
//! drawn and labelled, each label placed where it overlaps no other label and no dot
//! (`label_placement.rs`), joined to its point by a grey leader line when it had to move away.

use super::label_placement::{DOT_RADIUS, PixelBox, place_labels};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontStyle, register_font};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// One named line on a [`LineChart`]: `(x, y)` points joined in the order given.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// A horizontal reference line drawn across the chart, with a label (e.g. "max 54").
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    pub label: String,
    pub y: f64,
}

/// What a line chart shows. The axis ranges are computed from the series and markers.
#[derive(Debug, Clone, Copy)]
pub struct LineChart<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: &'a [Series],
    pub markers: &'a [Marker],
}

/// One labelled point on a [`ScatterChart`].
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterPoint {
    pub label: String,
    pub x: f64,
    pub y: f64,
}

/// What a scatter chart shows. The axis ranges are computed from the points.
#[derive(Debug, Clone, Copy)]
pub struct ScatterChart<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub points: &'a [ScatterPoint],
    /// Indices into `points` joined by a line (e.g. a Pareto front), drawn in this order. An
    /// index past the end of `points`, or of a point that cannot be drawn, is left out of the line.
    pub front: &'a [usize],
    /// Draw x on a base-10 logarithmic axis. Points with x ≤ 0 cannot be drawn there and are
    /// skipped.
    pub log_x: bool,
}

/// A chart file that could not be drawn or written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write chart {}: {problem}", .path.display())]
pub struct PlotError {
    /// The output file being written.
    pub path: PathBuf,
    /// What went wrong: the plotters or I/O error text.
    pub problem: String,
}

/// Writes `<dir>/<stem>.png` (1200×700) and `<dir>/<stem>.svg`; `dir` must exist.
///
/// One colour per series from a fixed palette of eight, in series order (it repeats from the
/// ninth series on); a legend to the right of the plot lists the series labels, and
/// each marker is a dashed grey line with its label just right of the plot.
pub fn write_line_chart(dir: &Path, stem: &str, chart: &LineChart) -> Result<(), PlotError> {
    write_png_and_svg(dir, stem, &LinePlan::new(chart))
}

/// Writes `<dir>/<stem>.png` (1200×700) and `<dir>/<stem>.svg`; each point is labelled with its
/// text and the front is drawn as a line through its points, which are highlighted.
pub fn write_scatter_chart(dir: &Path, stem: &str, chart: &ScatterChart) -> Result<(), PlotError> {
    write_png_and_svg(dir, stem, &ScatterPlan::new(chart))
}

/// Values of larger magnitude are treated like NaN: skipped. Keeping every coordinate below this
/// keeps every axis span and margin finite, which plotters' tick placement needs.
pub const LARGEST_PLOTTABLE_MAGNITUDE: f64 = 1e300;

/// A line series with more points than this is decimated for drawing (see the module doc).
pub const DECIMATE_ABOVE_POINTS: usize = 10_000;

/// The number of x columns a decimated series is reduced to: about one per pixel of plot width.
pub const DECIMATION_COLUMNS: usize = 1200;

/// Series colours, used in order and repeated: the Tableau-10 colours without grey (grey is kept
/// for markers and grid lines) and without the pale yellow, which is hard to see on white.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0x1f, 0x77, 0xb4), // blue
    RGBColor(0xff, 0x7f, 0x0e), // orange
    RGBColor(0x2c, 0xa0, 0x2c), // green
    RGBColor(0xd6, 0x27, 0x28), // red
    RGBColor(0x94, 0x67, 0xbd), // purple
    RGBColor(0x8c, 0x56, 0x4b), // brown
    RGBColor(0xe3, 0x77, 0xc2), // pink
    RGBColor(0x17, 0xbe, 0xcf), // cyan
];

const IMAGE_SIZE: (u32, u32) = (1200, 700);
const BYTES_PER_RGB_PIXEL: usize = 3;

const EMBEDDED_FONT: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/fonts/DejaVuSans.ttf"
));
/// The family plotters' default text styles use (`FontFamily::SansSerif`); registering the
/// embedded font under it makes titles, tick labels, axis descriptions and legends all find it.
pub(crate) const FONT_FAMILY: &str = "sans-serif";

const TITLE_FONT_SIZE: f64 = 28.0;
const AXIS_DESC_FONT_SIZE: f64 = 19.0;
const TICK_FONT_SIZE: f64 = 16.0;
const LEGEND_FONT_SIZE: f64 = 16.0;
const MARKER_FONT_SIZE: f64 = 15.0;
const POINT_LABEL_FONT_SIZE: f64 = 15.0;

const TEXT_COLOR: RGBColor = RGBColor(0x22, 0x22, 0x22);
const AXIS_COLOR: RGBColor = RGBColor(0x44, 0x44, 0x44);
const MARKER_COLOR: RGBColor = RGBColor(0x70, 0x70, 0x70);
const GRID_BOLD_COLOR: RGBColor = RGBColor(0xdd, 0xdd, 0xdd);
const GRID_LIGHT_COLOR: RGBColor = RGBColor(0xf0, 0xf0, 0xf0);
const LEGEND_BORDER_COLOR: RGBColor = RGBColor(0xbb, 0xbb, 0xbb);
const SCATTER_POINT_COLOR: RGBColor = PALETTE[0];
const SCATTER_FRONT_COLOR: RGBColor = PALETTE[3];
const LEADER_COLOR: RGBColor = RGBColor(0xaa, 0xaa, 0xaa);

/// Fractions of the data span added on each side of an axis.
const X_MARGIN: f64 = 0.02;
const Y_MARGIN: f64 = 0.06;
const SCATTER_X_MARGIN: f64 = 0.04;
/// Extra room right of and above scatter points, for their labels.
const SCATTER_LABEL_ROOM_X: f64 = 0.12;
const SCATTER_LABEL_ROOM_Y: f64 = 0.08;
/// Spans smaller than this fraction of the values' magnitude are shown as all-equal values.
const RELATIVE_SPAN_EPSILON: f64 = 1e-12;

/// Legend and marker-label panels never grow wider than these, in pixels; longer labels are cut
/// with an ellipsis.
const LEGEND_MAX_TEXT_WIDTH: u32 = 320;
const MARKER_MAX_TEXT_WIDTH: u32 = 180;
const LEGEND_ROW_HEIGHT: i32 = 26;
const TITLE_BAND_HEIGHT: i32 = 52;
const LEGEND_SWATCH_WIDTH: i32 = 28;
const LEGEND_PADDING: i32 = 12;
const PANEL_GAP: i32 = 10;

/// Registers the embedded font once per process; false if the font bytes could not be parsed.
/// (The preview's PNG captions use it too.)
pub(crate) fn embedded_font_registered() -> bool {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    *REGISTERED.get_or_init(|| register_font(FONT_FAMILY, FontStyle::Normal, EMBEDDED_FONT).is_ok())
}

/// A chart ready to be drawn on any plotters backend.
trait Drawing {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        target: RenderTarget,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>;
}

/// Which kind of backend a chart is drawn on. Two plotters raster quirks are worked around on
/// the PNG only, since an SVG viewer places text and joins lines itself:
/// - the `ab_glyph` rasterizer puts the baseline half a font size below the anchor, so text
///   anchored at its vertical centre comes out about a fifth of the font size too high;
/// - lines wider than one pixel are filled as polygons with unbounded inner joins, which throw
///   spikes far beyond the data where a line turns sharply (every frame-by-frame zigzag does).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RenderTarget {
    Raster,
    Vector,
}

impl RenderTarget {
    /// Pixels to add to the y of a vertically centred text so that it looks centred.
    fn text_center_nudge(self, font_size: f64) -> i32 {
        match self {
            RenderTarget::Raster => (0.22 * font_size).round() as i32,
            RenderTarget::Vector => 0,
        }
    }

    /// Draws a two-pixel-wide line through `pixels` (backend coordinates): one SVG polyline, or
    /// on a raster three one-pixel lines offset by a pixel, which have no joins to spike.
    fn draw_wide_line<DB: DrawingBackend>(
        self,
        root: &DrawingArea<DB, Shift>,
        pixels: &[(i32, i32)],
        color: RGBColor,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        match self {
            RenderTarget::Vector => root.draw(&PathElement::new(pixels, color.stroke_width(2))),
            RenderTarget::Raster => {
                for (dx, dy) in [(0, 0), (1, 0), (0, 1)] {
                    let shifted: Vec<(i32, i32)> =
                        pixels.iter().map(|&(x, y)| (x + dx, y + dy)).collect();
                    root.draw(&PathElement::new(shifted, color.stroke_width(1)))?;
                }
                Ok(())
            }
        }
    }
}

/// Draws `drawing` twice, into a pixel buffer and into an SVG string, then writes both files.
fn write_png_and_svg(dir: &Path, stem: &str, drawing: &impl Drawing) -> Result<(), PlotError> {
    let png_path = dir.join(format!("{stem}.png"));
    let svg_path = dir.join(format!("{stem}.svg"));
    if !embedded_font_registered() {
        return Err(PlotError::new(
            &png_path,
            "the embedded font assets/fonts/DejaVuSans.ttf could not be loaded",
        ));
    }

    let (width, height) = IMAGE_SIZE;
    let mut pixels = vec![0u8; width as usize * height as usize * BYTES_PER_RGB_PIXEL];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, IMAGE_SIZE).into_drawing_area();
        drawing
            .draw(&root, RenderTarget::Raster)
            .and_then(|()| root.present())
            .map_err(|error| PlotError::new(&png_path, error.to_string()))?;
    }
    let png_bytes = encode_rgb_png(&pixels, IMAGE_SIZE)
        .map_err(|error| PlotError::new(&png_path, error.to_string()))?;

    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, IMAGE_SIZE).into_drawing_area();
        drawing
            .draw(&root, RenderTarget::Vector)
            .and_then(|()| root.present())
            .map_err(|error| PlotError::new(&svg_path, error.to_string()))?;
    }

    std::fs::write(&png_path, png_bytes)
        .map_err(|error| PlotError::new(&png_path, error.to_string()))?;
    std::fs::write(&svg_path, svg).map_err(|error| PlotError::new(&svg_path, error.to_string()))
}

impl PlotError {
    fn new(path: &Path, problem: impl Into<String>) -> PlotError {
        PlotError {
            path: path.to_path_buf(),
            problem: problem.into(),
        }
    }
}

fn encode_rgb_png(
    pixels: &[u8],
    (width, height): (u32, u32),
) -> Result<Vec<u8>, png::EncodingError> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(pixels)?;
    writer.finish()?;
    Ok(bytes)
}

// ---------------------------------------------------------------------------------------------
// Line charts.

/// A line chart with its ranges computed and its series split and decimated for drawing.
struct LinePlan<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    x_range: Range<f64>,
    y_range: Range<f64>,
    series: Vec<PlannedSeries<'a>>,
    /// Only markers with a plottable y.
    markers: Vec<&'a Marker>,
    /// Whether any series has a plottable point.
    has_data: bool,
}

struct PlannedSeries<'a> {
    label: &'a str,
    color: RGBColor,
    /// Unbroken, non-empty runs of plottable points; a run of one point (or of one point
    /// repeated) is drawn as a dot.
    runs: Vec<Vec<(f64, f64)>>,
}

impl<'a> LinePlan<'a> {
    fn new(chart: &LineChart<'a>) -> LinePlan<'a> {
        let mut x_bounds = Bounds::default();
        let mut y_bounds = Bounds::default();
        for series in chart.series {
            for &(x, y) in &series.points {
                if is_plottable(x) && is_plottable(y) {
                    x_bounds.include(x);
                    y_bounds.include(y);
                }
            }
        }
        let markers: Vec<&Marker> = chart
            .markers
            .iter()
            .filter(|marker| is_plottable(marker.y))
            .collect();
        for marker in &markers {
            y_bounds.include(marker.y);
        }
        let has_data = x_bounds.min_max.is_some();
        let x_range = padded_range(x_bounds, X_MARGIN, X_MARGIN);
        let y_range = padded_range(y_bounds, Y_MARGIN, Y_MARGIN);

        let series = chart
            .series
            .iter()
            .enumerate()
            .map(|(series_idx, series)| PlannedSeries {
                label: &series.label,
                color: PALETTE[series_idx % PALETTE.len()],
                runs: drawable_runs(&series.points, &x_range),
            })
            .collect();
        LinePlan {
            title: chart.title,
            x_label: chart.x_label,
            y_label: chart.y_label,
            x_range,
            y_range,
            series,
            markers,
            has_data,
        }
    }

    fn legend_entries(&self) -> Vec<LegendEntry> {
        self.series
            .iter()
            .filter(|series| !series.label.is_empty())
            .map(|series| LegendEntry {
                text: if series.runs.is_empty() {
                    format!("{} (no data)", series.label)
                } else {
                    series.label.to_string()
                },
                color: series.color,
            })
            .collect()
    }
}

impl Drawing for LinePlan<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        target: RenderTarget,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let body = draw_title(root, self.title, target)?;

        let legend = Legend::measure(root, self.legend_entries())?;
        let marker_style = text_style(MARKER_FONT_SIZE).color(&MARKER_COLOR);
        let mut marker_labels = Vec::with_capacity(self.markers.len());
        let mut marker_panel_width = 0;
        for marker in &self.markers {
            let label = fit_text(root, &marker.label, &marker_style, MARKER_MAX_TEXT_WIDTH)?;
            let (label_width, _) = root.estimate_text_size(&label, &marker_style)?;
            marker_panel_width = marker_panel_width.max(label_width as i32 + PANEL_GAP);
            marker_labels.push(label);
        }
        let right_panel_width = marker_panel_width + legend.width;

        let (body_width, _) = body.dim_in_pixel();
        let plot_width = (body_width as i32 - right_panel_width).max(body_width as i32 / 2);
        let (plot_part, _) = body.split_horizontally(plot_width);

        let x_format = TickFormat::for_linear_range(&self.x_range);
        let y_format = TickFormat::for_linear_range(&self.y_range);
        let y_label_area = y_label_area_width(root, &y_format, &self.y_range)?;
        let mut chart = ChartBuilder::on(&plot_part)
            .margin_top(10)
            .margin_bottom(10)
            .margin_left(14)
            .margin_right(if right_panel_width > 0 { 8 } else { 30 })
            .x_label_area_size(56)
            .y_label_area_size(y_label_area)
            .build_cartesian_2d(self.x_range.clone(), self.y_range.clone())?;
        let format_x = |x: &f64| x_format.label(*x);
        let format_y = |y: &f64| y_format.label(*y);
        configure_axes(
            &mut chart,
            AxisTexts {
                x_label: self.x_label,
                y_label: self.y_label,
                format_x: &format_x,
                format_y: &format_y,
            },
            target,
        )?;
        if !self.has_data {
            draw_no_data_note(root, chart.plotting_area().get_pixel_range(), target)?;
        }

        let dash_style = MARKER_COLOR.stroke_width(1);
        for marker in &self.markers {
            let ends = [(self.x_range.start, marker.y), (self.x_range.end, marker.y)];
            chart.draw_series(DashedLineSeries::new(ends, 8, 5, dash_style))?;
        }

        for series in &self.series {
            for run in &series.runs {
                // A run whose points all coincide has no length to draw: show it as a dot.
                if run.iter().all(|point| *point == run[0]) {
                    chart.draw_series([Circle::new(run[0], 3, series.color.filled())])?;
                } else {
                    let pixels: Vec<(i32, i32)> =
                        run.iter().map(|point| chart.backend_coord(point)).collect();
                    target.draw_wide_line(root, &pixels, series.color)?;
                }
            }
        }

        let (plot_pixels_x, plot_pixels_y) = chart.plotting_area().get_pixel_range();
        let marker_label_x = plot_pixels_x.end + PANEL_GAP / 2;
        let wanted_rows: Vec<i32> = self
            .markers
            .iter()
            .map(|marker| chart.backend_coord(&(self.x_range.end, marker.y)).1)
            .collect();
        let (_, marker_text_height) = root.estimate_text_size("Mg", &marker_style)?;
        let rows = spread_apart(&wanted_rows, marker_text_height as i32 + 2, &plot_pixels_y);
        let marker_style = marker_style.pos(Pos::new(HPos::Left, VPos::Center));
        let nudge = target.text_center_nudge(MARKER_FONT_SIZE);
        for (label, row) in marker_labels.iter().zip(rows) {
            root.draw(&Text::new(
                label.as_str(),
                (marker_label_x, row + nudge),
                marker_style.clone(),
            ))?;
        }

        let legend_x = plot_pixels_x.end + marker_panel_width + PANEL_GAP;
        legend.draw(root, (legend_x, plot_pixels_y.start), target)
    }
}

/// Replaces non-plottable points by breaks and, for a long series, decimates as the module doc
/// says. For a short series every point is its own "column", so nothing is merged.
fn drawable_runs(points: &[(f64, f64)], x_range: &Range<f64>) -> Vec<Vec<(f64, f64)>> {
    let decimate = points.len() > DECIMATE_ABOVE_POINTS;
    let x_span = x_range.end - x_range.start;
    let column_of = |point_idx: usize, x: f64| -> usize {
        if decimate {
            let fraction = (x - x_range.start) / x_span;
            ((fraction * DECIMATION_COLUMNS as f64) as usize).min(DECIMATION_COLUMNS - 1)
        } else {
            point_idx
        }
    };

    let mut runs = Vec::new();
    let mut run = Vec::new();
    let mut column: Option<ColumnExtremes> = None;
    let mut broken_since_last_point = false;
    for (point_idx, &(x, y)) in points.iter().enumerate() {
        if !(is_plottable(x) && is_plottable(y)) {
            broken_since_last_point = true;
            continue;
        }
        let point_column = column_of(point_idx, x);
        match &mut column {
            // A break inside one column is narrower than a pixel: bridge it.
            Some(extremes) if extremes.column == point_column => {
                extremes.include(point_idx, (x, y));
            }
            _ => {
                if let Some(extremes) = column.take() {
                    extremes.append_to(&mut run);
                }
                if broken_since_last_point && !run.is_empty() {
                    runs.push(std::mem::take(&mut run));
                }
                column = Some(ColumnExtremes::new(point_column, point_idx, (x, y)));
            }
        }
        broken_since_last_point = false;
    }
    if let Some(extremes) = column {
        extremes.append_to(&mut run);
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// The first, lowest, highest and last point of a run of consecutive points in one column, each
/// with its index in the series.
struct ColumnExtremes {
    column: usize,
    first: (usize, (f64, f64)),
    lowest: (usize, (f64, f64)),
    highest: (usize, (f64, f64)),
    last: (usize, (f64, f64)),
}

impl ColumnExtremes {
    fn new(column: usize, point_idx: usize, point: (f64, f64)) -> ColumnExtremes {
        let indexed = (point_idx, point);
        ColumnExtremes {
            column,
            first: indexed,
            lowest: indexed,
            highest: indexed,
            last: indexed,
        }
    }

    fn include(&mut self, point_idx: usize, point: (f64, f64)) {
        if point.1 < self.lowest.1.1 {
            self.lowest = (point_idx, point);
        }
        if point.1 > self.highest.1.1 {
            self.highest = (point_idx, point);
        }
        self.last = (point_idx, point);
    }

    /// Appends the distinct kept points in series order.
    fn append_to(self, run: &mut Vec<(f64, f64)>) {
        let mut kept = [self.first, self.lowest, self.highest, self.last];
        kept.sort_by_key(|(point_idx, _)| *point_idx);
        let mut previous_idx = None;
        for (point_idx, point) in kept {
            if previous_idx != Some(point_idx) {
                run.push(point);
                previous_idx = Some(point_idx);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Scatter charts.

/// A scatter chart with its ranges computed and its undrawable points removed.
struct ScatterPlan<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    x_range: Range<f64>,
    y_range: Range<f64>,
    log_x: bool,
    /// Only the drawable points.
    points: Vec<PlannedPoint<'a>>,
    /// The drawable front points, in front order.
    front: Vec<(f64, f64)>,
}

struct PlannedPoint<'a> {
    label: &'a str,
    position: (f64, f64),
    on_front: bool,
}

impl<'a> ScatterPlan<'a> {
    fn new(chart: &ScatterChart<'a>) -> ScatterPlan<'a> {
        let log_x = chart.log_x;
        let drawable = |point: &ScatterPoint| -> bool {
            is_plottable(point.x) && is_plottable(point.y) && (!log_x || point.x > 0.0)
        };
        let mut on_front = vec![false; chart.points.len()];
        for &point_idx in chart.front {
            if let Some(flag) = on_front.get_mut(point_idx) {
                *flag = true;
            }
        }
        let points: Vec<PlannedPoint> = chart
            .points
            .iter()
            .zip(on_front)
            .filter(|(point, _)| drawable(point))
            .map(|(point, on_front)| PlannedPoint {
                label: &point.label,
                position: (point.x, point.y),
                on_front,
            })
            .collect();
        let front = chart
            .front
            .iter()
            .filter_map(|&point_idx| chart.points.get(point_idx))
            .filter(|point| drawable(point))
            .map(|point| (point.x, point.y))
            .collect();

        let mut x_bounds = Bounds::default();
        let mut y_bounds = Bounds::default();
        for point in &points {
            let (x, y) = point.position;
            x_bounds.include(if log_x { x.log10() } else { x });
            y_bounds.include(y);
        }
        // On a logarithmic axis the margins are fractions of the span in decades.
        let x_range = padded_range(
            x_bounds,
            SCATTER_X_MARGIN,
            SCATTER_X_MARGIN + SCATTER_LABEL_ROOM_X,
        );
        let x_range = if log_x {
            let decades = with_a_whole_decade(x_range);
            10f64.powf(decades.start)..10f64.powf(decades.end)
        } else {
            x_range
        };
        let y_range = padded_range(y_bounds, Y_MARGIN, Y_MARGIN + SCATTER_LABEL_ROOM_Y);
        ScatterPlan {
            title: chart.title,
            x_label: chart.x_label,
            y_label: chart.y_label,
            x_range,
            y_range,
            log_x,
            points,
            front,
        }
    }

    /// Everything after the coordinate system is chosen, for either kind of x axis.
    fn draw_on<DB, X>(
        &self,
        root: &DrawingArea<DB, Shift>,
        chart: &mut ChartContext<'_, DB, Cartesian2d<X, RangedCoordf64>>,
        format_x: &dyn Fn(&f64) -> String,
        target: RenderTarget,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
    where
        DB: DrawingBackend,
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let y_format = TickFormat::for_linear_range(&self.y_range);
        let format_y = |y: &f64| y_format.label(*y);
        let texts = AxisTexts {
            x_label: self.x_label,
            y_label: self.y_label,
            format_x,
            format_y: &format_y,
        };
        configure_axes(chart, texts, target)?;
        if self.points.is_empty() {
            draw_no_data_note(root, chart.plotting_area().get_pixel_range(), target)?;
        }

        if self.front.len() > 1 {
            let pixels: Vec<(i32, i32)> = self
                .front
                .iter()
                .map(|point| chart.backend_coord(point))
                .collect();
            target.draw_wide_line(root, &pixels, SCATTER_FRONT_COLOR)?;
        }
        let label_style = text_style(POINT_LABEL_FONT_SIZE)
            .color(&TEXT_COLOR)
            .pos(Pos::new(HPos::Left, VPos::Top));
        // Front points first: their labels get the best spots.
        let mut order: Vec<usize> = (0..self.points.len()).collect();
        order.sort_by_key(|&k| !self.points[k].on_front);
        let pixels: Vec<(i32, i32)> = order
            .iter()
            .map(|&k| chart.backend_coord(&self.points[k].position))
            .collect();
        let mut sizes = Vec::with_capacity(order.len());
        for &k in &order {
            let (width, height) = root.estimate_text_size(self.points[k].label, &label_style)?;
            sizes.push((width as i32, height as i32));
        }
        let (x_pixels, y_pixels) = chart.plotting_area().get_pixel_range();
        let area = PixelBox {
            left: x_pixels.start,
            top: y_pixels.start,
            width: x_pixels.end - x_pixels.start,
            height: y_pixels.end - y_pixels.start,
        };
        let placements = place_labels(&pixels, &sizes, area);
        for (&pixel, placement) in pixels.iter().zip(&placements) {
            if placement.needs_leader {
                let end = placement.label.nearest_to(pixel);
                root.draw(&PathElement::new(
                    vec![pixel, end],
                    LEADER_COLOR.stroke_width(1),
                ))?;
            }
        }
        for (&k, &pixel) in order.iter().zip(&pixels) {
            let point = &self.points[k];
            let color = if point.on_front {
                SCATTER_FRONT_COLOR
            } else {
                SCATTER_POINT_COLOR
            };
            root.draw(&Circle::new(pixel, DOT_RADIUS as u32, color.filled()))?;
            root.draw(&Circle::new(
                pixel,
                DOT_RADIUS as u32,
                WHITE.stroke_width(1),
            ))?;
        }
        for (&k, placement) in order.iter().zip(&placements) {
            root.draw(&Text::new(
                self.points[k].label.to_string(),
                (placement.label.left, placement.label.top),
                label_style.clone(),
            ))?;
        }
        Ok(())
    }
}

impl Drawing for ScatterPlan<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        target: RenderTarget,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let body = draw_title(root, self.title, target)?;
        let y_format = TickFormat::for_linear_range(&self.y_range);
        let y_label_area = y_label_area_width(root, &y_format, &self.y_range)?;
        let mut builder = ChartBuilder::on(&body);
        builder
            .margin_top(10)
            .margin_bottom(10)
            .margin_left(14)
            .margin_right(30)
            .x_label_area_size(56)
            .y_label_area_size(y_label_area);
        if self.log_x {
            let mut chart = builder
                .build_cartesian_2d(self.x_range.clone().log_scale(), self.y_range.clone())?;
            self.draw_on(root, &mut chart, &|x: &f64| log_tick_label(*x), target)
        } else {
            let x_format = TickFormat::for_linear_range(&self.x_range);
            let mut chart =
                builder.build_cartesian_2d(self.x_range.clone(), self.y_range.clone())?;
            self.draw_on(root, &mut chart, &|x: &f64| x_format.label(*x), target)
        }
    }
}

/// Widens a range of base-10 exponents so that it contains a whole number, the position of a
/// labelled tick on plotters' logarithmic axis (which places no tick inside a decade otherwise).
fn with_a_whole_decade(exponents: Range<f64>) -> Range<f64> {
    if exponents.start.ceil() <= exponents.end {
        return exponents;
    }
    let below = exponents.start - exponents.start.floor();
    let above = exponents.end.ceil() - exponents.end;
    if below <= above {
        exponents.start.floor()..exponents.end
    } else {
        exponents.start..exponents.end.ceil()
    }
}

// ---------------------------------------------------------------------------------------------
// Shared layout: ranges, tick labels, axes, legend.

/// True for values that can be placed on an axis: finite and not absurdly large.
fn is_plottable(value: f64) -> bool {
    value.is_finite() && value.abs() <= LARGEST_PLOTTABLE_MAGNITUDE
}

/// The smallest and largest of the values seen, if any.
#[derive(Debug, Default, Clone, Copy)]
struct Bounds {
    min_max: Option<(f64, f64)>,
}

impl Bounds {
    fn include(&mut self, value: f64) {
        self.min_max = Some(match self.min_max {
            None => (value, value),
            Some((min, max)) => (min.min(value), max.max(value)),
        });
    }
}

/// An axis range around the bounds with `low_margin` and `high_margin` (fractions of the span)
/// added; the unit range when there are no values, and a band of ±10 % (±1 around zero) when
/// all values are equal or too close together to tell apart.
fn padded_range(bounds: Bounds, low_margin: f64, high_margin: f64) -> Range<f64> {
    let Some((min, max)) = bounds.min_max else {
        return 0.0..1.0;
    };
    let magnitude = min.abs().max(max.abs());
    let span = max - min;
    if span <= magnitude * RELATIVE_SPAN_EPSILON {
        let middle = min / 2.0 + max / 2.0;
        let half_band = if magnitude == 0.0 {
            1.0
        } else {
            magnitude * 0.1
        };
        return (middle - half_band)..(middle + half_band);
    }
    // Every value is at most LARGEST_PLOTTABLE_MAGNITUDE, so the span and margins are finite.
    (min - span * low_margin)..(max + span * high_margin)
}

/// How tick labels on one linear axis are written: enough decimals to tell ticks apart, trailing
/// zeros dropped, and scientific notation for very large or very small magnitudes.
#[derive(Debug, Clone, Copy)]
struct TickFormat {
    /// Ticks closer to zero than this are written "0" (hides "-0" and 1e-17 rounding noise).
    zero_below: f64,
    notation: TickNotation,
}

#[derive(Debug, Clone, Copy)]
enum TickNotation {
    Decimal { decimals: usize },
    Scientific { mantissa_decimals: usize },
}

impl TickFormat {
    fn for_linear_range(range: &Range<f64>) -> TickFormat {
        const MAX_DIGITS: f64 = 12.0;
        // Plotters puts about ten ticks on an axis; one more digit covers denser ticks.
        let tick_step = (range.end - range.start) / 10.0;
        let magnitude = range.start.abs().max(range.end.abs());
        let notation = if !(1e-3..1e7).contains(&magnitude) {
            let digits = (magnitude / tick_step).log10().ceil() + 1.0;
            TickNotation::Scientific {
                mantissa_decimals: digits.clamp(0.0, MAX_DIGITS) as usize,
            }
        } else {
            let decimals = (-tick_step.log10()).ceil() + 1.0;
            TickNotation::Decimal {
                decimals: decimals.clamp(0.0, MAX_DIGITS) as usize,
            }
        };
        TickFormat {
            zero_below: tick_step * 1e-6,
            notation,
        }
    }

    fn label(&self, value: f64) -> String {
        if value.abs() < self.zero_below {
            return "0".to_string();
        }
        match self.notation {
            TickNotation::Decimal { decimals } => {
                trim_fraction_zeros(&format!("{value:.decimals$}")).to_string()
            }
            TickNotation::Scientific { mantissa_decimals } => {
                let text = format!("{value:.mantissa_decimals$e}");
                match text.split_once('e') {
                    Some((mantissa, exponent)) => {
                        format!("{}e{exponent}", trim_fraction_zeros(mantissa))
                    }
                    None => text,
                }
            }
        }
    }
}

/// Tick labels on a logarithmic axis: plain numbers from 0.001 to 10^7, scientific beyond.
fn log_tick_label(value: f64) -> String {
    // Within a decade plotters ticks 1…9 × 10^k; labelling them all crowds the upper end of each
    // decade, so only the 1, 2 and 5 ticks carry a label.
    let mantissa = value.abs() / 10f64.powf(value.abs().log10().floor());
    if ![1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-6) {
        return String::new();
    }
    if (1e-3..1e7).contains(&value.abs()) {
        trim_fraction_zeros(&format!("{value:.3}")).to_string()
    } else {
        let text = format!("{value:.2e}");
        match text.split_once('e') {
            Some((mantissa, exponent)) => format!("{}e{exponent}", trim_fraction_zeros(mantissa)),
            None => text,
        }
    }
}

/// "2.500" → "2.5", "3.000" → "3", "40" → "40".
fn trim_fraction_zeros(number: &str) -> &str {
    if number.contains('.') {
        number.trim_end_matches('0').trim_end_matches('.')
    } else {
        number
    }
}

fn text_style<'a>(size: f64) -> TextStyle<'a> {
    TextStyle::from((FONT_FAMILY, size).into_font()).color(&TEXT_COLOR)
}

/// Room for the y tick labels (measured on a sample of values) and the rotated y description.
fn y_label_area_width<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    format: &TickFormat,
    range: &Range<f64>,
) -> Result<u32, DrawingAreaErrorKind<DB::ErrorType>> {
    const SAMPLES: usize = 20;
    let tick_style = text_style(TICK_FONT_SIZE);
    let mut widest_label = 0;
    for sample_idx in 0..=SAMPLES {
        let value = range.start + (range.end - range.start) * sample_idx as f64 / SAMPLES as f64;
        let (width, _) = root.estimate_text_size(&format.label(value), &tick_style)?;
        widest_label = widest_label.max(width);
    }
    let (_, desc_height) = root.estimate_text_size("Mg", &text_style(AXIS_DESC_FONT_SIZE))?;
    Ok(widest_label + desc_height + 28)
}

/// Draws the title centred in a band at the top and returns the area below the band.
fn draw_title<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    target: RenderTarget,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (width, _) = root.dim_in_pixel();
    let style = text_style(TITLE_FONT_SIZE);
    let title = fit_text(root, title, &style, width.saturating_sub(40))?;
    let style = style.pos(Pos::new(HPos::Center, VPos::Center));
    let center = (
        width as i32 / 2,
        TITLE_BAND_HEIGHT / 2 + target.text_center_nudge(TITLE_FONT_SIZE),
    );
    root.draw(&Text::new(title, center, style))?;
    Ok(root.split_vertically(TITLE_BAND_HEIGHT).1)
}

/// Writes "no data" in the middle of an empty plot, so that it does not look like a bug.
fn draw_no_data_note<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    (plot_x, plot_y): (Range<i32>, Range<i32>),
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let style = text_style(AXIS_DESC_FONT_SIZE)
        .color(&MARKER_COLOR)
        .pos(Pos::new(HPos::Center, VPos::Center));
    let center = (
        (plot_x.start + plot_x.end) / 2,
        (plot_y.start + plot_y.end) / 2 + target.text_center_nudge(AXIS_DESC_FONT_SIZE),
    );
    root.draw(&Text::new("no data", center, style))
}

/// The axis descriptions and tick label formatters of one chart.
struct AxisTexts<'a> {
    x_label: &'a str,
    y_label: &'a str,
    format_x: &'a dyn Fn(&f64) -> String,
    format_y: &'a dyn Fn(&f64) -> String,
}

fn configure_axes<DB, X>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, RangedCoordf64>>,
    texts: AxisTexts,
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(texts.x_label)
        .y_desc(texts.y_label)
        .x_labels(10)
        .y_labels(10)
        .x_label_formatter(texts.format_x)
        .y_label_formatter(texts.format_y)
        .y_label_offset(target.text_center_nudge(TICK_FONT_SIZE))
        .label_style(text_style(TICK_FONT_SIZE))
        .axis_desc_style(text_style(AXIS_DESC_FONT_SIZE))
        .axis_style(AXIS_COLOR.stroke_width(1))
        .bold_line_style(GRID_BOLD_COLOR.stroke_width(1))
        .light_line_style(GRID_LIGHT_COLOR.stroke_width(1))
        .max_light_lines(4)
        .draw()
}

/// Moves wanted pixel rows apart so that neighbours are at least `min_gap` apart, staying within
/// `limits` where there is room; returns the rows in the order given.
fn spread_apart(wanted: &[i32], min_gap: i32, limits: &Range<i32>) -> Vec<i32> {
    let mut order: Vec<usize> = (0..wanted.len()).collect();
    order.sort_by_key(|&idx| (wanted[idx], idx));
    let mut rows: Vec<i32> = order.iter().map(|&idx| wanted[idx]).collect();
    for idx in 1..rows.len() {
        rows[idx] = rows[idx].max(rows[idx - 1] + min_gap);
    }
    if let Some(last) = rows.last_mut() {
        *last = (*last).min(limits.end - min_gap / 2);
    }
    for idx in (0..rows.len().saturating_sub(1)).rev() {
        rows[idx] = rows[idx].min(rows[idx + 1] - min_gap);
    }
    let mut result = vec![0; wanted.len()];
    for (sorted_idx, &original_idx) in order.iter().enumerate() {
        result[original_idx] = rows[sorted_idx];
    }
    result
}

struct LegendEntry {
    text: String,
    color: RGBColor,
}

/// The legend box: one row per entry, a colour swatch then the label. Zero width when empty.
struct Legend {
    entries: Vec<LegendEntry>,
    /// Total width including the gap before it.
    width: i32,
    box_width: i32,
}

impl Legend {
    fn measure<DB: DrawingBackend>(
        root: &DrawingArea<DB, Shift>,
        mut entries: Vec<LegendEntry>,
    ) -> Result<Legend, DrawingAreaErrorKind<DB::ErrorType>> {
        if entries.is_empty() {
            return Ok(Legend {
                entries,
                width: 0,
                box_width: 0,
            });
        }
        // Rows that do not fit in the image height are summarised in a last row.
        let max_rows = ((IMAGE_SIZE.1 as i32 - 140) / LEGEND_ROW_HEIGHT).max(1) as usize;
        if entries.len() > max_rows {
            let n_hidden = entries.len() - (max_rows - 1);
            entries.truncate(max_rows - 1);
            entries.push(LegendEntry {
                text: format!("… and {n_hidden} more"),
                color: WHITE,
            });
        }
        let style = text_style(LEGEND_FONT_SIZE);
        let mut widest_text = 0;
        for entry in &mut entries {
            entry.text = fit_text(root, &entry.text, &style, LEGEND_MAX_TEXT_WIDTH)?;
            widest_text = widest_text.max(root.estimate_text_size(&entry.text, &style)?.0 as i32);
        }
        let box_width = LEGEND_PADDING * 2 + LEGEND_SWATCH_WIDTH + 8 + widest_text;
        Ok(Legend {
            entries,
            width: box_width + PANEL_GAP * 2,
            box_width,
        })
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        (left, top): (i32, i32),
        target: RenderTarget,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        if self.entries.is_empty() {
            return Ok(());
        }
        let box_height = LEGEND_PADDING * 2 + LEGEND_ROW_HEIGHT * self.entries.len() as i32 - 8;
        root.draw(&Rectangle::new(
            [(left, top), (left + self.box_width, top + box_height)],
            LEGEND_BORDER_COLOR.stroke_width(1),
        ))?;
        let style = text_style(LEGEND_FONT_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
        for (row_idx, entry) in self.entries.iter().enumerate() {
            let row_center = top + LEGEND_PADDING + 9 + LEGEND_ROW_HEIGHT * row_idx as i32;
            let swatch_left = left + LEGEND_PADDING;
            root.draw(&PathElement::new(
                [
                    (swatch_left, row_center),
                    (swatch_left + LEGEND_SWATCH_WIDTH, row_center),
                ],
                entry.color.stroke_width(3),
            ))?;
            root.draw(&Text::new(
                entry.text.as_str(),
                (
                    swatch_left + LEGEND_SWATCH_WIDTH + 8,
                    row_center + target.text_center_nudge(LEGEND_FONT_SIZE),
                ),
                style.clone(),
            ))?;
        }
        Ok(())
    }
}

/// The text itself if it is at most `max_width` pixels wide, else its longest prefix that fits
/// with an ellipsis appended (found by bisection, so a huge label costs a few measurements).
fn fit_text<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
    max_width: u32,
) -> Result<String, DrawingAreaErrorKind<DB::ErrorType>> {
    if root.estimate_text_size(text, style)?.0 <= max_width {
        return Ok(text.to_string());
    }
    let chars: Vec<char> = text.chars().collect();
    let shortened =
        |n_kept: usize| -> String { chars[..n_kept].iter().chain(['…'].iter()).collect() };
    // Invariant: `n_fitting` chars plus the ellipsis fit (0 is accepted even if it does not),
    // `n_too_many` chars plus the ellipsis do not.
    let (mut n_fitting, mut n_too_many) = (0, chars.len());
    while n_too_many - n_fitting > 1 {
        let n_tried = (n_fitting + n_too_many) / 2;
        if root.estimate_text_size(&shortened(n_tried), style)?.0 <= max_width {
            n_fitting = n_tried;
        } else {
            n_too_many = n_tried;
        }
    }
    Ok(shortened(n_fitting))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(label: &str, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.to_string(),
            points,
        }
    }

    fn marker(label: &str, y: f64) -> Marker {
        Marker {
            label: label.to_string(),
            y,
        }
    }

    /// Writes a line chart titled "Test chart" and returns the PNG and SVG paths, or the error.
    fn write_line(
        dir: &Path,
        stem: &str,
        series: &[Series],
        markers: &[Marker],
    ) -> Result<(PathBuf, PathBuf), PlotError> {
        let chart = LineChart {
            title: "Test chart",
            x_label: "frame",
            y_label: "triangles",
            series,
            markers,
        };
        write_line_chart(dir, stem, &chart)?;
        Ok((
            dir.join(format!("{stem}.png")),
            dir.join(format!("{stem}.svg")),
        ))
    }

    /// A decoded chart PNG: its size and its RGB pixels.
    struct DecodedPng {
        size: (u32, u32),
        pixels: Vec<[u8; 3]>,
    }

    impl DecodedPng {
        fn read(path: &Path) -> DecodedPng {
            let bytes = std::fs::read(path).expect("the PNG was written");
            let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
            let mut reader = decoder.read_info().expect("the PNG header decodes");
            let mut buffer = vec![0; reader.output_buffer_size().expect("the PNG fits in memory")];
            let info = reader
                .next_frame(&mut buffer)
                .expect("the PNG pixels decode");
            assert_eq!(info.color_type, png::ColorType::Rgb);
            let pixels = buffer[..info.buffer_size()]
                .chunks_exact(3)
                .map(|rgb| [rgb[0], rgb[1], rgb[2]])
                .collect();
            DecodedPng {
                size: (info.width, info.height),
                pixels,
            }
        }

        fn n_distinct_colours(&self) -> usize {
            self.pixels
                .iter()
                .collect::<std::collections::HashSet<_>>()
                .len()
        }

        fn n_pixels_of(&self, colour: RGBColor) -> usize {
            let wanted = [colour.0, colour.1, colour.2];
            self.pixels.iter().filter(|&&pixel| pixel == wanted).count()
        }
    }

    /// Checks both files of a chart and returns the decoded PNG for further checks.
    fn check_written_chart(
        png_path: &Path,
        svg_path: &Path,
        expected_texts: &[&str],
    ) -> DecodedPng {
        let png = DecodedPng::read(png_path);
        assert_eq!(png.size, (1200, 700));
        assert!(
            png.n_distinct_colours() > 1,
            "the PNG is a single flat colour"
        );
        let svg = std::fs::read_to_string(svg_path).expect("the SVG was written");
        assert!(
            svg.starts_with("<svg"),
            "not an SVG: {}",
            &svg[..svg.len().min(80)]
        );
        for text in expected_texts {
            assert!(svg.contains(text), "the SVG lacks the text {text:?}");
        }
        png
    }

    #[test]
    fn two_series_and_a_marker_write_a_png_and_an_svg_with_their_text() {
        let dir = tempfile::tempdir().unwrap();
        let roam = series(
            "ROAM",
            (0..500)
                .map(|f| (f as f64, 40.0 + (f as f64 / 30.0).sin() * 10.0))
                .collect(),
        );
        let wu = series(
            "Wu life-axis",
            (0..500)
                .map(|f| (f as f64, 30.0 + (f as f64 / 50.0).cos() * 8.0))
                .collect(),
        );
        let (png_path, svg_path) = write_line(
            dir.path(),
            "triangles",
            &[roam, wu],
            &[marker("max 54", 54.0)],
        )
        .unwrap();
        let png = check_written_chart(
            &png_path,
            &svg_path,
            &[
                "Test chart",
                "ROAM",
                "Wu life-axis",
                "max 54",
                "frame",
                "triangles",
            ],
        );
        // A legend swatch has well under 200 pixels; a line across the plot has thousands.
        for colour in [PALETTE[0], PALETTE[1]] {
            let n_pixels = png.n_pixels_of(colour);
            assert!(n_pixels > 1000, "{colour:?} covers only {n_pixels} pixels");
        }
        assert!(
            png.n_pixels_of(MARKER_COLOR) > 100,
            "the marker line is missing"
        );
    }

    #[test]
    fn a_series_of_one_repeated_point_is_drawn_as_a_dot() {
        let dir = tempfile::tempdir().unwrap();
        // No label, so no legend swatch: any pixel of the series colour is the dot.
        let repeated = series("", vec![(2.0, 5.0); 50]);
        let (png_path, svg_path) = write_line(dir.path(), "repeated", &[repeated], &[]).unwrap();
        let png = check_written_chart(&png_path, &svg_path, &["Test chart"]);
        assert!(
            png.n_pixels_of(PALETTE[0]) > 10,
            "the repeated point is invisible"
        );
    }

    #[test]
    fn degenerate_line_charts_are_drawn_without_error() {
        let dir = tempfile::tempdir().unwrap();
        let cases: Vec<(&str, Vec<Series>, Vec<Marker>)> = vec![
            ("no_series", vec![], vec![]),
            ("no_series_one_marker", vec![], vec![marker("budget", 5.0)]),
            ("empty_series", vec![series("empty", vec![])], vec![]),
            ("single_point", vec![series("one", vec![(3.0, 7.0)])], vec![]),
            ("all_equal", vec![series("flat", vec![(2.0, 5.0); 50])], vec![marker("same", 5.0)]),
            ("all_zero", vec![series("zero", (0..10).map(|f| (f as f64, 0.0)).collect())], vec![]),
            (
                "non_finite",
                vec![series(
                    "gappy",
                    vec![
                        (0.0, 1.0),
                        (1.0, f64::NAN),
                        (f64::INFINITY, 2.0),
                        (3.0, 4.0),
                        (4.0, 5.0),
                        (5.0, f64::NEG_INFINITY),
                        (6.0, 1.0),
                    ],
                )],
                vec![marker("nan", f64::NAN), marker("inf", f64::INFINITY)],
            ),
            ("only_non_finite", vec![series("nan", vec![(f64::NAN, f64::NAN); 3])], vec![]),
            (
                "extreme_magnitudes",
                vec![
                    series("huge", vec![(-1e300, 1e300), (1e300, -1e300), (0.0, 1e301)]),
                    series("tiny", vec![(1e-300, 1e-300), (2e-300, 3e-300)]),
                ],
                vec![],
            ),
            (
                "tiny_span",
                vec![series("near", vec![(0.0, 1.0), (1.0, 1.0 + 1e-15), (2.0, 1.0)])],
                vec![],
            ),
            (
                "long_and_many_labels",
                (0..40)
                    .map(|idx| series(&format!("series {idx} with a very long label that cannot fit into the legend"), vec![(0.0, idx as f64), (1.0, idx as f64 + 1.0)]))
                    .collect(),
                vec![marker("a marker label far too long to fit on the right of the plot", 3.0), marker("close", 3.1)],
            ),
        ];
        for (stem, series, markers) in cases {
            let (png_path, svg_path) = write_line(dir.path(), stem, &series, &markers)
                .unwrap_or_else(|error| panic!("{stem}: {error}"));
            check_written_chart(&png_path, &svg_path, &["Test chart"]);
        }
    }

    #[test]
    fn a_million_frame_series_is_decimated_to_a_small_svg() {
        let dir = tempfile::tempdir().unwrap();
        let n_frames = 1_000_000;
        let points: Vec<(f64, f64)> = (0..n_frames)
            .map(|frame| {
                let spike = if frame == 777_777 { 500.0 } else { 0.0 };
                (frame as f64, 100.0 + (frame % 1000) as f64 * 0.01 + spike)
            })
            .collect();
        let (png_path, svg_path) =
            write_line(dir.path(), "million", &[series("frames", points)], &[]).unwrap();
        check_written_chart(&png_path, &svg_path, &["frames"]);
        let svg_bytes = std::fs::metadata(&svg_path).unwrap().len();
        assert!(
            svg_bytes < 1_000_000,
            "the SVG has {svg_bytes} bytes: not decimated"
        );
    }

    #[test]
    fn decimation_keeps_every_column_extreme_in_order() {
        let x_range = 0.0..1_000_000.0;
        let points: Vec<(f64, f64)> = (0..1_000_000)
            .map(|frame| {
                (
                    frame as f64,
                    if frame == 500_123 {
                        -7.0
                    } else {
                        (frame % 97) as f64
                    },
                )
            })
            .collect();
        let runs = drawable_runs(&points, &x_range);
        assert_eq!(runs.len(), 1);
        let kept = &runs[0];
        assert!(
            kept.len() <= 4 * DECIMATION_COLUMNS,
            "kept {} points",
            kept.len()
        );
        assert!(
            kept.contains(&(500_123.0, -7.0)),
            "the global minimum was dropped"
        );
        assert_eq!(kept.first(), points.first());
        assert_eq!(kept.last(), points.last());
        assert!(
            kept.windows(2).all(|pair| pair[0].0 < pair[1].0),
            "order changed"
        );
    }

    #[test]
    fn non_finite_points_break_a_short_line() {
        let points = [
            (0.0, 1.0),
            (1.0, 2.0),
            (2.0, f64::NAN),
            (3.0, 3.0),
            (4.0, 4.0),
        ];
        let runs = drawable_runs(&points, &(0.0..4.0));
        assert_eq!(
            runs,
            vec![vec![(0.0, 1.0), (1.0, 2.0)], vec![(3.0, 3.0), (4.0, 4.0)]]
        );
    }

    #[test]
    fn tick_labels_are_short_and_exact() {
        let frames = TickFormat::for_linear_range(&(-100.0..10_100.0));
        assert_eq!(frames.label(2000.0), "2000");
        assert_eq!(frames.label(-0.0000001), "0");
        let fractions = TickFormat::for_linear_range(&(0.0..1.0));
        assert_eq!(fractions.label(0.25), "0.25");
        assert_eq!(fractions.label(0.30000000000000004), "0.3");
        let huge = TickFormat::for_linear_range(&(0.0..1e8));
        assert_eq!(huge.label(3e7), "3e7");
        assert_eq!(huge.label(2.5e7), "2.5e7");
        assert_eq!(log_tick_label(1000.0), "1000");
        assert_eq!(log_tick_label(0.01), "0.01");
        assert_eq!(log_tick_label(1e9), "1e9");
    }

    fn scatter_point(label: &str, x: f64, y: f64) -> ScatterPoint {
        ScatterPoint {
            label: label.to_string(),
            x,
            y,
        }
    }

    fn write_scatter(
        dir: &Path,
        stem: &str,
        points: &[ScatterPoint],
        front: &[usize],
        log_x: bool,
    ) -> Result<(PathBuf, PathBuf), PlotError> {
        let chart = ScatterChart {
            title: "Cost against error",
            x_label: "microseconds per frame",
            y_label: "max screen error (px)",
            points,
            front,
            log_x,
        };
        write_scatter_chart(dir, stem, &chart)?;
        Ok((
            dir.join(format!("{stem}.png")),
            dir.join(format!("{stem}.svg")),
        ))
    }

    #[test]
    fn a_scatter_chart_with_a_front_writes_both_files() {
        let dir = tempfile::tempdir().unwrap();
        let points = [
            scatter_point("Wu τ=1", 120.0, 2.0),
            scatter_point("Wu τ=4", 60.0, 4.5),
            scatter_point("ROAM", 300.0, 1.5),
            scatter_point("Lindstrom", 900.0, 1.2),
            scatter_point("naive", 2500.0, 3.0),
        ];
        for (stem, log_x) in [("linear", false), ("log", true)] {
            let (png_path, svg_path) =
                write_scatter(dir.path(), stem, &points, &[1, 0, 2, 3], log_x).unwrap();
            check_written_chart(
                &png_path,
                &svg_path,
                &["Cost against error", "Wu τ=1", "Lindstrom"],
            );
        }
    }

    #[test]
    fn degenerate_scatter_charts_are_drawn_without_error() {
        let dir = tempfile::tempdir().unwrap();
        let cases: Vec<(&str, Vec<ScatterPoint>, Vec<usize>, bool)> = vec![
            ("empty", vec![], vec![], false),
            ("empty_log", vec![], vec![0, 3], true),
            (
                "one_point_log",
                vec![scatter_point("one", 50.0, 1.0)],
                vec![0],
                true,
            ),
            (
                "bad_points_and_indices",
                vec![
                    scatter_point("nan", f64::NAN, 1.0),
                    scatter_point("zero x", 0.0, 1.0),
                    scatter_point("ok", 5.0, 2.0),
                    scatter_point("negative x", -3.0, 2.0),
                ],
                vec![0, 1, 2, 3, 99],
                true,
            ),
            (
                "same_place",
                vec![scatter_point("a", 1.0, 1.0), scatter_point("b", 1.0, 1.0)],
                vec![0, 1],
                false,
            ),
        ];
        for (stem, points, front, log_x) in cases {
            let (png_path, svg_path) = write_scatter(dir.path(), stem, &points, &front, log_x)
                .unwrap_or_else(|error| panic!("{stem}: {error}"));
            check_written_chart(&png_path, &svg_path, &["Cost against error"]);
        }
    }

    #[test]
    fn a_missing_directory_is_an_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("does_not_exist");
        let error = write_line(&missing, "chart", &[], &[]).unwrap_err();
        assert_eq!(error.path, missing.join("chart.png"));
        assert!(error.to_string().contains("chart.png"), "{error}");
    }
}
