"""Reading the committed outputs: report.md tables and summary.json records under plots/.

Every reader fails with `OutputMissing`, naming the file and what was looked for, so that a doc
check says which output a figure needs rather than a Python traceback.
"""

import json
import os
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
# The committed outputs, or another run's folder of them (`ROAMSIM_PLOTS=/tmp/runs`, laid out as
# plots/ is: one folder per experiment) to see what the generators print from a fresh run.
PLOTS = Path(os.environ.get("ROAMSIM_PLOTS") or ROOT / "plots").resolve()


class OutputMissing(Exception):
    """A committed output, or a table, row or column in it, that a generator needs is absent."""


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def shown(path):
    """`path` as a message names it: relative to the repository when it lies in it."""
    try:
        return str(path.relative_to(ROOT))
    except ValueError:
        return str(path)


def tables(report):
    """Every table of a report.md, in order, as (section heading, header cells, rows), each row
    a dict keyed by header cell."""
    if not report.exists():
        raise OutputMissing(f"{shown(report)}: missing (run "
                            f"`bash scripts/regenerate-plots.sh {report.parent.name}`)")
    found = []
    section = ""
    lines = report.read_text(encoding="utf-8").splitlines()
    k = 0
    while k < len(lines):
        line = lines[k]
        if line.startswith("#"):
            section = line.lstrip("#").strip()
        if line.startswith("| ") and k + 1 < len(lines) and lines[k + 1].startswith("|---"):
            header = cells(line)
            rows = []
            k += 2
            while k < len(lines) and lines[k].startswith("|"):
                rows.append(dict(zip(header, cells(lines[k]))))
                k += 1
            found.append((section, header, rows))
            continue
        k += 1
    return found


def report_path(experiment):
    return PLOTS / experiment / "report.md"


def table(experiment, section_starts, header_first="entry"):
    """The rows, keyed by their first cell, of the first table under a heading starting with
    `section_starts` whose first header cell is `header_first` ({} when there is none)."""
    for section, header, rows in tables(report_path(experiment)):
        if section.startswith(section_starts) and header[0] == header_first:
            return {row[header_first]: row for row in rows}
    return {}


def main_table(experiment):
    """The comparison table of a run's report.md, keyed by entry label."""
    for _section, header, rows in tables(report_path(experiment)):
        if header[:2] == ["entry", "algorithm"] and "rendered" in header:
            return {row["entry"]: row for row in rows}
    raise OutputMissing(f"plots/{experiment}/report.md: no main comparison table "
                        "(was the run completed?)")


def main_cell(experiment, entry, column):
    """One cell of the comparison table, with clear errors for a missing row or column."""
    rows = main_table(experiment)
    if entry not in rows:
        raise OutputMissing(f"plots/{experiment}/report.md: no entry {entry!r} in the comparison "
                            f"table (entries: {', '.join(rows)})")
    row = rows[entry]
    if column not in row:
        raise OutputMissing(f"plots/{experiment}/report.md: no column {column!r} (columns: "
                            f"{', '.join(row)})")
    return row[column]


def summary(experiment):
    path = PLOTS / experiment / "summary.json"
    if not path.exists():
        raise OutputMissing(f"plots/{experiment}/summary.json: missing (run "
                            f"`bash scripts/regenerate-plots.sh {experiment}`)")
    return json.loads(path.read_text(encoding="utf-8"))


def tuned(experiment):
    """label -> 'parameter = value' for the tuned entries of a run, from summary.json."""
    found = {}
    for entry in summary(experiment)["algorithms"]:
        record = entry.get("tuning")
        if record:
            found[entry["label"]] = f"{record['parameter']} = {record['value']:.4g}" + (
                "" if record.get("reached", True) else " (not reached)"
            )
    return found
