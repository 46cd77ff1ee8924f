"""The shared readers, cells and inline generators of the reproduction pages' generators
(`reproductions.py` and the `repro_*.py` modules beside it, one per page that grew its own).

A table is a list of entries (rows) and a list of columns, each column a header and a function
of (experiment, entry label) giving the printed cell (`entry_table`); the pages' tables differ in
their columns, which are built from a few shared readers: a mean over frames (from summary.json,
or from frames.csv over a range of frames where the page says so), a fact, a report.md cell.
Inline generators print one such figure into a sentence. Nothing here is measured: every figure
is read, or computed the way the page says (a ratio of two printed figures, a count of frames).
Report columns are read by header name; the update time by `update p50 (µs)`, or by the first
figure of the older `update p50 / p95 (µs)` in outputs written before it (`update_p50`).
Not here: any one paper's tables (their modules), the study's (`generators.py`).
"""

from .outputs import OutputMissing, main_cell, summary, table
from .runs import column, entry, fact, grouped, mean, reports, stat

def source(experiment, note=""):
    """The line naming the run a table is printed from; `note` says which frames it sums up."""
    return (f"From `plots/{experiment}/` (`bash scripts/regenerate-plots.sh {experiment}`, "
            f"{frames_note(experiment)}{note}):\n")


def frames_note(experiment):
    """How many frames the run flew and which the figures summarise."""
    first = next(iter(entry_labels(experiment)))
    record = entry(experiment, first)
    if record["frames_summarised"] == record["frames"]:
        return f"{record['frames']} frames"
    return (f"{record['frames']} frames, the last {record['frames_summarised']} summarised "
            "after the warm-up")


def entry_labels(experiment):
    return [record["label"] for record in summary(experiment)["algorithms"]]


def entry_table(experiment, labels, columns, header_note=True):
    """A markdown table: one row per entry label, one column per (header, cell function)."""
    if header_note:
        print(source(experiment))
    print("| " + " | ".join(header for header, _cell in columns) + " |")
    print("|" + "---|" * len(columns))
    for label in labels:
        print("| " + " | ".join(cell(experiment, label) for _header, cell in columns) + " |")
    print()


# Cells: each returns a function of (experiment, label).

def label_cell(text=None):
    return lambda _experiment, label: f"`{label}`" if text is None else text[label]


def signed(value, digits=0):
    """`value` with the typographic minus the pages use: −41."""
    return f"{value:.{digits}f}".replace("-", "−")


def mean_of(name, digits=0, separator=" ", first=None, last=None):
    """The mean of a frames.csv column: summary.json's mean, or over frames first…last."""
    def cell(experiment, label):
        if first is None and last is None:
            value = stat(experiment, label, name)
        else:
            value = mean(column(experiment, label, name, first or 0, last))
        return grouped(value, digits, separator)
    return cell


def max_of(name, digits=0, separator=" "):
    return lambda experiment, label: grouped(stat(experiment, label, name, "max"), digits,
                                             separator)


def report(name):
    """A report.md comparison-table cell, by its header."""
    return lambda experiment, label: main_cell(experiment, label, name)


def update_p50(experiment, label):
    """The median update time (µs) of the entry's timing pass, as report.md prints it (outputs
    written before the frame columns have `update p50 / p95 (µs)`: its first figure)."""
    try:
        return main_cell(experiment, label, "update p50 (µs)")
    except OutputMissing:
        return main_cell(experiment, label, "update p50 / p95 (µs)").split("/")[0].strip()


def section(experiment, heading, label, name):
    """A cell of the report.md table under `heading` (Popping, Meshes beyond …), by entry."""
    rows = table(experiment, heading)
    if label not in rows or name not in rows[label]:
        raise OutputMissing(f"plots/{experiment}/report.md: no {name!r} of {label!r} under a "
                            f"heading starting with {heading!r}")
    return rows[label][name]


def joined(*cells, separator=" / "):
    return lambda experiment, label: separator.join(cell(experiment, label) for cell in cells)


# Inline figures.

def frames_mean(experiment, label, name, first="0", last="", digits="1"):
    """frames-mean EXPERIMENT ENTRY COLUMN [FIRST [LAST [DIGITS]]]: the mean of a frames.csv
    column over frames FIRST…LAST (LAST empty: to the end); COLUMN may be `a+b`, the sum of
    two columns per frame."""
    names = name.split("+")
    per_name = [column(experiment, label, n, int(first), int(last) if last else None)
                for n in names]
    values = [sum(parts) for parts in zip(*per_name)]
    print(grouped(mean(values), int(digits)), end="")


def summary_stat(experiment, label, name, which="mean", digits="1"):
    """stat EXPERIMENT ENTRY COLUMN [mean|max|p50|p95 [DIGITS]]: summary.json's statistic of a
    frames.csv column over the summarised frames."""
    print(grouped(stat(experiment, label, name, which), int(digits)), end="")


def summary_fact(experiment, label, name, digits="1"):
    """fact EXPERIMENT ENTRY FACT [DIGITS]: one of an entry's facts in summary.json."""
    print(grouped(float(fact(experiment, label, name)), int(digits)), end="")


def update_p50_inline(experiment, label):
    """update-p50 EXPERIMENT ENTRY: the entry's median update time (µs) in report.md."""
    print(update_p50(experiment, label), end="")


def wu_reference_speedup(experiment, *taus):
    """wu-reference-speedup EXPERIMENT TAU ...: the range over the given τ and both zones of the
    reference's median update divided by Wu's (entries `wu tau_px=T, zone=Z` and
    `reference tau_px=T, zone=Z`), as `19–50`."""
    ratios = []
    for tau in taus:
        for zone in ("paper", "conservative"):
            wu = float(update_p50(experiment, f"wu tau_px={tau}, zone={zone}"))
            reference = float(update_p50(experiment, f"reference tau_px={tau}, zone={zone}"))
            ratios.append(reference / wu)
    print(f"{min(ratios):.0f}–{max(ratios):.0f}", end="")


def section_cell(experiment, heading, label, name, digits=None):
    """section-cell EXPERIMENT HEADING ENTRY COLUMN [DIGITS]: a cell of the report.md table under
    the heading starting with HEADING (Popping, Meshes, …); DIGITS rounds it."""
    value = section(experiment, heading, label, name)
    print(value if digits is None else f"{float(value):.{int(digits)}f}", end="")


def frames_sum(experiment, label, name):
    """frames-sum EXPERIMENT ENTRY COLUMN: the sum of a frames.csv column over the flight."""
    print(grouped(sum(column(experiment, label, name))), end="")


def run_record(experiment, key):
    """run EXPERIMENT KEY: a figure of summary.json's `run` record (peak_resident_bytes, …),
    what the operating system reported to the run, grouped by thousands."""
    record = summary(experiment).get("run") or {}
    if key not in record:
        raise OutputMissing(f"plots/{experiment}/summary.json: no run.{key} (run: "
                            f"{', '.join(record)})")
    print(grouped(float(record[key])), end="")


def frames_above(experiment, label, name, threshold, first="0"):
    """frames-above EXPERIMENT ENTRY COLUMN THRESHOLD [FIRST]: how many frames from FIRST on
    have COLUMN above THRESHOLD."""
    values = column(experiment, label, name, int(first))
    print(sum(1 for value in values if value > float(threshold)), end="")


def frames_extreme(experiment, label, name, which, first="0", last="", digits="0"):
    """frames-extreme EXPERIMENT ENTRY COLUMN min|max [FIRST [LAST [DIGITS]]]: the smallest or
    largest value of a frames.csv column over frames FIRST…LAST (LAST empty: to the end)."""
    values = column(experiment, label, name, int(first), int(last) if last else None)
    value = {"min": min, "max": max}[which](values)
    print(grouped(value, int(digits)).replace("-", "−"), end="")


def frames_off(experiment, label, name, goal, percent, first="0"):
    """frames-off EXPERIMENT ENTRY COLUMN GOAL PERCENT [FIRST]: how many frames from FIRST on
    have COLUMN more than PERCENT % below GOAL (a negative PERCENT: more than |PERCENT| % above
    it)."""
    values = column(experiment, label, name, int(first))
    goal, percent = float(goal), float(percent)
    if percent >= 0:
        count = sum(1 for value in values if value < goal * (1 - percent / 100))
    else:
        count = sum(1 for value in values if value > goal * (1 - percent / 100))
    print(count, end="")


def frames_worst_percent(experiment, label, name, goal, first="0", digits="1"):
    """frames-worst EXPERIMENT ENTRY COLUMN GOAL [FIRST [DIGITS]]: the frame from FIRST on
    farthest from GOAL, as a signed percentage of GOAL (−7.8)."""
    values = column(experiment, label, name, int(first))
    goal = float(goal)
    worst = max(values, key=lambda value: abs(value - goal))
    print(signed(100 * (worst - goal) / goal, int(digits)), end="")


def stat_ratio(experiment, label_a, name_a, label_b, name_b, which="mean", digits="2"):
    """ratio EXPERIMENT ENTRY_A COLUMN_A ENTRY_B COLUMN_B [mean|max|p50|p95 [DIGITS]]: A's
    summary.json statistic divided by B's (COLUMN `update-p50`: report.md's median update)."""
    def value(label, name):
        if name == "update-p50":
            return float(update_p50(experiment, label))
        return stat(experiment, label, name, which)
    print(f"{value(label_a, name_a) / value(label_b, name_b):.{int(digits)}f}", end="")


GENERATORS = {
    "frames-mean": (frames_mean, "frames-mean EXPERIMENT ENTRY COLUMN [FIRST [LAST [DIGITS]]]: "
                                 "a mean over frames of frames.csv, inline"),
    "stat": (summary_stat, "stat EXPERIMENT ENTRY COLUMN [mean|max|p50|p95 [DIGITS]]: "
                           "summary.json's statistic of a column, inline"),
    "fact": (summary_fact, "fact EXPERIMENT ENTRY FACT [DIGITS]: an entry's fact, inline"),
    "update-p50": (update_p50_inline, "update-p50 EXPERIMENT ENTRY: the median update time "
                                      "(µs) of report.md, either header, inline"),
    "wu-reference-speedup": (wu_reference_speedup, "wu-reference-speedup EXPERIMENT TAU ...: "
                                                   "the reference's update over Wu's, a range"),
    "section-cell": (section_cell, "section-cell EXPERIMENT HEADING ENTRY COLUMN [DIGITS]: a "
                                   "cell of another report.md table, inline"),
    "frames-sum": (frames_sum, "frames-sum EXPERIMENT ENTRY COLUMN: a column's sum over the "
                               "flight, inline"),
    "run": (run_record, "run EXPERIMENT KEY: a figure of summary.json's run record, inline"),
    "frames-above": (frames_above, "frames-above EXPERIMENT ENTRY COLUMN THRESHOLD [FIRST]: "
                                   "frames whose COLUMN exceeds THRESHOLD, inline"),
    "frames-extreme": (frames_extreme, "frames-extreme EXPERIMENT ENTRY COLUMN min|max [FIRST "
                                       "[LAST [DIGITS]]]: a column's extreme over frames, inline"),
    "frames-off": (frames_off, "frames-off EXPERIMENT ENTRY COLUMN GOAL PERCENT [FIRST]: frames "
                               "more than PERCENT % below GOAL, inline"),
    "frames-worst": (frames_worst_percent, "frames-worst EXPERIMENT ENTRY COLUMN GOAL [FIRST "
                                           "[DIGITS]]: the farthest frame from GOAL, in %, inline"),
    "stat-ratio": (stat_ratio, "stat-ratio EXPERIMENT ENTRY_A COLUMN_A ENTRY_B COLUMN_B [WHICH [DIGITS]]: "
                          "one entry's statistic over another's, inline"),
}
