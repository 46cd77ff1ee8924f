"""The generators of docs/reproductions/*.md: each paper's tables, printed from the committed
outputs of the experiments the page runs (`plots/<experiment>/`, made by
`bash scripts/regenerate-plots.sh reproductions`).

This module holds the Lindstrom, ROAM, chunked LOD and stitching-strips pages' generators and
gathers every page's into `GENERATORS`: the shared readers, cells and inline generators are in
`repro_common.py`; Röttger's, Lauritsen–Nielsen's, Wu's Table 1 and Vaněk–Ježek's pages each
have their module (`repro_rottger.py`, `repro_lauritsen.py`, `repro_wu.py`, `repro_vanek.py`).
Nothing here is measured: every figure is read, or computed the way the page says.
Not here: the study's and performance.md's generators (`generators.py`).
"""

from . import repro_common, repro_lauritsen, repro_rottger, repro_vanek, repro_wu
from .outputs import main_cell
from .repro_common import (entry_labels, entry_table, label_cell, max_of, mean_of, report,
                           section, source, update_p50)
from .runs import column, grouped, mean, reports, stat

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


# The 2019 stitching strips (docs/reproductions/stitching-strips.md).

def stitching_peak():
    """The three methods, the ρ_thr sweep and box distance on the flight towards the peak."""
    def mean_max(name, digits):
        return lambda e, label: (f"{stat(e, label, name):.{digits}f} / "
                                 f"{stat(e, label, name, 'max'):.{digits}f}")

    name = "stitching-strips-peak"
    entry_table(name, entry_labels(name), [
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


GENERATORS = {
    **repro_common.GENERATORS,
    "lindstrom-sweep": (lindstrom_sweep, "Lindstrom'96: the τ sweep's polygons beside the "
                                         "paper's (docs/reproductions/lindstrom.md)"),
    "lindstrom-work": (lindstrom_work, "Lindstrom'96: work per frame and audited error per τ"),
    "roam-deferral": (roam_deferral, "ROAM'97 §7.3: deferral on the turning circle "
                                     "(docs/reproductions/roam.md)"),
    "roam-pop": (roam_pop, "ROAM'97 pop test: counts per entry, line and circle"),
    "stitching-peak": (stitching_peak, "the 2019 stitching strips on the flight towards the "
                                       "peak (docs/reproductions/stitching-strips.md)"),
    "chunked-tau": (chunked_tau, "chunked LOD over the paper's τ range "
                                 "(docs/reproductions/chunked.md)"),
    "chunked-skirts": (chunked_skirts, "chunked LOD: δ_c skirts against covering skirts"),
    "chunked-morphing": (chunked_morphing, "chunked LOD: with and without morphing"),
    **repro_rottger.GENERATORS,
    **repro_lauritsen.GENERATORS,
    **repro_wu.GENERATORS,
    **repro_vanek.GENERATORS,
}
