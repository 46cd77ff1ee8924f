//! Line and scatter charts, each written as a PNG (1200×700) and an SVG of the same drawing, and
//! the map of a terrain and a flight over it (`map.rs`, 1200×1000).
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
//!   column, so a run of 10^6 frames draws at most 4 800 points per series and its SVG stays
//!   small.
//!   A gap (skipped point) inside one column is invisible at that resolution and is bridged.
//!   Series whose x jumps back and forth are not reduced much: line charts expect ordered x.
//!
//! What it deliberately does not do: compute statistics, pick which quantities to plot, or
//! decide file names beyond `<stem>.png`/`<stem>.svg`; those belong to the callers. The scatter
//! chart is meant for tens of points (one per algorithm or setting): every point is drawn;
//! without groups every point is labelled, with groups (colour per group, marker shape per
//! variant, a legend) only the front's points are; each label placed where it overlaps no other
//! label and no dot (`label_placement.rs`), joined to its point by a grey leader line when it had
//! to move away.
//!
//! Colour is a function of the algorithm, never of a series' position: each of the ten
//! algorithms has a hue of its own (at least 25° from any other; none is grey or black, which draw
//! markers, grid and the Pareto front), so an algorithm has the same colour in every plot of a
//! run and across runs, whatever else a plot shows. The entries of one algorithm are told apart
//! by their variant (their order among the run's entries of that algorithm, counted by the
//! caller over the whole run): lightness steps of the hue (base, darker, lighter, darkest), then
//! from the fifth entry on the same steps dashed, then dotted; a scatter point also takes a
//! marker shape per variant. Shades come before dashes because per-frame lines zigzag from frame
//! to frame and break a dash pattern up (`palette.rs`).
//!
//! The parts: `line.rs` (the line chart's plan and drawing), `map.rs` (a terrain and a flight
//! over it, seen from above), `decimation.rs` (breaks and the decimation of long series), `palette.rs` (colours, shades and dashes), `scatter.rs` (the
//! scatter chart), `ticks.rs` (ranges, tick labels,
//! axes) and `legend.rs` (legend, marker labels, text fitting); this file holds the public types,
//! the shared style and the writing of both files.

mod decimation;
mod legend;
mod line;
mod map;
mod palette;
mod scatter;
#[cfg(test)]
mod tests;
mod ticks;

use legend::fit_text;
use line::LinePlan;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontStyle, register_font};
use scatter::ScatterPlan;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

pub use map::{
    HeightRaster, MAP_SIDE_PX, MapChart, MapFormat, map_raster_size, write_map, write_map_file,
};
pub use palette::variants_in_order;

/// One named line on a [`LineChart`]: `(x, y)` points joined in the order given.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    /// The entry's algorithm (`wu`, `roam`, …), which fixes the line's hue (`palette.rs`).
    pub algorithm: String,
    /// The entry's place among the run's entries of its algorithm ([`variants_in_order`]),
    /// which picks a shade of that hue and, from the fifth on, a dash pattern.
    pub variant: usize,
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
    /// Draw y on a base-10 logarithmic axis, for series that differ by orders of magnitude.
    /// Points with y ≤ 0 cannot be drawn there and break their line.
    pub log_y: bool,
    /// x values marked by a thin vertical band across the plot (e.g. frames that broke the speed
    /// bounds), listed in the legend under `marked_x_label` when there are any.
    pub marked_x: &'a [f64],
    pub marked_x_label: &'a str,
}

/// One labelled point on a [`ScatterChart`].
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterPoint {
    pub label: String,
    pub x: f64,
    pub y: f64,
    /// The point's group: its algorithm, whose colour it takes (`palette.rs`). Empty for every
    /// point: one colour, every point labelled. Otherwise each group has a legend row, each
    /// point of a group a marker shape and a shade of the colour by its order in the group (its
    /// variant: give every entry of a run a point, so that it is the variant of the run's line
    /// plots), and only front points are labelled.
    pub group: String,
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
/// Each series' colour is its algorithm's (the same in every chart), shaded, and from the fifth
/// entry of an algorithm dashed, by its variant (`palette.rs`); a legend to the right of the plot lists the series labels (a label too
/// long for the legend wraps onto more rows, never cut), and each marker is a dashed grey line
/// with its label just right of the plot. A series whose points are those of an earlier one
/// (exactly, or within about two pixels at every x) is drawn over it and says so in the legend
/// (`= <earlier label>, drawn over it`, or `≈`), so that a hidden line is never silently
/// missing. With `log_y` the y axis is logarithmic; `marked_x` draws pale red bands.
pub fn write_line_chart(dir: &Path, stem: &str, chart: &LineChart) -> Result<(), PlotError> {
    write_png_and_svg(dir, stem, &LinePlan::new(chart))
}

/// Writes `<dir>/<stem>.png` (1200×700) and `<dir>/<stem>.svg`; the front is drawn as a line
/// through its points, which are highlighted. Without groups every point is labelled with its
/// text; with groups, colours tell groups apart (each algorithm's own, a legend names them),
/// marker shapes and shades the variants within a group, and only the front's points carry labels, so that tens of points
/// stay readable.
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
/// The points of an ungrouped scatter chart (a grouped one colours them by algorithm).
const SCATTER_POINT_COLOR: RGBColor = RGBColor(0x1f, 0x77, 0xb4);
/// The Pareto front's line and rings: black, the colour no algorithm has.
const SCATTER_FRONT_COLOR: RGBColor = BLACK;
const LEADER_COLOR: RGBColor = RGBColor(0xaa, 0xaa, 0xaa);
/// The vertical bands of [`LineChart::marked_x`]: a pale red, behind the series.
const MARKED_X_COLOR: RGBColor = RGBColor(0xf4, 0xb6, 0xb6);

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

fn text_style<'a>(size: f64) -> TextStyle<'a> {
    TextStyle::from((FONT_FAMILY, size).into_font()).color(&TEXT_COLOR)
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
