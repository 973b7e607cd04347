#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Failure probability against haematocrit for every (d, Ca) of a sweep (SPEC section 7), with the
standard deviation over the cells as error bars and the displacement ceiling d/lambda.
Input: a CSV with one row per run and the columns haematocrit_percent, row_shift_um,
capillary_number, p_f_mean, p_f_std, pillar_spacing_um (the last five as in dld-analyze's
<stem>-summary.csv; the sweep adds the haematocrit). Rows without p_f_mean are left out."""
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


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("csv", help="one row per run")
    ap.add_argument("-o", "--output", required=True, help="PNG file")
    a = ap.parse_args()
    try:
        with open(a.csv, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"plot_study.py: error: {a.csv}: cannot read ({e.strerror})")
    missing = [c for c in COLUMNS if not rows or c not in rows[0]]
    if missing:
        sys.exit(f"plot_study.py: error: {a.csv}: missing column(s) {', '.join(missing)}"
                 f" (expected {', '.join(COLUMNS)})")
    groups = defaultdict(list)  # (d, Ca) -> [(Ht, mean, std, lambda)]
    kinds = defaultdict(set)  # (d, Ca) -> {"p_fZ", "p_fD"}
    for i, r in enumerate(rows, start=2):
        v = {k: number(r, k, a.csv, i) for k in COLUMNS}
        if math.isnan(v["p_f_mean"]):
            continue
        groups[(v["row_shift_um"], v["capillary_number"])].append(
            (v["haematocrit_percent"], v["p_f_mean"], v["p_f_std"], v["pillar_spacing_um"]))
        if r.get("failure"):  # p_fZ or p_fD: which failure the run's expected mode makes it
            kinds[(v["row_shift_um"], v["capillary_number"])].add(r["failure"])
    shifts = sorted({d for d, _ in groups})
    if not shifts:
        sys.exit(f"plot_study.py: error: {a.csv}: no row with a failure probability")
    import matplotlib  # only now: the checks above answer without it

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(shifts), figsize=(4.5 * len(shifts), 4), squeeze=False,
                             sharex=True, sharey=True)
    for ax, d in zip(axes[0], shifts):
        lam = None
        for (dd, ca), pts in sorted(groups.items()):
            if dd != d:
                continue
            pts.sort()
            lam = pts[0][3]
            ax.errorbar([p[0] for p in pts], [p[1] for p in pts],
                        yerr=[0 if math.isnan(p[2]) else p[2] for p in pts], marker="o",
                        capsize=3,
                        label=f"Ca = {ca:g}" + "".join(f" ({k})" for k in sorted(kinds[(dd, ca)])))
        ax.axhline(d / lam, color="k", ls="--", lw=1,
                   label=f"p_fD ceiling d/lambda = {d / lam:.3f}")
        ax.axhline(0, color="0.5", lw=0.5)
        ax.set_title(f"d = {d:g} um")
        ax.set_xlabel("Ht [%]")
        ax.set_xlim(0, 50)  # the study's haematocrits, 8-45.6 %: runs still to come have a place
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("failure probability (p_fZ or p_fD, mean +- std)")
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    print(f"plot: {a.output}")


if __name__ == "__main__":
    main()
