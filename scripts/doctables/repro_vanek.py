"""The generators of docs/reproductions/vanek.md (Vaněk and Ježek 2004 at the paper's scale),
printed from `plots/vanek-16k/`: the four entries at equal triangles, and the held entry's work
per frame. Every figure is over the summarised frames (after the experiment's warm-up) unless a
generator says otherwise. Not here: the shared readers and inline generators
(`repro_common.py`), vanek's figures on other pages.
"""

from .outputs import summary
from .repro_common import section, source, update_p50
from .runs import column, entry, grouped, reports, stat

VANEK = "vanek-16k"
HELD = "vanek target=850000 culled"


def _summarised(label, name):
    """A frames.csv column over the summarised frames (after the warm-up)."""
    return column(VANEK, label, name, summary(VANEK)["flight"]["warm_up_frames"])


def _update_ms(label):
    return f"{float(update_p50(VANEK, label)) / 1000:.1f} ms"


def vanek_16k():
    """The four entries at equal triangles: mesh, view, strips, audited error, update."""
    def mesh(label):
        text = grouped(stat(VANEK, label, "triangles"))
        if reports(VANEK, label, "triangles_in_view_blocks"):
            in_blocks = stat(VANEK, label, "triangles_in_view_blocks")
            text += f" ({grouped(in_blocks)} in the cone's blocks)"
        return text

    def strips(label):
        if not reports(VANEK, label, "triangles_degenerate"):
            return "—"
        return " / ".join(grouped(stat(VANEK, label, name))
                          for name in ("triangles_surface", "triangles_degenerate"))

    def audit(label):
        return (f"{stat(VANEK, label, 'audit_projected_mean_px'):.3f} / "
                f"{stat(VANEK, label, 'audit_projected_p95_px'):.3f} / "
                f"{stat(VANEK, label, 'audit_projected_max_px', 'max'):.2f}")

    print(source(VANEK))
    print("| entry | triangles (mesh) | in view | surface / degenerate "
          "| audited error mean / p95 (mean over frames) / max (px) | median update |")
    print("|---|---|---|---|---|---|")
    for record in summary(VANEK)["algorithms"]:
        label = record["label"]
        rendered = grouped(stat(VANEK, label, "triangles_rendered"))
        print(f"| {label} | {mesh(label)} | {rendered} | {strips(label)} | {audit(label)} "
              f"| {_update_ms(label)} |")
    print()


def vanek_work():
    """The held entry's work per frame: patches, strips, the distance multiplier, changes."""
    patches = float(entry(VANEK, HELD)["facts"]["patches"])
    culled = stat(VANEK, HELD, "patches_culled")

    def per_frame(name, digits=0):
        return grouped(stat(VANEK, HELD, name), digits)

    holes = stat(VANEK, HELD, "audit_holes", "max")
    cracks = stat(VANEK, HELD, "audit_crack_samples", "max")
    print(f"Per frame, the held entry (`{HELD}`, means over the summarised frames of "
          f"`plots/{VANEK}/frames.csv`): {grouped(patches - culled)} patches drawn of "
          f"{grouped(patches)} ({grouped(culled)} culled), {per_frame('strip_indices')} strip "
          f"indices, {per_frame('collapsed_triangles')} collapsed border triangles, the distance "
          f"multiplier μ at {stat(VANEK, HELD, 'distance_multiplier'):.2f} (between "
          f"{min(_summarised(HELD, 'distance_multiplier')):.2f} and "
          f"{max(_summarised(HELD, 'distance_multiplier')):.2f}); "
          f"{per_frame('splits', 1)} patches a frame change to a finer level and "
          f"{per_frame('merges', 1)} to a coarser, {per_frame('vertices_inserted')} vertices "
          f"rewritten. Holes in the worst frame: {holes:.0f}; crack samples in the worst "
          f"frame: {cracks:.0f}.")
    print()


def vanek_held():
    """report.md's verdict on the held entries' target ("Budgets and targets")."""
    for label in (HELD, f"{HELD} exp 2"):
        print(f"`{label}`: held? {section(VANEK, 'Budgets and targets', label, 'held?')}; mean "
              f"off by {section(VANEK, 'Budgets and targets', label, 'mean off by')}.")
    print()


def bound(which):
    """vanek-bound rotation|derived: the run's rotation bound (rad a frame, 4 digits) and
    whether summary.json says it was derived from the flight."""
    bounds = summary(VANEK)["flight"]["speed_bounds"]
    if which == "derived":
        print("derived from the flight" if bounds["rotation_rad_per_frame_derived"]
              else "declared", end="")
    else:
        print(f"{bounds['rotation_rad_per_frame']:.4f}", end="")


def passes(label=HELD):
    """vanek-passes [ENTRY]: metric_evaluations a frame over the patches not culled (both means
    over the summarised frames): how many times the target search computed the level of every
    patch in view, inline."""
    patches = float(entry(VANEK, label)["facts"]["patches"])
    in_view = patches - stat(VANEK, label, "patches_culled")
    print(f"{stat(VANEK, label, 'metric_evaluations') / in_view:.1f}", end="")


def update_ms(label):
    """vanek-update-ms ENTRY: report.md's median update in ms, inline."""
    print(_update_ms(label), end="")


GENERATORS = {
    "vanek-16k": (vanek_16k, "Vaněk–Ježek at the paper's scale beside Wu and Lindstrom "
                             "(docs/reproductions/vanek.md)"),
    "vanek-work": (vanek_work, "Vaněk–Ježek: the held entry's work per frame"),
    "vanek-held": (vanek_held, "Vaněk–Ježek: report.md's verdict on the triangle targets"),
    "vanek-bound": (bound, "vanek-bound rotation|derived: the run's rotation bound, inline"),
    "vanek-passes": (passes, "vanek-passes [ENTRY]: level computations over patches, inline"),
    "vanek-update-ms": (update_ms, "vanek-update-ms ENTRY: the median update in ms, inline"),
}
