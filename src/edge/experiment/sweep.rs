//! Sweeps: one written experiment or algorithm entry expanding into many points.
//!
//! Two kinds share one expansion rule (the cartesian product of the listed values, parameters in
//! alphabetical order, the first one varying slowest):
//! - an algorithm entry's `"sweep": {"tau_px": [1, 2]}` sets the entry's own parameters
//!   (expanded in `entries.rs`, where the entries are checked);
//! - the experiment's top-level `"sweep": {"terrain.synthetic.level": [10, 12]}` sets any field
//!   of the experiment by its path (`.`-separated keys, `[k]` for an array element): each point
//!   is a whole experiment, with its own terrain, run one after another. Its `"together"` group
//!   (`{"path": [...], "other.path": [...]}`, lists of one length) is one axis whose k-th point
//!   sets every listed field to its k-th value, for settings that must change in step.
//!
//! This module only rewrites JSON values (stage 1, before parsing: SPEC §8's experiment file);
//! it knows nothing of what the fields mean. Every point is then parsed and checked like a
//! written experiment.
//!
//! **Fields that move in step.** A `"together"` group exists so that a flight made faster
//! declares the speed bounds that match it (`experiments/study-speed.json`): a cartesian product
//! would pair fast flights with slow bounds (speed violations every frame) and slow flights with
//! loose bounds (needlessly short lives), and one experiment per speed would lose the sweep's
//! table and plots.

use super::problems::FieldProblem;
use serde_json::Value;

/// Most points one sweep may expand into.
pub(super) const MAX_SWEEP_POINTS: usize = 10_000;

/// One point of a sweep: the value chosen for each swept parameter, in the sweep's order.
pub type SweepChoice = Vec<(String, Value)>;

/// The cartesian product of the axes, the first axis varying slowest.
pub(super) fn cartesian(axes: &[(String, Vec<Value>)]) -> Vec<SweepChoice> {
    let options: Vec<Vec<SweepChoice>> = axes
        .iter()
        .map(|(parameter, values)| {
            values
                .iter()
                .map(|value| vec![(parameter.clone(), value.clone())])
                .collect()
        })
        .collect();
    product_of_options(&options)
}

/// The cartesian product of axes whose options each set one or more fields (a `together` group
/// sets several), the first axis varying slowest; a point's choice lists the fields in axis order.
fn product_of_options(axes: &[Vec<SweepChoice>]) -> Vec<SweepChoice> {
    let points: usize = axes.iter().map(Vec::len).product();
    (0..points)
        .map(|point| {
            let mut rest = point;
            let mut picked: Vec<&SweepChoice> = axes
                .iter()
                .rev()
                .map(|options| {
                    let option = &options[rest % options.len()];
                    rest /= options.len();
                    option
                })
                .collect();
            picked.reverse();
            picked.into_iter().flatten().cloned().collect()
        })
        .collect()
}

/// `parameter=value, …` as labels and error paths show a point: numbers and booleans as JSON
/// writes them, strings without quotes, lists and objects as JSON.
pub fn choice_label(choice: &[(String, Value)]) -> String {
    choice
        .iter()
        .map(|(parameter, value)| match value {
            Value::String(text) => format!("{parameter}={text}"),
            other => format!("{parameter}={other}"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// One point of the experiment's top-level sweep, as a whole experiment document.
pub(super) struct ExperimentPoint {
    /// `None` when the experiment has no top-level sweep (its only point is itself).
    pub choice: Option<SweepChoice>,
    /// The point's short name from the sweep's `"labels"`, if it gives them.
    pub label: Option<String>,
    pub document: Value,
}

/// The key of a top-level sweep's list of point labels.
const LABELS: &str = "labels";

/// Longest point label (it names a folder).
const MAX_LABEL_CHARS: usize = 64;

/// The sweep's `"labels"`: one per point, in the points' order, each a safe folder name (ASCII
/// letters, digits and `-_.+=`, not starting with `.`, at most [`MAX_LABEL_CHARS`]), no two alike.
fn point_labels(labels: &Value, points: usize) -> Result<Vec<String>, FieldProblem> {
    let problem = |field: String, problem: String| FieldProblem { field, problem };
    let Some(list) = labels.as_array() else {
        return Err(problem(
            format!("sweep.{LABELS}"),
            format!("expected a list of {points} point labels, one per point in the sweep's order"),
        ));
    };
    if list.len() != points {
        return Err(problem(
            format!("sweep.{LABELS}"),
            format!(
                "{} labels: expected {points}, one per point of the sweep (in its order, the \
                 first swept field varying slowest)",
                list.len()
            ),
        ));
    }
    let mut seen: Vec<String> = Vec::new();
    for (k, label) in list.iter().enumerate() {
        let field = format!("sweep.{LABELS}[{k}]");
        let Some(text) = label.as_str() else {
            return Err(problem(field, format!("{label}: expected a string")));
        };
        let safe = !text.is_empty()
            && text.chars().count() <= MAX_LABEL_CHARS
            && !text.starts_with('.')
            && text
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_.+=".contains(c));
        if !safe {
            return Err(problem(
                field,
                format!(
                    "{text:?}: expected 1 to {MAX_LABEL_CHARS} ASCII letters, digits or -_.+= \
                     not starting with '.' (the label names the point's folder)"
                ),
            ));
        }
        if let Some(earlier) = seen.iter().position(|s| s == text) {
            return Err(problem(
                field,
                format!("{text:?} is already the label of point {earlier}: expected unique labels"),
            ));
        }
        seen.push(text.to_string());
    }
    Ok(seen)
}

/// Point `k`'s document (its top-level sweep expanded away) of an experiment file's text, as the
/// plan expanded it; `None` when the text is not JSON or has no point `k`. For outputs that write
/// the experiment back (`tuned-experiment.json`).
pub fn point_document(bytes: &[u8], k: usize) -> Option<Value> {
    let document = serde_json::from_slice(bytes).ok()?;
    let mut points = expand_experiment(document).ok()?;
    (k < points.len()).then(|| points.swap_remove(k).document)
}

/// Fields a top-level sweep may not set: they identify the experiment or the sweep itself.
const UNSWEEPABLE: &[&str] = &["format_version", "name", "sweep"];

/// Expands the document's top-level `"sweep"` (removed from every point). A document without one
/// is its own single point.
pub(super) fn expand_experiment(mut document: Value) -> Result<Vec<ExperimentPoint>, FieldProblem> {
    let sweep = match document.as_object_mut() {
        Some(top) => top.remove("sweep"),
        None => None,
    };
    let Some(sweep) = sweep else {
        return Ok(vec![ExperimentPoint {
            choice: None,
            label: None,
            document,
        }]);
    };
    let problem = |field: String, problem: String| FieldProblem { field, problem };
    let Some(sweep) = sweep.as_object().filter(|s| !s.is_empty()) else {
        return Err(problem(
            "sweep".into(),
            "expected a non-empty object of field paths and value lists, e.g. \
             {\"terrain.synthetic.level\": [10, 12]}"
                .into(),
        ));
    };
    let mut axes: Vec<Vec<SweepChoice>> = Vec::new();
    for (key, values) in sweep {
        if key == LABELS {
            continue;
        }
        if key == TOGETHER {
            axes.push(together_axis(values)?);
        } else {
            let values = sweep_values(key, values)?;
            axes.push(
                values
                    .into_iter()
                    .map(|value| vec![(key.clone(), value)])
                    .collect(),
            );
        }
    }
    if let Some(together) = sweep.get(TOGETHER).and_then(Value::as_object)
        && let Some(repeated) = together.keys().find(|path| sweep.contains_key(*path))
    {
        return Err(problem(
            format!("sweep.{TOGETHER}.{repeated}"),
            "also swept on its own: expected each field in one axis".into(),
        ));
    }
    let points: usize = axes.iter().map(Vec::len).product();
    if axes.is_empty() {
        return Err(problem(
            "sweep".into(),
            format!("only {LABELS:?}: expected at least one swept field"),
        ));
    }
    if points > MAX_SWEEP_POINTS {
        return Err(problem(
            "sweep".into(),
            format!("{points} points: expected at most {MAX_SWEEP_POINTS}"),
        ));
    }
    let mut labels = match sweep.get(LABELS) {
        Some(labels) => point_labels(labels, points)?
            .into_iter()
            .map(Some)
            .collect(),
        None => vec![None; points],
    }
    .into_iter();
    product_of_options(&axes)
        .into_iter()
        .map(|choice| {
            let mut point = document.clone();
            for (path, value) in &choice {
                set_field(&mut point, path, value.clone())
                    .map_err(|message| problem(format!("sweep.{path}"), message))?;
            }
            Ok(ExperimentPoint {
                choice: Some(choice),
                label: labels.next().flatten(),
                document: point,
            })
        })
        .collect()
}

/// The key of a top-level sweep's group of fields that change in step.
const TOGETHER: &str = "together";

/// A swept field's non-empty list of values; the path must point into the settings.
fn sweep_values(path: &str, values: &Value) -> Result<Vec<Value>, FieldProblem> {
    let problem = |problem: String| FieldProblem {
        field: format!("sweep.{path}"),
        problem,
    };
    let Some(values) = values.as_array().filter(|v| !v.is_empty()) else {
        return Err(problem("expected a non-empty list of values".into()));
    };
    let first = path.split(['.', '[']).next().unwrap_or_default();
    if UNSWEEPABLE.contains(&first) {
        return Err(problem(format!(
            "{first:?} cannot be swept: expected a path into the experiment's settings"
        )));
    }
    Ok(values.clone())
}

/// `"together": {"path": [v0, v1, …], "other.path": [w0, w1, …]}`: one axis whose k-th option
/// sets every listed field to its k-th value (the lists must be equally long), for settings that
/// must change in step (a flight's speed and the speed bounds that declare it).
fn together_axis(group: &Value) -> Result<Vec<SweepChoice>, FieldProblem> {
    let field = format!("sweep.{TOGETHER}");
    let Some(group) = group.as_object().filter(|g| !g.is_empty()) else {
        return Err(FieldProblem {
            field,
            problem: "expected a non-empty object of field paths and equally long value lists"
                .into(),
        });
    };
    let mut lists = Vec::new();
    for (path, values) in group {
        if path == TOGETHER {
            return Err(FieldProblem {
                field: format!("{field}.{path}"),
                problem: "groups do not nest: expected a field path".into(),
            });
        }
        let values = sweep_values(path, values).map_err(|p| FieldProblem {
            field: format!("{field}.{path}"),
            problem: p.problem,
        })?;
        lists.push((path.clone(), values));
    }
    let length = lists[0].1.len();
    if let Some((path, values)) = lists.iter().find(|(_, v)| v.len() != length) {
        return Err(FieldProblem {
            field: format!("{field}.{path}"),
            problem: format!(
                "{} values: expected {length}, as many as {:?} has (the fields of a group change in step)",
                values.len(),
                lists[0].0
            ),
        });
    }
    Ok((0..length)
        .map(|k| {
            lists
                .iter()
                .map(|(path, values)| (path.clone(), values[k].clone()))
                .collect()
        })
        .collect())
}

/// One step of a field path.
#[derive(Debug, PartialEq)]
enum Step<'a> {
    Key(&'a str),
    Index(usize),
}

fn parse_path(path: &str) -> Result<Vec<Step<'_>>, String> {
    let invalid = || {
        format!(
            "{path:?} is not a field path: expected keys separated by '.', with [k] for an \
             array element, e.g. \"algorithms[0].tau_px\""
        )
    };
    let mut steps = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = part.split_once('[').map_or((part, ""), |(k, r)| (k, r));
        if key.is_empty() {
            return Err(invalid());
        }
        steps.push(Step::Key(key));
        while !rest.is_empty() {
            let (index, after) = rest.split_once(']').ok_or_else(invalid)?;
            steps.push(Step::Index(index.parse().map_err(|_| invalid())?));
            rest = match after.strip_prefix('[') {
                Some(next) => next,
                None if after.is_empty() => "",
                None => return Err(invalid()),
            };
        }
    }
    Ok(steps)
}

/// Sets the field at `path`. Every step but the last must exist; the last key may be new (an
/// optional field the written experiment left out), an array index must exist.
fn set_field(document: &mut Value, path: &str, value: Value) -> Result<(), String> {
    let steps = parse_path(path)?;
    let mut here = document;
    for (k, step) in steps.iter().enumerate() {
        let last = k + 1 == steps.len();
        here = match (step, here) {
            (Step::Key(key), Value::Object(object)) => {
                if last {
                    object.insert(key.to_string(), value);
                    return Ok(());
                }
                object
                    .get_mut(*key)
                    .ok_or_else(|| format!("the experiment has no field {key:?} on this path"))?
            }
            (Step::Index(index), Value::Array(array)) => {
                let length = array.len();
                let element = array.get_mut(*index).ok_or_else(|| {
                    format!("element [{index}] does not exist (the list has {length})")
                })?;
                if last {
                    *element = value;
                    return Ok(());
                }
                element
            }
            (Step::Key(key), _) => {
                return Err(format!("cannot set {key:?}: its parent is not an object"));
            }
            (Step::Index(index), _) => {
                return Err(format!("cannot set [{index}]: its parent is not a list"));
            }
        };
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn the_first_axis_varies_slowest() {
        let axes = vec![
            ("a".to_string(), vec![json!(1), json!(2)]),
            ("b".to_string(), vec![json!("x"), json!("y"), json!("z")]),
        ];
        let labels: Vec<String> = cartesian(&axes).iter().map(|c| choice_label(c)).collect();
        assert_eq!(
            labels,
            [
                "a=1, b=x", "a=1, b=y", "a=1, b=z", "a=2, b=x", "a=2, b=y", "a=2, b=z"
            ]
        );
    }

    /// The labels the sweep `{"view.far_m": [1000, 2000], "labels": labels}` gives its points,
    /// or its problem as `field: problem`.
    fn labels_of(labels: Value) -> Result<Vec<Option<String>>, String> {
        let document =
            json!({"view": {"far_m": 1}, "sweep": {"view.far_m": [1000, 2000], "labels": labels}});
        expand_experiment(document)
            .map(|points| points.into_iter().map(|p| p.label).collect())
            .map_err(|p| format!("{}: {}", p.field, p.problem))
    }

    #[test]
    fn sweep_points_take_their_labels_in_order_and_bad_labels_are_named() {
        assert_eq!(
            labels_of(json!(["near", "far"])),
            Ok(vec![Some("near".to_string()), Some("far".to_string())])
        );
        let problem = |labels: Value| labels_of(labels).unwrap_err();
        assert!(
            problem(json!(["near"])).starts_with("sweep.labels: 1 labels: expected 2"),
            "{}",
            problem(json!(["near"]))
        );
        assert!(
            problem(json!(["a", "a"]))
                .starts_with("sweep.labels[1]: \"a\" is already the label of point 0"),
            "{}",
            problem(json!(["a", "a"]))
        );
        for unsafe_label in ["a/b", "..", "", "π", "a b"] {
            let text = problem(json!(["ok", unsafe_label]));
            assert!(
                text.starts_with("sweep.labels[1]: ") && text.contains("names the point's folder"),
                "{unsafe_label:?}: {text}"
            );
        }
        assert!(problem(json!([1, 2])).starts_with("sweep.labels[0]: 1: expected a string"));
        assert!(problem(json!("near")).starts_with("sweep.labels: expected a list"));
        let only_labels = expand_experiment(json!({"sweep": {"labels": ["a"]}}));
        assert!(only_labels.is_err_and(|p| p.field == "sweep"));
    }

    #[test]
    fn a_top_level_sweep_sets_nested_fields_and_leaves_the_rest() {
        let document = json!({
            "name": "s",
            "terrain": {"synthetic": {"level": 10, "seed": 1}},
            "algorithms": [{"name": "wu", "tau_px": 2}],
            "sweep": {"terrain.synthetic.level": [10, 12], "algorithms[0].tau_px": [4]}
        });
        let points = expand_experiment(document).unwrap();
        assert_eq!(points.len(), 2);
        for (point, level) in points.iter().zip([10, 12]) {
            assert_eq!(
                point.document["terrain"]["synthetic"]["level"],
                json!(level)
            );
            assert_eq!(point.document["terrain"]["synthetic"]["seed"], json!(1));
            assert_eq!(point.document["algorithms"][0]["tau_px"], json!(4));
            assert!(point.document.get("sweep").is_none());
        }
        assert_eq!(
            choice_label(points[1].choice.as_ref().unwrap()),
            "algorithms[0].tau_px=4, terrain.synthetic.level=12"
        );
    }

    #[test]
    fn a_together_group_moves_its_fields_in_step_as_one_axis() {
        let document = json!({
            "flight": {"frames": 10, "path": {"circle": {"frames_per_lap": 100}}},
            "speed_bounds": {"horizontal_m_per_frame": 1},
            "view": {"far_m": 1},
            "sweep": {
                "together": {
                    "flight.path.circle.frames_per_lap": [6000, 600],
                    "speed_bounds.horizontal_m_per_frame": [25, 250]
                },
                "view.far_m": [1000, 2000]
            }
        });
        let points = expand_experiment(document).unwrap();
        let labels: Vec<String> = points
            .iter()
            .map(|p| choice_label(p.choice.as_ref().unwrap()))
            .collect();
        let group = |lap: u32, speed: u32| {
            format!(
                "flight.path.circle.frames_per_lap={lap}, speed_bounds.horizontal_m_per_frame={speed}"
            )
        };
        assert_eq!(
            labels,
            [
                format!("{}, view.far_m=1000", group(6000, 25)),
                format!("{}, view.far_m=2000", group(6000, 25)),
                format!("{}, view.far_m=1000", group(600, 250)),
                format!("{}, view.far_m=2000", group(600, 250)),
            ]
        );
        assert_eq!(
            points[2].document["speed_bounds"]["horizontal_m_per_frame"],
            json!(250)
        );
        assert_eq!(
            points[2].document["flight"]["path"]["circle"]["frames_per_lap"],
            json!(600)
        );
    }

    #[test]
    fn a_together_group_needs_lists_of_one_length() {
        let cases = [
            (
                json!({"a": 1, "b": 1, "sweep": {"together": {"a": [1, 2], "b": [1]}}}),
                "sweep.together.b",
            ),
            (json!({"sweep": {"together": {}}}), "sweep.together"),
            (json!({"sweep": {"together": [1]}}), "sweep.together"),
            (
                json!({"sweep": {"together": {"name": ["x"]}}}),
                "sweep.together.name",
            ),
            (
                json!({"sweep": {"together": {"together": {"a": [1]}}}}),
                "sweep.together.together",
            ),
            (
                json!({"a": 1, "sweep": {"a": [1, 2], "together": {"a": [3, 4]}}}),
                "sweep.together.a",
            ),
        ];
        for (document, field) in cases {
            let error = expand_experiment(document).err().expect("an invalid group");
            assert_eq!(error.field, field, "{}", error.problem);
        }
    }

    #[test]
    fn a_document_without_a_sweep_is_its_own_point() {
        let points = expand_experiment(json!({"name": "plain"})).unwrap();
        assert_eq!(points.len(), 1);
        assert!(points[0].choice.is_none());
    }

    #[test]
    fn bad_sweeps_name_the_swept_field() {
        let cases = [
            (json!({"sweep": {}}), "sweep"),
            (json!({"sweep": {"view.far_m": []}}), "sweep.view.far_m"),
            (json!({"sweep": {"name": ["a"]}}), "sweep.name"),
            (
                json!({"view": {}, "sweep": {"view.far.x": [1]}}),
                "sweep.view.far.x",
            ),
            (json!({"a": [1], "sweep": {"a[3]": [1]}}), "sweep.a[3]"),
            (json!({"a": 1, "sweep": {"a[x]": [1]}}), "sweep.a[x]"),
            (json!({"sweep": {"a..b": [1]}}), "sweep.a..b"),
        ];
        for (document, field) in cases {
            let error = expand_experiment(document).err().expect("an invalid sweep");
            assert_eq!(error.field, field, "{}", error.problem);
        }
    }

    #[test]
    fn a_new_optional_field_may_be_swept_in() {
        let document = json!({"terrain": {"file": {"path": "t.hgt"}},
                              "sweep": {"terrain.file.height_scale": [1, 2]}});
        let points = expand_experiment(document).unwrap();
        assert_eq!(
            points[1].document["terrain"]["file"]["height_scale"],
            json!(2)
        );
    }
}
