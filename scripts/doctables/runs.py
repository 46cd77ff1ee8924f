"""Reading one run's per-entry figures: summary.json's statistics and facts, frames.csv's rows.

The reproductions' generators (`reproductions.py`) quote means over a run's frames, facts of an
entry, and figures over a range of frames (frames 1–399, 100–999) that summary.json does not
hold; these readers give each, and fail with `OutputMissing` naming the file, the entry and
the column when one is absent. This module computes nothing a doc does not say how to compute.
"""

import csv
import functools

from .outputs import PLOTS, OutputMissing, summary


def _entries(experiment):
    return {entry["label"]: entry for entry in summary(experiment)["algorithms"]}


def entry(experiment, label):
    """summary.json's record of one entry."""
    entries = _entries(experiment)
    if label not in entries:
        raise OutputMissing(f"plots/{experiment}/summary.json: no entry {label!r} (entries: "
                            f"{', '.join(entries)})")
    return entries[label]


def stat(experiment, label, column, which="mean"):
    """A statistic (mean, max, p50, p95) of one frames.csv column over the summarised frames."""
    columns = entry(experiment, label)["columns"]
    if column not in columns:
        raise OutputMissing(f"plots/{experiment}/summary.json: entry {label!r} has no column "
                            f"{column!r}")
    value = columns[column].get(which)
    if value is None:
        raise OutputMissing(f"plots/{experiment}/summary.json: entry {label!r} column {column!r} "
                            f"has no {which!r}")
    return value


def fact(experiment, label, name):
    """One of an entry's facts (summary.json `facts`)."""
    facts = entry(experiment, label).get("facts") or {}
    if name not in facts:
        raise OutputMissing(f"plots/{experiment}/summary.json: entry {label!r} has no fact "
                            f"{name!r} (facts: {', '.join(facts)})")
    return facts[name]


@functools.lru_cache(maxsize=None)
def _frames(experiment):
    path = PLOTS / experiment / "frames.csv"
    if not path.exists():
        raise OutputMissing(f"plots/{experiment}/frames.csv: missing (run "
                            f"`bash scripts/regenerate-plots.sh {experiment}`)")
    by_label = {}
    with path.open(encoding="utf-8", newline="") as handle:
        for row in csv.DictReader(handle):
            by_label.setdefault(row["algorithm"], []).append(row)
    return by_label


def reports(experiment, label, name):
    """Whether the entry reports frames.csv column `name` (an entry leaves the columns of
    another algorithm's counters empty)."""
    rows = _frames(experiment).get(label) or []
    return bool(rows) and rows[-1].get(name, "") != ""


def column(experiment, label, name, first=0, last=None):
    """One frames.csv column of one entry as floats, frames `first` to `last` inclusive (empty
    cells, columns an entry does not report, are refused)."""
    rows = _frames(experiment).get(label)
    if rows is None:
        raise OutputMissing(f"plots/{experiment}/frames.csv: no rows of entry {label!r}")
    values = []
    for row in rows:
        frame = int(row["frame"])
        if frame < first or (last is not None and frame > last):
            continue
        cell = row.get(name, "")
        if cell == "":
            raise OutputMissing(f"plots/{experiment}/frames.csv: entry {label!r} has no "
                                f"{name!r} in frame {frame}")
        values.append(float(cell))
    return values


def mean(values):
    return sum(values) / len(values)


def grouped(value, digits=0, separator=" "):
    """`value` with `digits` decimals and its thousands grouped: 110117 → '110 117'."""
    text = f"{value:,.{digits}f}"
    return text.replace(",", separator)
