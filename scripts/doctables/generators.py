"""Every generator a doc can name, by name: what each prints, from which committed outputs.

A generator is called with the marker's arguments (strings) and prints its text; `render`
captures it. Block generators print whole lines; inline ones print one figure, no newline.
Adding a generator: write the function, add it to `GENERATORS` with a one-line description.
"""

import contextlib
import inspect
import io

from . import reproductions, study
from .outputs import OutputMissing, main_cell, main_table, table, tables, report_path, tuned


def equal_triangles(name):
    """The study's equal-triangle table of one experiment (docs/study.md §1–§3), timed on the
    time axis of a drawn frame (`study.time_columns`)."""
    main = main_table(name)
    popping = table(name, "Popping")
    settings = tuned(name)
    time_headers = [header for header, _cell in study.time_columns(next(iter(main.values())))]
    print(f"From `plots/{name}/report.md` (`bash scripts/regenerate-plots.sh {name}`):\n")
    headers = (["entry", "tuned", "rendered", "triangles", "audited error max / mean / p95 (px)",
                "popping RMSE / max (px)"] + time_headers
               + ["operations per frame", "bytes per sample"])
    print("| " + " | ".join(headers) + " |")
    print("|" + "---|" * len(headers))
    for label, row in main.items():
        pop = popping.get(label, {})
        pop_cell = f"{pop.get('RMSE (px)', '—')} / {pop.get('max (px)', '—')}"
        times = [cell for _header, cell in study.time_columns(row)]
        cells = ([label, settings.get(label, "—"), row["rendered"], row["triangles"],
                  row["error max / mean / mean of p95 (px)"], pop_cell] + times
                 + [row["splits + merges per frame"], row["bytes per sample"]])
        print("| " + " | ".join(cells) + " |")
    print()


MORPHING = (
    ("chunked LOD (eq. 3.5's per-chunk morph)", "chunked", "chunked morph"),
    ("Röttger (the paper's geomorphing)", "rottger", "rottger geomorphing"),
    ("geomipmapping (de Boer's, borders at the coarser factor)", "geomipmap", "geomipmap morph"),
)


def morphing():
    """Popping, audited p95 and time without and with each algorithm's morphing, on the
    study's three flights (docs/study.md §4)."""
    flights = study.FLIGHTS
    main = {name: main_table(name) for name in flights}
    popping = {name: table(name, "Popping") for name in flights}
    time_header = study.time_columns(next(iter(main[flights[0]].values())))[0][0]
    print("From `plots/study-circle/`, `study-low-rough/` and `study-turning/report.md` (in that "
          "order; `bash scripts/regenerate-plots.sh study`), each entry tuned to 6000 rendered "
          "triangles with and without morphing:\n")
    print(f"| algorithm | popping max (px), off → on | audited p95 (px), off → on "
          f"| {time_header}, off → on |")
    print("|---|---|---|---|")

    def pairs(figure):
        return ", ".join(f"{figure(name, off)} → {figure(name, on)}" for name in flights)

    for title, off, on in MORPHING:
        for name in flights:
            for label in (off, on):
                if label not in main[name] or label not in popping[name]:
                    raise OutputMissing(f"plots/{name}/report.md: no entry {label!r} in its "
                                        "comparison or popping table")
        pop = pairs(lambda name, label: popping[name][label]["max (px)"])
        p95 = pairs(lambda name, label: main[name][label][
            "error max / mean / mean of p95 (px)"].split("/")[2].strip())
        time = pairs(lambda name, label: study.time_columns(main[name][label])[0][1])
        print(f"| {title} | {pop} | {p95} | {time} |")
    print()


def error_targets():
    """Rendered triangles each algorithm needed for each audited error target."""
    name = "study-error-targets"
    main = main_table(name)
    settings = tuned(name)
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
    """Each accuracy-vs-time entry's nominal tolerance against its audited error."""
    main = main_table("accuracy-vs-time")
    print(
        "From `plots/accuracy-vs-time/report.md` "
        "(`bash scripts/regenerate-plots.sh accuracy-vs-time`): each entry's nominal tolerance "
        "against its audited error.\n"
    )
    print("| entry | nominal | rendered | audited max / mean / p95 (px) | max ÷ nominal |")
    print("|---|---|---|---|---|")
    for label, row in main.items():
        nominal_px = None
        for part in label.replace(",", " ").split():
            if part.startswith(("tau_px=", "rho_threshold_px=")):
                nominal_px = float(part.split("=")[1])
        errors = row["error max / mean / mean of p95 (px)"]
        largest = float(errors.split("/")[0])
        ratio = f"{largest / nominal_px:.2f}" if nominal_px else "—"
        shown = f"{nominal_px:g} px" if nominal_px else "(not a pixel tolerance)"
        print(f"| {label} | {shown} | {row['rendered']} | {errors} | {ratio} |")
    print()


def sweep(name, section):
    """A sweep's table across its points, the first under a heading starting with `section`."""
    for found_section, header, rows in tables(report_path(name)):
        if found_section.startswith(section):
            print(f"From `plots/{name}/report.md` (`bash scripts/regenerate-plots.sh {name}`), "
                  f"{found_section[0].lower() + found_section[1:]}:\n")
            print("| " + " | ".join(short_point(h) for h in header) + " |")
            print("|" + "---|" * len(header))
            for row in rows:
                print("| " + " | ".join(row[h] for h in header) + " |")
            print()
            return
    raise OutputMissing(f"plots/{name}/report.md: no table under a heading starting with "
                        f"{section!r}")


def sweep_time(name):
    """A sweep's table of the time to a drawn frame across its points."""
    sweep(name, study.time_section(name))


def sweep_points_column(name, column):
    """One comparison-table column of each sweep point's own report.md, an entry a row, a point
    a column (the sweep's report.md has no table of it)."""
    points = study.sweep_points(name)
    per_point = [main_table(f"{name}/{folder}") for _point, folder in points]
    if study.pre_frame_ns_lacks(next(iter(per_point[0].values())), column):
        return
    labels = []
    for rows in per_point:
        labels += [label for label in rows if label not in labels]
    print(f"From each point's `plots/{name}/…/report.md`, {column} (means over each point's "
          "frames):\n")
    print("| entry | " + " | ".join(short_point(point) for point, _folder in points) + " |")
    print("|---|" + "---|" * len(points))
    for label in labels:
        cells = [rows[label][column] if label in rows else "—" for rows in per_point]
        print(f"| {label} | " + " | ".join(cells) + " |")
    print()


def short_point(cell):
    """A sweep point's column header by its first swept value, the field by its last key:
    `flight.path.circle.frames_per_lap=190, speed_bounds…` → `frames_per_lap=190`."""
    first = cell.split(", ")[0]
    if "=" not in first:
        return cell
    field, value = first.split("=", 1)
    return f"{field.split('.')[-1]}={value}"


def pareto():
    """The Pareto-front sentence of each study run's report.md."""
    for name in ("accuracy-vs-time", "study-circle", "study-low-rough", "study-turning"):
        path = report_path(name)
        if not path.exists():
            raise OutputMissing(f"plots/{name}/report.md: missing")
        for line in path.read_text(encoding="utf-8").splitlines():
            if line.startswith("On the accuracy-versus-time Pareto front"):
                print(f"`plots/{name}/report.md`: {line}\n")


def cell(experiment, entry, column, part=None):
    """One cell of a run's comparison table (inline). `part` k picks the k-th of the figures a
    cell joins with " / " (0 first)."""
    value = main_cell(experiment, entry, column)
    if part is not None:
        pieces = [p.strip() for p in value.split("/")]
        k = int(part)
        if not 0 <= k < len(pieces):
            raise OutputMissing(f"plots/{experiment}/report.md: {entry!r} {column!r} is "
                                f"{value!r}, which has no part {k}")
        value = pieces[k]
    print(value, end="")


GENERATORS = {
    "study-circle": (lambda: equal_triangles("study-circle"),
                     "the study's equal-triangle table on its circle (docs/study.md)"),
    "study-low-rough": (lambda: equal_triangles("study-low-rough"),
                        "the same on the low flight over rough terrain"),
    "study-turning": (lambda: equal_triangles("study-turning"),
                      "the same on the turning flight"),
    "study-error-targets": (error_targets, "triangles each algorithm needs per error target"),
    "study-nominal": (nominal, "nominal tolerance against audited error (accuracy-vs-time)"),
    "study-speed": (lambda: (sweep_time("study-speed"),
                             sweep_points_column("study-speed", "upload per frame (kB)"),
                             sweep_points_column("study-speed", "draw calls"),
                             sweep("study-speed", "Mean triangles")),
                    "the speed sweep: time to a drawn frame, upload, draw calls and triangles "
                    "per point"),
    "study-scaling": (lambda: (sweep_time("study-scaling"),
                               sweep_points_column("study-scaling", "upload per frame (kB)"),
                               sweep_points_column("study-scaling", "draw calls"),
                               sweep("study-scaling", "Memory")),
                      "the terrain-size sweep: time to a drawn frame, upload, draw calls and "
                      "memory per point"),
    "scaling": (lambda: (sweep("scaling", "Median update time"), sweep("scaling", "Memory"),
                         sweep("scaling", "Mean triangles")),
                "the committed terrain-size sweep: update time, memory, triangles per point "
                "(docs/performance.md)"),
    "study-morphing": (morphing, "popping, p95 and time without and with morphing on the "
                                 "study's flights"),
    "study-pareto": (pareto, "the Pareto-front sentences of the study's runs"),
    "cell": (cell, "cell EXPERIMENT ENTRY COLUMN [PART]: one figure of a run's comparison "
                   "table, inline"),
    "figure": (study.figures, "figure COLUMN DIGITS ENTRY[|ENTRY…] EXPERIMENT …: an entry's "
                              "figure (time, update or a column[:K]), or its range, inline"),
    "ratio": (study.ratio, "ratio COLUMN DIGITS NUMERATOR DENOMINATOR EXPERIMENT …: one entry's "
                           "figure over another's, or the range over experiments, inline"),
    "more": (study.more, "more COLUMN DIGITS ENTRY[|ENTRY…] OTHER EXPERIMENT …: percent above "
                         "OTHER's figure, inline"),
    "less": (study.less, "less COLUMN DIGITS ENTRY[|ENTRY…] OTHER EXPERIMENT …: percent below "
                         "OTHER's figure, inline"),
    "probe-gap": (study.probe_gap, "probe-gap DIGITS ENTRY[|ENTRY…] EXPERIMENT …: the largest "
                                   "gap (%) between a tuned entry's run and probe means, inline"),
    "preprocessing": (study.preprocessing, "preprocessing DIGITS ALGORITHM EXPERIMENT …: its "
                                           "own preprocessing per sample (µs), inline"),
    "quotient": (study.quotient, "quotient DIGITS COLUMN COLUMN ENTRY[|ENTRY…] EXPERIMENT …: "
                                 "one column over another for the same entry, inline"),
    "growth": (study.growth, "growth COLUMN DIGITS FROM TO ENTRY[|ENTRY…]: an entry's figure "
                             "in TO over FROM (sweep points: NAME@VALUE), inline"),
    # docs/reproductions/*.md: their own module.
    **reproductions.GENERATORS,
}


class UnknownGenerator(Exception):
    """A marker names a generator that does not exist, or gives it the wrong arguments."""


def render(name, arguments):
    """What generator `name` prints for `arguments`, as a string."""
    if name not in GENERATORS:
        raise UnknownGenerator(f"no generator {name!r} (known: {', '.join(GENERATORS)})")
    function, _description = GENERATORS[name]
    try:
        inspect.signature(function).bind(*arguments)
    except TypeError as error:
        raise UnknownGenerator(f"generator {name!r} with arguments {arguments}: {error}")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        function(*arguments)
    return out.getvalue()
