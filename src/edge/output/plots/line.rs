//! Line charts: the plan (axis ranges, series split into drawable runs, colours) and its drawing.

use super::decimation::drawable_runs;
use super::legend::{Legend, LegendEntry, fit_text, spread_apart};
use super::ticks::{
    AxisTexts, Bounds, TickFormat, configure_axes, is_plottable, padded_range, y_label_area_width,
};
use super::{
    Drawing, LineChart, MARKER_COLOR, MARKER_FONT_SIZE, MARKER_MAX_TEXT_WIDTH, Marker, PALETTE,
    PANEL_GAP, RenderTarget, X_MARGIN, Y_MARGIN, draw_no_data_note, draw_title, text_style,
};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::ops::Range;

/// A line chart with its ranges computed and its series split and decimated for drawing.
pub(super) struct LinePlan<'a> {
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

pub(super) struct PlannedSeries<'a> {
    label: &'a str,
    color: RGBColor,
    /// Unbroken, non-empty runs of plottable points; a run of one point (or of one point
    /// repeated) is drawn as a dot.
    runs: Vec<Vec<(f64, f64)>>,
}

impl<'a> LinePlan<'a> {
    pub(super) fn new(chart: &LineChart<'a>) -> LinePlan<'a> {
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

    pub(super) fn legend_entries(&self) -> Vec<LegendEntry> {
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
