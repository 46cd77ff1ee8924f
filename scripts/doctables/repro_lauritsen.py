"""The generators of docs/reproductions/lauritsen.md (Lauritsen and Nielsen 2005): runtime detail,
node creation and load latency from `plots/lauritsen/`, the 65 537² run from
`plots/lauritsen-65537/`. Not here: the shared readers (`repro_common.py`).
"""

from .repro_common import entry_table, label_cell, mean_of, source, update_p50
from .runs import column, grouped, mean, reports, stat


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


def _cost(label, against, audit, name):
    """Per frame, `label`'s audited error minus `against`'s (the same flight without loading)."""
    return [a - b for a, b in zip(column(LAURITSEN, label, f"{audit}_{name}_px"),
                                  column(LAURITSEN, against, f"{audit}_{name}_px"))]


def worst_frame(label, against, audit, threshold="1"):
    """lauritsen-worst-frame ENTRY AGAINST AUDIT [THRESHOLD]: the last frame whose largest error
    (AUDIT: audit_projected or audit_detail_projected) costs more than THRESHOLD px against
    AGAINST, inline."""
    costs = _cost(label, against, audit, "max")
    frames = [frame for frame, cost in enumerate(costs) if cost > float(threshold)]
    print(frames[-1] if frames else "none", end="")


def cost_after(label, against, audit, first):
    """lauritsen-cost-after ENTRY AGAINST AUDIT FIRST: the largest cost on a frame's largest
    error from frame FIRST on (px, two digits), inline."""
    costs = _cost(label, against, audit, "max")[int(first):]
    print(f"{max(costs):.2f}".replace("-", "−"), end="")


def cost_figure(label, against, audit, name, which, digits="3"):
    """lauritsen-cost ENTRY AGAINST AUDIT mean|p95|max mean|max [DIGITS]: the mean or the
    largest over frames of the per-frame cost of ENTRY's error against AGAINST, inline."""
    costs = _cost(label, against, audit, name)
    value = mean(costs) if which == "mean" else max(costs)
    print(f"{value:+.{int(digits)}f}".replace("-", "−"), end="")


def chunk_bytes(experiment, label, kind, per="chunk"):
    """lauritsen-chunk-bytes EXPERIMENT ENTRY source|detail [chunk|sample]: the bytes a resident
    source chunk (resident_bytes over resident_chunks) or a cached synthesised chunk
    (detail_bytes over detail_cached) holds, in the frame holding the most; per 65² drawn height
    sample with `sample`, inline."""
    names = {"source": ("resident_bytes", "resident_chunks"),
             "detail": ("detail_bytes", "detail_cached")}[kind]
    held = column(experiment, label, names[0])
    chunks = column(experiment, label, names[1])
    frame = max(range(len(chunks)), key=lambda k: chunks[k])
    value = held[frame] / chunks[frame]
    if per == "sample":
        print(f"{value / 65 ** 2:.1f}", end="")
    else:
        print(grouped(value), end="")


GENERATORS = {
    "lauritsen-detail": (lauritsen_detail, "Lauritsen–Nielsen: the source and three levels of "
                                           "detail (docs/reproductions/lauritsen.md)"),
    "lauritsen-creation": (lauritsen_creation, "Lauritsen–Nielsen: node creation with and "
                                               "without the limit"),
    "lauritsen-latency": (lauritsen_latency, "Lauritsen–Nielsen: the error cost of load latency"),
    "lauritsen-worst-frame": (worst_frame, "lauritsen-worst-frame ENTRY AGAINST AUDIT [THRESHOLD]: "
                                           "the last frame whose max error costs more, inline"),
    "lauritsen-cost-after": (cost_after, "lauritsen-cost-after ENTRY AGAINST AUDIT FIRST: the "
                                         "largest cost on a frame's max from FIRST on, inline"),
    "lauritsen-cost": (cost_figure, "lauritsen-cost ENTRY AGAINST AUDIT STAT mean|max [DIGITS]: "
                                    "the error cost of loading, inline"),
    "lauritsen-chunk-bytes": (chunk_bytes, "lauritsen-chunk-bytes EXPERIMENT ENTRY source|detail "
                                           "[chunk|sample]: bytes a chunk holds, inline"),
}
