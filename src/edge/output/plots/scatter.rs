//! Scatter charts: the plan (drawable points, the front, linear or logarithmic x) and its drawing
//! with placed labels: `accuracy_vs_time` (`docs/output-formats.md`, "plots/"). It computes no
//! front (the caller's, from `sim::stats`) and places no label itself (`label_placement.rs`).

use super::super::label_placement::{DOT_RADIUS, PixelBox, place_labels};
use super::legend::{Legend, LegendEntry};
use super::palette::{Dash, algorithm_colour, stroke};
use super::ticks::{
    AxisTexts, Bounds, TickFormat, configure_axes, is_plottable, log_tick_label, padded_range,
    y_label_area_width,
};
use super::{
    Drawing, LEADER_COLOR, PANEL_GAP, POINT_LABEL_FONT_SIZE, RenderTarget, SCATTER_FRONT_COLOR,
    SCATTER_LABEL_ROOM_X, SCATTER_LABEL_ROOM_Y, SCATTER_POINT_COLOR, SCATTER_X_MARGIN,
    ScatterChart, ScatterPoint, TEXT_COLOR, Y_MARGIN, draw_no_data_note, draw_title, text_style,
};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::ops::Range;

/// A scatter chart with its ranges computed and its undrawable points removed.
pub(super) struct ScatterPlan<'a> {
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
    /// The groups' names in order of first appearance; empty for an ungrouped chart.
    groups: Vec<&'a str>,
    /// The most variants any group has.
    max_variants: usize,
}

pub(super) struct PlannedPoint<'a> {
    label: &'a str,
    position: (f64, f64),
    on_front: bool,
    /// The point's group's index among the groups, in order of first appearance (grouped
    /// charts only), and its variant: its position within its group.
    group: Option<usize>,
    variant: usize,
}

/// The shades of a group's variants, in order (`palette.rs`, repeated from the fifth on).
const VARIANT_SHADES: [&str; 4] = ["base", "darker", "lighter", "darkest"];

/// Marker shapes for a group's variants, in order (repeated from the sixth variant on).
pub(super) const VARIANT_SHAPES: [&str; 5] =
    ["circle", "square", "triangle", "diamond", "triangle down"];

impl<'a> ScatterPlan<'a> {
    pub(super) fn new(chart: &ScatterChart<'a>) -> ScatterPlan<'a> {
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
        let grouped = chart.points.iter().any(|p| !p.group.is_empty());
        let mut groups: Vec<&str> = Vec::new();
        let mut variants: Vec<usize> = Vec::new();
        let mut membership = Vec::with_capacity(chart.points.len());
        for point in chart.points {
            let group_idx = match groups.iter().position(|g| *g == point.group) {
                Some(idx) => idx,
                None => {
                    groups.push(&point.group);
                    variants.push(0);
                    groups.len() - 1
                }
            };
            membership.push((group_idx, variants[group_idx]));
            variants[group_idx] += 1;
        }
        if !grouped {
            groups.clear();
        }
        let max_variants = variants.iter().copied().max().unwrap_or(0);
        let points: Vec<PlannedPoint> = chart
            .points
            .iter()
            .zip(on_front)
            .zip(membership)
            .filter(|((point, _), _)| drawable(point))
            .map(|((point, on_front), (group_idx, variant))| PlannedPoint {
                label: &point.label,
                position: (point.x, point.y),
                on_front,
                group: grouped.then_some(group_idx),
                variant,
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
            groups,
            max_variants,
        }
    }

    /// The legend of a grouped chart: one row per group in its colour, and what the shapes mean.
    pub(super) fn legend_entries(&self) -> Vec<LegendEntry> {
        let mut entries: Vec<LegendEntry> = self
            .groups
            .iter()
            .map(|group| LegendEntry {
                text: group.to_string(),
                color: algorithm_colour(group),
                dash: Dash::Solid,
            })
            .collect();
        if !entries.is_empty() && self.max_variants > 1 {
            let shapes = VARIANT_SHAPES[..self.max_variants.min(VARIANT_SHAPES.len())].join(", ");
            let shades = VARIANT_SHADES[..self.max_variants.min(VARIANT_SHADES.len())].join(", ");
            entries.push(LegendEntry {
                text: format!(
                    "marker and shade: the entry's variant within its algorithm, in entry order \
                     ({shapes}; {shades})"
                ),
                color: WHITE,
                dash: Dash::Solid,
            });
        }
        if !entries.is_empty() {
            entries.push(LegendEntry {
                text: "ringed in black and labelled: on the front".to_string(),
                color: SCATTER_FRONT_COLOR,
                dash: Dash::Solid,
            });
        }
        entries
    }

    /// Everything after the coordinate system is chosen, for either kind of x axis.
    pub(super) fn draw_on<DB, X>(
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
        // Front points first: their labels get the best spots. A grouped chart labels only them.
        let grouped = !self.groups.is_empty();
        let mut order: Vec<usize> = (0..self.points.len())
            .filter(|&k| !grouped || self.points[k].on_front)
            .collect();
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
        if grouped {
            // Every point, front ones last so they are on top.
            let mut all: Vec<usize> = (0..self.points.len()).collect();
            all.sort_by_key(|&k| self.points[k].on_front);
            for k in all {
                let point = &self.points[k];
                let pixel = chart.backend_coord(&point.position);
                let group = point.group.map_or("", |k| self.groups[k]);
                let color = stroke(group, point.variant).color;
                if point.on_front {
                    root.draw(&Circle::new(
                        pixel,
                        DOT_RADIUS as u32 + 4,
                        SCATTER_FRONT_COLOR.stroke_width(2),
                    ))?;
                }
                draw_shape(root, pixel, point.variant, color)?;
            }
        } else {
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
        let legend = Legend::measure(root, self.legend_entries())?;
        let (body_width, _) = body.dim_in_pixel();
        let plot_width = (body_width as i32 - legend.width).max(body_width as i32 / 2);
        let (plot_part, _) = body.split_horizontally(plot_width);
        let y_format = TickFormat::for_linear_range(&self.y_range);
        let y_label_area = y_label_area_width(root, &y_format, &self.y_range)?;
        let mut builder = ChartBuilder::on(&plot_part);
        builder
            .margin_top(10)
            .margin_bottom(10)
            .margin_left(14)
            .margin_right(if legend.width > 0 { 8 } else { 30 })
            .x_label_area_size(56)
            .y_label_area_size(y_label_area);
        if self.log_x {
            let mut chart = builder
                .build_cartesian_2d(self.x_range.clone().log_scale(), self.y_range.clone())?;
            self.draw_on(
                root,
                &mut chart,
                &|x: &f64| log_tick_label(*x, false),
                target,
            )?;
            let (x_pixels, y_pixels) = chart.plotting_area().get_pixel_range();
            legend.draw(root, (x_pixels.end + PANEL_GAP, y_pixels.start), target)
        } else {
            let x_format = TickFormat::for_linear_range(&self.x_range);
            let mut chart =
                builder.build_cartesian_2d(self.x_range.clone(), self.y_range.clone())?;
            self.draw_on(root, &mut chart, &|x: &f64| x_format.label(*x), target)?;
            let (x_pixels, y_pixels) = chart.plotting_area().get_pixel_range();
            legend.draw(root, (x_pixels.end + PANEL_GAP, y_pixels.start), target)
        }
    }
}

/// Draws marker shape number `variant` (of [`VARIANT_SHAPES`], repeated) at `pixel`, filled
/// with `color` and outlined in white.
fn draw_shape<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    (x, y): (i32, i32),
    variant: usize,
    color: RGBColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let r = DOT_RADIUS;
    let outline: Vec<(i32, i32)> = match variant % VARIANT_SHAPES.len() {
        0 => {
            root.draw(&Circle::new((x, y), r as u32, color.filled()))?;
            return root.draw(&Circle::new((x, y), r as u32, WHITE.stroke_width(1)));
        }
        1 => vec![
            (x - r, y - r),
            (x + r, y - r),
            (x + r, y + r),
            (x - r, y + r),
        ],
        2 => vec![(x, y - r - 1), (x + r + 1, y + r), (x - r - 1, y + r)],
        3 => vec![
            (x, y - r - 2),
            (x + r + 2, y),
            (x, y + r + 2),
            (x - r - 2, y),
        ],
        _ => vec![(x - r - 1, y - r), (x + r + 1, y - r), (x, y + r + 1)],
    };
    root.draw(&Polygon::new(outline.clone(), color.filled()))?;
    let mut closed = outline.clone();
    closed.push(outline[0]);
    root.draw(&PathElement::new(closed, WHITE.stroke_width(1)))
}

/// Widens a range of base-10 exponents so that it contains a whole number, the position of a
/// labelled tick on plotters' logarithmic axis (which places no tick inside a decade otherwise).
pub(super) fn with_a_whole_decade(exponents: Range<f64>) -> Range<f64> {
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
