//! Recorded camera logs (SPEC §8): one pose per frame, as CSV, the `recorded` flight of
//! `docs/experiment-format.md` ("Flight"). This file only reads poses; the flight built from
//! them and its check against the speed bounds are the core's (`sim::flight`).
//!
//! [`read_flight_log`] reads the file and hands its bytes to [`parse_flight_log_bytes`], which
//! parses from memory: the entry point of the fuzz target and the parser property tests.
//!
//! Format: a header line `frame,x_m,y_m,z_m,yaw_deg,pitch_deg`, then one line per frame with
//! frames 0, 1, 2, … in order, every value a finite number. Blank lines and lines starting with
//! `#` are skipped. Every error names the file, the line and the column.

use crate::sim::view::Pose;
use glam::DVec3;
use std::fmt;
use std::path::{Path, PathBuf};

/// The header a log must start with.
pub const FLIGHT_LOG_HEADER: &str = "frame,x_m,y_m,z_m,yaw_deg,pitch_deg";

/// A flight log could not be read.
#[derive(Clone, Debug, PartialEq)]
pub struct FlightLogError {
    pub path: PathBuf,
    /// 1-based line number; 0 for the file as a whole.
    pub line: usize,
    pub problem: String,
}

impl fmt::Display for FlightLogError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.path.display(), self.problem)
        } else {
            write!(
                f,
                "{}, line {}: {}",
                self.path.display(),
                self.line,
                self.problem
            )
        }
    }
}

impl std::error::Error for FlightLogError {}

/// Reads a log file.
pub fn read_flight_log(path: &Path) -> Result<Vec<Pose>, FlightLogError> {
    let bytes = std::fs::read(path).map_err(|error| FlightLogError {
        path: path.to_path_buf(),
        line: 0,
        problem: format!("cannot read the file: {error}"),
    })?;
    parse_flight_log_bytes(path, &bytes)
}

/// Parses a log's bytes, already in memory (`path` only names it in errors): they must be UTF-8
/// text. This is the entry point of the fuzz target and the parser property tests.
pub fn parse_flight_log_bytes(path: &Path, bytes: &[u8]) -> Result<Vec<Pose>, FlightLogError> {
    let text = std::str::from_utf8(bytes).map_err(|error| FlightLogError {
        path: path.to_path_buf(),
        line: 0,
        problem: format!("not UTF-8 text: {error}"),
    })?;
    parse_flight_log(path, text)
}

/// Parses a log's text (`path` only names it in errors).
pub fn parse_flight_log(path: &Path, text: &str) -> Result<Vec<Pose>, FlightLogError> {
    let error = |line: usize, problem: String| FlightLogError {
        path: path.to_path_buf(),
        line,
        problem,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let Some((header_line, header)) = lines.next() else {
        return Err(error(
            0,
            format!("empty: expected the header {FLIGHT_LOG_HEADER}"),
        ));
    };
    let header: String = header
        .split(',')
        .map(str::trim)
        .collect::<Vec<_>>()
        .join(",");
    if header != FLIGHT_LOG_HEADER {
        return Err(error(
            header_line,
            format!("header {header:?}: expected {FLIGHT_LOG_HEADER}"),
        ));
    }
    const COLUMNS: [&str; 6] = ["frame", "x_m", "y_m", "z_m", "yaw_deg", "pitch_deg"];
    let mut poses = Vec::new();
    for (line, content) in lines {
        let fields: Vec<&str> = content.split(',').map(str::trim).collect();
        if fields.len() != COLUMNS.len() {
            return Err(error(
                line,
                format!("{} values: expected {}", fields.len(), COLUMNS.len()),
            ));
        }
        let frame: u64 = fields[0].parse().map_err(|_| {
            error(
                line,
                format!("frame {:?}: expected a whole number", fields[0]),
            )
        })?;
        if frame != poses.len() as u64 {
            return Err(error(
                line,
                format!(
                    "frame {frame}: expected frame {} (frames start at 0 and go up by 1)",
                    poses.len()
                ),
            ));
        }
        let mut values = [0.0f64; 5];
        for (k, value) in values.iter_mut().enumerate() {
            let text = fields[k + 1];
            *value = text
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    error(
                        line,
                        format!("{} {text:?}: expected a finite number", COLUMNS[k + 1]),
                    )
                })?;
        }
        poses.push(Pose {
            position: DVec3::new(values[0], values[1], values[2]),
            yaw: values[3].to_radians(),
            pitch: values[4].to_radians(),
        });
    }
    if poses.is_empty() {
        return Err(error(
            0,
            "no poses after the header: expected at least one frame".into(),
        ));
    }
    Ok(poses)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<Pose>, FlightLogError> {
        parse_flight_log(Path::new("log.csv"), text)
    }

    #[test]
    fn a_log_with_comments_reads_in_degrees() {
        let poses = parse(
            "# recorded\nframe,x_m,y_m,z_m,yaw_deg,pitch_deg\n0,1,2,3,90,-45\n1,2,2,3,90,-45\n",
        )
        .unwrap();
        assert_eq!(poses.len(), 2);
        assert!((poses[0].yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(poses[1].position, DVec3::new(2.0, 2.0, 3.0));
    }

    #[test]
    fn a_nan_is_rejected_with_line_and_column() {
        let error = parse("frame,x_m,y_m,z_m,yaw_deg,pitch_deg\n0,1,2,NaN,0,0\n").unwrap_err();
        assert_eq!(error.line, 2);
        assert!(
            error
                .to_string()
                .contains("z_m \"NaN\": expected a finite number"),
            "{error}"
        );
    }

    #[test]
    fn a_skipped_frame_is_rejected() {
        let error =
            parse("frame,x_m,y_m,z_m,yaw_deg,pitch_deg\n0,0,0,0,0,0\n2,0,0,0,0,0\n").unwrap_err();
        assert!(
            error
                .to_string()
                .contains("log.csv, line 3: frame 2: expected frame 1"),
            "{error}"
        );
    }

    #[test]
    fn a_wrong_header_is_rejected() {
        let error = parse("t,x,y,z\n").unwrap_err();
        assert!(error.to_string().contains("expected frame,x_m"), "{error}");
    }
}
