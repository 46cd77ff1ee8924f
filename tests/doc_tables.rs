//! The docs' generated figures (`scripts/doc-tables`): the committed docs hold exactly what the
//! scripts print from the committed outputs (the study, performance.md and a reproduction page
//! among them), and a doc whose generated text differs by one digit fails the check, which names the doc, the line and the command; filling puts the figure back.
//! The scripts are Python 3 (standard library only); `.ci/run` runs the same check on its own.

mod common;

use common::experiment::repository;
use std::path::Path;
use std::process::{Command, Output};

fn doc_tables(arguments: &[&str]) -> Output {
    let script = repository().join("scripts/doc-tables");
    Command::new("python3")
        .arg(&script)
        .args(arguments)
        .output()
        .unwrap_or_else(|error| panic!("cannot run python3 {}: {error}", script.display()))
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A copy of `doc` (relative to the repository) in `folder` with the first digit after its
/// first generated marker changed (d → d+1 mod 10), and the line of that digit.
fn with_one_digit_changed(doc: &str, folder: &Path) -> (std::path::PathBuf, usize) {
    let original = std::fs::read_to_string(repository().join(doc)).unwrap();
    let marker = original
        .find("<!-- scripts/doc-tables ")
        .unwrap_or_else(|| panic!("{doc} has no generated text"));
    let after_marker = marker + original[marker..].find("-->").unwrap() + 3;
    let offset = after_marker
        + original[after_marker..]
            .find(|c: char| c.is_ascii_digit())
            .unwrap();
    let digit = original.as_bytes()[offset] - b'0';
    let mut changed = original.clone();
    changed.replace_range(
        offset..offset + 1,
        &char::from(b'0' + (digit + 1) % 10).to_string(),
    );
    let path = folder.join(Path::new(doc).file_name().unwrap());
    std::fs::write(&path, changed).unwrap();
    (path, original[..offset].matches('\n').count() + 1)
}

#[test]
fn the_committed_docs_hold_what_the_scripts_print_from_the_committed_outputs() {
    let output = doc_tables(&["--check"]);
    assert!(
        output.status.success(),
        "scripts/doc-tables --check failed:\n{}{}",
        text(&output.stdout),
        text(&output.stderr)
    );
    assert!(text(&output.stdout).contains("match the committed outputs"));
}

#[test]
fn one_digit_changed_in_a_generated_table_fails_the_check_and_filling_puts_it_back() {
    let folder = tempfile::tempdir().unwrap();
    for doc in [
        "docs/study.md",
        "docs/performance.md",
        "docs/reproductions/lindstrom.md",
        "docs/reproductions/vanek.md",
    ] {
        let (copy, line) = with_one_digit_changed(doc, folder.path());
        let copy_argument = copy.to_str().unwrap();

        let check = doc_tables(&["--check", "--doc", copy_argument]);
        assert_eq!(
            check.status.code(),
            Some(1),
            "{doc}: the check did not fail"
        );
        let message = text(&check.stderr);
        assert!(
            message.contains("differs from what it prints from the committed outputs"),
            "{doc}: {message}"
        );
        // The message names the doc and the line of the marker, which is at or above the digit.
        let named_line: usize = message
            .split(&format!("{copy_argument}:"))
            .nth(1)
            .and_then(|rest| rest.split(':').next())
            .and_then(|number| number.parse().ok())
            .unwrap_or_else(|| panic!("{doc}: no file:line in {message}"));
        assert!(
            named_line <= line,
            "{doc}: line {named_line} named, digit on {line}"
        );

        let fill = doc_tables(&["--doc", copy_argument]);
        assert!(fill.status.success(), "{doc}: {}", text(&fill.stderr));
        assert_eq!(
            std::fs::read_to_string(&copy).unwrap(),
            std::fs::read_to_string(repository().join(doc)).unwrap(),
            "{doc}: filling did not restore the committed text"
        );
    }
}

#[test]
fn a_marker_naming_no_generator_or_never_closed_is_refused_with_its_line() {
    let folder = tempfile::tempdir().unwrap();
    let cases = [
        (
            "unknown.md",
            "# A doc\n\nA figure: <!-- scripts/doc-tables no-such-table -->1<!-- /scripts/doc-tables -->.\n",
            "unknown.md:3: `scripts/doc-tables no-such-table`: no generator 'no-such-table'",
        ),
        (
            "unclosed.md",
            "# A doc\n<!-- scripts/doc-tables study-circle -->\n| a |\n",
            "unclosed.md:2: `study-circle` is never closed",
        ),
    ];
    for (name, contents, expected) in cases {
        let path = folder.path().join(name);
        std::fs::write(&path, contents).unwrap();
        let check = doc_tables(&["--check", "--doc", path.to_str().unwrap()]);
        assert_eq!(check.status.code(), Some(1), "{name}");
        assert!(
            text(&check.stderr).contains(expected),
            "{name}: {}",
            text(&check.stderr)
        );
        let fill = doc_tables(&["--doc", path.to_str().unwrap()]);
        assert_eq!(fill.status.code(), Some(1), "{name}: filling went on");
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            contents,
            "{name}: written"
        );
    }
}

#[test]
fn a_marker_written_in_inline_code_is_text_and_not_a_marker() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("describes.md");
    let contents = "Figures sit between `<!-- scripts/doc-tables NAME ARGUMENTS -->` and \
                    `<!-- /scripts/doc-tables -->`.\n";
    std::fs::write(&path, contents).unwrap();
    let check = doc_tables(&["--check", "--doc", path.to_str().unwrap()]);
    assert!(check.status.success(), "{}", text(&check.stderr));
    assert!(text(&check.stdout).contains("0 generated span(s) in 1 doc(s)"));
}

/// `scripts/doc-tables ARGUMENTS` reading the outputs under `plots` (`ROAMSIM_PLOTS`).
fn doc_tables_reading(plots: &Path, arguments: &[&str]) -> Output {
    let script = repository().join("scripts/doc-tables");
    Command::new("python3")
        .arg(&script)
        .args(arguments)
        .env("ROAMSIM_PLOTS", plots)
        .output()
        .unwrap_or_else(|error| panic!("cannot run python3 {}: {error}", script.display()))
}

/// A `study-circle` output folder under `plots` holding a report.md with this comparison
/// table (header and rows) and a summary.json in which `wu` was tuned.
fn study_circle_output(plots: &Path, table: &str) {
    let folder = plots.join("study-circle");
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::write(
        folder.join("report.md"),
        format!("# study-circle\n\n{table}"),
    )
    .unwrap();
    std::fs::write(
        folder.join("summary.json"),
        r#"{"algorithms": [{"label": "wu", "tuning": {"parameter": "tau_px", "value": 1.296, "reached": true}}]}"#,
    )
    .unwrap();
}

fn printed(plots: &Path, arguments: &[&str]) -> String {
    let output = doc_tables_reading(plots, arguments);
    assert!(
        output.status.success(),
        "{arguments:?}: {}",
        text(&output.stderr)
    );
    text(&output.stdout)
}

#[test]
fn the_study_reads_its_time_from_the_drawn_frame_where_the_outputs_time_it() {
    let plots = tempfile::tempdir().unwrap();
    study_circle_output(
        plots.path(),
        "| entry | algorithm | triangles | rendered | error max / mean / mean of p95 (px) | frame p50 / p95 (µs) | update p50 (µs) | upload per frame (kB) | draw calls | splits + merges per frame | evaluations per split or merge | bytes per sample |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n\
         | wu | wu | 8608 | 6021 | 2.30 / 0.244 / 0.79 | 23.0 / 30.0 | 14.8 | 3.1 | 12 | 11.1 | 9.6 | 6.85 |\n\
         | reference whole terrain | reference | 40459 | 6002 | 2.33 / 0.246 / 0.80 | 1236.0 / 1500.0 | 1213.0 | 900.0 | 1 | 8415.1 † | 1.0 † | 5.50 |\n\
         | reference in view | reference | 8600 | 6021 | 2.30 / 0.244 / 0.79 | 92.0 / 120.0 | 70.8 | 200.0 | 1 | 1200.0 † | 1.0 † | 5.50 |\n",
    );
    let table = printed(plots.path(), &["--print", "study-circle"]);
    assert!(
        table.contains(
            "| popping RMSE / max (px) | frame p50 (µs) | update p50 (µs) | upload per frame (kB) \
             | draw calls | operations per frame |"
        ),
        "{table}"
    );
    assert!(
        table.contains("| wu | tau_px = 1.296 | 6021 | 8608 | 2.30 / 0.244 / 0.79 | — / — | 23.0 | 14.8 | 3.1 | 12 | 11.1 | 6.85 |"),
        "{table}"
    );
    let wu_against = |reference: &str| {
        printed(
            plots.path(),
            &[
                "--print",
                "ratio",
                "time",
                "1",
                reference,
                "wu",
                "study-circle",
            ],
        )
    };
    assert_eq!(wu_against("reference in view"), "4.0");
    assert_eq!(wu_against("reference whole terrain"), "53.7");
}

/// The fallback for the outputs committed before issue #31 (`scripts/doctables/study.py`,
/// `pre_frame_ns_*`): this test goes with it once the study is regenerated.
#[test]
fn outputs_from_before_the_drawn_frame_print_their_update_time_as_the_docs_quote_it() {
    let plots = tempfile::tempdir().unwrap();
    study_circle_output(
        plots.path(),
        "| entry | algorithm | triangles | rendered | error max / mean / mean of p95 (px) | update p50 / p95 (µs) | splits + merges per frame | evaluations per split or merge | bytes per sample |\n\
         |---|---|---|---|---|---|---|---|---|\n\
         | wu | wu | 8608 | 6021 | 2.30 / 0.244 / 0.79 | 14.8 / 20.0 | 11.1 | 9.6 | 6.85 |\n\
         | reference | reference | 40459 | 6002 | 2.33 / 0.246 / 0.80 | 1213.0 / 1400.0 | 8415.1 † | 1.0 † | 5.50 |\n",
    );
    let table = printed(plots.path(), &["--print", "study-circle"]);
    assert!(
        table.contains("| popping RMSE / max (px) | update p50 (µs) | operations per frame |"),
        "{table}"
    );
    assert!(!table.contains("frame p50"), "{table}");
    let wu_against = |reference: &str| {
        printed(
            plots.path(),
            &[
                "--print",
                "ratio",
                "time",
                "1",
                reference,
                "wu",
                "study-circle",
            ],
        )
    };
    assert_eq!(wu_against("reference whole terrain"), "82.0");
    assert_eq!(
        wu_against("reference in view"),
        "not yet measured (the committed outputs predate that entry)"
    );
}
