"""The generators of docs/reproductions/*.md: each paper's tables, printed from the committed
outputs of the experiments the page runs (`plots/<experiment>/`, made by
`bash scripts/regenerate-plots.sh reproductions`).

A table is a list of entries (rows) and a list of columns, each column a header and a function
of (experiment, entry label) giving the printed cell (`entry_table`); the pages' tables differ in
their columns, which are built from a few shared readers: a mean over frames (from summary.json,
or from frames.csv over a range of frames where the page says so), a fact, a report.md cell.
Inline generators print one such figure into a sentence. Nothing here is measured: every figure
is read, or computed the way the page says (a ratio of two printed figures, a count of frames).
Not here: the study's and performance.md's generators (`generators.py`). Report columns are read
by header name; the update time by `update p50 (µs)`, or by the first figure of the older
`update p50 / p95 (µs)` in outputs written before it (`update_p50`).
"""

from .outputs import OutputMissing, main_cell, summary, table
from .runs import column, entry, fact, grouped, mean, reports, stat


def source(experiment, note=""):
    """The line naming the run a table is printed from; `note` says which frames it sums up."""
    return (f"From `plots/{experiment}/` (`bash scripts/regenerate-plots.sh {experiment}`, "
            f"{frames_note(experiment)}{note}):\n")


def frames_note(experiment):
    """How many frames the run flew and which the figures summarise."""
    first = next(iter(_labels(experiment)))
    record = entry(experiment, first)
    if record["frames_summarised"] == record["frames"]:
        return f"{record['frames']} frames"
    return (f"{record['frames']} frames, the last {record['frames_summarised']} summarised "
            "after the warm-up")


def _labels(experiment):
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


# Lindstrom et al. 1996 (docs/reproductions/lindstrom.md).

LINDSTROM = "lindstrom-tau-sweep"
LINDSTROM_PAPER = {"0.5": 62497, "1": 23287, "2": 8612, "4": 3385}


def _lindstrom_label(tau):
    return f"lindstrom τ={tau}"


def lindstrom_sweep():
    """The τ sweep's polygon counts beside the paper's, with the ratio per halving of τ."""
    taus = list(LINDSTROM_PAPER)
    mesh = [stat(LINDSTROM, _lindstrom_label(t), "triangles") for t in taus]
    rendered = [stat(LINDSTROM, _lindstrom_label(t), "triangles_rendered") for t in taus]
    paper = [LINDSTROM_PAPER[t] for t in taus]

    def ratio(values, k):
        return f"{values[k] / values[k + 1]:.2f}" if k + 1 < len(values) else "—"

    print(source(LINDSTROM))
    print("| τ (px) | paper polygons | ratio to next τ | triangles (mesh) | ratio "
          "| triangles rendered | ratio |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for k, tau in enumerate(taus):
        print(f"| {tau} | {grouped(paper[k], 0, ',')} | {ratio(paper, k)} "
              f"| {grouped(mesh[k], 0, ',')} | {ratio(mesh, k)} "
              f"| {grouped(rendered[k], 0, ',')} | {ratio(rendered, k)} |")
    print()
    halvings = len(taus) - 1
    parts = []
    for name, values in (("paper", paper), ("mesh", mesh), ("rendered", rendered)):
        whole = values[0] / values[-1]
        parts.append(f"{name} ×{whole:.1f} (×{whole ** (1 / halvings):.2f}"
                     + (" per halving on average)" if name == "paper" else ")"))
    print(f"Over the three halvings (τ = {taus[0]} → {taus[-1]}): " + ", ".join(parts) + ".\n")


def lindstrom_work():
    """What Lindstrom's algorithm did per frame at each τ, and its audited error."""
    def blocks(experiment, label):
        return " / ".join(grouped(stat(experiment, label, name), digits, ",")
                          for name, digits in (("blocks_coarsest", 0), ("blocks_partial", 0),
                                               ("blocks_finest", 1)))

    def errors(experiment, label):
        return (f"{stat(experiment, label, 'audit_projected_max_px'):.2f} / "
                f"{stat(experiment, label, 'audit_projected_max_px', 'max'):.2f} / "
                f"{stat(experiment, label, 'audit_projected_mean_px'):.2f}")

    def above(experiment, label):
        tau = float(label.split("=")[1])
        values = column(experiment, label, "audit_projected_max_px")
        return f"{sum(1 for v in values if v > tau)} of {len(values)}"

    taus = {_lindstrom_label(t): t for t in LINDSTROM_PAPER}
    entry_table(LINDSTROM, list(taus), [
        ("τ (px)", label_cell(taus)),
        ("metric evaluations", mean_of("metric_evaluations", 0, ",")),
        ("vertices decided by interval", mean_of("vertices_by_interval", 0, ",")),
        ("forced activations", mean_of("forced_activations", 0, ",")),
        ("blocks coarsest / partial / finest", blocks),
        ("audited error: mean of maxima / worst / mean (projected px)", errors),
        ("frames above τ", above),
        ("update p50 (µs)", update_p50),
    ])


# ROAM'97 (docs/reproductions/roam.md).

def _priorities(experiment, label):
    return mean(column(experiment, label, "priority_recomputations", 1))


def roam_deferral():
    """Priorities recomputed and update time with and without deferral, one run."""
    name = "roam-deferral"
    rows = ["roam τ=8px flags", "roam τ=8px flags deferral", "roam target=6000 flags",
            "roam target=6000 flags deferral"]

    def priorities(experiment, label):
        text = grouped(_priorities(experiment, label), 1)
        if label.endswith(" deferral"):
            without = _priorities(experiment, label[: -len(" deferral")])
            text += f" (**{without / _priorities(experiment, label):.1f}× fewer**)"
        return text

    def update(experiment, label):
        text = update_p50(experiment, label)
        if label.endswith(" deferral"):
            without = float(update_p50(experiment, label[: -len(" deferral")]))
            text += f" (**{without / float(update_p50(experiment, label)):.1f}× faster**)"
        return text

    def revalidations(experiment, label):
        if not reports(experiment, label, "revalidations"):
            return "—"
        return grouped(sum(column(experiment, label, "revalidations")))

    entry_table(name, rows, [
        ("entry", label_cell()),
        ("priorities recomputed per frame (mean, frames 1–399)", priorities),
        ("update p50 (µs), this run", update),
        ("revalidations (flight)", revalidations),
        ("splits + merges per frame", report("splits + merges per frame")),
    ])


def roam_pop():
    """The pop test's counts per entry (straight flight and circle), from frame 1 on."""
    def operations(first):
        def cell(experiment, label):
            splits = column(experiment, label, "splits", first)
            merges = column(experiment, label, "merges", first)
            return f"{mean([s + m for s, m in zip(splits, merges)]):.1f}"
        return cell

    def splits(experiment, label):
        return (f"{mean(column(experiment, label, 'splits', 1)):.1f} "
                f"({mean(column(experiment, label, 'forced_splits', 1)):.2f})")

    def per_strip(experiment, label):
        if not reports(experiment, label, "triangles_per_strip"):
            return "—"
        return f"{stat(experiment, label, 'triangles_per_strip'):.2f}"

    columns = [
        ("entry", label_cell()),
        ("splits + merges per frame, frames 1 on", operations(1)),
        ("the same, every frame", operations(0)),
        ("splits (forced), frames 1 on", splits),
        ("priorities recomputed per frame, frames 1 on",
         lambda e, label: grouped(_priorities(e, label), 0)),
        ("wedgie classifications per frame", mean_of("flag_tests", 0)),
        ("triangles per strip", per_strip),
        ("update p50 (µs), this run", update_p50),
    ]
    entry_table("roam-pop", ["roam 3000", "roam 3000 deferral", "roam 3000 per-vertex",
                             "roam 3000 heap", "roam-rebuild 3000", "roam tau16",
                             "roam tau16 deferral", "roam-rebuild tau16", "roam 3000 no strips",
                             "roam-rebuild 3000 no strips"], columns)
    entry_table("roam-pop-circle", ["roam 3000", "roam-rebuild 3000", "roam tau16",
                                    "roam-rebuild tau16"], columns)


# Chunked LOD (docs/reproductions/chunked.md).

CHUNKED = "chunked-tau"


def chunked_tau():
    """Polygons, skirts, chunks, error, popping and time over the paper's τ range."""
    taus = {f"chunked τ={t}px": t for t in ("32", "16", "8", "4", "2")}

    def skirts(experiment, label):
        skirt = stat(experiment, label, "triangles_skirt")
        return f"{grouped(skirt)} ({100 * skirt / stat(experiment, label, 'triangles'):.1f} %)"

    def popping(experiment, label):
        metres = float(section(experiment, "Popping", label, "max (m)"))
        return f"{metres:.1f} / {section(experiment, 'Popping', label, 'max (px)')}"

    entry_table(CHUNKED, list(taus), [
        ("τ (px)", label_cell(taus)),
        ("triangles drawn (mean)", mean_of("triangles")),
        ("of which skirts", skirts),
        ("chunks drawn", mean_of("chunks_drawn", 1)),
        ("in the view volume", mean_of("triangles_rendered")),
        ("audited error max / mean / p95 (px)", report("error max / mean / mean of p95 (px)")),
        ("popping max (m / px)", popping),
        ("update p50 (µs)", update_p50),
    ])


def _metres(heading, name, digits):
    return lambda e, label: f"{float(section(e, heading, label, name)):.{digits}f}"


def chunked_skirts():
    """The paper's skirt depth against the covering depth at τ = 4 px."""
    rows = [
        ("crack gap max (m)", _metres("Meshes", "crack gap max (m)", 1)),
        ("left open by skirts, max (m)", lambda e, label: f"{float(section(e, 'Meshes', label, 'left open by skirts max (m)')):.2f}".rstrip("0").rstrip(".")),
        ("triangles", mean_of("triangles")),
    ]
    _two_columns(rows, ("chunked τ=4px", "skirt depth δ_c (the paper's)"),
                 ("chunked τ=4px covering skirts", "covering"))


def chunked_morphing():
    """Chunked LOD at τ = 4 px with and without morphing (eq. 3.5)."""
    def popping_m(e, label):
        return (f"{float(section(e, 'Popping', label, 'RMSE (m)')):.3f} / "
                f"{float(section(e, 'Popping', label, 'max (m)')):.{1 if 'morph' not in label else 2}f}")

    def errors(e, label):
        largest, average, p95 = (p.strip() for p in main_cell(
            e, label, "error max / mean / mean of p95 (px)").split("/"))
        return f"{average} / {p95} / {largest}"

    rows = [
        ("popping RMSE / max (m)", popping_m),
        ("popping max (px)", lambda e, label: section(e, "Popping", label, "max (px)")),
        ("audited error mean / p95 / max (px)", errors),
        ("morphing vertices / vertices changed per frame",
         lambda e, label: f"{grouped(stat(e, label, 'morphing_vertices'))} / "
                          f"{grouped(stat(e, label, 'vertices_changed'))}"),
        ("crack gap left open by δ_c skirts, max (m)", _metres("Meshes", "left open by skirts max (m)", 2)),
    ]
    _two_columns(rows, ("chunked τ=4px", "without morphing"), ("chunked τ=4px morph", "with morphing"))


def _two_columns(rows, first, second):
    """Two entries side by side, one row per (header, cell function): `first` and `second` are
    (entry label, column heading)."""
    print(source(CHUNKED))
    print(f"| τ = 4 px | {first[1]} | {second[1]} |")
    print("|---|---|---|")
    for header, cell in rows:
        print(f"| {header} | {cell(CHUNKED, first[0])} | {cell(CHUNKED, second[0])} |")
    print()


# Röttger et al. 1998 (docs/reproductions/rottger.md): figures over frames 100–999.

ROTTGER = "rottger-fans"
SETTLED = 100


def _settled(experiment, label, name):
    return column(experiment, label, name, SETTLED)


def _settled_mean(name, digits=0):
    return lambda e, label: grouped(mean(_settled(e, label, name)), digits)


def rottger_operating_point():
    """The controlled entries at the paper's C and load, beside the paper's figures."""
    def per_fan(e, label):
        return f"{mean(_settled(e, label, 'fan_vertices')) / mean(_settled(e, label, 'fans')):.2f}"

    def resolution(e, label):
        values = sorted(_settled(e, label, "desired_resolution_c"))
        middle = values[len(values) // 2] if len(values) % 2 else (
            values[len(values) // 2 - 1] + values[len(values) // 2]) / 2
        if values[0] == values[-1]:
            return f"{values[0]:g}"
        return f"{middle:.1f} ({values[0]:.1f}–{values[-1]:.1f})"

    def drawn(e, label):
        fans = _settled(e, label, "fans")
        vertices = _settled(e, label, "fan_vertices")
        triangles = mean([v - 2 * f for v, f in zip(vertices, fans)])
        return f"{grouped(triangles)} / {grouped(mean(_settled(e, label, 'triangles')))}"

    rows = ["C=8 vertices=15000", "C=8 vertices=15000 euclidean", "C=8 vertices=15000 local d2",
            "C=8 vertices=15000 whole tile", "C=32 c=0"]
    print(source(ROTTGER, f"; means over frames {SETTLED}–999"))
    print("| entry | fans | fan vertices | vertices per fan | c (median, range) "
          "| triangles drawn / mesh | forced splits | update p50 (µs) |")
    print("|---|---:|---:|---:|---|---:|---:|---:|")
    print("| **paper** (Yukon, 25 Hz) | ≈ 1600 | ≈ 15 000 | ≈ 9.4 | chosen for 25 Hz | — | — | — |")
    for label in rows:
        cells = [f"`{label}`", _settled_mean("fans")(ROTTGER, label),
                 _settled_mean("fan_vertices")(ROTTGER, label), per_fan(ROTTGER, label),
                 resolution(ROTTGER, label), drawn(ROTTGER, label),
                 _settled_mean("forced_splits", 2)(ROTTGER, label), update_p50(ROTTGER, label)]
        print("| " + " | ".join(cells) + " |")
    print()


def rottger_geomorphing():
    """Popping, error and time with and without geomorphing (means over frames 100–999)."""
    def pair(name, digits_m, digits_px, which):
        def cell(e, label):
            if which == "mean":
                metres, pixels = (mean(_settled(e, label, f"{name}_{unit}")) for unit in ("m", "px"))
            else:
                metres, pixels = (max(_settled(e, label, f"{name}_{unit}")) for unit in ("m", "px"))
            return f"{metres:.{digits_m}f} / {pixels:.{digits_px}f}"
        return cell

    def morphing(e, label):
        if not reports(e, label, "morphing_vertices"):
            return "—"
        value = mean(_settled(e, label, "morphing_vertices"))
        if value == 0:
            return "—"
        return f"{grouped(value)} of {grouped(mean(_settled(e, label, 'triangles')))} triangles"

    print(source(ROTTGER, f"; means over frames {SETTLED}–999, maxima over the same frames"))
    columns = [
        ("entry", label_cell()),
        ("popping RMSE (m / px)", pair("popping_rmse", 3, 4, "mean")),
        ("popping max (m / px)", pair("popping_max", 1, 2, "max")),
        ("mean of each frame's max (px)", _settled_mean("popping_max_px", 3)),
        ("audited p95, mean (px)", _settled_mean("audit_projected_p95_px", 3)),
        ("audited max (px)", lambda e, label: f"{max(_settled(e, label, 'audit_projected_max_px')):.2f}"),
        ("morphing vertices", morphing),
        ("upload per frame (kB)", report("upload per frame (kB)")),
        ("update p50 (µs)", update_p50),
    ]
    print("| " + " | ".join(h for h, _c in columns) + " |")
    print("|" + "---|" * len(columns))
    for label in ("C=8 vertices=15000", "C=8 vertices=15000 geomorphing"):
        print("| " + " | ".join(c(ROTTGER, label) for _h, c in columns) + " |")
    print()


def _sweep_label(c_min, c):
    """The label of the sweep's point (C, c): `sweep desired_resolution=c, minimum_resolution=C`."""
    for label in _labels(ROTTGER):
        if not label.startswith("sweep "):
            continue
        point = dict(part.split("=") for part in label[len("sweep "):].split(", "))
        if point.get("minimum_resolution") == str(c_min) and point.get(
                "desired_resolution") == str(c):
            return label
    if (c_min, c) == (32, 0):
        return "C=32 c=0"
    return None


def rottger_c_sweep():
    """Fan vertices against C at c = 0 and c = 90, and their growth per doubling of C."""
    sizes = [2, 4, 8, 16, 32]

    def vertices(label):
        return mean(_settled(ROTTGER, label, "fan_vertices")) if label else None

    print(source(ROTTGER, f"; means over frames {SETTLED}–999"))
    print("| C | fan vertices, c = 0 | ratio | fans | vertices per fan | fan vertices, c = 90 "
          "| ratio | audited p95 (px), c = 0 / 90 | update p50 (µs), c = 0 / 90 |")
    print("|---:|---:|---:|---:|---:|---:|---:|---|---|")
    previous = {0: None, 90: None}
    for size in sizes:
        cells = [str(size)]
        labels = {c: _sweep_label(size, c) for c in (0, 90)}
        for c in (0, 90):
            label = labels[c]
            value = vertices(label)
            if value is None:
                cells += ["—", "—"] if c == 90 else ["—", "—", "—", "—"]
                continue
            ratio = f"×{value / previous[c]:.1f}" if previous[c] else "—"
            previous[c] = value
            cells += [grouped(value), ratio]
            if c == 0:
                fans = mean(_settled(ROTTGER, label, "fans"))
                cells += [grouped(fans), f"{value / fans:.1f}"]
        p95 = [f"{mean(_settled(ROTTGER, labels[c], 'audit_projected_p95_px')):.2f}"
               if labels[c] else "—" for c in (0, 90)]
        times = [update_p50(ROTTGER, labels[c]) if labels[c] else "—" for c in (0, 90)]
        cells += [" / ".join(p95), " / ".join(times)]
        print("| " + " | ".join(cells) + " |")
    print()


def settled_mean_inline(experiment, label, name, digits="1"):
    """settled-mean EXPERIMENT ENTRY COLUMN [DIGITS]: the mean over frames 100 to the end."""
    print(grouped(mean(column(experiment, label, name, SETTLED)), int(digits)), end="")


# The 2019 stitching strips (docs/reproductions/stitching-strips.md).

def stitching_peak():
    """The three methods, the ρ_thr sweep and box distance on the flight towards the peak."""
    def mean_max(name, digits):
        return lambda e, label: (f"{stat(e, label, name):.{digits}f} / "
                                 f"{stat(e, label, name, 'max'):.{digits}f}")

    name = "stitching-strips-peak"
    entry_table(name, _labels(name), [
        ("entry", label_cell()),
        ("triangles", mean_of("triangles")),
        ("M-blocks", mean_of("m_blocks", 1)),
        ("strips", mean_of("strips", 1)),
        ("F mean", mean_of("tessellation_factor_mean", 2)),
        ("popping RMSE m (mean / max)", mean_max("popping_rmse_m", 2)),
        ("popping RMSE px (mean / max)", mean_max("popping_rmse_px", 3)),
        ("popping max m (largest)", max_of("popping_max_m", 1)),
        ("audit mean px", mean_of("audit_projected_mean_px", 2)),
    ])


# Lauritsen and Nielsen 2005 (docs/reproductions/lauritsen.md).

LAURITSEN = "lauritsen"


def _sum(name):
    return lambda e, label: grouped(sum(column(e, label, name)))


def lauritsen_detail():
    """The source alone and extended by three levels of detail, both audits."""
    def source_errors(e, label):
        return (f"{stat(e, label, 'audit_projected_mean_px'):.3f} / "
                f"{stat(e, label, 'audit_projected_p95_px'):.2f} / "
                f"{stat(e, label, 'audit_projected_max_px', 'max'):.2f}")

    def detail_errors(e, label):
        if not reports(e, label, "audit_detail_projected_mean_px"):
            return "—"
        return (f"{stat(e, label, 'audit_detail_projected_mean_px'):.3f} / "
                f"{stat(e, label, 'audit_detail_projected_p95_px'):.2f}")

    def deepest(e, label):
        if not reports(e, label, "detail_deepest_level_drawn"):
            return "— (the source)"
        return f"{stat(e, label, 'detail_deepest_level_drawn', 'max'):.0f}"

    entry_table(LAURITSEN, ["source", "detail, limit 4", "detail, no limit"], [
        ("entry", label_cell()),
        ("triangles (mean)", mean_of("triangles")),
        ("error vs source: mean / p95 / max (px)", source_errors),
        ("error vs detail-extended surface: mean / p95 (px)", detail_errors),
        ("deepest level drawn", deepest),
        ("update p50 (µs)", update_p50),
    ])


def lauritsen_creation():
    """Node creation per frame with and without the creation limit (§3.4.4)."""
    def made(e, label):
        return (f"{stat(e, label, 'detail_synthesised'):.2f} / "
                f"{stat(e, label, 'detail_synthesised', 'max'):.0f}")

    entry_table(LAURITSEN, ["detail, limit 4", "detail, no limit"], [
        ("entry", label_cell()),
        ("chunks made per frame: mean / max", made),
        ("requests refused (flight)", _sum("detail_refused")),
        ("chunks drawn coarser than wanted (sum over frames)", _sum("chunks_coarser")),
        ("error vs detail surface, mean (px)", mean_of("audit_detail_projected_mean_px", 4)),
    ])


def lauritsen_latency():
    """The error cost of load latency, against the same flight without it."""
    pairs = [("source, latency 4", "source", "audit_projected"),
             ("detail, latency 4", "detail, limit 4", "audit_detail_projected")]
    print(source(LAURITSEN))
    print("| entry (against) | frames whose mean error is higher | mean cost (px, over all "
          "frames): mean / p95 error | largest cost in a frame (px): mean / max error "
          "| chunks drawn coarser (sum) | resident source chunks: max / bytes |")
    print("|---|---|---|---|---|---|")
    for label, against, audit in pairs:
        def cost(name):
            return [a - b for a, b in zip(column(LAURITSEN, label, f"{audit}_{name}_px"),
                                          column(LAURITSEN, against, f"{audit}_{name}_px"))]
        means, p95s, maxima = cost("mean"), cost("p95"), cost("max")
        higher = sum(1 for c in means if c > 0)
        print(f"| `{label}` (`{against}`) | {higher} of {len(means)} "
              f"| {mean(means):+.3f} / {mean(p95s):+.3f} | {max(means):+.2f} / {max(maxima):+.0f} "
              f"| {grouped(sum(column(LAURITSEN, label, 'chunks_coarser')))} "
              f"| {stat(LAURITSEN, label, 'resident_chunks', 'max'):.0f} / "
              f"{grouped(stat(LAURITSEN, label, 'resident_bytes', 'max'))} |")
    print()


# Wu et al. 2001, Table 1 (docs/reproductions/wu-table1.md): means over frames 1 on.

WU = "wu-table1"
WU_PAPER_ERROR = {3000: 3.2, 5000: 2.5, 6000: 2.3, 8000: 2.0, 12000: 1.6}


def _wu(name, label, which="mean"):
    values = column(WU, label, name, 1)
    return {"mean": mean, "min": min, "max": max}[which](values)


def _wu_audit(label):
    return (f"{stat(WU, label, 'audit_projected_mean_px'):.3f} / "
            f"{stat(WU, label, 'audit_projected_p95_px'):.2f} / "
            f"{stat(WU, label, 'audit_projected_max_px', 'max'):.2f}")


def _wu_counts(label):
    return [grouped(_wu(name, label)) for name in ("triangles_in_view_blocks",
                                                   "triangles_rendered", "triangles")]


def wu_table1_fixed():
    """Table 1 at the paper's initial τ: budget against error, beside the paper's."""
    reference_p95 = stat(WU, "wu budget=6000", "audit_projected_p95_px")
    print(source(WU, "; means over frames 1 on"))
    print("| budget | paper: average error (px) | paper · √budget | the paper's formula τ (px) "
          "| τ · √budget | initial τ in use (px) | Wu's count in view (mean) "
          "| `triangles_rendered` (mean) | whole mesh (mean) "
          "| audited projected error: mean / p95 / max (px) "
          "| our p95 relative to 6000 | paper relative to 6000 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for budget, paper in WU_PAPER_ERROR.items():
        label = f"wu budget={budget}"
        formula = float(fact(WU, label, "paper_initial_tau_px"))
        initial = float(fact(WU, label, "initial_tau_px"))
        p95 = stat(WU, label, "audit_projected_p95_px")
        print(f"| {budget} | {paper} | {paper * budget ** 0.5:.0f} | {formula:.2f} "
              f"| {formula * budget ** 0.5:.0f} | {initial:.2f} | " + " | ".join(_wu_counts(label))
              + f" | {_wu_audit(label)} | {p95 / reference_p95:.2f} "
              f"| {paper / WU_PAPER_ERROR[6000]:.2f} |")
    print()


def wu_table1_recentred():
    """Table 1 with τ re-centred: τ and b over the flight, counts and error."""
    reference_p95 = stat(WU, "wu budget=6000 τ re-centred", "audit_projected_p95_px")
    print(source(WU, "; means over frames 1 on"))
    print("| budget | τ over the flight: mean [min, max] (px) | b: min / max / mean "
          "| Wu's count in view | `triangles_rendered` | whole mesh "
          "| audited error: mean / p95 / max (px) | p95 relative to 6000 |")
    print("|---|---|---|---|---|---|---|---|")
    for budget in WU_PAPER_ERROR:
        label = f"wu budget={budget} τ re-centred"
        tau = column(WU, label, "tau_px")
        b = column(WU, label, "base_b", 1)
        p95 = stat(WU, label, "audit_projected_p95_px")
        print(f"| {budget} | {mean(tau):.2f} [{min(tau):.2f}, {max(tau):.2f}] "
              f"| {signed(min(b))} / {signed(max(b))} / {signed(mean(b), 1)} | " + " | ".join(_wu_counts(label))
              + f" | {_wu_audit(label)} | {p95 / reference_p95:.2f} |")
    print()


def wu_table1_flight():
    """The 6000-frame flight's statistics at 6000 triangles, beside the paper's §7."""
    entries = ["wu budget=6000", "wu budget=6000 τ re-centred", "wu budget=6000 everywhere"]

    def b(label):
        return (f"{signed(_wu('base_b', label, 'max'))} / {signed(_wu('base_b', label, 'min'))} "
                f"/ {signed(_wu('base_b', label), 1)}")

    def one(name, digits=0):
        return lambda label: grouped(_wu(name, label), digits)

    def splits(label):
        return f"{_wu('splits', label):.2f} ({_wu('forced_splits', label):.2f})"

    def vertices(label):
        return f"{_wu('vertices_inserted', label):.1f} / {_wu('vertices_deleted', label):.1f}"

    def per_operation(label):
        operations = _wu("splits", label) + _wu("merges", label)
        return f"{_wu('life_recomputations', label) / operations:.2f}"

    def in_view(label):
        return (f"{grouped(_wu('triangles_in_view_blocks', label))} / "
                f"{grouped(_wu('triangles_rendered', label))}")

    def ratio(label):
        whole = _wu("triangles", label)
        return (f"{whole / _wu('triangles_in_view_blocks', label):.2f} "
                f"({whole / _wu('triangles_rendered', label):.2f})")

    rows = [
        ("b max / min / mean", "54 / −41 / ≈ 0", b),
        ("splittable nodes (inactive, both corner parents active)", "1238", one("splittable")),
        ("split queue (inactive, quadtree parent active)", "—", one("split_queue")),
        ("mergeable nodes", "525", one("mergeable")),
        ("valid-life recomputations", "128.7", one("life_recomputations", 1)),
        ("nodes tested against the view cone", "—", one("cone_tests", 1)),
        ("splits (of which forced)", "11.5", splits),
        ("merges", "2.3", one("merges", 2)),
        ("vertices inserted / deleted", "23.3 / 23.3", vertices),
        ("recomputations per split or merge", "9.3", per_operation),
        ("whole mesh", "≈ rendered", one("triangles")),
        ("Wu's count in view / `triangles_rendered`", "6000 / —", in_view),
        ("whole mesh ÷ Wu's count (÷ `triangles_rendered`)", "≈ 1", ratio),
    ]
    print(source(WU))
    print("| per frame, mean (frames 1 on) | paper | `in_view` | `in_view`, τ re-centred "
          "| `everywhere` |")
    print("|---|---|---|---|---|")
    for header, paper, cell in rows:
        print(f"| {header} | {paper} | " + " | ".join(cell(label) for label in entries) + " |")
    print()


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
    "lindstrom-sweep": (lindstrom_sweep, "Lindstrom'96: the τ sweep's polygons beside the "
                                         "paper's (docs/reproductions/lindstrom.md)"),
    "lindstrom-work": (lindstrom_work, "Lindstrom'96: work per frame and audited error per τ"),
    "roam-deferral": (roam_deferral, "ROAM'97 §7.3: deferral on the turning circle "
                                     "(docs/reproductions/roam.md)"),
    "roam-pop": (roam_pop, "ROAM'97 pop test: counts per entry, line and circle"),
    "settled-mean": (settled_mean_inline, "settled-mean EXPERIMENT ENTRY COLUMN [DIGITS]: a "
                                          "mean over frames 100 on, inline"),
    "rottger-operating-point": (rottger_operating_point, "Röttger'98: the controlled entries "
                                                         "(docs/reproductions/rottger.md)"),
    "rottger-c-sweep": (rottger_c_sweep, "Röttger'98: fan vertices against C at c = 0 and 90"),
    "rottger-geomorphing": (rottger_geomorphing, "Röttger'98: with and without geomorphing"),
    "stitching-peak": (stitching_peak, "the 2019 stitching strips on the flight towards the "
                                       "peak (docs/reproductions/stitching-strips.md)"),
    "wu-table1": (wu_table1_fixed, "Wu'01 Table 1 at the paper's τ "
                                   "(docs/reproductions/wu-table1.md)"),
    "wu-table1-recentred": (wu_table1_recentred, "Wu'01 Table 1 with τ re-centred"),
    "wu-table1-flight": (wu_table1_flight, "Wu'01 §7: the flight's statistics at 6000 triangles"),
    "lauritsen-detail": (lauritsen_detail, "Lauritsen–Nielsen: the source and three levels of "
                                           "detail (docs/reproductions/lauritsen.md)"),
    "lauritsen-creation": (lauritsen_creation, "Lauritsen–Nielsen: node creation with and "
                                               "without the limit"),
    "lauritsen-latency": (lauritsen_latency, "Lauritsen–Nielsen: the error cost of load latency"),
    "chunked-tau": (chunked_tau, "chunked LOD over the paper's τ range "
                                 "(docs/reproductions/chunked.md)"),
    "chunked-skirts": (chunked_skirts, "chunked LOD: δ_c skirts against covering skirts"),
    "chunked-morphing": (chunked_morphing, "chunked LOD: with and without morphing"),
}
