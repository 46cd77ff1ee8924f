//! `roamsim info`: a terrain described as an experiment reads it, with the time and memory of its
//! preprocessing, and, with `--map FILE`, its map (a PNG or an SVG) to plan a flight over it.
//!
//! A terrain file is read through the experiment's own stages (`experiment::load_terrain_file`)
//! with the `terrain.file` keys given as options (`--height-scale`, `--spacing-m`, …), so what
//! `info` prints is what a run with those keys gets. An experiment file is loaded point by point
//! as a run loads it, and described with exactly its terrain; its map shows the first point's
//! terrain and flight. The command line (clap) is `main.rs`'s; this file takes plain values and
//! writes to the `Write` it is given.

use crate::edge::experiment::{self, TerrainReport};
use crate::edge::output::flight_map::{FlightOnMap, write_map_to};
use crate::edge::terrain_info::{describe_preprocessing, describe_terrain};
use crate::sim::terrain::Heightfield;
use serde_json::{Map, Value, json};
use std::io::Write;
use std::path::{Path, PathBuf};

/// What `roamsim info` was asked.
#[derive(Debug, Clone, Default)]
pub struct InfoRequest {
    /// An experiment (`.json`) or a terrain file.
    pub path: PathBuf,
    /// The `terrain.file` keys given. Only for a terrain file.
    pub file_keys: TerrainFileKeys,
    /// Where to draw the map (`.png` or `.svg`), if anywhere.
    pub map: Option<PathBuf>,
}

/// The `terrain.file` keys other than `path` (docs/experiment-format.md, "Terrain"), each
/// `None` or empty when not given.
#[derive(Debug, Clone, Default)]
pub struct TerrainFileKeys {
    /// `format: {"raw": …}`.
    pub raw: Option<RawKeys>,
    pub height_scale: Option<f64>,
    pub height_offset_m: Option<f64>,
    pub nodata: Option<f64>,
    /// One number for both axes, or dx and dy.
    pub spacing_m: Vec<f64>,
    /// `pad` (the default) or `crop`.
    pub fit: Option<&'static str>,
    /// Column and row.
    pub crop_origin: Vec<usize>,
    /// x, y and z.
    pub origin_m: Vec<f64>,
}

/// `format.raw`'s keys.
#[derive(Debug, Clone)]
pub struct RawKeys {
    pub columns: usize,
    pub rows: usize,
    /// As the format names it: `i16le`, `u16be`, `f32le`, …
    pub sample: &'static str,
    pub north_first: bool,
}

impl TerrainFileKeys {
    /// The `terrain.file` object for `path`, as an experiment would write it.
    pub fn object(&self, path: &Path) -> Result<Map<String, Value>, String> {
        let mut file = Map::new();
        file.insert("path".into(), json!(path.to_string_lossy()));
        if let Some(raw) = &self.raw {
            file.insert(
                "format".into(),
                json!({ "raw": { "columns": raw.columns, "rows": raw.rows,
                                 "sample": raw.sample, "north_first": raw.north_first } }),
            );
        }
        let numbers = [
            ("height_scale", self.height_scale),
            ("height_offset_m", self.height_offset_m),
            ("nodata", self.nodata),
        ];
        for (key, value) in numbers {
            if let Some(value) = value {
                file.insert(key.into(), json!(value));
            }
        }
        match self.spacing_m[..] {
            [] => {}
            [d] => {
                file.insert("spacing_m".into(), json!({ "dx": d, "dy": d }));
            }
            [dx, dy] => {
                file.insert("spacing_m".into(), json!({ "dx": dx, "dy": dy }));
            }
            _ => {
                return Err(format!(
                    "--spacing-m: {} numbers: expected one (both axes) or two (dx,dy)",
                    self.spacing_m.len()
                ));
            }
        }
        file.insert("fit".into(), json!(self.fit.unwrap_or("pad")));
        if !self.crop_origin.is_empty() {
            file.insert("crop_origin".into(), json!(self.crop_origin));
        }
        if !self.origin_m.is_empty() {
            file.insert("origin_m".into(), json!(self.origin_m));
        }
        Ok(file)
    }

    /// The options given, as `--height-scale`, for an error message.
    pub fn given(&self) -> Vec<&'static str> {
        [
            (self.raw.is_some(), "--raw-…"),
            (self.height_scale.is_some(), "--height-scale"),
            (self.height_offset_m.is_some(), "--height-offset-m"),
            (self.nodata.is_some(), "--nodata"),
            (!self.spacing_m.is_empty(), "--spacing-m"),
            (self.fit.is_some(), "--fit"),
            (!self.crop_origin.is_empty(), "--crop-origin"),
            (!self.origin_m.is_empty(), "--origin-m"),
        ]
        .into_iter()
        .filter_map(|(given, name)| given.then_some(name))
        .collect()
    }
}

/// Why `info` stopped.
#[derive(Debug)]
pub enum InfoFailure {
    /// Writing to the output failed (a closed pipe among others).
    Output(std::io::Error),
    /// Anything else, in words for the user.
    Error(String),
}

impl From<std::io::Error> for InfoFailure {
    fn from(error: std::io::Error) -> InfoFailure {
        InfoFailure::Output(error)
    }
}

impl From<String> for InfoFailure {
    fn from(message: String) -> InfoFailure {
        InfoFailure::Error(message)
    }
}

/// Runs `roamsim info`, writing its report to `out`.
pub fn run_info(request: &InfoRequest, out: &mut dyn Write) -> Result<(), InfoFailure> {
    let is_experiment = request
        .path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if is_experiment {
        info_experiment(request, out)
    } else {
        info_terrain_file(request, out)
    }
}

/// A terrain file read with the request's `terrain.file` keys.
fn info_terrain_file(request: &InfoRequest, out: &mut dyn Write) -> Result<(), InfoFailure> {
    let path = &request.path;
    let file = request.file_keys.object(path)?;
    let (field, report) =
        experiment::load_terrain_file(path, &Value::Object(file)).map_err(|e| {
            let hint = if e.problems.iter().any(|p| p.field == "terrain.file") {
                " (for a raw file give --raw-columns, --raw-rows and --raw-sample, e.g. \
                 --raw-columns 1025 --raw-rows 1025 --raw-sample i16le)"
            } else {
                ""
            };
            format!("{e}{hint}")
        })?;
    write!(out, "{}", describe_terrain(&report))?;
    if let Some(map) = &request.map {
        draw_map(map, &field, &report, None, out)?;
    }
    write!(out, "{}", describe_preprocessing(field))?;
    Ok(())
}

/// Every point of an experiment, each with exactly its terrain; the map of the first.
fn info_experiment(request: &InfoRequest, out: &mut dyn Write) -> Result<(), InfoFailure> {
    let path = &request.path;
    let given = request.file_keys.given();
    if !given.is_empty() {
        return Err(InfoFailure::Error(format!(
            "{}: {} describe a terrain file; an experiment declares its terrain's in terrain.file",
            path.display(),
            given.join(", ")
        )));
    }
    let plan = experiment::plan(path).map_err(|e| e.to_string())?;
    for k in 0..plan.n_points() {
        if let Some(choice) = plan.choice(k) {
            writeln!(
                out,
                "sweep point {}/{}: {}",
                k + 1,
                plan.n_points(),
                experiment::choice_label(choice)
            )?;
        }
        let experiment = plan.load_point(k).map_err(|e| e.to_string())?;
        write!(out, "{}", describe_terrain(&experiment.terrain))?;
        if k == 0
            && let Some(map) = &request.map
        {
            let flight = FlightOnMap {
                flight: &experiment.flight,
                view: experiment.view,
                violations: &experiment.violations,
            };
            draw_map(
                map,
                &experiment.field,
                &experiment.terrain,
                Some(flight),
                out,
            )?;
        }
        write!(out, "{}", describe_preprocessing(experiment.field))?;
    }
    Ok(())
}

fn draw_map(
    map: &Path,
    field: &Heightfield,
    report: &TerrainReport,
    flight: Option<FlightOnMap>,
    out: &mut dyn Write,
) -> Result<(), InfoFailure> {
    let title = match flight {
        Some(f) => format!(
            "The flight over {}: {} frames",
            report.source,
            f.flight.n_frames()
        ),
        None => format!("Terrain {}", report.source),
    };
    write_map_to(map, field, &title, flight).map_err(|e| e.to_string())?;
    writeln!(out, "{:<16}{}", "map", map.display())?;
    Ok(())
}
