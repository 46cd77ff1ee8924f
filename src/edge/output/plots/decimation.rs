//! Decimation of long line series for drawing, and the breaks at non-plottable points (the rule
//! is in the module doc of `plots`; the reader's side is `docs/output-formats.md`, "plots/"). It
//! thins only what is drawn: `frames.csv` and every summary keep every frame.

use super::ticks::is_plottable;
use super::{DECIMATE_ABOVE_POINTS, DECIMATION_COLUMNS};
use std::ops::Range;

/// Replaces non-plottable points by breaks and, for a long series, decimates as the module doc
/// says. For a short series every point is its own "column", so nothing is merged.
pub(super) fn drawable_runs(points: &[(f64, f64)], x_range: &Range<f64>) -> Vec<Vec<(f64, f64)>> {
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
pub(super) struct ColumnExtremes {
    column: usize,
    first: (usize, (f64, f64)),
    lowest: (usize, (f64, f64)),
    highest: (usize, (f64, f64)),
    last: (usize, (f64, f64)),
}

impl ColumnExtremes {
    pub(super) fn new(column: usize, point_idx: usize, point: (f64, f64)) -> ColumnExtremes {
        let indexed = (point_idx, point);
        ColumnExtremes {
            column,
            first: indexed,
            lowest: indexed,
            highest: indexed,
            last: indexed,
        }
    }

    pub(super) fn include(&mut self, point_idx: usize, point: (f64, f64)) {
        if point.1 < self.lowest.1.1 {
            self.lowest = (point_idx, point);
        }
        if point.1 > self.highest.1.1 {
            self.highest = (point_idx, point);
        }
        self.last = (point_idx, point);
    }

    /// Appends the distinct kept points in series order.
    pub(super) fn append_to(self, run: &mut Vec<(f64, f64)>) {
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
