"""The generators of docs/reproductions/rottger.md (Röttger et al. 1998): the controlled entries,
the C sweep and geomorphing, printed from `plots/rottger-fans/`. Not here: the shared readers
(`repro_common.py`), the other pages' tables.
"""

from .outputs import OutputMissing, main_table
from .repro_common import entry_labels, label_cell, report, source, update_p50
from .runs import column, grouped, mean, reports


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
        return f"{grouped(value)} of {grouped(mean(_settled(e, label, 'mesh_vertices')))} vertices"

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
    for label in entry_labels(ROTTGER):
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


def growth(c, which="vertices", digits="1"):
    """rottger-growth c [vertices|update [DIGITS]]: the growth per doubling of C (2 → 4 → … →
    32 where the run has the point) at c, of the fan vertices (means over frames 100–999) or of
    report.md's median update, as `×2.9, ×3.3, …`."""
    values = []
    for size in (2, 4, 8, 16, 32):
        label = _sweep_label(size, int(c))
        if label is None:
            continue
        if which == "update":
            values.append(float(update_p50(ROTTGER, label)))
        else:
            values.append(mean(_settled(ROTTGER, label, "fan_vertices")))
    ratios = [f"×{b / a:.{int(digits)}f}" for a, b in zip(values, values[1:])]
    print(", ".join(ratios), end="")


def settled_ratio(label_a, name_a, label_b, name_b, digits="2"):
    """rottger-ratio ENTRY_A COLUMN_A ENTRY_B COLUMN_B [DIGITS]: A's mean over frames 100–999
    divided by B's (COLUMN `update-p50`: report.md's median update)."""
    def value(label, name):
        if name == "update-p50":
            return float(update_p50(ROTTGER, label))
        return mean(_settled(ROTTGER, label, name))
    print(f"{value(label_a, name_a) / value(label_b, name_b):.{int(digits)}f}", end="")


def sweep_point(c_min, c, name, digits="0", which="mean"):
    """rottger-point C c COLUMN [DIGITS [mean|sum|max|frames]]: the sweep point's mean over frames
    100–999, or over the whole flight its sum, its largest value or the frames where it is not
    zero, inline."""
    label = _sweep_label(int(c_min), int(c))
    if label is None:
        raise OutputMissing(f"plots/{ROTTGER}/summary.json: no sweep point C={c_min}, c={c}")
    if name == "update-p50":
        print(update_p50(ROTTGER, label), end="")
        return
    if which == "mean":
        value = mean(_settled(ROTTGER, label, name))
    else:
        values = column(ROTTGER, label, name)
        value = {"sum": sum(values), "max": max(values),
                 "frames": sum(1 for v in values if v != 0)}[which]
    print(grouped(value, int(digits)), end="")

def bytes_range():
    """rottger-bytes-range: the smallest and largest bytes per sample of report.md's comparison
    table over the run's entries, as `6.27–11.43`, inline."""
    values = [float(row["bytes per sample"]) for row in main_table(ROTTGER).values()]
    print(f"{min(values):.2f}–{max(values):.2f}", end="")


GENERATORS = {
    "settled-mean": (settled_mean_inline, "settled-mean EXPERIMENT ENTRY COLUMN [DIGITS]: a "
                                          "mean over frames 100 on, inline"),
    "rottger-operating-point": (rottger_operating_point, "Röttger'98: the controlled entries "
                                                         "(docs/reproductions/rottger.md)"),
    "rottger-c-sweep": (rottger_c_sweep, "Röttger'98: fan vertices against C at c = 0 and 90"),
    "rottger-geomorphing": (rottger_geomorphing, "Röttger'98: with and without geomorphing"),
    "rottger-growth": (growth, "rottger-growth c [vertices|update [DIGITS]]: growth per "
                               "doubling of C, inline"),
    "rottger-ratio": (settled_ratio, "rottger-ratio ENTRY_A COLUMN_A ENTRY_B COLUMN_B [DIGITS]: "
                                     "a ratio of means over frames 100–999, inline"),
    "rottger-point": (sweep_point, "rottger-point C c COLUMN [DIGITS [mean|sum|max|frames]]: a "
                                   "sweep point's figure, inline"),
    "rottger-bytes-range": (bytes_range, "rottger-bytes-range: bytes per sample over the entries, "
                                         "inline"),
}
