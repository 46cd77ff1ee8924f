//! The ESRI ASCII grid reader (`.asc`): a header of `key value` lines, then `nrows × ncols`
//! numbers, north row first (the options it takes: `docs/experiment-format.md`, "Terrain"). The
//! rows are turned over so that grid row 0 is the south edge, as every reader's grid is. It does
//! not reproject: a `.prj` only says whether the cell size is in degrees (below).
//!
//! Header keys are case-insensitive and may come in any order: `ncols`, `nrows`, `xllcorner` or
//! `xllcenter`, `yllcorner` or `yllcenter`, `cellsize` (or `dx` and `dy`), and optionally
//! `NODATA_value`.
//!
//! **Units.** The format does not say what unit the cell size is in. A `.prj` file beside the
//! grid (read by `read_terrain`; the fuzz targets pass none) decides: when it declares a
//! geographic coordinate system (WKT `GEOGCS` with no `PROJCS`, or the old ESRI `Projection
//! GEOGRAPHIC`), the cell size is in degrees and is converted to metres at the latitude of the
//! grid's centre, as SRTM tiles are, and the conversion is reported. Otherwise the cell size is
//! taken to be metres (a projected `.prj` is believed; its linear unit is not read) — except,
//! unless a `.prj` says projected, where it may be degrees: a cell under 1 with the corner and
//! the far edges inside longitude and latitude ranges (1′ ETOPO grids, 0.1° grids, SRTM's 3″). Such a grid gets no spacing and a note
//! that says why, so that the run asks for `spacing_m` (or a `.prj`) instead of silently flying
//! over a terrain a hundred thousand times too small.
//!
//! Values may be separated by any whitespace. When the file has exactly one line per row, each
//! line must hold `ncols` values and a short row is named as such; otherwise (rows wrapped over
//! several lines) the values are read as one stream and only their total is checked.

use super::{
    FileRowOrder, METRES_PER_DEGREE_LATITUDE, ReadOptions, SampleCollector, StoredPrecision,
    TerrainReadError, describe_position,
};
use crate::sim::terrain::{SampleGrid, Spacing};
use std::path::Path;

/// Reads an ESRI ASCII grid; the spacing is the cell size in metres, or converted from degrees
/// when the `.prj` text says the grid is geographic (see the module documentation), with a note
/// saying how it was read or why there is none.
pub(super) fn read(
    path: &Path,
    bytes: &[u8],
    options: &ReadOptions,
    prj: Option<&str>,
) -> Result<(SampleGrid, Option<Spacing>, Option<String>), TerrainReadError> {
    let lines: Vec<TextLine<'_>> = bytes
        .split(|&byte| byte == b'\n')
        .enumerate()
        .map(|(index, text)| TextLine {
            number: index + 1,
            text,
            n_tokens: tokens_of(text).count(),
        })
        .filter(|line| line.n_tokens > 0)
        .collect();
    let (header, n_header_lines) = parse_header(path, &lines)?;
    let data_lines = &lines[n_header_lines..];
    let (columns, rows) = (header.columns, header.rows);

    // With one line per row, a row of the wrong length is named before the total is checked.
    let one_line_per_row = data_lines.len() == rows;
    if one_line_per_row {
        for (file_row, line) in data_lines.iter().enumerate() {
            if line.n_tokens != columns {
                return Err(TerrainReadError::new(
                    path,
                    format!(
                        "row {} of {rows} (line {}) has {} values, expected {columns} (ncols)",
                        file_row + 1,
                        line.number,
                        line.n_tokens
                    ),
                ));
            }
        }
    }
    // Every value takes at least one byte, so a header declaring more values than the file has
    // bytes is refused before allocating.
    let n_values_found: usize = data_lines.iter().map(|line| line.n_tokens).sum();
    let n_values_expected = columns.checked_mul(rows).filter(|&n| n <= bytes.len());
    let Some(n_values_expected) = n_values_expected.filter(|&n| n <= n_values_found) else {
        return Err(TerrainReadError::new(
            path,
            format!(
                "the file ends after {n_values_found} of the {} values the header declares \
                 (nrows {rows} × ncols {columns})",
                describe_product(columns, rows)
            ),
        ));
    };

    let mut collector = SampleCollector::new(
        path,
        columns,
        rows,
        FileRowOrder::NorthFirst,
        StoredPrecision::Exact,
        header.nodata,
        options,
    )?;
    let tokens = data_lines
        .iter()
        .flat_map(|line| tokens_of(line.text).map(move |token| (line.number, token)));
    for (value_index, (line_number, token)) in tokens.enumerate() {
        if value_index >= n_values_expected {
            return Err(TerrainReadError::new(
                path,
                format!(
                    "line {line_number} holds more than the {n_values_expected} values the \
                     header declares (nrows {rows} × ncols {columns})"
                ),
            ));
        }
        let value = parse_number(token).ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!(
                    "{} (line {line_number}): expected a number, found '{}'",
                    describe_position(
                        value_index / columns,
                        rows,
                        value_index % columns,
                        columns,
                        FileRowOrder::NorthFirst
                    ),
                    show_token(token)
                ),
            )
        })?;
        collector.push(value)?;
    }
    let grid = collector.finish()?;
    let (spacing, note) = units(path, &header, prj)?;
    Ok((grid, spacing, note))
}

/// Whether a `.prj` text declares a projected coordinate system (WKT1 `PROJCS`, WKT2
/// `PROJCRS`, or the old ESRI `Projection` line naming anything but GEOGRAPHIC).
pub(super) fn prj_is_projected(prj: &str) -> bool {
    let upper = prj.to_ascii_uppercase();
    let esri_projected = upper.lines().any(|line| {
        let mut words = line.split_whitespace();
        words.next() == Some("PROJECTION") && words.next().is_some_and(|w| w != "GEOGRAPHIC")
    });
    upper.contains("PROJCS") || upper.contains("PROJCRS") || esri_projected
}

/// Whether a `.prj` text declares a geographic (longitude/latitude) coordinate system: WKT1
/// `GEOGCS` or WKT2 `GEOGCRS`/`GEODCRS` with no projection, or the old ESRI `Projection
/// GEOGRAPHIC`.
pub(super) fn prj_is_geographic(prj: &str) -> bool {
    let upper = prj.to_ascii_uppercase();
    let wkt_geographic = ["GEOGCS", "GEOGCRS", "GEODCRS"]
        .iter()
        .any(|key| upper.contains(key))
        && !prj_is_projected(prj);
    let esri_geographic = upper.lines().any(|line| {
        let mut words = line.split_whitespace();
        words.next() == Some("PROJECTION") && words.next() == Some("GEOGRAPHIC")
    });
    wkt_geographic || esri_geographic
}

/// The spacing in metres and a note: degrees converted when the `.prj` says geographic, metres
/// otherwise, none when the numbers look like degrees and nothing says so.
fn units(
    path: &Path,
    header: &AsciiGridHeader,
    prj: Option<&str>,
) -> Result<(Option<Spacing>, Option<String>), TerrainReadError> {
    let Spacing { dx, dy } = header.spacing;
    // The south-west corner of the south-west cell.
    let (west, south) = header.lower_left_corner;
    let (east, north) = (
        west + dx * header.columns as f64,
        south + dy * header.rows as f64,
    );
    if prj.is_some_and(prj_is_geographic) {
        let centre_latitude = (south + north) / 2.0;
        if !(-90.0..=90.0).contains(&south) || !(-90.0..=90.0).contains(&north) {
            return Err(TerrainReadError::new(
                path,
                format!(
                    "the .prj says the grid is geographic, but its rows span latitudes \
                     {south}° to {north}° (yll… and nrows × cellsize); expected −90° to 90°"
                ),
            ));
        }
        let spacing = Spacing {
            dx: dx * METRES_PER_DEGREE_LATITUDE * centre_latitude.to_radians().cos(),
            dy: dy * METRES_PER_DEGREE_LATITUDE,
        };
        let note = format!(
            "cell size {dx}° × {dy}° (geographic, from the .prj) converted at the grid's centre \
             latitude {centre_latitude:.4}°: {:.3} m × {:.3} m",
            spacing.dx, spacing.dy
        );
        return Ok((Some(spacing), Some(note)));
    }
    let looks_like_degrees = !prj.is_some_and(prj_is_projected)
        && dx < 1.0
        && dy < 1.0
        && (-180.0..=360.0).contains(&west)
        && (-180.0..=360.0).contains(&east)
        && (-90.0..=90.0).contains(&south)
        && (-90.0..=90.0).contains(&north);
    if looks_like_degrees {
        let note = format!(
            "its cell size {dx} may be degrees, not metres (under 1 with the whole grid inside \
             longitude and latitude ranges), and no .prj beside it says which; put the grid's \
             .prj beside it (a geographic one converts the cell size at the grid's latitude, a \
             projected one keeps metres) or give spacing_m in metres"
        );
        // (A projected `.prj` is taken at its word: metres, whatever the numbers.)
        // A metre grid of sub-metre cells near the origin with no `.prj` lands here too: it is
        // asked for its spacing rather than guessed.
        return Ok((None, Some(note)));
    }
    Ok((Some(header.spacing), None))
}

/// A line of the file that holds at least one token. Lines keep their text rather than their
/// tokens, so reading costs a few words per line, not per value.
struct TextLine<'a> {
    /// Counted from 1.
    number: usize,
    text: &'a [u8],
    n_tokens: usize,
}

/// The whitespace-separated tokens of a line (`\r` counts as whitespace).
fn tokens_of(text: &[u8]) -> impl Iterator<Item = &[u8]> {
    text.split(|byte| byte.is_ascii_whitespace())
        .filter(|token| !token.is_empty())
}

/// What the header declares.
#[derive(Clone, Copy, Debug, PartialEq)]
struct AsciiGridHeader {
    columns: usize,
    rows: usize,
    /// The cell size, in the file's unit (metres or degrees).
    spacing: Spacing,
    /// x and y of the south-west corner of the south-west cell (from `…corner`, or `…center`
    /// less half a cell), in the file's unit.
    lower_left_corner: (f64, f64),
    nodata: Option<f64>,
}

/// The header keys, lower-case.
const HEADER_KEYS: [&str; 10] = [
    "ncols",
    "nrows",
    "xllcorner",
    "xllcenter",
    "yllcorner",
    "yllcenter",
    "cellsize",
    "dx",
    "dy",
    "nodata_value",
];

/// Reads the header lines (those whose first token is a header key) and returns the header and
/// how many lines it took.
fn parse_header(
    path: &Path,
    lines: &[TextLine<'_>],
) -> Result<(AsciiGridHeader, usize), TerrainReadError> {
    let mut values: [Option<(&[u8], usize)>; HEADER_KEYS.len()] = [None; HEADER_KEYS.len()];
    let mut n_header_lines = 0;
    for line in lines {
        let mut tokens = tokens_of(line.text);
        let Some(key_index) = tokens.next().and_then(|token| {
            HEADER_KEYS
                .iter()
                .position(|key| token.eq_ignore_ascii_case(key.as_bytes()))
        }) else {
            break;
        };
        let key = HEADER_KEYS[key_index];
        let (Some(value), None) = (tokens.next(), tokens.next()) else {
            return Err(TerrainReadError::new(
                path,
                format!(
                    "line {}: the header line '{key}' has {} values; expected exactly one",
                    line.number,
                    line.n_tokens - 1
                ),
            ));
        };
        if values[key_index].is_some() {
            return Err(TerrainReadError::new(
                path,
                format!("line {}: the header key '{key}' appears twice", line.number),
            ));
        }
        values[key_index] = Some((value, line.number));
        n_header_lines += 1;
    }
    let value_of = |key: &str| {
        HEADER_KEYS
            .iter()
            .position(|candidate| *candidate == key)
            .and_then(|index| values[index])
    };
    let first_non_header = lines.get(n_header_lines);
    let missing = |keys: &str| {
        let found = match first_non_header {
            Some(line) => format!(
                "found '{}' on line {}",
                tokens_of(line.text)
                    .next()
                    .map_or(String::new(), show_token),
                line.number
            ),
            None => "found the end of the file".to_string(),
        };
        TerrainReadError::new(
            path,
            format!("the header has no {keys}: expected {keys}, {found}"),
        )
    };

    let columns = required_count(
        path,
        "ncols",
        value_of("ncols").ok_or_else(|| missing("ncols"))?,
    )?;
    let rows = required_count(
        path,
        "nrows",
        value_of("nrows").ok_or_else(|| missing("nrows"))?,
    )?;
    // x then y: (value, given as a cell centre).
    let mut lower_left = [(0.0, false); 2];
    for (axis, (corner, centre)) in [("xllcorner", "xllcenter"), ("yllcorner", "yllcenter")]
        .into_iter()
        .enumerate()
    {
        match (value_of(corner), value_of(centre)) {
            (Some(_), Some((_, line_number))) => {
                return Err(TerrainReadError::new(
                    path,
                    format!(
                        "line {line_number}: the header gives both {corner} and {centre}; \
                         expected one of them"
                    ),
                ));
            }
            (Some(value), None) => {
                lower_left[axis] = (finite_number(path, corner, value)?, false);
            }
            (None, Some(value)) => {
                lower_left[axis] = (finite_number(path, centre, value)?, true);
            }
            (None, None) => return Err(missing(&format!("{corner} or {centre}"))),
        }
    }
    let spacing = match (value_of("cellsize"), value_of("dx"), value_of("dy")) {
        (Some(cell_size), None, None) => {
            let cell_size = positive_number(path, "cellsize", cell_size)?;
            Spacing {
                dx: cell_size,
                dy: cell_size,
            }
        }
        (None, Some(dx), Some(dy)) => Spacing {
            dx: positive_number(path, "dx", dx)?,
            dy: positive_number(path, "dy", dy)?,
        },
        (None, None, None) => return Err(missing("cellsize (or dx and dy)")),
        _ => {
            return Err(TerrainReadError::new(
                path,
                "the header gives an incomplete or double cell size: expected either cellsize \
                 or both dx and dy",
            ));
        }
    };
    let nodata = match value_of("nodata_value") {
        Some((text, line_number)) => Some(parse_number(text).ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!(
                    "line {line_number}: NODATA_value is '{}'; expected a number",
                    show_token(text)
                ),
            )
        })?),
        None => None,
    };
    let corner = |(value, is_centre): (f64, bool), cell: f64| {
        if is_centre { value - cell / 2.0 } else { value }
    };
    let header = AsciiGridHeader {
        columns,
        rows,
        spacing,
        lower_left_corner: (
            corner(lower_left[0], spacing.dx),
            corner(lower_left[1], spacing.dy),
        ),
        nodata,
    };
    Ok((header, n_header_lines))
}

/// A whole, positive count (ncols, nrows).
fn required_count(
    path: &Path,
    key: &str,
    (text, line_number): (&[u8], usize),
) -> Result<usize, TerrainReadError> {
    std::str::from_utf8(text)
        .ok()
        .and_then(|text| text.parse::<usize>().ok())
        .filter(|&count| count > 0)
        .ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!(
                    "line {line_number}: {key} is '{}'; expected a positive whole number",
                    show_token(text)
                ),
            )
        })
}

fn finite_number(
    path: &Path,
    key: &str,
    (text, line_number): (&[u8], usize),
) -> Result<f64, TerrainReadError> {
    parse_number(text)
        .filter(|value| value.is_finite())
        .ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!(
                    "line {line_number}: {key} is '{}'; expected a finite number",
                    show_token(text)
                ),
            )
        })
}

fn positive_number(
    path: &Path,
    key: &str,
    (text, line_number): (&[u8], usize),
) -> Result<f64, TerrainReadError> {
    parse_number(text)
        .filter(|value| value.is_finite() && *value > 0.0)
        .ok_or_else(|| {
            TerrainReadError::new(
                path,
                format!(
                    "line {line_number}: {key} is '{}'; expected a positive number of metres",
                    show_token(text)
                ),
            )
        })
}

/// A decimal number as Rust writes and reads it (`-12`, `3.5e2`, `nan`, `inf`).
fn parse_number(token: &[u8]) -> Option<f64> {
    std::str::from_utf8(token).ok()?.parse::<f64>().ok()
}

/// A token for an error message: at most 40 characters, invalid UTF-8 replaced.
fn show_token(token: &[u8]) -> String {
    let text = String::from_utf8_lossy(token);
    if text.chars().count() > 40 {
        let head: String = text.chars().take(40).collect();
        format!("{head}…")
    } else {
        text.into_owned()
    }
}

/// "25" or "more than this machine can count".
fn describe_product(columns: usize, rows: usize) -> String {
    columns.checked_mul(rows).map_or_else(
        || "more than this machine can count".to_string(),
        |n| n.to_string(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str =
        "ncols 4\nnrows 3\nxllcorner 100.0\nyllcorner 200.0\ncellsize 30\nNODATA_value -9999\n";

    fn read_asc(text: &str) -> Result<(SampleGrid, Option<Spacing>), TerrainReadError> {
        read_asc_beside(text, None).map(|(grid, spacing, _)| (grid, spacing))
    }

    fn read_asc_beside(
        text: &str,
        prj: Option<&str>,
    ) -> Result<(SampleGrid, Option<Spacing>, Option<String>), TerrainReadError> {
        read(
            Path::new("grid.asc"),
            text.as_bytes(),
            &ReadOptions::AS_STORED,
            prj,
        )
    }

    /// A 3 × 3 grid of 3-arc-second cells whose south-west corner is at 8.5° E, 47° N.
    const DEGREES: &str = "ncols 3\nnrows 3\nxllcorner 8.5\nyllcorner 47.0\n\
                           cellsize 0.000833333333\n1 2 3\n4 5 6\n7 8 9\n";

    #[test]
    fn a_grid_in_degrees_with_a_geographic_prj_is_converted_at_its_latitude_and_says_so() {
        let prj = "GEOGCS[\"GCS_WGS_1984\",DATUM[\"D_WGS_1984\",SPHEROID[\"WGS_1984\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"Degree\",0.017453292519943295]]";
        let (_, spacing, note) = read_asc_beside(DEGREES, Some(prj)).unwrap();
        let spacing = spacing.expect("converted");
        let cell = 0.000833333333;
        let latitude = 47.0 + 1.5 * cell;
        assert!((spacing.dy - cell * METRES_PER_DEGREE_LATITUDE).abs() < 1e-9);
        assert!(
            (spacing.dx - cell * METRES_PER_DEGREE_LATITUDE * latitude.to_radians().cos()).abs()
                < 1e-9
        );
        assert!((spacing.dy - 92.6).abs() < 0.1, "{spacing:?}");
        let note = note.expect("the conversion is reported");
        assert!(note.contains("geographic, from the .prj"), "{note}");
        let old_style = "Projection    GEOGRAPHIC\nDatum         WGS84\nUnits         DD\n";
        assert_eq!(
            read_asc_beside(DEGREES, Some(old_style)).unwrap().1,
            Some(spacing)
        );
    }

    #[test]
    fn a_grid_that_looks_like_degrees_without_a_prj_gets_no_spacing_and_a_reason() {
        let (_, spacing, note) = read_asc_beside(DEGREES, None).unwrap();
        assert_eq!(spacing, None, "never 0.0008 m cells without a word");
        let note = note.expect("a reason");
        assert!(note.contains("may be degrees"), "{note}");
        assert!(note.contains("spacing_m"), "{note}");
        // A projected .prj keeps the numbers as metres… and a centimetre grid of metres is
        // still suspicious only without one.
        let projected = "PROJCS[\"UTM 32N\",GEOGCS[\"WGS 84\"],UNIT[\"metre\",1]]";
        let (_, spacing, _) = read_asc_beside(DEGREES, Some(projected)).unwrap();
        assert_eq!(
            spacing,
            Some(Spacing {
                dx: 0.000833333333,
                dy: 0.000833333333
            })
        );
    }

    #[test]
    fn a_coarse_degree_grid_or_a_wkt2_prj_is_never_read_as_metres() {
        // 1′ cells (ETOPO1) near 10° E, 45° N: 0.0167 "m" cells without a word, before.
        let arc_minute = "ncols 3\nnrows 3\nxllcorner 10\nyllcorner 45\ncellsize 0.0166666667\n\
                          1 2 3\n4 5 6\n7 8 9\n";
        let (_, spacing, note) = read_asc_beside(arc_minute, None).unwrap();
        assert_eq!(spacing, None, "{note:?}");
        let wkt2 = "GEOGCRS[\"WGS 84\",DATUM[\"World Geodetic System 1984\"],CS[ellipsoidal,2]]";
        let (_, spacing, _) = read_asc_beside(arc_minute, Some(wkt2)).unwrap();
        let spacing = spacing.expect("converted");
        assert!((spacing.dy - 1852.0).abs() < 1.0, "{spacing:?}");
        // An unrecognised .prj says nothing: the numbers decide, and they may be degrees.
        let (_, spacing, _) = read_asc_beside(arc_minute, Some("")).unwrap();
        assert_eq!(spacing, None);
    }

    #[test]
    fn a_metre_grid_just_above_the_threshold_stays_in_metres() {
        let text = "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n4 5 6\n7 8 9\n";
        let (_, spacing, note) = read_asc_beside(text, None).unwrap();
        assert_eq!(spacing, Some(Spacing { dx: 1.0, dy: 1.0 }));
        assert_eq!(note, None);
    }

    #[test]
    fn a_metre_grid_near_the_origin_stays_in_metres() {
        let text = "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 30\n1 2 3\n4 5 6\n7 8 9\n";
        let (_, spacing, note) = read_asc_beside(text, None).unwrap();
        assert_eq!(spacing, Some(Spacing { dx: 30.0, dy: 30.0 }));
        assert_eq!(note, None);
    }

    fn error_of(text: &str) -> String {
        match read_asc(text) {
            Ok(_) => panic!("expected an error for {text:?}"),
            Err(error) => error.to_string(),
        }
    }

    #[test]
    fn a_well_formed_grid_is_flipped_with_voids_and_spacing() {
        let text = format!("{HEADER}1 2 3 4\n5 -9999 7 8\n9 10 11 12.5\n");
        let (grid, spacing) = read_asc(&text).unwrap();
        assert_eq!((grid.width(), grid.height()), (4, 3));
        assert_eq!(grid.height_at(0, 2), 1.0);
        assert_eq!(grid.height_at(3, 0), 12.5);
        assert_eq!(grid.void_indices(), &[5]);
        assert_eq!(spacing, Some(Spacing { dx: 30.0, dy: 30.0 }));
    }

    #[test]
    fn keys_are_case_insensitive_in_any_order_with_crlf_and_wrapped_rows() {
        let text = "NROWS 3\r\nNCOLS 3\r\nYLLCENTER 0\r\nXLLCENTER 0\r\nDX 2\r\nDY 3.5\r\n\
                    1 2 3 4\r\n5 6 7 8 9\r\n";
        let (grid, spacing) = read_asc(text).unwrap();
        assert_eq!(grid.height_at(0, 0), 7.0);
        assert_eq!(grid.void_indices(), &[] as &[usize]);
        assert_eq!(spacing, Some(Spacing { dx: 2.0, dy: 3.5 }));
    }

    #[test]
    fn a_missing_header_key_is_named() {
        let error = error_of("nrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n");
        assert!(error.contains("grid.asc"), "{error}");
        assert!(
            error.contains("expected ncols, found '1' on line 5"),
            "{error}"
        );
        let error = error_of("foo 3\n");
        assert!(
            error.contains("expected ncols, found 'foo' on line 1"),
            "{error}"
        );
        let error = error_of("ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\n");
        assert!(
            error.contains("expected cellsize (or dx and dy)"),
            "{error}"
        );
    }

    #[test]
    fn bad_header_values_are_named() {
        let error = error_of("ncols 3.5\nnrows 3\n");
        assert!(error.contains("line 1: ncols is '3.5'; expected a positive whole number"));
        let error = error_of("ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize -1\n");
        assert!(error.contains("cellsize is '-1'"), "{error}");
        let error = error_of("ncols 3 4\n");
        assert!(error.contains("'ncols' has 2 values"), "{error}");
        let error = error_of("ncols 3\nncols 3\n");
        assert!(error.contains("'ncols' appears twice"), "{error}");
        let error = error_of("ncols 3\nnrows 3\nxllcorner 0\nxllcenter 0\n");
        assert!(error.contains("both xllcorner and xllcenter"), "{error}");
    }

    #[test]
    fn a_short_row_is_named() {
        let text = format!("{HEADER}1 2 3 4\n5 6 7\n9 10 11 12 13\n");
        let error = error_of(&text);
        assert!(
            error.contains("row 2 of 3 (line 8) has 3 values, expected 4"),
            "{error}"
        );
    }

    #[test]
    fn a_short_file_says_how_many_values_it_has() {
        let text = format!("{HEADER}1 2 3 4\n5 6 7 8\n");
        let error = error_of(&text);
        assert!(
            error.contains("the file ends after 8 of the 12 values"),
            "{error}"
        );
    }

    #[test]
    fn extra_values_are_refused() {
        let text = format!("{HEADER}1 2 3 4\n5 6 7 8\n9 10 11 12\n13\n");
        let error = error_of(&text);
        assert!(
            error.contains("line 10 holds more than the 12 values"),
            "{error}"
        );
    }

    #[test]
    fn a_non_number_is_named_by_row_and_column() {
        let text = format!("{HEADER}1 2 3 4\n5 6 x7 8\n9 10 11 12\n");
        let error = error_of(&text);
        assert!(
            error.contains("row 2 of 3 (counted from the north edge"),
            "{error}"
        );
        assert!(error.contains("column 3 of 4 (line 8)"), "{error}");
        assert!(error.contains("expected a number, found 'x7'"), "{error}");
    }

    #[test]
    fn nan_is_an_error_unless_declared_nodata() {
        let text = format!("{HEADER}1 2 3 4\n5 nan 7 8\n9 10 11 12\n");
        let error = error_of(&text);
        assert!(
            error.contains("column 2 of 4: the stored value is NaN"),
            "{error}"
        );
        let text = text.replace("-9999", "NaN");
        let (grid, _) = read_asc(&text).unwrap();
        assert_eq!(grid.void_indices(), &[5]);
    }

    #[test]
    fn a_huge_declared_size_is_refused_before_allocating() {
        let text = "ncols 100000\nnrows 100000\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3\n";
        let error = error_of(text);
        assert!(
            error.contains("ends after 3 of the 10000000000 values"),
            "{error}"
        );
    }
}
