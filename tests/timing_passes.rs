//! Update times measured without the effects' cache damage: by default an audited run flies
//! each entry again with every effect off (a timing pass) and takes its times; `--repeat N`
//! takes each frame's median over N passes and records the passes' spread; the counts,
//! errors and meshes are the measured pass's whatever the timing, and `--time-with-effects`
//! keeps the measured pass's times.

mod common;

use common::cli::{fails_with, frames_without_timing, succeeds};
use common::experiment::{save, short_quickstart};
use serde_json::Value;
use std::path::Path;

fn facts(summary: &Path) -> Vec<Value> {
    let value: Value = serde_json::from_str(&std::fs::read_to_string(summary).unwrap()).unwrap();
    value["algorithms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["facts"].clone())
        .collect()
}

#[test]
fn timing_passes_change_only_the_times_and_record_their_spread() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    save(cwd, "timed", &short_quickstart(12));
    succeeds(&["run", "timed.json", "--out", "default"], cwd);
    succeeds(
        &["run", "timed.json", "--out", "three", "--repeat", "3"],
        cwd,
    );
    succeeds(
        &["run", "timed.json", "--out", "kept", "--time-with-effects"],
        cwd,
    );
    let frames = |out: &str| frames_without_timing(&cwd.join(out).join("frames.csv"));
    assert_eq!(frames("three"), frames("default"));
    assert_eq!(frames("kept"), frames("default"));
    for (out, passes) in [("default", 1.0), ("three", 3.0), ("kept", 0.0)] {
        for entry in facts(&cwd.join(out).join("summary.json")) {
            assert_eq!(entry["timing_passes"], passes, "{out}: {entry}");
            let spread = [
                "update_p50_us_least_of_passes",
                "update_p50_us_median_of_passes",
                "update_p50_us_greatest_of_passes",
            ]
            .map(|fact| entry[fact].as_f64());
            if passes == 0.0 {
                assert_eq!(spread, [None, None, None], "{out}: {entry}");
            } else {
                let [least, median, greatest] = spread.map(|v| v.expect("the spread"));
                assert!(
                    0.0 < least && least <= median && median <= greatest,
                    "{entry}"
                );
                if passes == 1.0 {
                    assert_eq!(least, greatest, "one pass has one median: {entry}");
                }
            }
        }
    }
    fails_with(
        &["run", "timed.json", "--repeat", "2", "--time-with-effects"],
        cwd,
        &["--repeat", "--time-with-effects"],
    );
    fails_with(&["run", "timed.json", "--repeat", "0"], cwd, &["--repeat"]);
}
