//! The colour of a series or a point: a function of its algorithm, so that an algorithm looks the
//! same in every plot of a run and across runs, whatever else a plot shows
//! (`docs/output-formats.md`, "plots/").
//!
//! Each of the ten algorithms has one hue of its own, at least 25° from every other on the colour
//! wheel (a test checks it); no algorithm is black or grey (grey draws the markers and the
//! grid, black the Pareto front). Entries of one algorithm are told apart by their *variant*,
//! their place among the run's entries of that algorithm (the caller counts it over the whole run,
//! so that an entry keeps it in a plot that leaves others out): the variant picks a lightness step
//! of the algorithm's hue (base, darker, lighter, darkest: mixed with black or white, which keeps
//! the hue), and, from the fifth entry of an algorithm on, a dash pattern for lines (solid, dashed,
//! dotted); scatter points add a marker shape per variant. Twelve entries of one algorithm (the
//! largest such run, `wu-table1`, has eleven) thus all look different. Lightness rather than
//! dashes comes first because per-frame lines zigzag from frame to frame, which breaks a dash
//! pattern up, and because a shade stays visible in a legend swatch and on a scatter point alike.

use plotters::style::RGBColor;

/// Each algorithm (as the experiment file names it) and its colour.
const ALGORITHM_COLOURS: [(&str, RGBColor); 10] = [
    ("lindstrom", RGBColor(0xd6, 0x27, 0x28)),        // red, 0°
    ("roam", RGBColor(0xf0, 0x7c, 0x0a)),             // orange, 30°
    ("roam-rebuild", RGBColor(0x9e, 0x99, 0x1a)),     // olive, 58°
    ("vanek", RGBColor(0x57, 0x9e, 0x1a)),            // yellow-green, 92°
    ("geomipmap", RGBColor(0x1e, 0xa0, 0x3c)),        // green, 134°
    ("rottger", RGBColor(0x15, 0x9e, 0x8c)),          // teal, 173°
    ("wu", RGBColor(0x1f, 0x77, 0xb4)),               // blue, 205°
    ("stitching-strips", RGBColor(0x3d, 0x3d, 0xc8)), // indigo, 240°
    ("reference", RGBColor(0x8a, 0x3f, 0xc4)),        // purple, 274°
    ("chunked", RGBColor(0xc8, 0x32, 0x9a)),          // magenta, 320°
];

/// The colour of a series of no known algorithm (only tests draw such).
const UNKNOWN_ALGORITHM_COLOUR: RGBColor = RGBColor(0x55, 0x55, 0x55);

/// Lightness steps, in variant order: the fraction of black (negative) or white (positive) mixed
/// into the algorithm's colour.
const SHADE_STEPS: [f64; 4] = [0.0, -0.4, 0.45, -0.65];

/// A line's dash pattern.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Dash {
    Solid,
    /// Drawn for `on` pixels, then left out for `off`, along the line.
    Pattern {
        on: f64,
        off: f64,
    },
}

/// Dash patterns, in variant order, each used for [`SHADE_STEPS`]`.len()` variants.
const DASHES: [Dash; 3] = [
    Dash::Solid,
    Dash::Pattern { on: 10.0, off: 6.0 },
    Dash::Pattern { on: 3.0, off: 4.0 },
];

/// How a series or point of `algorithm`'s `variant`-th entry of a run is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Stroke {
    pub(super) color: RGBColor,
    pub(super) dash: Dash,
}

/// The base colour of `algorithm`: its legend colour in a scatter chart.
pub(super) fn algorithm_colour(algorithm: &str) -> RGBColor {
    ALGORITHM_COLOURS
        .iter()
        .find(|(name, _)| *name == algorithm)
        .map_or(UNKNOWN_ALGORITHM_COLOUR, |(_, colour)| *colour)
}

/// The stroke of the `variant`-th entry (0 for the first) of `algorithm` in a run.
pub(super) fn stroke(algorithm: &str, variant: usize) -> Stroke {
    let RGBColor(r, g, b) = algorithm_colour(algorithm);
    let step = SHADE_STEPS[variant % SHADE_STEPS.len()];
    let mix = |channel: u8| -> u8 {
        let channel = f64::from(channel);
        let mixed = if step < 0.0 {
            channel * (1.0 + step)
        } else {
            channel + (255.0 - channel) * step
        };
        mixed.round().clamp(0.0, 255.0) as u8
    };
    Stroke {
        color: RGBColor(mix(r), mix(g), mix(b)),
        dash: DASHES[(variant / SHADE_STEPS.len()) % DASHES.len()],
    }
}

/// Each entry's variant: how many entries of the same algorithm come before it. The callers
/// count over all the entries of a run, so that an entry's look does not depend on the plot.
pub fn variants_in_order<S: AsRef<str>>(algorithms: &[S]) -> Vec<usize> {
    algorithms
        .iter()
        .enumerate()
        .map(|(k, algorithm)| {
            algorithms[..k]
                .iter()
                .filter(|earlier| earlier.as_ref() == algorithm.as_ref())
                .count()
        })
        .collect()
}

/// The parts of the polyline through `pixels` that a dash pattern draws, each a polyline of its
/// own; the pattern runs on across the polyline's corners. `Solid` gives the polyline itself.
pub(super) fn dash_pieces(pixels: &[(i32, i32)], dash: Dash) -> Vec<Vec<(i32, i32)>> {
    let Dash::Pattern { on, off } = dash else {
        return vec![pixels.to_vec()];
    };
    let round = |(x, y): (f64, f64)| (x.round() as i32, y.round() as i32);
    let mut pieces: Vec<Vec<(i32, i32)>> = Vec::new();
    let mut current: Vec<(i32, i32)> = Vec::new();
    // Where in the pattern the walk is: drawing (`drawing`) with `left` pixels to go.
    let (mut drawing, mut left) = (true, on);
    if let Some(&first) = pixels.first() {
        current.push(first);
    }
    for pair in pixels.windows(2) {
        let (a, b) = ((f64::from(pair[0].0), f64::from(pair[0].1)), pair[1]);
        let b = (f64::from(b.0), f64::from(b.1));
        let length = (b.0 - a.0).hypot(b.1 - a.1);
        let mut done = 0.0;
        while length - done > left {
            done += left;
            let t = done / length;
            let point = round((a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t));
            if drawing {
                current.push(point);
                pieces.push(std::mem::take(&mut current));
            } else {
                current.push(point);
            }
            drawing = !drawing;
            left = if drawing { on } else { off };
        }
        left -= length - done;
        if drawing {
            current.push(round(b));
        } else {
            current.clear();
        }
    }
    if drawing && current.len() > 1 {
        pieces.push(current);
    }
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edge::experiment::KNOWN_ALGORITHMS;

    /// The smallest angle between two algorithms' hues, in degrees.
    const MIN_HUE_DISTANCE_DEGREES: f64 = 25.0;

    /// The hue of a colour in degrees (HSL/HSV hue), `None` for a grey.
    fn hue_degrees(RGBColor(r, g, b): RGBColor) -> Option<f64> {
        let (r, g, b) = (f64::from(r), f64::from(g), f64::from(b));
        let (max, min) = (r.max(g).max(b), r.min(g).min(b));
        let chroma = max - min;
        if chroma == 0.0 {
            return None;
        }
        let sector = if max == r {
            ((g - b) / chroma).rem_euclid(6.0)
        } else if max == g {
            (b - r) / chroma + 2.0
        } else {
            (r - g) / chroma + 4.0
        };
        Some(sector * 60.0)
    }

    fn hue_distance(a: f64, b: f64) -> f64 {
        let d = (a - b).rem_euclid(360.0);
        d.min(360.0 - d)
    }

    /// The colour each algorithm's entries get in a plot of the entries `algorithms`, as the
    /// callers compute it.
    fn colours_in_plot(algorithms: &[&str]) -> Vec<(String, RGBColor)> {
        algorithms
            .iter()
            .zip(variants_in_order(algorithms))
            .map(|(name, variant)| (name.to_string(), stroke(name, variant).color))
            .collect()
    }

    #[test]
    fn every_algorithm_has_a_hue_of_its_own() {
        for name in KNOWN_ALGORITHMS {
            assert!(
                ALGORITHM_COLOURS.iter().any(|(known, _)| known == name),
                "{name} has no colour"
            );
        }
        for (k, (name, colour)) in ALGORITHM_COLOURS.iter().enumerate() {
            let hue = hue_degrees(*colour).expect("no algorithm is grey");
            for (other_name, other) in &ALGORITHM_COLOURS[k + 1..] {
                let distance = hue_distance(hue, hue_degrees(*other).unwrap());
                assert!(
                    distance >= MIN_HUE_DISTANCE_DEGREES,
                    "{name} and {other_name} are {distance:.1}° apart"
                );
            }
        }
    }

    #[test]
    fn an_algorithms_colour_does_not_depend_on_the_other_series_of_a_plot() {
        // The held-out Alpine run's two plots: the Pareto plot has every entry, the error plot
        // fewer, in another order.
        let pareto = colours_in_plot(&[
            "reference",
            "wu",
            "lindstrom",
            "roam",
            "geomipmap",
            "chunked",
        ]);
        let error = colours_in_plot(&["chunked", "lindstrom", "geomipmap", "wu"]);
        for (name, colour) in &error {
            let in_pareto = pareto.iter().find(|(other, _)| other == name);
            assert_eq!(in_pareto.map(|(_, c)| c), Some(colour), "{name}");
            assert_eq!(*colour, algorithm_colour(name), "{name}");
        }
    }

    #[test]
    fn entries_of_one_algorithm_differ_in_shade_or_dash_and_keep_its_hue() {
        let base = hue_degrees(algorithm_colour("wu")).unwrap();
        let strokes: Vec<Stroke> = (0..12).map(|variant| stroke("wu", variant)).collect();
        for (k, a) in strokes.iter().enumerate() {
            let hue = hue_degrees(a.color).unwrap();
            assert!(hue_distance(hue, base) < 3.0, "variant {k}: hue {hue}");
            for b in &strokes[k + 1..] {
                assert_ne!(a, b, "variant {k} looks like a later one");
            }
        }
    }

    #[test]
    fn variants_count_the_earlier_entries_of_the_same_algorithm() {
        assert_eq!(
            variants_in_order(&["wu", "roam", "wu", "wu", "roam"]),
            [0, 0, 1, 2, 1]
        );
    }

    #[test]
    fn a_dash_pattern_runs_on_across_corners() {
        let pieces = dash_pieces(
            &[(0, 0), (8, 0), (8, 20)],
            Dash::Pattern { on: 10.0, off: 6.0 },
        );
        // 0..10 along the path (around the corner), 16..26, and 26..28 is off.
        assert_eq!(
            pieces,
            [vec![(0, 0), (8, 0), (8, 2)], vec![(8, 8), (8, 18)]]
        );
        assert_eq!(
            dash_pieces(&[(0, 0), (5, 5)], Dash::Solid),
            [vec![(0, 0), (5, 5)]]
        );
    }
}
