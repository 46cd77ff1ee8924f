//! Axes: plottable values, axis ranges with their margins, tick label formats (linear and
//! logarithmic), and the axis configuration every chart shares (the axes `docs/output-formats.md`,
//! "plots/", names for each plot). It chooses no linear or logarithmic scale: each chart's
//! caller does.

use super::{
    AXIS_COLOR, AXIS_DESC_FONT_SIZE, GRID_BOLD_COLOR, GRID_LIGHT_COLOR,
    LARGEST_PLOTTABLE_MAGNITUDE, RELATIVE_SPAN_EPSILON, RenderTarget, TICK_FONT_SIZE, text_style,
};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::prelude::*;
use std::ops::Range;

/// True for values that can be placed on an axis: finite and not absurdly large.
pub(super) fn is_plottable(value: f64) -> bool {
    value.is_finite() && value.abs() <= LARGEST_PLOTTABLE_MAGNITUDE
}

/// The smallest and largest of the values seen, if any.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct Bounds {
    pub(super) min_max: Option<(f64, f64)>,
}

impl Bounds {
    pub(super) fn include(&mut self, value: f64) {
        self.min_max = Some(match self.min_max {
            None => (value, value),
            Some((min, max)) => (min.min(value), max.max(value)),
        });
    }
}

/// An axis range around the bounds with `low_margin` and `high_margin` (fractions of the span)
/// added; the unit range when there are no values, and a band of ±10 % (±1 around zero) when
/// all values are equal or too close together to tell apart.
pub(super) fn padded_range(bounds: Bounds, low_margin: f64, high_margin: f64) -> Range<f64> {
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
pub(super) struct TickFormat {
    /// Ticks closer to zero than this are written "0" (hides "-0" and 1e-17 rounding noise).
    zero_below: f64,
    notation: TickNotation,
}

#[derive(Debug, Clone, Copy)]
pub(super) enum TickNotation {
    Decimal { decimals: usize },
    Scientific { mantissa_decimals: usize },
}

impl TickFormat {
    pub(super) fn for_linear_range(range: &Range<f64>) -> TickFormat {
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

    pub(super) fn label(&self, value: f64) -> String {
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
/// Within a decade plotters ticks 1…9 × 10^k; on an axis of several decades labelling them all
/// crowds the upper end of each decade, so only the 1, 2 and 5 ticks carry a label unless
/// `every_multiple` (an axis short enough for all of them).
pub(super) fn log_tick_label(value: f64, every_multiple: bool) -> String {
    let mantissa = value.abs() / 10f64.powf(value.abs().log10().floor());
    let whole = (mantissa - mantissa.round()).abs() < 1e-6;
    let labelled = if every_multiple {
        whole
    } else {
        [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-6)
    };
    if !labelled {
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
pub(super) fn trim_fraction_zeros(number: &str) -> &str {
    if number.contains('.') {
        number.trim_end_matches('0').trim_end_matches('.')
    } else {
        number
    }
}

/// Room for the y tick labels (measured on a sample of values) and the rotated y description.
pub(super) fn y_label_area_width<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    format: &TickFormat,
    range: &Range<f64>,
) -> Result<u32, DrawingAreaErrorKind<DB::ErrorType>> {
    pub(super) const SAMPLES: usize = 20;
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

/// The axis descriptions and tick label formatters of one chart.
pub(super) struct AxisTexts<'a> {
    pub(super) x_label: &'a str,
    pub(super) y_label: &'a str,
    pub(super) format_x: &'a dyn Fn(&f64) -> String,
    pub(super) format_y: &'a dyn Fn(&f64) -> String,
}

pub(super) fn configure_axes<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    texts: AxisTexts,
    target: RenderTarget,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
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
