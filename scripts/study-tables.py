#!/usr/bin/env python3
"""Prints the tables of docs/study.md from the study's committed outputs (plots/study-*/ and
plots/accuracy-vs-time/), after `bash scripts/regenerate-plots.sh study`.

It computes nothing roamsim did not: every figure is read from a run's report.md (the tables
roamsim writes) or summary.json (the tuned parameters); it only selects, joins and orders them.
Python 3 standard library only.

    python3 scripts/study-tables.py            # every table, in the order of docs/study.md
    python3 scripts/study-tables.py circle     # one: circle low-rough turning error-targets
                                               #      nominal speed scaling pareto
    python3 scripts/study-tables.py --fill docs/study.md
        # rewrites, in that file, what stands between `<!-- study-tables NAME -->` and
        # `<!-- /study-tables -->` with table NAME (how docs/study.md's tables were made)
"""

import contextlib
import io
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PLOTS = ROOT / "plots"


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def tables(report):
    """Every table of a report.md: {first header cell of the table's header + section: rows}.

    Returns a list of (section, header, rows), rows as dicts keyed by header cell."""
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


def table(report, section_starts, header_first="entry"):
    for section, header, rows in tables(report):
        if section.startswith(section_starts) and header[0] == header_first:
            return {row[header_first]: row for row in rows}
    return {}


def main_table(report):
    for _section, header, rows in tables(report):
        if header[:2] == ["entry", "algorithm"] and "rendered" in header:
            return {row["entry"]: row for row in rows}
    raise SystemExit(f"{report}: no main comparison table (was the run completed?)")


def summary(folder):
    path = folder / "summary.json"
    if not path.exists():
        raise SystemExit(f"{path}: missing: run `bash scripts/regenerate-plots.sh study` first")
    return json.loads(path.read_text(encoding="utf-8"))


def tuned(summary_json):
    """label -> 'parameter = value' for tuned entries, from summary.json's `tuning` records."""
    found = {}
    for entry in summary_json["algorithms"]:
        record = entry.get("tuning")
        if record:
            found[entry["label"]] = f"{record['parameter']} = {record['value']:.4g}" + (
                "" if record.get("reached", True) else " (not reached)"
            )
    return found


def equal_triangles(name):
    folder = PLOTS / name
    report = folder / "report.md"
    main = main_table(report)
    popping = table(report, "Popping")
    settings = tuned(summary(folder))
    print(f"From `plots/{name}/report.md` (`bash scripts/regenerate-plots.sh {name}`):\n")
    print(
        "| entry | tuned | rendered | triangles | audited error max / mean / p95 (px) "
        "| popping RMSE / max (px) | update p50 (µs) | operations per frame | bytes per sample |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for label, row in main.items():
        pop = popping.get(label, {})
        pop_cell = f"{pop.get('RMSE (px)', '—')} / {pop.get('max (px)', '—')}"
        update = row["update p50 / p95 (µs)"].split("/")[0].strip()
        print(
            f"| {label} | {settings.get(label, '—')} | {row['rendered']} | {row['triangles']} "
            f"| {row['error max / mean / mean of p95 (px)']} | {pop_cell} | {update} "
            f"| {row['splits + merges per frame']} | {row['bytes per sample']} |"
        )
    print()


def error_targets():
    folder = PLOTS / "study-error-targets"
    main = main_table(folder / "report.md")
    settings = tuned(summary(folder))
    algorithms = []
    for label in main:
        base = label.rsplit(" @", 1)[0]
        if base not in algorithms:
            algorithms.append(base)
    print(
        "From `plots/study-error-targets/report.md` "
        "(`bash scripts/regenerate-plots.sh study-error-targets`): rendered triangles (and the "
        "audited mean of per-frame p95 the tuned entry reached) for each target.\n"
    )
    print("| algorithm | 1 px | 2 px | 4 px |")
    print("|---|---|---|---|")
    for base in algorithms:
        row = [base]
        for px in (1, 2, 4):
            entry = main.get(f"{base} @{px}px")
            if entry is None:
                row.append("—")
                continue
            p95 = entry["error max / mean / mean of p95 (px)"].split("/")[-1].strip()
            note = "" if "not reached" not in settings.get(f"{base} @{px}px", "") else " †"
            row.append(f"{entry['rendered']} ({p95} px){note}")
        print("| " + " | ".join(row) + " |")
    print("\n† the search did not reach the target within its tolerance: the closest probe.\n")


def nominal():
    report = PLOTS / "accuracy-vs-time" / "report.md"
    main = main_table(report)
    print(
        "From `plots/accuracy-vs-time/report.md` "
        "(`bash scripts/regenerate-plots.sh accuracy-vs-time`): each entry's nominal tolerance "
        "against its audited error.\n"
    )
    print("| entry | nominal | rendered | audited max / mean / p95 (px) | max ÷ nominal |")
    print("|---|---|---|---|---|")
    for label, row in main.items():
        nominal = None
        for part in label.replace(",", " ").split():
            if part.startswith(("tau_px=", "rho_threshold_px=")):
                nominal = float(part.split("=")[1])
        errors = row["error max / mean / mean of p95 (px)"]
        largest = float(errors.split("/")[0])
        ratio = f"{largest / nominal:.2f}" if nominal else "—"
        shown = f"{nominal:g} px" if nominal else "(not a pixel tolerance)"
        print(f"| {label} | {shown} | {row['rendered']} | {errors} | {ratio} |")
    print()


def sweep(name, section):
    report = PLOTS / name / "report.md"
    for found_section, header, rows in tables(report):
        if found_section.startswith(section):
            print(f"From `plots/{name}/report.md` (`bash scripts/regenerate-plots.sh {name}`), "
                  f"{found_section[0].lower() + found_section[1:]}:\n")
            print("| " + " | ".join(short_point(h) for h in header) + " |")
            print("|" + "---|" * len(header))
            for row in rows:
                print("| " + " | ".join(row[h] for h in header) + " |")
            print()
            return
    raise SystemExit(f"{report}: no table under a heading starting with {section!r}")


def short_point(cell):
    """A sweep point's column header by its first swept value, the field by its last key:
    `flight.path.circle.frames_per_lap=190, speed_bounds…` → `frames_per_lap=190`."""
    first = cell.split(", ")[0]
    if "=" not in first:
        return cell
    field, value = first.split("=", 1)
    return f"{field.split('.')[-1]}={value}"


def pareto():
    for name in ("accuracy-vs-time", "study-circle", "study-low-rough", "study-turning"):
        text = (PLOTS / name / "report.md").read_text(encoding="utf-8")
        for line in text.splitlines():
            if line.startswith("On the accuracy-versus-time Pareto front"):
                print(f"`plots/{name}/report.md`: {line}\n")


def render(which):
    """Table `which` as text (what `print_table` prints)."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        print_table(which)
    return out.getvalue()


def fill(path):
    text = Path(path).read_text(encoding="utf-8")
    block = re.compile(r"(<!-- study-tables ([a-z-]+) -->\n)(.*?)(<!-- /study-tables -->)", re.S)
    filled = block.sub(lambda m: m.group(1) + render(m.group(2)) + m.group(4), text)
    Path(path).write_text(filled, encoding="utf-8")


def main():
    if sys.argv[1:2] == ["--fill"]:
        for path in sys.argv[2:]:
            fill(path)
        return
    chosen = sys.argv[1:] or [
        "circle", "low-rough", "turning", "error-targets", "nominal", "speed", "scaling", "pareto",
    ]
    for which in chosen:
        print(f"### {which}\n")
        print_table(which)


def print_table(which):
    if which in ("circle", "low-rough", "turning"):
        equal_triangles(f"study-{which}")
    elif which == "error-targets":
        error_targets()
    elif which == "nominal":
        nominal()
    elif which == "speed":
        sweep("study-speed", "Median update time")
        sweep("study-speed", "Mean triangles")
    elif which == "scaling":
        sweep("study-scaling", "Median update time")
        sweep("study-scaling", "Memory")
    elif which == "pareto":
        pareto()
    else:
        raise SystemExit(f"unknown table {which!r}: expected one of circle low-rough turning "
                         "error-targets nominal speed scaling pareto")

if __name__ == "__main__":
    main()
