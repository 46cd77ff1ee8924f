//! Text beside the plot: the legend box, marker labels spread apart, and text cut to fit
//! (`docs/output-formats.md`, "plots/": legend labels wrap onto more rows and are never cut; a
//! marker label or a title too wide is). It writes no label's words: the callers do.

use super::palette::{Dash, dash_pieces};
use super::{
    IMAGE_SIZE, LEGEND_BORDER_COLOR, LEGEND_FONT_SIZE, LEGEND_MAX_TEXT_WIDTH, LEGEND_PADDING,
    LEGEND_ROW_HEIGHT, LEGEND_SWATCH_WIDTH, PANEL_GAP, RenderTarget, text_style,
};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::ops::Range;

/// Moves wanted pixel rows apart so that neighbours are at least `min_gap` apart, staying within
/// `limits` where there is room; returns the rows in the order given.
pub(super) fn spread_apart(wanted: &[i32], min_gap: i32, limits: &Range<i32>) -> Vec<i32> {
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

pub(super) struct LegendEntry {
    pub(super) text: String,
    pub(super) color: RGBColor,
    /// The swatch's dash pattern: the series' own.
    pub(super) dash: Dash,
}

/// The legend box: one row per entry, a colour swatch (dashed as its series) then the label; a label wider than the
/// legend wraps at spaces onto rows of its own without a swatch (a single word too wide
/// for a row is cut). Zero width when empty.
pub(super) struct Legend {
    /// Rows: the text, and the swatch on an entry's first row only.
    entries: Vec<(String, Option<(RGBColor, Dash)>)>,
    /// Total width including the gap before it.
    pub(super) width: i32,
    box_width: i32,
}

impl Legend {
    pub(super) fn measure<DB: DrawingBackend>(
        root: &DrawingArea<DB, Shift>,
        entries: Vec<LegendEntry>,
    ) -> Result<Legend, DrawingAreaErrorKind<DB::ErrorType>> {
        if entries.is_empty() {
            return Ok(Legend {
                entries: Vec::new(),
                width: 0,
                box_width: 0,
            });
        }
        let style = text_style(LEGEND_FONT_SIZE);
        // Each entry's rows: its label wrapped to the legend's width.
        let mut wrapped: Vec<(Vec<String>, (RGBColor, Dash))> = Vec::with_capacity(entries.len());
        for entry in &entries {
            let mut lines = Vec::new();
            for line in wrap_text(root, &entry.text, &style, LEGEND_MAX_TEXT_WIDTH)? {
                lines.push(fit_text(root, &line, &style, LEGEND_MAX_TEXT_WIDTH)?);
            }
            wrapped.push((lines, (entry.color, entry.dash)));
        }
        // Entries whose rows do not fit in the image height are summarised in a last row.
        let max_rows = ((IMAGE_SIZE.1 as i32 - 140) / LEGEND_ROW_HEIGHT).max(1) as usize;
        let mut rows: Vec<(String, Option<(RGBColor, Dash)>)> = Vec::new();
        for (k, (lines, color)) in wrapped.iter().enumerate() {
            let room_after = if k + 1 < wrapped.len() { 1 } else { 0 };
            if rows.len() + lines.len() + room_after > max_rows {
                let n_hidden = wrapped.len() - k;
                rows.push((format!("… and {n_hidden} more"), None));
                break;
            }
            for (line_idx, line) in lines.iter().enumerate() {
                rows.push((line.clone(), (line_idx == 0).then_some(*color)));
            }
        }
        let mut widest_text = 0;
        for (line, _) in &rows {
            widest_text = widest_text.max(root.estimate_text_size(line, &style)?.0 as i32);
        }
        let entries = rows;
        let box_width = LEGEND_PADDING * 2 + LEGEND_SWATCH_WIDTH + 8 + widest_text;
        Ok(Legend {
            entries,
            width: box_width + PANEL_GAP * 2,
            box_width,
        })
    }

    pub(super) fn draw<DB: DrawingBackend>(
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
        for (row_idx, (text, swatch)) in self.entries.iter().enumerate() {
            let row_center = top + LEGEND_PADDING + 9 + LEGEND_ROW_HEIGHT * row_idx as i32;
            let swatch_left = left + LEGEND_PADDING;
            if let Some((color, dash)) = swatch {
                let ends = [
                    (swatch_left, row_center),
                    (swatch_left + LEGEND_SWATCH_WIDTH, row_center),
                ];
                for piece in dash_pieces(&ends, *dash) {
                    root.draw(&PathElement::new(piece, color.stroke_width(3)))?;
                }
            }
            root.draw(&Text::new(
                text.as_str(),
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

/// `text` split at spaces into lines no wider than `max_width` (a word wider than that on a
/// line of its own).
pub(super) fn wrap_text<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
    max_width: u32,
) -> Result<Vec<String>, DrawingAreaErrorKind<DB::ErrorType>> {
    let mut lines: Vec<String> = Vec::new();
    let mut current = String::new();
    for word in text.split(' ') {
        let candidate = if current.is_empty() {
            word.to_string()
        } else {
            format!("{current} {word}")
        };
        if current.is_empty() || root.estimate_text_size(&candidate, style)?.0 <= max_width {
            current = candidate;
        } else {
            lines.push(std::mem::replace(&mut current, word.to_string()));
        }
    }
    lines.push(current);
    Ok(lines)
}

/// The text itself if it is at most `max_width` pixels wide, else its longest prefix that fits
/// with an ellipsis appended (found by bisection, so a huge label costs a few measurements).
pub(super) fn fit_text<DB: DrawingBackend>(
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
