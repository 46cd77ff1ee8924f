//! Sharded runs: `roamsim run EXP --shard K/N` runs the K-th of N deterministic parts of an
//! experiment and writes its raw results to `shard.json`; `roamsim merge DIR…` reads the N
//! shard folders back and writes exactly the outputs one `roamsim run EXP` writes (the same
//! writers over the same results), apart from timing columns and run metadata.
//!
//! **Units and parts.** An experiment's work units are its (sweep point, algorithm entry) pairs
//! in the experiment's order: point 0's entries, then point 1's, and so on. Shard K of N takes
//! the K-th of N contiguous, nearly equal runs of them (units ⌊(K−1)·U/N⌋ up to ⌊K·U/N⌋), not
//! every N-th unit, so a shard loads as few of the sweep's terrains as it can (a sweep over
//! terrain sizes keeps a shard's memory to its own points), at the price of balance, which N
//! controls. Each unit runs exactly as in a whole run (its own fresh algorithm over the point's
//! terrain and flight), so its counts, columns and meshes are those of the whole run; only its
//! timings differ.
//!
//! **The shard file** (`shard.json`, format `"roamsim shard"`, version 1): the experiment's
//! name, file (absolute path) and content hash, K and N, the run's `--frames` and `--check`, and
//! per unit its results: every frame's statistics ([`frame_codec`], exact), the algorithm's
//! extra columns and run facts, its memory and preprocessing, its exported meshes; per point,
//! the terrain's preprocessing and the flight's speed-bound violations. Floating-point values
//! are stored as their bit patterns.
//!
//! **Merging** checks before writing anything: every folder holds a shard file of this format;
//! all are of the same experiment (name and content hash), of the same N, `--frames`,
//! `--check` and timing (`--repeat`, `--time-with-effects`); each K from 1 to N is there exactly once; the experiment file is still there and
//! unchanged (its content hash), since merging loads each point's terrain and flight again for
//! the writers (summary.json's terrain and flight sections; nothing is simulated). A merge
//! refuses to guess.
//!
//! This module is the format and its checks; `edge::session` runs and merges.

pub mod frame_codec;

use crate::sim::stats::FrameStats;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::{Path, PathBuf};

/// The shard file's name inside a shard folder.
pub const SHARD_FILE: &str = "shard.json";
const FORMAT: &str = "roamsim shard";
const FORMAT_VERSION: u32 = 2;

/// Which part of the work: the `index`-th (1-based) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardSpec {
    pub index: usize,
    pub count: usize,
}

impl ShardSpec {
    /// Parses `K/N` (1 ≤ K ≤ N).
    pub fn parse(text: &str) -> Result<ShardSpec, String> {
        let expected = "expected K/N with whole numbers 1 ≤ K ≤ N, such as 2/3";
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| format!("--shard {text:?}: {expected}"))?;
        let parse = |part: &str| part.trim().parse::<usize>().ok();
        match (parse(k), parse(n)) {
            (Some(index), Some(count)) if index >= 1 && index <= count => {
                Ok(ShardSpec { index, count })
            }
            _ => Err(format!("--shard {text:?}: {expected}")),
        }
    }

    /// The units (indices into the experiment's units in order) this shard runs, of `units`.
    pub fn units(&self, units: usize) -> std::ops::Range<usize> {
        let (k, n) = (self.index - 1, self.count);
        (k * units / n)..((k + 1) * units / n)
    }
}

impl fmt::Display for ShardSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// What a shard ran: the file's whole content.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardFile {
    pub format: String,
    pub format_version: u32,
    pub experiment: ShardExperiment,
    pub shard: ShardSpec,
    /// `--frames`, when given.
    pub max_frames: Option<u64>,
    /// `--check`.
    pub check_meshes: bool,
    /// `--repeat` (timing passes) and `--time-with-effects`.
    pub repeat: u32,
    pub time_with_effects: bool,
    pub threads: usize,
    pub command_line: Option<Vec<String>>,
    /// The points this shard ran entries of, in order.
    pub points: Vec<ShardPoint>,
}

/// The experiment a shard belongs to.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardExperiment {
    pub name: String,
    /// Absolute path of the experiment file when the shard ran.
    pub file: PathBuf,
    /// The path as the command line gave it (what a whole run records in `summary.json`).
    pub file_as_given: PathBuf,
    pub content_sha256: String,
}

impl ShardExperiment {
    /// The path to read the experiment from when merging: the path as given when, from here,
    /// it names the same file (so the merged outputs record it as a whole run would), else
    /// the absolute path.
    pub fn file_to_read(&self) -> PathBuf {
        let same = std::fs::canonicalize(&self.file_as_given).is_ok_and(|p| p == self.file);
        if same {
            self.file_as_given.clone()
        } else {
            self.file.clone()
        }
    }
}

/// One sweep point's share of a shard.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardPoint {
    pub point: usize,
    /// The terrain's preprocessing: seconds and bytes per sample (f64 bits).
    pub preprocessing_seconds_bits: u64,
    pub bytes_per_sample_bits: u64,
    /// Bytes of the shared preprocessed terrain (f64 bits).
    pub hierarchy_bytes_bits: u64,
    pub violation_frames: Vec<u64>,
    pub entries: Vec<ShardEntry>,
}

/// One algorithm entry's results.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardEntry {
    /// Its index among the point's entries.
    pub entry: usize,
    pub label: String,
    pub memory_bytes: usize,
    pub preprocessing_seconds_bits: u64,
    pub bytes_per_sample_bits: u64,
    pub extra_columns: Vec<String>,
    /// Run facts: name and value (f64 bits).
    pub facts: Vec<(String, u64)>,
    /// Exported meshes: frame and PLY text.
    pub meshes: Vec<(u64, String)>,
    /// Every frame, [`frame_codec::encode_frame`].
    pub frames: Vec<Vec<u64>>,
    /// A tuned entry's search (absent for an entry without `tune`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tuning: Option<ShardTuning>,
}

/// A tuned entry's search as a shard keeps it (f64 bits); the target, parameter and tolerance
/// come from the experiment when merging.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardTuning {
    pub value_bits: u64,
    pub probe_mean_bits: u64,
    pub reached: bool,
    pub probe_frames: u64,
    pub probe_stride: u64,
    /// Each probe's value and mean (f64 bits).
    pub probes: Vec<(u64, u64)>,
    pub full_run_mean_bits: u64,
    /// The plateau the search stopped on, if it did (absent in shards written before plateaus).
    #[serde(default)]
    pub plateau: Option<ShardPlateau>,
}

/// A search's plateau as a shard keeps it: its value and mean ranges (f64 bits), probes and
/// reason.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardPlateau {
    pub values_bits: (u64, u64),
    pub means_bits: (u64, u64),
    pub probes: usize,
    pub reason: String,
}

impl ShardFile {
    /// A shard file of this format for `experiment`, with no points yet.
    pub fn new(
        experiment: ShardExperiment,
        shard: ShardSpec,
        (max_frames, check_meshes): (Option<u64>, bool),
        (repeat, time_with_effects): (u32, bool),
        threads: usize,
        command_line: Option<Vec<String>>,
    ) -> ShardFile {
        ShardFile {
            format: FORMAT.to_string(),
            format_version: FORMAT_VERSION,
            experiment,
            shard,
            max_frames,
            check_meshes,
            repeat,
            time_with_effects,
            threads,
            command_line,
            points: Vec::new(),
        }
    }
}

impl ShardEntry {
    /// The frames decoded; an error names the entry and the frame that is malformed.
    pub fn decode_frames(&self) -> Result<Vec<FrameStats>, String> {
        self.frames
            .iter()
            .enumerate()
            .map(|(k, words)| {
                frame_codec::decode_frame(words).ok_or_else(|| {
                    format!(
                        "entry {:?}: frame record {k} is malformed (cut, padded or edited)",
                        self.label
                    )
                })
            })
            .collect()
    }
}

/// Why shards cannot be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("roamsim merge needs at least one shard folder")]
    NoShards,
    #[error(
        "{path}: cannot read the shard file: {source} (a shard folder is what `roamsim run EXP --shard K/N` writes)"
    )]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: not a roamsim shard file: {problem}")]
    Malformed { path: PathBuf, problem: String },
    /// `theirs` and `ours`: the experiments' names and content hashes.
    #[error(
        "{path}: shard of experiment {theirs}, but {first} is of {ours}: every shard must be of the same experiment file"
    )]
    OtherExperiment {
        path: PathBuf,
        first: PathBuf,
        theirs: String,
        ours: String,
    },
    #[error("{path}: {what} is {theirs}, but {first} has {ours}: every shard must be run alike")]
    Mismatch {
        path: PathBuf,
        first: PathBuf,
        what: &'static str,
        theirs: String,
        ours: String,
    },
    #[error("shard {shard} is given twice: {first} and {second}")]
    Duplicate {
        shard: ShardSpec,
        first: PathBuf,
        second: PathBuf,
    },
    #[error(
        "shard(s) {missing} of {count} missing (given: {given}); run them with `roamsim run EXP --shard K/{count}`"
    )]
    Missing {
        missing: String,
        count: usize,
        given: String,
    },
    #[error(
        "{path}: the experiment file changed since the shards ran (content sha256 {now}, the shards have {then}); rerun the shards"
    )]
    ExperimentChanged {
        path: PathBuf,
        now: String,
        then: String,
    },
    #[error("{path}: {problem}")]
    Inconsistent { path: PathBuf, problem: String },
}

/// Reads one shard folder's file.
pub fn read_shard(folder: &Path) -> Result<ShardFile, MergeError> {
    let path = folder.join(SHARD_FILE);
    let text = std::fs::read_to_string(&path).map_err(|source| MergeError::Read {
        path: path.clone(),
        source,
    })?;
    let file: ShardFile = serde_json::from_str(&text).map_err(|error| MergeError::Malformed {
        path: path.clone(),
        problem: error.to_string(),
    })?;
    if file.format != FORMAT || file.format_version != FORMAT_VERSION {
        return Err(MergeError::Malformed {
            path,
            problem: format!(
                "format {:?} version {}, expected {FORMAT:?} version {FORMAT_VERSION}",
                file.format, file.format_version
            ),
        });
    }
    if file.shard.index == 0 || file.shard.index > file.shard.count {
        return Err(MergeError::Malformed {
            path,
            problem: format!("shard {} is not K/N with 1 ≤ K ≤ N", file.shard),
        });
    }
    Ok(file)
}

/// Reads every folder's shard file and checks that together they are the whole of one run:
/// the same experiment and settings, each shard of 1..=N exactly once. Returns them ordered by
/// K, each with its folder.
pub fn read_complete_set(folders: &[PathBuf]) -> Result<Vec<(PathBuf, ShardFile)>, MergeError> {
    let mut shards = Vec::new();
    for folder in folders {
        shards.push((folder.clone(), read_shard(folder)?));
    }
    let Some((first_path, first)) = shards.first() else {
        return Err(MergeError::NoShards);
    };
    for (path, shard) in &shards[1..] {
        if shard.experiment.name != first.experiment.name
            || shard.experiment.content_sha256 != first.experiment.content_sha256
        {
            let described =
                |e: &ShardExperiment| format!("{:?} (content sha256 {})", e.name, e.content_sha256);
            return Err(MergeError::OtherExperiment {
                path: path.clone(),
                first: first_path.clone(),
                theirs: described(&shard.experiment),
                ours: described(&first.experiment),
            });
        }
        let mismatch = |what, theirs: String, ours: String| MergeError::Mismatch {
            path: path.clone(),
            first: first_path.clone(),
            what,
            theirs,
            ours,
        };
        if shard.shard.count != first.shard.count {
            return Err(mismatch(
                "the number of shards N",
                shard.shard.count.to_string(),
                first.shard.count.to_string(),
            ));
        }
        if shard.max_frames != first.max_frames {
            return Err(mismatch(
                "--frames",
                format!("{:?}", shard.max_frames),
                format!("{:?}", first.max_frames),
            ));
        }
        if shard.check_meshes != first.check_meshes {
            return Err(mismatch(
                "--check",
                shard.check_meshes.to_string(),
                first.check_meshes.to_string(),
            ));
        }
        let timing = |s: &ShardFile| {
            if s.time_with_effects {
                "--time-with-effects".to_string()
            } else {
                format!("--repeat {}", s.repeat)
            }
        };
        if timing(shard) != timing(first) {
            return Err(mismatch(
                "the timing (--repeat, --time-with-effects)",
                timing(shard),
                timing(first),
            ));
        }
    }
    let count = first.shard.count;
    let mut by_index: Vec<Option<(PathBuf, ShardFile)>> = (0..count).map(|_| None).collect();
    for (path, shard) in shards {
        let slot = &mut by_index[shard.shard.index - 1];
        if let Some((earlier, _)) = slot {
            return Err(MergeError::Duplicate {
                shard: shard.shard,
                first: earlier.clone(),
                second: path,
            });
        }
        *slot = Some((path, shard));
    }
    let missing: Vec<String> = (1..=count)
        .filter(|k| by_index[k - 1].is_none())
        .map(|k| k.to_string())
        .collect();
    if !missing.is_empty() {
        let given: Vec<String> = (1..=count)
            .filter(|k| by_index[k - 1].is_some())
            .map(|k| format!("{k}/{count}"))
            .collect();
        return Err(MergeError::Missing {
            missing: missing.join(", "),
            count,
            given: given.join(", "),
        });
    }
    Ok(by_index.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shard_is_k_of_n_with_k_from_1_to_n() {
        assert_eq!(
            ShardSpec::parse("2/3"),
            Ok(ShardSpec { index: 2, count: 3 })
        );
        for bad in ["0/3", "4/3", "3", "a/b", "1/0", "-1/3", ""] {
            let error = ShardSpec::parse(bad).expect_err(bad);
            assert!(error.contains("1 ≤ K ≤ N"), "{bad}: {error}");
        }
    }

    #[test]
    fn the_parts_cover_every_unit_once_in_order() {
        for units in 0..20 {
            for count in 1..8 {
                let mut covered = Vec::new();
                for index in 1..=count {
                    covered.extend(ShardSpec { index, count }.units(units));
                }
                assert_eq!(
                    covered,
                    (0..units).collect::<Vec<_>>(),
                    "{units} units, {count}"
                );
            }
        }
        // Nearly equal: 10 units in 3 parts are 3, 3 and 4.
        let sizes: Vec<usize> = (1..=3)
            .map(|index| ShardSpec { index, count: 3 }.units(10).len())
            .collect();
        assert_eq!(sizes, [3, 3, 4]);
    }
}
