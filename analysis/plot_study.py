#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Failure probability against haematocrit for every (d, Ca) of a sweep (SPEC section 7), with the
standard deviation over the cells as error bars and the displacement ceiling d/lambda.
Input: a CSV with one row per run and the columns haematocrit_percent, row_shift_um,
capillary_number, p_f_mean, p_f_std, pillar_spacing_um (the last five as in dld-analyze's
<stem>-summary.csv; the sweep adds the haematocrit). Rows without p_f_mean are left out.
--unfinished CSV adds runs that have not finished (dld-sweep --summary --unfinished: each cell
over the pillars it passed so far) as open markers, labelled with the state and the pillars of
the run's slowest cell (column slowest_cell_pillars): not results of the study's rule."""
import argparse
import csv
import math
import sys
from collections import defaultdict

COLUMNS = ["haematocrit_percent", "row_shift_um", "capillary_number", "p_f_mean", "p_f_std",
           "pillar_spacing_um"]


def number(row, key, path, line):
    try:
        return float(row[key]) if row[key] != "" else math.nan
    except ValueError:
        sys.exit(f"plot_study.py: error: {path}:{line}: column {key}: '{row[key]}' is not a number")


def read_rows(path, may_be_empty=False):
    """The rows of a CSV with COLUMNS, or a one-line error naming the file. may_be_empty: a file
    without rows (a sweep's summary before its first run has finished) gives none."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"plot_study.py: error: {path}: cannot read ({e.strerror})")
    if may_be_empty and not rows:
        return rows
    missing = [c for c in COLUMNS if not rows or c not in rows[0]]
    if missing:
        sys.exit(f"plot_study.py: error: {path}: missing column(s) {', '.join(missing)}"
                 f" (expected {', '.join(COLUMNS)})")
    return rows


def points(rows, path, groups, kinds, extra=()):
    """Adds each row with a failure probability to groups[(d, Ca)] as (Ht, mean, std, lambda,
    *extra columns) and its failure kind (p_fZ or p_fD) to kinds[(d, Ca)]."""
    for i, r in enumerate(rows, start=2):
        v = {k: number(r, k, path, i) for k in COLUMNS}
        if math.isnan(v["p_f_mean"]):
            continue
        key = (v["row_shift_um"], v["capillary_number"])
        groups[key].append((v["haematocrit_percent"], v["p_f_mean"], v["p_f_std"],
                            v["pillar_spacing_um"]) + tuple(r.get(c, "") for c in extra))
        if r.get("failure"):  # p_fZ or p_fD: which failure the run's expected mode makes it
            kinds[key].add(r["failure"])


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("csv", help="one row per finished run")
    ap.add_argument("-o", "--output", required=True, help="PNG file")
    ap.add_argument("--unfinished", help="one row per unfinished run, as far as it got (state, "
                    "slowest_cell_pillars columns)")
    a = ap.parse_args()
    groups = defaultdict(list)  # (d, Ca) -> [(Ht, mean, std, lambda)]
    kinds = defaultdict(set)  # (d, Ca) -> {"p_fZ", "p_fD"}
    points(read_rows(a.csv, may_be_empty=a.unfinished is not None), a.csv, groups, kinds)
    so_far = defaultdict(list)  # (d, Ca) -> [(Ht, mean, std, lambda, state, slowest pillars)]
    if a.unfinished:
        rows = read_rows(a.unfinished)
        for c in ("state", "slowest_cell_pillars"):
            if c not in rows[0]:
                sys.exit(f"plot_study.py: error: {a.unfinished}: missing column {c}")
        points(rows, a.unfinished, so_far, kinds, ("state", "slowest_cell_pillars"))
    shifts = sorted({d for d, _ in list(groups) + list(so_far)})
    if not shifts:
        sys.exit(f"plot_study.py: error: {a.csv}: no row with a failure probability")
    import matplotlib  # only now: the checks above answer without it

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(shifts), figsize=(4.5 * len(shifts), 4), squeeze=False,
                             sharex=True, sharey=True)
    series = sorted(set(groups) | set(so_far))
    colour = {key: f"C{i}" for i, key in enumerate(series)}
    for ax, d in zip(axes[0], shifts):
        lam = None
        for key in series:
            dd, ca = key
            if dd != d:
                continue
            label = f"Ca = {ca:g}" + "".join(f" ({k})" for k in sorted(kinds[key]))
            if groups[key]:
                pts = sorted(groups[key])
                lam = pts[0][3]
                ax.errorbar([p[0] for p in pts], [p[1] for p in pts],
                            yerr=[0 if math.isnan(p[2]) else p[2] for p in pts], marker="o",
                            capsize=3, color=colour[key], label=label)
            for n, p in enumerate(sorted(so_far[key])):
                lam = p[3]
                ax.errorbar([p[0]], [p[1]], yerr=[0 if math.isnan(p[2]) else p[2]], marker="o",
                            mfc="white", ls="none", capsize=3, color=colour[key],
                            label=(label + ", unfinished: as far as it got") if n == 0 else None)
                note = f"{p[4]}, slowest cell {float(p[5] or 'nan'):.1f} pillars"
                ax.annotate(note, (p[0], p[1]), textcoords="offset points",
                            xytext=(5, -10 - 8 * (n % 2)), fontsize=6, color=colour[key])
                print(f"unfinished: d {dd:g} um, Ca {ca:g}, Ht {p[0]:g} %: {p[1]:.4f} +- "
                      f"{p[2]:.4f} ({note})")
        ax.axhline(d / lam, color="k", ls="--", lw=1,
                   label=f"p_fD ceiling d/lambda = {d / lam:.3f}")
        ax.axhline(0, color="0.5", lw=0.5)
        ax.set_title(f"d = {d:g} um")
        ax.set_xlabel("Ht [%]")
        ax.set_xlim(0, 50)  # the study's haematocrits, 8-45.6 %: runs still to come have a place
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("failure probability (p_fZ or p_fD, mean +- std)")
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    print(f"plot: {a.output}")


if __name__ == "__main__":
    main()
