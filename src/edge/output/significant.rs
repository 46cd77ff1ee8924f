//! Numbers for a person to read: three significant digits and, where a column's name carries
//! one, its unit (`tau_px 49.4 px`, `distance_multiplier 2.11`). What captions and command
//! output print; never what a table or `summary.json` holds (they keep every digit:
//! `columns::format_number`).

/// `value` with three significant digits: whole numbers (counts) in full, others rounded
/// (`49.35…` → `49.4`, `2.1112…` → `2.11`, `1234.6` → `1235`, `0.000123456` → `0.000123`),
/// trailing zeros dropped; magnitudes below 10⁻⁴ or at least 10¹⁵ in scientific notation
/// (`1.23e-7`). Not-a-number and infinities print as Rust writes them.
pub fn three_significant(value: f64) -> String {
    if !value.is_finite() {
        return format!("{value}");
    }
    if value.fract() == 0.0 && value.abs() < 1e15 {
        return format!("{}", value as i64);
    }
    let magnitude = value.abs();
    if !(1e-4..1e15).contains(&magnitude) {
        let text = format!("{value:.2e}");
        // `1.20e-7` → `1.2e-7`.
        return match text.split_once('e') {
            Some((mantissa, exponent)) => format!("{}e{exponent}", trim_zeros(mantissa)),
            None => text,
        };
    }
    let digits_before_point = magnitude.log10().floor() as i32 + 1;
    let decimals = (3 - digits_before_point).max(0) as usize;
    let text = format!("{value:.decimals$}");
    if decimals == 0 {
        text
    } else {
        trim_zeros(&text).to_string()
    }
}

/// The unit a column's name ends in (`_px`, `_m`, `_ms`, `_ns`, `_bytes`, `_deg`, `_rad`), as
/// written after a number; `None` for a count or a plain ratio.
pub fn unit_of_column(column: &str) -> Option<&'static str> {
    const SUFFIXES: [(&str, &str); 7] = [
        ("_px", "px"),
        ("_m", "m"),
        ("_ms", "ms"),
        ("_ns", "ns"),
        ("_bytes", "bytes"),
        ("_deg", "°"),
        ("_rad", "rad"),
    ];
    SUFFIXES
        .iter()
        .find(|(suffix, _)| column.ends_with(suffix))
        .map(|(_, unit)| *unit)
}

/// `column value unit`, the value with [`three_significant`] digits: `tau_px 49.4 px`.
pub fn column_with_unit(column: &str, value: f64) -> String {
    match unit_of_column(column) {
        Some(unit) => format!("{column} {} {unit}", three_significant(value)),
        None => format!("{column} {}", three_significant(value)),
    }
}

fn trim_zeros(text: &str) -> &str {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_caption_figure_has_three_significant_digits() {
        assert_eq!(three_significant(49.350746413054104), "49.4");
        assert_eq!(three_significant(2.1112903567211143), "2.11");
        assert_eq!(three_significant(0.000123456), "0.000123");
        assert_eq!(three_significant(-0.5), "-0.5");
        assert_eq!(three_significant(1234.6), "1235");
        assert_eq!(three_significant(999.96), "1000");
        assert_eq!(three_significant(1.2e-7), "1.2e-7");
    }

    #[test]
    fn counts_are_printed_whole() {
        assert_eq!(three_significant(123456.0), "123456");
        assert_eq!(three_significant(-3.0), "-3");
        assert_eq!(three_significant(0.0), "0");
    }

    #[test]
    fn a_column_named_with_a_unit_is_printed_with_it() {
        assert_eq!(
            column_with_unit("tau_px", 49.350746413054104),
            "tau_px 49.4 px"
        );
        assert_eq!(
            column_with_unit("distance_multiplier", 2.1112903567211143),
            "distance_multiplier 2.11"
        );
        assert_eq!(
            column_with_unit("skirt_depth_max_m", 12.0),
            "skirt_depth_max_m 12 m"
        );
        assert_eq!(
            column_with_unit("detail_synthesis_ms", 0.25),
            "detail_synthesis_ms 0.25 ms"
        );
        assert_eq!(column_with_unit("base_b", -3.0), "base_b -3");
    }
}
