//! Sharded runs (`roamsim run --shard K/N`, `roamsim merge`; `docs/sharding.md`), through the
//! binary as a batch system runs them: each shard in its own process. The merged outputs must
//! equal one whole run's apart from timings and run metadata (frames.csv without its timing columns,
//! summary.json without its timing and run fields, the same files); a missing, duplicated or
//! foreign shard, or an experiment changed since the shards ran, is refused with an error that
//! names it, and writes nothing.

mod common;

use common::cli::{fails_with, files, frames_without_timing, succeeds, summary_without_timing};
use common::experiment::{save, short_quickstart};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A two-point sweep (fovy 50° and 60°) of a 12-frame quickstart with three of its entries,
/// audited with popping, and one mesh export: 6 units.
fn small_sweep(dir: &Path) -> PathBuf {
    let mut experiment = short_quickstart(12);
    experiment["name"] = "sharded".into();
    let algorithms = experiment["algorithms"].as_array().unwrap().clone();
    let keep = ["wu budget=6000", "chunked target=6000", "vanek target=6000"];
    experiment["algorithms"] = Value::Array(
        algorithms
            .into_iter()
            .filter(|a| keep.contains(&a["label"].as_str().unwrap()))
            .collect(),
    );
    assert_eq!(experiment["algorithms"].as_array().unwrap().len(), 3);
    experiment["sweep"] = serde_json::json!({ "view.fovy_deg": [50, 60] });
    experiment["effects"]["audit"] = serde_json::json!({ "stride": 8, "popping": true });
    experiment["outputs"]["meshes"] =
        serde_json::json!({ "entries": ["chunked target=6000"], "frames": [2] });
    save(dir, "sharded", &experiment)
}

#[test]
fn three_shards_in_three_processes_merge_into_the_whole_run() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    small_sweep(cwd);
    succeeds(
        &["run", "sharded.json", "--out", "whole", "--threads", "2"],
        cwd,
    );
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let out = format!("shards/{k}");
        succeeds(
            &["run", "sharded.json", "--shard", &shard, "--out", &out],
            cwd,
        );
        assert_eq!(files(&cwd.join(&out)), [PathBuf::from("shard.json")]);
    }
    // In any order.
    succeeds(
        &[
            "merge", "shards/3", "shards/1", "shards/2", "--out", "merged",
        ],
        cwd,
    );
    let (whole, merged) = (cwd.join("whole"), cwd.join("merged"));
    let whole_files = files(&whole);
    assert_eq!(files(&merged), whole_files);
    assert!(whole_files.len() > 10, "{whole_files:?}");
    for file in &whole_files {
        let name = file.to_string_lossy();
        if name.ends_with("frames.csv") {
            assert_eq!(
                frames_without_timing(&merged.join(file)),
                frames_without_timing(&whole.join(file)),
                "{name}"
            );
        } else if name.ends_with("summary.json") {
            assert_eq!(
                summary_without_timing(&merged.join(file)),
                summary_without_timing(&whole.join(file)),
                "{name}"
            );
        } else if name.ends_with(".ply")
            || name.ends_with("flight.csv")
            || name.ends_with("plots/map.png")
            || name.ends_with("plots/map.svg")
        {
            assert_eq!(
                std::fs::read(merged.join(file)).unwrap(),
                std::fs::read(whole.join(file)).unwrap(),
                "{name}"
            );
        }
    }
}

#[test]
fn a_missing_duplicated_or_foreign_shard_or_a_changed_experiment_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let path = small_sweep(cwd);
    for k in 1..=3 {
        let (shard, out) = (format!("{k}/3"), format!("s{k}"));
        succeeds(
            &[
                "run",
                "sharded.json",
                "--shard",
                &shard,
                "--out",
                &out,
                "--frames",
                "3",
            ],
            cwd,
        );
    }
    fails_with(
        &["merge", "s1", "s3", "--out", "m"],
        cwd,
        &["shard(s) 2 of 3 missing", "1/3, 3/3"],
    );
    fails_with(
        &["merge", "s1", "s2", "s2", "s3", "--out", "m"],
        cwd,
        &["shard 2/3 is given twice", "s2"],
    );
    fails_with(
        &["merge", "s1", "nowhere", "--out", "m"],
        cwd,
        &["nowhere", "shard.json"],
    );
    // Another N.
    succeeds(
        &[
            "run",
            "sharded.json",
            "--shard",
            "1/2",
            "--out",
            "half",
            "--frames",
            "3",
        ],
        cwd,
    );
    fails_with(
        &["merge", "s1", "s2", "half", "--out", "m"],
        cwd,
        &["half", "the number of shards N is 2", "3"],
    );
    // Another experiment's shard.
    let mut other = short_quickstart(3);
    other["name"] = "other".into();
    save(cwd, "other", &other);
    succeeds(
        &["run", "other.json", "--shard", "2/3", "--out", "foreign"],
        cwd,
    );
    fails_with(
        &["merge", "s1", "foreign", "s3", "--out", "m"],
        cwd,
        &[
            "foreign",
            "shard of experiment \"other\"",
            "every shard must be of the same experiment",
        ],
    );
    // Another timing.
    succeeds(
        &[
            "run",
            "sharded.json",
            "--shard",
            "2/3",
            "--out",
            "timed",
            "--frames",
            "3",
            "--repeat",
            "2",
        ],
        cwd,
    );
    fails_with(
        &["merge", "s1", "timed", "s3", "--out", "m"],
        cwd,
        &["timed", "the timing", "--repeat 2", "--repeat 1"],
    );
    // Other --frames.
    succeeds(
        &["run", "sharded.json", "--shard", "2/3", "--out", "long"],
        cwd,
    );
    fails_with(
        &["merge", "s1", "long", "s3", "--out", "m"],
        cwd,
        &["long", "--frames"],
    );
    // The experiment edited after the shards ran.
    let mut edited: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    edited["description"] = "edited".into();
    std::fs::write(&path, serde_json::to_string(&edited).unwrap()).unwrap();
    fails_with(
        &["merge", "s1", "s2", "s3", "--out", "m"],
        cwd,
        &["sharded.json", "changed since the shards ran"],
    );
    assert!(!cwd.join("m").exists(), "a refused merge wrote its output");
    // A bad --shard.
    fails_with(
        &["run", "sharded.json", "--shard", "4/3"],
        cwd,
        &["1 ≤ K ≤ N"],
    );
}
