"""The generators of docs/reproductions/wu-table1.md (Wu et al. 2001, Table 1 and §7's flight),
printed from `plots/wu-table1/`. Not here: the shared readers (`repro_common.py`), Wu's
figures on other pages.
"""

from .repro_common import signed, source
from .runs import column, fact, grouped, mean, stat


# Wu et al. 2001, Table 1 (docs/reproductions/wu-table1.md): means over frames 1 on.

WU = "wu-table1"
WU_PAPER_ERROR = {3000: 3.2, 5000: 2.5, 6000: 2.3, 8000: 2.0, 12000: 1.6}


def _wu(name, label, which="mean"):
    """A statistic of a frames.csv column over frames 1 on; `a+b` sums two columns per frame."""
    parts = [column(WU, label, part, 1) for part in name.split("+")]
    values = [sum(frame) for frame in zip(*parts)]
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


def wu_figure(label, name, which="mean", digits="1"):
    """wu-mean ENTRY COLUMN [mean|min|max [DIGITS]]: a frames.csv column's mean, smallest or
    largest value over frames 1 on, inline."""
    value = _wu(name, label, which)
    print(grouped(value, int(digits)).replace("-", "−"), end="")


def wu_ratio(label_a, name_a, label_b, name_b, digits="2"):
    """wu-ratio ENTRY_A COLUMN_A ENTRY_B COLUMN_B [DIGITS]: A's mean over frames 1 on divided by
    B's, inline."""
    print(f"{_wu(name_a, label_a) / _wu(name_b, label_b):.{int(digits)}f}", end="")


def wu_against_paper(label, name, paper):
    """wu-vs-paper ENTRY COLUMN PAPER: how far the mean over frames 1 on is from the paper's
    figure, a signed whole percentage (−36 %), inline."""
    percent = 100 * (_wu(name, label) / float(paper) - 1)
    print(f"{'+' if round(percent) > 0 else ''}{signed(percent)} %", end="")


def wu_budget_held(mode=""):
    """wu-budget-held [recentred]: the largest distance, over the five budgets, of the mean in-view
    count (frames 1 on) from the budget, in % of it, inline."""
    suffix = " τ re-centred" if mode == "recentred" else ""
    worst = max(abs(_wu("triangles_in_view_blocks", f"wu budget={budget}{suffix}") / budget - 1)
                for budget in WU_PAPER_ERROR)
    print(f"{100 * worst:.1f}", end="")


def wu_fact(label, name, digits="2"):
    """wu-fact ENTRY FACT [DIGITS]: one of the entry's facts in summary.json, inline."""
    print(f"{float(fact(WU, label, name)):.{int(digits)}f}", end="")


def wu_handovers(label):
    """wu-handovers ENTRY: the frames whose τ differs from the previous frame's (the hand-overs
    of re-centring), inline."""
    tau = column(WU, label, "tau_px")
    print(sum(1 for before, after in zip(tau, tau[1:]) if after != before), end="")


GENERATORS = {
    "wu-table1": (wu_table1_fixed, "Wu'01 Table 1 at the paper's τ "
                                   "(docs/reproductions/wu-table1.md)"),
    "wu-table1-recentred": (wu_table1_recentred, "Wu'01 Table 1 with τ re-centred"),
    "wu-table1-flight": (wu_table1_flight, "Wu'01 §7: the flight's statistics at 6000 triangles"),
    "wu-mean": (wu_figure, "wu-mean ENTRY COLUMN [mean|min|max [DIGITS]]: over frames 1 on, "
                           "inline"),
    "wu-ratio": (wu_ratio, "wu-ratio ENTRY_A COLUMN_A ENTRY_B COLUMN_B [DIGITS]: a ratio of "
                           "means over frames 1 on, inline"),
    "wu-vs-paper": (wu_against_paper, "wu-vs-paper ENTRY COLUMN PAPER: the mean against the "
                                      "paper's figure, in %, inline"),
    "wu-budget-held": (wu_budget_held, "wu-budget-held [recentred]: the in-view count's largest "
                                       "distance from its budget, in %, inline"),
    "wu-fact": (wu_fact, "wu-fact ENTRY FACT [DIGITS]: an entry's fact, inline"),
    "wu-handovers": (wu_handovers, "wu-handovers ENTRY: frames whose τ changed, inline"),
}
