#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Plots one analysed run (called by dld-analyze): cell trajectories (y/lambda against x/lambda,
with the array inclination d/lambda and the horizontal from the mean start) and the outlet
histogram (SPEC section 7), correct outlets green, wrong ones red (grey: expected mode unknown).
Reads the cells run files (or the run file dld-run merges them into) and the CSVs dld-analyze
wrote."""
import argparse
import csv
import os
import sys

os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")  # read a run file while it is written
import h5py  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def cells_groups(f):
    """/cells of a cells run file, else every /membrane-K/cells of dld-run's run file."""
    if "cells" in f:
        return [f["cells"]]
    return [f[m]["cells"] for m in f if m.startswith("membrane-") and "cells" in f[m]]


def trajectories(files):
    """(first_cell + k, x [um], y [um]) per cell of every run file."""
    out = []
    for path in files:
        try:
            f = h5py.File(path, "r")
        except OSError as e:
            sys.exit(f"plot_run.py: error: {path}: cannot open HDF5 run file ({e})")
        with f:
            for cells in cells_groups(f):
                rows = cells["samples"][...]
                first = int(cells.attrs["first_cell"])
                for k in range(int(cells.attrs["count"])):
                    out.append((first + k, rows[:, 1 + 4 * k], rows[:, 2 + 4 * k]))
    return sorted(out, key=lambda t: t[0])


def plot_trajectories(files, cells, summary, png):
    lam = float(summary["pillar_spacing_um"])
    d = float(summary["row_shift_um"])
    tracks = trajectories(files)
    fig, ax = plt.subplots(figsize=(9, 5))
    for cid, x, y in tracks:
        ax.plot(x / lam, y / lam, lw=1, label=f"cell {cid}" if len(tracks) <= 10 else None)
    x0 = np.mean([float(c["x0_um"]) for c in cells]) / lam
    y0 = np.mean([float(c["y0_um"]) for c in cells]) / lam
    xmax = max(float(np.max(x)) for _, x, _ in tracks) / lam
    xs = np.array([x0, max(xmax, x0 + 1)])
    ax.plot(xs, y0 + (d / lam) * (xs - x0), "k--", lw=1,
            label=f"array inclination d/lambda = {d / lam:.4f}")
    ax.plot(xs, [y0, y0], "k:", lw=1, label="horizontal")
    ends = [(float(c["x0_um"]) / lam + int(c["pillars"]), float(c["y_end_um"]) / lam)
            for c in cells if c["y_end_um"]]
    if ends:
        ax.plot(*zip(*ends), "ko", ms=4, mfc="none", label="evaluated")
    ax.set_xlabel("x / lambda")
    ax.set_ylabel("y / lambda")
    expected = summary["expected_mode"]
    ax.set_title(f"{summary['scene_name']}: d = {d} um, Ca = {summary['capillary_number'] or '?'}, "
                 f"expected {expected}")
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def plot_outlets(outlets, summary, png):
    rows = [r for r in outlets if r["outlet"].startswith("O")]
    colour = {"yes": "tab:green", "no": "tab:red", "": "0.6"}
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.bar([r["outlet"] for r in rows], [float(r["fraction"]) for r in rows],
           color=[colour[r["correct"]] for r in rows], edgecolor="k")
    for i, r in enumerate(rows):
        ax.text(i, float(r["fraction"]), f"{r['count']}", ha="center", va="bottom")
    # Empty bars are invisible: the outlet names carry the colour too, with their y range [um].
    ax.set_xticks(range(len(rows)))
    ax.set_xticklabels([f"{r['outlet']}\n[{float(r['y_low_um']):.0f}, {float(r['y_high_um']):.0f}]"
                        for r in rows], fontsize=8)
    for label, r in zip(ax.get_xticklabels(), rows):
        label.set_color(colour[r["correct"]] if r["correct"] else "k")
    outside = [r for r in outlets if r["outlet"] == "outside"]
    if outside and int(outside[0]["count"]) > 0:
        ax.text(0.98, 0.95, f"outside the outlets: {outside[0]['count']}", transform=ax.transAxes,
                ha="right", va="top", fontsize=8)
    ax.set_ylim(0, 1.1)
    ax.set_ylabel("fraction of cells")
    known = summary["expected_mode"] != "unknown"
    ax.set_title(f"outlets after {summary['outlet_pillars']} columns"
                 + (f" (expected {summary['expected_mode']}: green correct, red wrong)" if known
                    else " (expected mode unknown)"), fontsize=9)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("runs", nargs="+", help="cells run files <stem>-cells-K.h5 or the run file")
    ap.add_argument("--cells", required=True)
    ap.add_argument("--summary", required=True)
    ap.add_argument("--outlets", required=True)
    ap.add_argument("--trajectories-png", required=True)
    ap.add_argument("--outlets-png", required=True)
    a = ap.parse_args()
    summary = read_csv(a.summary)[0]
    plot_trajectories(a.runs, read_csv(a.cells), summary, a.trajectories_png)
    plot_outlets(read_csv(a.outlets), summary, a.outlets_png)


if __name__ == "__main__":
    main()
