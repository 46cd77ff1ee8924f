"""The study's figures (docs/study.md) on the time axis of a drawn frame: the time columns its
tables print, and the inline figures of its prose (one entry's figure or a range of them, a
ratio of two entries, a growth across a sweep's points).

The time axis is report.md's `frame p50 / p95 (µs)` (`frame_ns`: the update plus the upkeep of
the buffers an algorithm keeps, issue #31); `update p50 (µs)`, `upload per frame (kB)` and
`draw calls` stand beside it. Outputs written before #31 have `update p50 / p95 (µs)` only, the
reference whole-terrain entry labelled `reference` and no in-view reference: the block marked
"Before issue #31's regeneration" below reads them as the docs print them today, and is deleted,
with its calls, once `bash scripts/regenerate-plots.sh study` has rewritten the outputs.

This module selects figures report.md and summary.json hold and divides them (ratios, percent
differences, growths); it computes nothing else.
"""

import decimal
import functools
import re

from .outputs import PLOTS, OutputMissing, main_table, shown, summary, tables
from .runs import entry

TIME = "frame p50 / p95 (µs)"
TIME_SECTION = "Median time to a drawn frame"


def first(cell):
    """The first of the figures a cell joins with " / "."""
    return cell.split("/")[0].strip()


def time_columns(row):
    """[(header, cell)]: the time columns a study table prints for one comparison-table row."""
    if TIME not in row:
        return pre_frame_ns_time_columns(row)
    return [
        ("frame p50 (µs)", first(row[TIME])),
        ("update p50 (µs)", row["update p50 (µs)"]),
        ("upload per frame (kB)", row["upload per frame (kB)"]),
        ("draw calls", row["draw calls"]),
    ]


def time_section(name):
    """The heading of a sweep report's time table."""
    if any(section.startswith(TIME_SECTION) for section, _h, _r in tables(report(name))):
        return TIME_SECTION
    return PRE_FRAME_NS_TIME_SECTION


def report(name):
    return PLOTS / name / "report.md"


# --- Before issue #31's regeneration -------------------------------------------------------
# The committed outputs predate `frame_ns`. Each fallback here prints what the docs print from
# them today, so that `scripts/doc-tables --check` passes until the lead regenerates the study;
# then this block goes, with every use of its `pre_frame_ns_*` / `PRE_FRAME_NS_*` names and of
# `NotYetRun` (time_columns, time_section, row_of, sweep_time_figure, inline, over_entries,
# generators.sweep_points_column).


def pre_frame_ns_time_columns(row):
    """Time column fallback: the one time column of outputs before #31, the update's median."""
    return [("update p50 (µs)", first(row["update p50 / p95 (µs)"]))]


# Sweep heading fallback: the sweep reports' time table before #31.
PRE_FRAME_NS_TIME_SECTION = "Median update time"

# Entry label fallback: the whole-terrain reference was `reference` before the in-view one came.
PRE_FRAME_NS_LABELS = {"reference whole terrain": "reference"}

# Absent entry fallback: entries the committed outputs do not have yet; a figure that needs
# one prints this instead.
PRE_FRAME_NS_ABSENT = {"reference in view"}
PRE_FRAME_NS_ABSENT_TEXT = "not yet measured (the committed outputs predate that entry)"


def pre_frame_ns_lacks(row, column):
    """Sweep column fallback: a sweep point's report before #31 has no `column`: no table."""
    return column not in row


# --- End of the block before issue #31's regeneration --------------------------------------


class NotYetRun(Exception):
    """A figure needs an entry that the committed outputs predate (`PRE_FRAME_NS_ABSENT`)."""


FLIGHTS = ("study-circle", "study-low-rough", "study-turning")


def expanded(experiments):
    """The experiments a figure names: `flights` is the study's three flights, `NAME@*` every
    point of sweep NAME in its report's order."""
    found = []
    for spec in experiments:
        if spec == "flights":
            found += FLIGHTS
        elif spec.endswith("@*"):
            name = spec[:-2]
            found += [f"{name}@{folder}" for _point, folder in sweep_points(name)]
        else:
            found.append(spec)
    if not found:
        raise OutputMissing("no experiment named")
    return found


def experiment_folder(spec):
    """The outputs folder of `spec`: an experiment (`study-circle`), or one point of a sweep,
    named by one of its swept values (`study-speed@frames_per_lap=190`,
    `study-scaling@level=14`)."""
    if "@" not in spec:
        return spec
    name, value = spec.split("@", 1)
    folder = PLOTS / name
    if not folder.is_dir():
        raise OutputMissing(f"{shown(folder)}: missing (run `bash scripts/regenerate-plots.sh "
                            f"{name}`)")
    pattern = re.compile(r"(^|[._])" + re.escape(value) + r"(_|$)")
    found = sorted(p.name for p in folder.iterdir() if p.is_dir() and pattern.search(p.name))
    if len(found) != 1:
        raise OutputMissing(f"{shown(folder)}: {len(found)} point folders hold {value!r} "
                            f"(expected one: {', '.join(found) or 'none'})")
    return f"{name}/{found[0]}"


def row_of(spec, label):
    """The comparison-table row of entry `label` in `spec`'s report.md."""
    name = experiment_folder(spec)
    rows = main_table(name)
    if label not in rows and label in PRE_FRAME_NS_LABELS:
        label = PRE_FRAME_NS_LABELS[label]
    if label not in rows:
        if label in PRE_FRAME_NS_ABSENT:
            raise NotYetRun(label)
        raise OutputMissing(f"plots/{name}/report.md: no entry {label!r} in the comparison "
                            f"table (entries: {', '.join(rows)})")
    return name, rows[label]


def figure(spec, label, column):
    """One figure of an entry's comparison-table row, as a number. `column` is `time` (the
    time axis), `update` (the update's median), or a column's header, with `:K` to pick the
    K-th of the figures a cell joins with " / " (0 first); a † mark is left out."""
    if column == "time" and "@" in spec:
        return sweep_time_figure(spec, label)
    name, row = row_of(spec, label)
    times = dict(time_columns(row))
    if column == "time":
        cell = times.get("frame p50 (µs)") or times["update p50 (µs)"]
    elif column == "update":
        cell = times["update p50 (µs)"]
    else:
        header, _, part = column.partition(":")
        if header not in row:
            raise OutputMissing(f"plots/{name}/report.md: no column {header!r} (columns: "
                                f"{', '.join(row)})")
        cell = row[header]
        if part:
            pieces = [p.strip() for p in cell.split("/")]
            k = int(part)
            if not 0 <= k < len(pieces):
                raise OutputMissing(f"plots/{name}/report.md: {label!r} {header!r} is {cell!r}, "
                                    f"which has no part {k}")
            cell = pieces[k]
    try:
        return float(cell.replace("†", "").strip())
    except ValueError:
        raise OutputMissing(f"plots/{name}/report.md: {label!r} {column!r} is {cell!r}, not a "
                            "number")


def span_text(values, digits):
    """`values` printed with `digits` decimals: one figure when they print alike, else the
    smallest and the largest, `17–82`."""
    low, high = (rounded(v, digits) for v in (min(values), max(values)))
    return low if low == high else f"{low}–{high}"


def rounded(value, digits):
    """`value` with `digits` decimals, halves rounded up as roamsim prints them (156.5 → 157);
    negative `digits` round to tens, hundreds… (8415.1 with -2 → 8400)."""
    step = decimal.Decimal(1).scaleb(-int(digits))
    exact = decimal.Decimal(repr(value))
    if int(digits) >= 0:
        return str(exact.quantize(step, rounding=decimal.ROUND_HALF_UP))
    return str(int((exact / step).quantize(1, rounding=decimal.ROUND_HALF_UP) * step))


def inline(function):
    """An inline generator that prints `PRE_FRAME_NS_ABSENT_TEXT` for an entry not yet run."""
    @functools.wraps(function)
    def generator(*arguments):
        try:
            text = function(*arguments)
        except NotYetRun:
            text = PRE_FRAME_NS_ABSENT_TEXT
        print(text, end="")
    return generator


@inline
def figures(column, digits, entries, *experiments):
    """figure COLUMN DIGITS ENTRY[|ENTRY…] EXPERIMENT …: an entry's figure (`time`, `update` or
    a comparison-table column, see `figure`), or the range of it over the entries and
    experiments (`flights`, `NAME@*`: see `expanded`), with DIGITS decimals."""
    return span_text(over_entries(lambda spec, label: figure(spec, label, column), entries,
                                  experiments), digits)


def ratios(column, numerators, denominator, experiments):
    """Each numerator's figure over the denominator's, in each experiment. A numerator with one
    `*` stands for every entry it matches, each over the denominator whose `*` is replaced by
    the same text (`"roam deferral=true, *"` over `"roam deferral=false, *"`)."""
    found = []
    for spec in expanded(experiments):
        for numerator in numerators.split("|"):
            for label, matched in matching(spec, numerator):
                found.append(figure(spec, label, column)
                             / figure(spec, denominator.replace("*", matched), column))
    return found


def matching(spec, pattern):
    """[(label, the text `*` matched)] of the entries `pattern` names in `spec`."""
    if "*" not in pattern:
        return [(pattern, "")]
    head, tail = pattern.split("*", 1)
    regex = re.compile(re.escape(head) + "(.*)" + re.escape(tail) + "$")
    found = [(label, m.group(1)) for label in main_table(experiment_folder(spec))
             if (m := regex.match(label))]
    if not found:
        raise OutputMissing(f"plots/{experiment_folder(spec)}/report.md: no entry matches "
                            f"{pattern!r}")
    return found


@inline
def ratio(column, digits, numerators, denominator, *experiments):
    """ratio COLUMN DIGITS NUMERATOR[|NUMERATOR…] DENOMINATOR EXPERIMENT …: NUMERATOR's figure
    divided by DENOMINATOR's in each experiment; one ratio, or their range (`*`: see
    `ratios`)."""
    return span_text(ratios(column, numerators, denominator, experiments), digits)


@inline
def more(column, digits, entries, other, *experiments):
    """more COLUMN DIGITS ENTRY[|ENTRY…] OTHER EXPERIMENT …: how many percent ENTRY's figure is
    above OTHER's in each experiment (negative: below); one figure, or their range."""
    return span_text([(r - 1) * 100 for r in ratios(column, entries, other, experiments)],
                     digits)


@inline
def less(column, digits, entries, other, *experiments):
    """less COLUMN DIGITS ENTRY[|ENTRY…] OTHER EXPERIMENT …: how many percent ENTRY's figure is
    below OTHER's in each experiment (negative: above); one figure, or their range."""
    return span_text([(1 - r) * 100 for r in ratios(column, entries, other, experiments)],
                     digits)


@inline
def quotient(digits, numerator, denominator, entries, *experiments):
    """quotient DIGITS COLUMN COLUMN ENTRY[|ENTRY…] EXPERIMENT …: an entry's figure in one
    column over its figure in another (`triangles` over `rendered`); one figure, or their range."""
    return span_text(over_entries(lambda spec, label: figure(spec, label, numerator)
                                  / figure(spec, label, denominator), entries, experiments),
                     digits)


def over_entries(value, entries, experiments):
    """`value(experiment, entry)` for each of the entries in each experiment; an entry the
    outputs predate (`PRE_FRAME_NS_ABSENT`) is left out of a range that has others."""
    found = []
    for spec in expanded(experiments):
        for label in entries.split("|"):
            try:
                found.append(value(spec, label))
            except NotYetRun:
                if "|" not in entries:
                    raise
    if not found:
        raise NotYetRun(entries)
    return found


@inline
def growth(column, digits, start, ends, entries):
    """growth COLUMN DIGITS FROM TO[|TO…] ENTRY[|ENTRY…]: an entry's figure in TO divided by its
    figure in FROM (experiments or sweep points, `NAME@VALUE`); the range over them."""
    return span_text([figure(end, label, column) / figure(start, label, column)
                      for end in ends.split("|") for label in entries.split("|")], digits)


@inline
def probe_gap(digits, entries, *experiments):
    """probe-gap DIGITS ENTRY[|ENTRY…] EXPERIMENT …: the largest difference, in percent, between
    a tuned entry's full-flight mean and its probes' mean (summary.json `tuning`)."""
    gaps = []
    for spec in expanded(experiments):
        for label in entries.split("|"):
            record = entry(experiment_folder(spec), label).get("tuning")
            if not record:
                raise OutputMissing(f"plots/{spec}/summary.json: entry {label!r} was not tuned")
            gaps.append(abs(record["full_run_mean"] / record["probe_mean"] - 1) * 100)
    return rounded(max(gaps), digits)


@inline
def preprocessing(digits, algorithm, *experiments):
    """preprocessing DIGITS ALGORITHM EXPERIMENT …: the range over every entry of ALGORITHM of
    its own preprocessing, µs per height sample (summary.json `preprocessing.seconds` over the
    terrain's side²)."""
    values = []
    for spec in expanded(experiments):
        record = summary(experiment_folder(spec))
        samples = record["terrain"]["side"] ** 2
        values += [e["preprocessing"]["seconds"] * 1e6 / samples
                   for e in record["algorithms"] if e["name"] == algorithm]
    if not values:
        raise OutputMissing(f"no {algorithm!r} entry in {', '.join(experiments)}")
    return span_text(values, digits)


def sweep_time_figure(spec, label):
    """An entry's time at one sweep point as the sweep's report.md prints it (more digits than
    the point's own report: `4.19 (×1.00)`)."""
    name = spec.split("@", 1)[0]
    folder = experiment_folder(spec).split("/", 1)[1]
    point = next(point for point, found in sweep_points(name) if found == folder)
    section = time_section(name)
    for found_section, _header, rows in tables(report(name)):
        if found_section.startswith(section):
            for row in rows:
                if row["entry"] == PRE_FRAME_NS_LABELS.get(label, label) or row["entry"] == label:
                    return float(row[point].split("(")[0])
            if label in PRE_FRAME_NS_ABSENT:
                raise NotYetRun(label)
            raise OutputMissing(f"plots/{name}/report.md: no entry {label!r} under "
                                f"{found_section!r}")
    raise OutputMissing(f"plots/{name}/report.md: no table under {section!r}")


def sweep_points(name):
    """[(point cell, folder)] of a sweep, from its report.md's table of points."""
    for _section, header, rows in tables(report(name)):
        if header[:2] == ["point", "folder"]:
            return [(row["point"], row["folder"].strip("`")) for row in rows]
    raise OutputMissing(f"plots/{name}/report.md: no table of points")
