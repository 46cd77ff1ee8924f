//! What the outputs say about themselves is true: every warning or note that names a section of
//! report.md or a file names one that exists in that run, the end of a run lists only the files
//! it wrote, and every column of frames.csv is documented in docs/output-formats.md (and every
//! column documented there is one a run writes). Through the binary, on small synthetic
//! terrains.

mod common;

use common::cli::roamsim;
use common::experiment::{repository, save};
use serde_json::{Value, json};
use std::collections::BTreeSet;
use std::path::Path;

/// A 24-frame circle over a 129² synthetic terrain; audited, culling on, no plots.
fn experiment(name: &str, algorithms: Value) -> Value {
    json!({
        "format_version": 1,
        "name": name,
        "terrain": {"synthetic": {"level": 7, "seed": 3, "amplitude_m": 80, "roughness": 0.5,
                                  "spacing_m": {"dx": 30, "dy": 30}}},
        "view": {"width_px": 300, "height_px": 200, "fovy_deg": 60, "near_m": 1, "far_m": 50000},
        "speed_bounds": {"horizontal_m_per_frame": 50, "vertical_m_per_frame": 10,
                         "rotation_rad_per_frame": 0.05},
        "flight": {"frames": 24, "look": {"along_path": {"pitch_deg": -20}},
                   "path": {"circle": {"centre_m": [1900, 1900], "radius_m": 1000,
                                       "altitude_m": 600, "frames_per_lap": 300}}},
        "algorithms": algorithms,
        "effects": {"audit": {"stride": 2}, "culling": true},
        "outputs": {"plots": false}
    })
}

/// Every `(FILE, "SECTION")` pointer in `text`: the file and the section named.
fn section_pointers(text: &str) -> Vec<(String, String)> {
    let mut pointers = Vec::new();
    for line in text.lines() {
        let mut rest = line;
        while let Some(start) = rest.find(", \"") {
            let before = &rest[..start];
            let file = before.rsplit('(').next().unwrap_or_default().to_string();
            let after = &rest[start + 3..];
            let Some(end) = after.find("\")") else { break };
            pointers.push((file, after[..end].to_string()));
            rest = &after[end..];
        }
    }
    pointers
}

/// Runs `experiment` and checks every pointer it printed: each `(report, "section")` names a
/// report that exists with that `## section` heading, and each file the end of the run lists
/// exists. Returns stdout and stderr.
fn run_and_check_pointers(cwd: &Path, name: &str, experiment: &Value) -> (String, String) {
    save(cwd, name, experiment);
    let out = cwd.join(format!("out-{name}"));
    let output = roamsim(
        &[
            "run",
            &format!("{name}.json"),
            "--out",
            out.to_str().unwrap(),
        ],
        cwd,
    );
    let (stdout, stderr) = (
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    );
    assert!(output.status.success(), "{name}: {stderr}");
    for (file, section) in section_pointers(&stderr)
        .into_iter()
        .chain(section_pointers(&stdout))
    {
        let report = std::fs::read_to_string(out.join(&file))
            .unwrap_or_else(|e| panic!("{name}: a message names {file}, which is not there: {e}"));
        assert!(
            report.contains(&format!("\n## {section}\n")),
            "{name}: a message names section {section:?} of {file}, which has none: {stderr}"
        );
    }
    let wrote = stdout
        .lines()
        .find_map(|l| l.strip_prefix(&format!("wrote {}/: ", out.display())))
        .unwrap_or_else(|| panic!("{name}: no 'wrote' line: {stdout}"));
    for item in wrote.split(", ") {
        let file = item.split(' ').next().unwrap();
        assert!(
            out.join(file).exists(),
            "{name}: the end of the run lists {file}, not written"
        );
    }
    (stdout, stderr)
}

#[test]
fn every_section_and_file_a_message_names_exists_in_that_run() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    // A budget and a target no frame comes near, and a search that cannot reach its target.
    let goals = experiment(
        "goals",
        json!([
            {"name": "wu", "label": "wu budget", "budget_triangles": 900000},
            {"name": "roam", "label": "roam target", "target_triangles": 900000},
            {"name": "stitching-strips", "label": "strips @0.3px", "rho_threshold_px": 1,
             "block_level": 4, "tune": {"audit_p95_px": 0.3, "probe_frames": 8}},
        ]),
    );
    let (stdout, stderr) = run_and_check_pointers(cwd, "goals", &goals);
    assert_eq!(
        section_pointers(&stderr)
            .iter()
            .map(|(file, section)| format!("{file}: {section}"))
            .collect::<Vec<_>>(),
        [
            "report.md: Budgets and targets",
            "report.md: Budgets and targets",
            "report.md: Tuned entries"
        ],
        "{stderr}"
    );
    assert!(!stdout.contains("plots/"), "\"plots\": false: {stdout}");
    assert!(stdout.contains("tuned-experiment.json"), "{stdout}");

    // The same in a sweep with labelled points, plots on: each point's report is named.
    let mut sweep = goals.clone();
    sweep["name"] = "swept".into();
    sweep["sweep"] = json!({"view.fovy_deg": [50, 60], "labels": ["narrow", "wide"]});
    sweep["outputs"]["plots"] = true.into();
    let (stdout, stderr) = run_and_check_pointers(cwd, "swept", &sweep);
    let files: BTreeSet<String> = section_pointers(&stderr).into_iter().map(|p| p.0).collect();
    assert_eq!(
        files.into_iter().collect::<Vec<_>>(),
        ["narrow/report.md", "wide/report.md"]
    );
    assert!(stdout.contains("plots/"), "{stdout}");
    // The labels name the folders and the top report's columns; each point plots the
    // triangles its error-tuned entry needed and Wu's b for its budget entry.
    let out = cwd.join("out-swept");
    for label in ["narrow", "wide"] {
        for plot in ["triangles_for_error_target", "base_b"] {
            let path = out.join(format!("{label}/plots/{plot}.png"));
            assert!(path.exists(), "{}", path.display());
        }
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    for part in [
        "| narrow (view.fovy_deg=50) | `narrow` |",
        "## Mean rendered triangles per frame",
        "## Operation counters (means per frame)",
        "### strips @0.3px (stitching-strips)\n\n| counter | narrow | wide |",
        "| `tessellation_factor_32_64` |",
    ] {
        assert!(report.contains(part), "{part:?} missing: {report}");
    }

    // Without a budget, Wu's b stays 0: no base_b plot.
    let mut plain = experiment("plain", json!([{"name": "wu", "tau_px": 2}]));
    plain["outputs"]["plots"] = true.into();
    run_and_check_pointers(cwd, "plain", &plain);
    assert!(cwd.join("out-plain/plots/triangles.png").exists());
    assert!(!cwd.join("out-plain/plots/base_b.png").exists());
}

/// Every column name docs/output-formats.md gives in its frames.csv section: each
/// `` `name` `` there, brace groups expanded (`audit_{max,mean}_px`), and those the tables list
/// (the first cell of each row), which must be columns.
fn documented_columns() -> (BTreeSet<String>, BTreeSet<String>) {
    let doc = std::fs::read_to_string(repository().join("docs/output-formats.md")).unwrap();
    let start = doc.find("\n## frames.csv").expect("a frames.csv section");
    let end = start + 1 + doc[start + 1..].find("\n## ").unwrap();
    let section = &doc[start..end];
    fn expand(name: &str) -> Vec<String> {
        match (name.find('{'), name.find('}')) {
            (Some(open), Some(close)) => name[open + 1..close]
                .split(',')
                .flat_map(|part| expand(&format!("{}{part}{}", &name[..open], &name[close + 1..])))
                .collect(),
            _ => vec![name.to_string()],
        }
    }
    let names_in = |text: &str| -> Vec<String> {
        text.split('`')
            .skip(1)
            .step_by(2)
            .filter(|n| {
                n.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "_{},".contains(c))
            })
            .flat_map(expand)
            .collect()
    };
    let mentioned: BTreeSet<String> = names_in(section).into_iter().collect();
    let tabled: BTreeSet<String> = section
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .flat_map(|l| names_in(&format!("`{}", l.split(" |").next().unwrap())))
        .collect();
    (mentioned, tabled)
}

#[test]
fn every_frames_csv_column_of_a_run_with_every_effect_is_documented_and_no_documented_one_is_stale()
{
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let mut every = experiment(
        "every",
        json!([
            {"name": "reference", "tau_px": 4},
            {"name": "wu", "label": "wu budget", "budget_triangles": 1500, "cone_culling": true,
             "recentre_tau": true},
            {"name": "lindstrom", "tau_px": 4, "block_level": 3},
            {"name": "roam", "tau_px": 4, "deferral": true, "culling_flags": true, "strips": true},
            {"name": "roam-rebuild", "tau_px": 4},
            {"name": "rottger", "minimum_resolution": 8, "desired_resolution": 30,
             "target_triangles": 1500, "clipping": true, "geomorphing": true},
            {"name": "geomipmap", "tau_px": 4, "patch_level": 3, "morph": true, "box_culling": true},
            {"name": "chunked", "tau_px": 4, "chunk_level": 3, "box_culling": true, "morph": true,
             "detail": {"levels": 1, "seed": 1, "amplitude_m": 3, "max_queued_chunks": 8,
                        "cache_chunks": 64},
             "loading": {"latency_frames": 2, "bandwidth_chunks_per_frame": 16,
                         "resident_chunks": 256}},
            {"name": "vanek", "patch_level": 3, "min_dist_m": 200, "max_dist_m": 3000,
             "target_triangles": 1500, "box_culling": true},
            {"name": "stitching-strips", "rho_threshold_px": 1, "block_level": 4, "culling": true},
        ]),
    );
    every["effects"]["audit"]["popping"] = true.into();
    every["flight"]["frames"] = 6.into();
    save(cwd, "every", &every);
    let output = roamsim(&["run", "every.json", "--out", "out", "--check"], cwd);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let csv = std::fs::read_to_string(cwd.join("out/frames.csv")).unwrap();
    let header: BTreeSet<String> = csv
        .lines()
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let (mentioned, tabled) = documented_columns();
    let undocumented: Vec<&String> = header.difference(&mentioned).collect();
    let stale: Vec<&String> = tabled.difference(&header).collect();
    assert!(
        undocumented.is_empty() && stale.is_empty(),
        "frames.csv columns not documented in docs/output-formats.md: {undocumented:?}; \
         documented in its tables but not written by a run with every effect: {stale:?}"
    );
}
