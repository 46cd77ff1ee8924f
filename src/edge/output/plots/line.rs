//! Line charts: the plan (axis ranges, series split into drawable runs, colours) and its drawing:
//! the per-frame plots and a sweep's figures (`docs/output-formats.md`, "plots/" and "Swept
//! experiments"). It picks no series and computes no statistic: the callers (`run_plots.rs`,
//! `sweep_outputs.rs`) hand it the data.

use super::decimation::drawable_runs;
use super::legend::{Legend, LegendEntry, fit_text, spread_apart};
use super::palette::{Dash, Stroke, dash_pieces, stroke};
use super::scatter::with_a_whole_decade;
use super::ticks::log_tick_label;
use super::ticks::{
    AxisTexts, Bounds, TickFormat, configure_axes, is_plottable, padded_range, y_label_area_width,
};
use super::{
    Drawing, LineChart, MARKED_X_COLOR, MARKER_COLOR, MARKER_FONT_SIZE, MARKER_MAX_TEXT_WIDTH,
    Marker, PANEL_GAP, RenderTarget, X_MARGIN, Y_MARGIN, draw_no_data_note, draw_title, text_style,
};
use plotters::coord::Shift;
use plotters::coord::combinators::BindKeyPoints;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::ops::Range;

/// A line chart with its ranges computed and its series split and decimated for drawing.
pub(super) struct LinePlan<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    x_range: Range<f64>,
    /// In data units also on a logarithmic axis (whose ends are then powers of ten or between).
    y_range: Range<f64>,
    log_y: bool,
    series: Vec<PlannedSeries<'a>>,
    /// The marked x values inside the x range, and their legend text.
    marked_x: Vec<f64>,
    marked_x_label: &'a str,
    /// Only markers with a plottable y.
    markers: Vec<&'a Marker>,
    /// Whether any series has a plottable point.
    has_data: bool,
}

pub(super) struct PlannedSeries<'a> {
    label: &'a str,
    /// Its algorithm's colour, shaded and dashed by its variant.
    stroke: Stroke,
    /// The label of an earlier series this one hides (see [`coincidence`]), and whether the
    /// points are exactly the same.
    same_as: Option<(&'a str, bool)>,
    /// Unbroken, non-empty runs of plottable points; a run of one point (or of one point
    /// repeated) is drawn as a dot.
    runs: Vec<Vec<(f64, f64)>>,
}

impl<'a> LinePlan<'a> {
    pub(super) fn new(chart: &LineChart<'a>) -> LinePlan<'a> {
        let log_y = chart.log_y;
        // On a logarithmic axis a point is drawn at log10(y); y ≤ 0 is not drawable there.
        let axis_y = |y: f64| -> f64 {
            match (log_y, y > 0.0) {
                (false, _) => y,
                (true, true) => y.log10(),
                (true, false) => f64::NAN,
            }
        };
        let mut x_bounds = Bounds::default();
        let mut y_bounds = Bounds::default();
        for series in chart.series {
            for &(x, y) in &series.points {
                if is_plottable(x) && is_plottable(axis_y(y)) {
                    x_bounds.include(x);
                    y_bounds.include(axis_y(y));
                }
            }
        }
        let markers: Vec<&Marker> = chart
            .markers
            .iter()
            .filter(|marker| is_plottable(axis_y(marker.y)))
            .collect();
        for marker in &markers {
            y_bounds.include(axis_y(marker.y));
        }
        let has_data = x_bounds.min_max.is_some();
        let x_range = padded_range(x_bounds, X_MARGIN, X_MARGIN);
        let y_range = padded_range(y_bounds, Y_MARGIN, Y_MARGIN);
        // Two series within a pixel or two of each other everywhere hide one another.
        let axis_span = y_range.end - y_range.start;
        let y_range = if log_y {
            let decades = with_a_whole_decade(y_range);
            10f64.powf(decades.start)..10f64.powf(decades.end)
        } else {
            y_range
        };

        let series = chart
            .series
            .iter()
            .enumerate()
            .map(|(series_idx, series)| {
                let points: Vec<(f64, f64)> = if log_y {
                    series
                        .points
                        .iter()
                        .map(|&(x, y)| (x, if y > 0.0 { y } else { f64::NAN }))
                        .collect()
                } else {
                    series.points.clone()
                };
                let same_as = chart.series[..series_idx]
                    .iter()
                    .find_map(|earlier| coincidence(earlier, series, &axis_y, axis_span))
                    .map(|(earlier, exact)| (earlier.label.as_str(), exact));
                PlannedSeries {
                    label: &series.label,
                    stroke: stroke(&series.algorithm, series.variant),
                    same_as,
                    runs: drawable_runs(&points, &x_range),
                }
            })
            .collect();
        let marked_x = chart
            .marked_x
            .iter()
            .copied()
            .filter(|x| is_plottable(*x) && x_range.contains(x))
            .collect();
        LinePlan {
            title: chart.title,
            x_label: chart.x_label,
            y_label: chart.y_label,
            x_range,
            y_range,
            log_y,
            series,
            marked_x,
            marked_x_label: chart.marked_x_label,
            markers,
            has_data,
        }
    }

    pub(super) fn legend_entries(&self) -> Vec<LegendEntry> {
        let mut entries: Vec<LegendEntry> = self
            .series
            .iter()
            .filter(|series| !series.label.is_empty())
            .map(|series| LegendEntry {
                text: match (series.runs.is_empty(), series.same_as) {
                    (true, _) => format!("{} (no data)", series.label),
                    (false, Some((earlier, exact))) => format!(
                        "{} ({} {earlier}, drawn over it)",
                        series.label,
                        if exact { "=" } else { "≈" }
                    ),
                    (false, None) => series.label.to_string(),
                },
                color: series.stroke.color,
                dash: series.stroke.dash,
            })
            .collect();
        if !self.marked_x.is_empty() && !self.marked_x_label.is_empty() {
            entries.push(LegendEntry {
                text: format!("{} ({})", self.marked_x_label, self.marked_x.len()),
                color: MARKED_X_COLOR,
                dash: Dash::Solid,
            });
        }
        entries
    }
}

/// The fraction of the y axis's span within which two series' points count as coinciding:
/// about two pixels of the plot's height.
const COINCIDING_FRACTION_OF_SPAN: f64 = 0.004;

/// `earlier`, and whether the points are identical, when `later` has points at the same x
/// values that are all within [`COINCIDING_FRACTION_OF_SPAN`] of `axis_span` of `earlier`'s on
/// the axis (`axis_y`: log10 on a logarithmic axis), so that drawing `later` hides `earlier`.
fn coincidence<'s>(
    earlier: &'s super::Series,
    later: &super::Series,
    axis_y: &dyn Fn(f64) -> f64,
    axis_span: f64,
) -> Option<(&'s super::Series, bool)> {
    if earlier.points.is_empty() || earlier.points.len() != later.points.len() {
        return None;
    }
    if earlier.points == later.points {
        return Some((earlier, true));
    }
    let tolerance = COINCIDING_FRACTION_OF_SPAN * axis_span;
    let close = earlier.points.iter().zip(&later.points).all(|(a, b)| {
        let (ya, yb) = (axis_y(a.1), axis_y(b.1));
        a.0 == b.0 && ((ya - yb).abs() <= tolerance || (ya.is_nan() && yb.is_nan()))
    });
    close.then_some((earlier, false))
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
        let mut builder = ChartBuilder::on(&plot_part);
        builder
            .margin_top(10)
            .margin_bottom(10)
            .margin_left(14)
            .margin_right(if right_panel_width > 0 { 8 } else { 30 })
            .x_label_area_size(56)
            .y_label_area_size(y_label_area);
        let format_x = |x: &f64| x_format.label(*x);
        let panels = SidePanels {
            legend: &legend,
            marker_labels: &marker_labels,
            marker_panel_width,
        };
        if self.log_y {
            // Under about a decade and a half, every 1…9 × 10^k tick is labelled, so that a
            // reader can read values between the powers of ten; else 1, 2 and 5 only.
            let every_multiple = (self.y_range.end / self.y_range.start).log10() < 1.5;
            let ticks = log_ticks(self.y_range.start, self.y_range.end, every_multiple);
            let mut chart = builder.build_cartesian_2d(
                self.x_range.clone(),
                self.y_range.clone().log_scale().with_key_points(ticks),
            )?;
            self.draw_on(
                root,
                &mut chart,
                &format_x,
                &|y: &f64| log_tick_label(*y, every_multiple),
                &panels,
                target,
            )
        } else {
            let mut chart =
                builder.build_cartesian_2d(self.x_range.clone(), self.y_range.clone())?;
            self.draw_on(
                root,
                &mut chart,
                &format_x,
                &|y: &f64| y_format.label(*y),
                &panels,
                target,
            )
        }
    }
}

/// What is drawn right of the plot, measured before the plot is laid out.
struct SidePanels<'p> {
    legend: &'p Legend,
    marker_labels: &'p [String],
    marker_panel_width: i32,
}

impl LinePlan<'_> {
    /// Everything after the coordinate system is chosen, for either kind of y axis.
    fn draw_on<DB, Y>(
        &self,
        root: &DrawingArea<DB, Shift>,
        chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
        format_x: &dyn Fn(&f64) -> String,
        format_y: &dyn Fn(&f64) -> String,
        panels: &SidePanels,
        target: RenderTarget,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
    where
        DB: DrawingBackend,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        configure_axes(
            chart,
            AxisTexts {
                x_label: self.x_label,
                y_label: self.y_label,
                format_x,
                format_y,
            },
            target,
        )?;
        if !self.has_data {
            draw_no_data_note(root, chart.plotting_area().get_pixel_range(), target)?;
        }

        // Marked x values first, behind everything: one-pixel bands across the plot.
        let (plot_pixels_x, plot_pixels_y) = chart.plotting_area().get_pixel_range();
        for x in &self.marked_x {
            let column = chart.backend_coord(&(*x, self.y_range.start)).0;
            root.draw(&PathElement::new(
                [(column, plot_pixels_y.start), (column, plot_pixels_y.end)],
                MARKED_X_COLOR.stroke_width(1),
            ))?;
        }

        let dash_style = MARKER_COLOR.stroke_width(1);
        for marker in &self.markers {
            let ends = [(self.x_range.start, marker.y), (self.x_range.end, marker.y)];
            chart.draw_series(DashedLineSeries::new(ends, 8, 5, dash_style))?;
        }

        for series in &self.series {
            for run in &series.runs {
                // A run whose points all coincide has no length to draw: show it as a dot.
                let color = series.stroke.color;
                if run.iter().all(|point| *point == run[0]) {
                    chart.draw_series([Circle::new(run[0], 3, color.filled())])?;
                } else {
                    let pixels: Vec<(i32, i32)> =
                        run.iter().map(|point| chart.backend_coord(point)).collect();
                    for piece in dash_pieces(&pixels, series.stroke.dash) {
                        target.draw_wide_line(root, &piece, color)?;
                    }
                }
            }
        }

        let marker_style = text_style(MARKER_FONT_SIZE).color(&MARKER_COLOR);
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
        for (label, row) in panels.marker_labels.iter().zip(rows) {
            root.draw(&Text::new(
                label.as_str(),
                (marker_label_x, row + nudge),
                marker_style.clone(),
            ))?;
        }

        let legend_x = plot_pixels_x.end + panels.marker_panel_width + PANEL_GAP;
        panels
            .legend
            .draw(root, (legend_x, plot_pixels_y.start), target)
    }
}

/// The ticks of a logarithmic axis over `lo..hi` (both > 0): every whole multiple of each power
/// of ten (`every_multiple`), or 1, 2 and 5 times each. Plotters alone labels only the powers.
fn log_ticks(lo: f64, hi: f64, every_multiple: bool) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let multiples: &[f64] = if every_multiple {
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    } else {
        &[1.0, 2.0, 5.0]
    };
    let mut ticks = Vec::new();
    let mut decade = 10f64.powf(lo.log10().floor());
    while decade <= hi {
        ticks.extend(
            multiples
                .iter()
                .map(|m| decade * m)
                .filter(|v| (lo..=hi).contains(v)),
        );
        decade *= 10.0;
    }
    ticks
}

#[cfg(test)]
mod log_tick_tests {
    use super::log_ticks;

    #[test]
    fn a_short_log_axis_is_ticked_at_every_multiple_and_a_long_one_at_one_two_five() {
        assert_eq!(
            log_ticks(3500.0, 25000.0, true),
            [
                4000.0, 5000.0, 6000.0, 7000.0, 8000.0, 9000.0, 10000.0, 20000.0
            ]
        );
        assert_eq!(
            log_ticks(1.0, 1000.0, false),
            [1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0]
        );
        assert!(log_ticks(0.0, 10.0, true).is_empty());
    }
}
