//! Tests of the charts: files written, drawings of degenerate data, decimation, tick labels.

use super::decimation::drawable_runs;
use super::palette::{algorithm_colour, stroke};
use super::ticks::{TickFormat, log_tick_label};
use super::*;

/// A series of the first `wu` entry.
fn series(label: &str, points: Vec<(f64, f64)>) -> Series {
    algorithm_series("wu", 0, label, points)
}

fn algorithm_series(
    algorithm: &str,
    variant: usize,
    label: &str,
    points: Vec<(f64, f64)>,
) -> Series {
    Series {
        label: label.to_string(),
        points,
        algorithm: algorithm.to_string(),
        variant,
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
        log_y: false,
        marked_x: &[],
        marked_x_label: "",
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
fn check_written_chart(png_path: &Path, svg_path: &Path, expected_texts: &[&str]) -> DecodedPng {
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
    let roam = algorithm_series(
        "roam",
        0,
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
    for colour in [algorithm_colour("roam"), algorithm_colour("wu")] {
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
        png.n_pixels_of(algorithm_colour("wu")) > 10,
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
        (
            "single_point",
            vec![series("one", vec![(3.0, 7.0)])],
            vec![],
        ),
        (
            "all_equal",
            vec![series("flat", vec![(2.0, 5.0); 50])],
            vec![marker("same", 5.0)],
        ),
        (
            "all_zero",
            vec![series("zero", (0..10).map(|f| (f as f64, 0.0)).collect())],
            vec![],
        ),
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
        (
            "only_non_finite",
            vec![series("nan", vec![(f64::NAN, f64::NAN); 3])],
            vec![],
        ),
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
            vec![series(
                "near",
                vec![(0.0, 1.0), (1.0, 1.0 + 1e-15), (2.0, 1.0)],
            )],
            vec![],
        ),
        (
            "long_and_many_labels",
            (0..40)
                .map(|idx| {
                    series(
                        &format!(
                            "series {idx} with a very long label that cannot fit into the legend"
                        ),
                        vec![(0.0, idx as f64), (1.0, idx as f64 + 1.0)],
                    )
                })
                .collect(),
            vec![
                marker(
                    "a marker label far too long to fit on the right of the plot",
                    3.0,
                ),
                marker("close", 3.1),
            ],
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
    assert_eq!(log_tick_label(1000.0, false), "1000");
    assert_eq!(log_tick_label(0.01, false), "0.01");
    assert_eq!(log_tick_label(1e9, false), "1e9");
    // Several decades: 1, 2 and 5 only; a short axis: every multiple, so 6000 can be read.
    assert_eq!(log_tick_label(6000.0, false), "");
    assert_eq!(log_tick_label(6000.0, true), "6000");
    assert_eq!(log_tick_label(6500.0, true), "");
}

fn scatter_point(label: &str, x: f64, y: f64) -> ScatterPoint {
    ScatterPoint {
        label: label.to_string(),
        x,
        y,
        group: String::new(),
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

/// Writes `chart` under `stem` and returns the decoded PNG and the SVG text.
fn written_line_chart(dir: &Path, stem: &str, chart: &LineChart) -> (DecodedPng, String) {
    write_line_chart(dir, stem, chart).unwrap();
    let png = DecodedPng::read(&dir.join(format!("{stem}.png")));
    let svg = std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap();
    (png, svg)
}

/// The texts of an SVG's `<text>` elements.
fn svg_texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let start = t.find('>')? + 1;
            let end = t.find("</text>")?;
            Some(t[start..end].trim().to_string())
        })
        .collect()
}

#[test]
fn a_log_y_axis_shows_series_orders_of_magnitude_apart_and_skips_non_positive_values() {
    let dir = tempfile::tempdir().unwrap();
    let big = series(
        "big",
        (0..100).map(|f| (f as f64, 50_000.0 + f as f64)).collect(),
    );
    let small = algorithm_series(
        "roam",
        0,
        "small",
        (0..100)
            .map(|f| (f as f64, 20.0 + (f % 7) as f64))
            .collect(),
    );
    let with_zero = series(
        "zero at 5",
        (0..10)
            .map(|f| (f as f64, if f == 5 { 0.0 } else { 300.0 }))
            .collect(),
    );
    let chart = LineChart {
        title: "log",
        x_label: "frame",
        y_label: "triangles (log scale)",
        series: &[big, small, with_zero],
        markers: &[],
        log_y: true,
        marked_x: &[],
        marked_x_label: "",
    };
    let (png, svg) = written_line_chart(dir.path(), "log", &chart);
    let texts = svg_texts(&svg);
    // Decade ticks between the series are labelled: 100 and 1000 lie between 20 and 50 000.
    for tick in ["100", "1000", "10000"] {
        assert!(texts.iter().any(|t| t == tick), "no tick {tick}: {texts:?}");
    }
    // On a linear axis from 0 to 50 000 the small series would hug the bottom within a few
    // pixels; on the log axis its line is drawn well inside the plot.
    assert!(png.n_pixels_of(algorithm_colour("roam")) > 500);
}

#[test]
fn marked_frames_are_drawn_as_bands_and_counted_in_the_legend() {
    let dir = tempfile::tempdir().unwrap();
    let line = series("wu", (0..100).map(|f| (f as f64, 10.0)).collect());
    let chart = LineChart {
        title: "marked",
        x_label: "frame",
        y_label: "b",
        series: &[line],
        markers: &[],
        log_y: false,
        marked_x: &[20.0, 21.0, 60.0],
        marked_x_label: "frames breaking the speed bounds",
    };
    let (png, svg) = written_line_chart(dir.path(), "marked", &chart);
    assert!(
        svg.contains("frames breaking the speed bounds (3)"),
        "{svg}"
    );
    // Three bands the height of the plot, well over a hundred pixels each.
    assert!(
        png.n_pixels_of(MARKED_X_COLOR) > 3 * 300,
        "{}",
        png.n_pixels_of(MARKED_X_COLOR)
    );
}

#[test]
fn a_series_hidden_under_an_identical_one_says_so_in_the_legend() {
    let dir = tempfile::tempdir().unwrap();
    let points: Vec<(f64, f64)> = (0..50).map(|f| (f as f64, (f * f) as f64)).collect();
    let chart = LineChart {
        title: "same",
        x_label: "frame",
        y_label: "triangles",
        series: &[
            series("reference τ=2", points.clone()),
            series("wu τ=2", points),
        ],
        markers: &[],
        log_y: false,
        marked_x: &[],
        marked_x_label: "",
    };
    let (_, svg) = written_line_chart(dir.path(), "same", &chart);
    assert!(
        svg.contains("wu τ=2 (= reference τ=2, drawn over it)"),
        "{svg}"
    );
    // Within a pixel of each other everywhere: as hidden, said with ≈.
    let base: Vec<(f64, f64)> = (0..50).map(|f| (f as f64, 1000.0 + f as f64)).collect();
    let near: Vec<(f64, f64)> = base.iter().map(|&(x, y)| (x, y + 0.05)).collect();
    let apart: Vec<(f64, f64)> = base.iter().map(|&(x, y)| (x, y + 20.0)).collect();
    let chart = LineChart {
        series: &[
            series("roam", base),
            series("roam-rebuild", near),
            series("other", apart),
        ],
        ..chart
    };
    let (_, svg) = written_line_chart(dir.path(), "near", &chart);
    assert!(
        svg.contains("roam-rebuild (≈ roam, drawn over it)"),
        "{svg}"
    );
    assert!(!svg.contains("other (≈"), "{svg}");
}

#[test]
fn a_long_legend_label_wraps_and_is_never_cut() {
    let dir = tempfile::tempdir().unwrap();
    let label =
        "wu budget 12000 conservative zone (min -40, max 54, mean 3.25; mean 33 m) final-word";
    let chart = LineChart {
        title: "long",
        x_label: "frame",
        y_label: "b",
        series: &[series(label, vec![(0.0, 1.0), (1.0, 2.0)])],
        markers: &[],
        log_y: false,
        marked_x: &[],
        marked_x_label: "",
    };
    let (_, svg) = written_line_chart(dir.path(), "long", &chart);
    let texts = svg_texts(&svg);
    assert!(!texts.iter().any(|t| t.contains('…')), "{texts:?}");
    assert!(texts.iter().any(|t| t.ends_with("final-word")), "{texts:?}");
    assert!(
        texts.iter().any(|t| t.starts_with("wu budget")),
        "{texts:?}"
    );
}

#[test]
fn a_grouped_scatter_colours_groups_shapes_variants_and_labels_only_the_front() {
    let dir = tempfile::tempdir().unwrap();
    let mut points = Vec::new();
    for (group, base) in [("wu", 10.0), ("roam", 30.0), ("lindstrom", 90.0)] {
        for variant in 0..4 {
            let tau = f64::from(1 << variant);
            points.push(ScatterPoint {
                label: format!("{group} τ={tau}px with a long label"),
                x: base * (5.0 - tau),
                y: tau * base / 10.0,
                group: group.to_string(),
            });
        }
    }
    // The front: wu's four points (fastest at every accuracy).
    let front = [3, 2, 1, 0];
    let chart = ScatterChart {
        title: "grouped",
        x_label: "µs",
        y_label: "px",
        points: &points,
        front: &front,
        log_x: true,
    };
    write_scatter_chart(dir.path(), "grouped", &chart).unwrap();
    let svg = std::fs::read_to_string(dir.path().join("grouped.svg")).unwrap();
    let texts = svg_texts(&svg);
    for group in ["wu", "roam", "lindstrom"] {
        assert!(
            texts.iter().any(|t| t == group),
            "no legend row {group}: {texts:?}"
        );
    }
    assert!(
        texts.iter().any(|t| t == "wu τ=1px with a long label"),
        "{texts:?}"
    );
    assert!(
        !texts.iter().any(|t| t.starts_with("roam τ=")),
        "points off the front are not labelled: {texts:?}"
    );
    let png = DecodedPng::read(&dir.path().join("grouped.png"));
    // Each algorithm's colour, and a later variant's shade of it.
    for colour in [
        algorithm_colour("wu"),
        algorithm_colour("roam"),
        algorithm_colour("lindstrom"),
        stroke("roam", 1).color,
    ] {
        assert!(png.n_pixels_of(colour) > 100, "{colour:?}");
    }
}

#[test]
fn entries_of_one_algorithm_past_the_fourth_are_drawn_dashed_in_its_colour() {
    let dir = tempfile::tempdir().unwrap();
    let lines: Vec<Series> = (0..6)
        .map(|variant| {
            let y = 10.0 * variant as f64;
            algorithm_series(
                "chunked",
                variant,
                &format!("chunked {variant}"),
                (0..200).map(|f| (f as f64, y)).collect(),
            )
        })
        .collect();
    let (png_path, svg_path) = write_line(dir.path(), "variants", &lines, &[]).unwrap();
    let png = check_written_chart(&png_path, &svg_path, &["chunked 0", "chunked 5"]);
    // The fifth entry has the first one's colour, dashed: fewer pixels, but a line's worth.
    let solid = png.n_pixels_of(stroke("chunked", 0).color);
    assert_eq!(stroke("chunked", 4).color, stroke("chunked", 0).color);
    assert!(solid > 1500, "{solid} pixels");
    for variant in 1..4 {
        let colour = stroke("chunked", variant).color;
        assert!(png.n_pixels_of(colour) > 1000, "variant {variant}");
    }
}
