#!/usr/bin/python3
"""Volume change of cells against how fast they move: do held cells lose volume?

    analysis/volume_by_pace.py RUN.h5 [--window STEPS] [--pillar-radius UM] [--csv OUT.csv]

Cuts each cell's track (/membrane-k/cells/samples of a run file, or /cells/samples of a part
file: step, then per cell centroid x y z [um, device frame] and volume [um^3]) into windows of
--window steps, and for each window takes the cell's speed along x [um per 100 000 steps], its
volume change [% of its first volume] and whether its centroid lies within a cell radius (4 um)
of a pillar's surface (pillar centres at (lambda k, lambda j + d k), lambda and d from the file's
attributes). Prints the mean volume change per window for five classes of speed (the slowest
tenth, then quartiles), with the share of windows near a pillar; --csv writes every window.
A leak that follows the load on a cell shows as a loss in the slowest class only.
"""
import argparse
import csv
import sys

import h5py
import numpy as np

CELL_RADIUS_UM = 4.0  # "near a pillar": centroid within about one cell radius of its surface


def samples(path):
    """(samples[row, column], lambda_um, d_um) of a run file or a membrane part file."""
    try:
        f = h5py.File(path, "r", locking=False)
    except OSError as e:
        sys.exit(f"volume_by_pace.py: {path}: cannot open as HDF5 ({e})")
    with f:
        groups = [f[k]["cells"] for k in sorted(f) if k.startswith("membrane-") and "cells" in f[k]]
        if not groups and "cells" in f:
            groups = [f["cells"]]
        if not groups or any("samples" not in g for g in groups):
            sys.exit(f"volume_by_pace.py: {path}: no cells/samples (expected a dld-run run file)")
        attrs = groups[0].attrs
        if "pillar_spacing_um" not in attrs or "row_shift_um" not in attrs:
            sys.exit(f"volume_by_pace.py: {path}: cells has no pillar_spacing_um/row_shift_um")
        tables = [g["samples"][:] for g in groups]
        lam, d = float(attrs["pillar_spacing_um"]), float(attrs["row_shift_um"])
    n = min(len(t) for t in tables)
    return np.hstack([tables[0][:n, :1]] + [t[:n, 1:] for t in tables]), lam, d


def distance_to_pillar(x, y, lam, d, radius):
    """Distance [um] from (x, y) to the nearest pillar's surface."""
    best = np.inf
    for k in np.round(x / lam) + np.arange(-1, 2):
        j0 = np.round((y - d * k) / lam)
        for j in (j0 - 1, j0, j0 + 1):
            best = min(best, np.hypot(x - lam * k, y - (lam * j + d * k)) - radius)
    return best


def windows(a, lam, d, radius, per):
    """One row per cell and window: cell, first step, u_x [um/1e5 steps], dV [%], near pillar."""
    step = a[:, 0]
    rows = []
    for c in range((a.shape[1] - 1) // 4):
        x, y, v = a[:, 1 + 4 * c], a[:, 2 + 4 * c], a[:, 4 + 4 * c]
        for s in range(0, len(step) - per, per):
            e = s + per
            near = distance_to_pillar(x[s:e].mean(), y[s:e].mean(), lam, d, radius) < CELL_RADIUS_UM
            rows.append((c, step[s], (x[e] - x[s]) / (step[e] - step[s]) * 1e5,
                         (v[e] - v[s]) / v[0] * 100, near))
    return np.array(rows, dtype=float)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run")
    ap.add_argument("--window", type=int, default=100000, help="steps per window (100000)")
    ap.add_argument("--pillar-radius", type=float, default=10.0, help="um (10, the study's)")
    ap.add_argument("--csv")
    a = ap.parse_args()
    if a.window <= 0 or not a.pillar_radius > 0:
        sys.exit("volume_by_pace.py: --window and --pillar-radius must be positive")
    table, lam, d = samples(a.run)
    sample_steps = np.diff(table[:, 0])
    if len(sample_steps) == 0 or sample_steps[0] <= 0:
        sys.exit(f"volume_by_pace.py: {a.run}: fewer than two samples")
    per = max(1, int(round(a.window / sample_steps[0])))
    r = windows(table, lam, d, a.pillar_radius, per)
    if len(r) < 10:
        sys.exit(f"volume_by_pace.py: {a.run}: {len(r)} windows of {a.window} steps; need 10")
    edges = np.quantile(r[:, 2], [0, 0.1, 0.25, 0.5, 0.75, 1])
    print(f"{a.run}: {len(r)} windows of a cell's track, {per * sample_steps[0]:.0f} steps each "
          f"(d {d:g} um, lambda {lam:g} um)")
    print("u_x [um/1e5 steps]   windows   mean dV [%/window]   near a pillar")
    for i, (lo, hi) in enumerate(zip(edges[:-1], edges[1:])):
        m = (r[:, 2] >= lo) & ((r[:, 2] < hi) if i < 4 else (r[:, 2] <= hi))
        if not m.any():
            continue  # a class no window falls in (tied speeds)
        print(f"{lo:8.2f} .. {hi:7.2f}   {m.sum():7d}   {r[m, 3].mean():+18.4f}   "
              f"{r[m, 4].mean():12.2f}")
    if a.csv:
        with open(a.csv, "w", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(["cell", "first_step", "u_x_um_per_1e5_steps", "volume_change_percent",
                        "near_pillar"])
            for c, s, u, dv, near in r:
                w.writerow([int(c), int(s), f"{u:.6g}", f"{dv:.6g}", int(near)])


if __name__ == "__main__":
    main()
