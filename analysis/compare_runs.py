#!/usr/bin/python3
"""Two runs of the same cells side by side: how far their cells got at the same physical time.

    analysis/compare_runs.py A=run.h5 B=run.h5 [--times N] [--by time|advance] [--csv out.csv]
                             [--plot trajectories.png]

For runs that start from the same packed cells under two numerical settings (a wall rule, a time
step, a coupling): at N physical times spread over the span both runs have sampled, the mean
downstream advance of their cells [um] and its ratio B/A (the suspension's relative speed), the
mean lateral advance [um], and each run's largest cell volume loss [% of the cell's first
sample]. Runs at different time steps are compared at the same time (each run's samples
interpolated linearly). Runs whose cells start elsewhere are compared all the same, with a warning:
then it is two suspensions, not two settings. Reads /membrane-k/cells/samples of a run file, or
/cells/samples of a membrane part file (run-cells-k.h5), and their dt_s attribute.

--by advance compares at the same downstream advance instead, for settings whose flows differ in
physical speed (a Reynolds number raised at the same capillary number runs the same device faster):
at N advances up to the distance the median cell has travelled in both runs, over the cells that
have travelled that far in both, each cell's lateral position where it has advanced that far (its
own track), the mean lateral advance of each run, the largest difference between a cell's two
lateral positions [um], the physical times each run took to get there (mean advance), and each
run's largest volume loss by then. --plot draws every cell's track (lateral against downstream
advance) of both runs over the same span, and each cell's lateral difference.
"""
import argparse
import sys

import h5py
import numpy as np


def samples(path):
    """(time_ms[sample], step[sample], cells[sample, cell, (x, y, z, V)]) of one run, all membrane
    parts side by side; SystemExit with one line naming the file on bad input."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        sys.exit(f"{path}: cannot open as HDF5 ({e})")
    with f:
        groups = [f[k]["cells"] for k in sorted(f) if k.startswith("membrane-")
                  and "cells/samples" in f[k]]
        if not groups and "cells/samples" in f:
            groups = [f["cells"]]
        if not groups:
            sys.exit(f"{path}: no /membrane-k/cells/samples or /cells/samples "
                     "(expected a run file or a membrane part file of dld-run)")
        if "dt_s" not in groups[0].attrs:
            sys.exit(f"{path}: cells group without its dt_s attribute")
        dt_s = float(groups[0].attrs["dt_s"])
        tables = [g["samples"][:] for g in groups]
    n = min(len(t) for t in tables)
    if n < 2 or any((t.shape[1] - 1) % 4 for t in tables):
        sys.exit(f"{path}: expected at least 2 samples of step then x, y, z, V per cell")
    step = tables[0][:n, 0]
    cells = np.concatenate([t[:n, 1:].reshape(n, -1, 4) for t in tables], axis=1)
    return step * dt_s * 1e3, step, cells


def at(time_ms, t, values):
    """values[sample, ...] interpolated linearly to time_ms."""
    flat = values.reshape(len(t), -1)
    return np.array([np.interp(time_ms, t, flat[:, k]) for k in range(flat.shape[1])]).reshape(
        values.shape[1:])


def compare(a, b, times):
    """Rows (time_ms, step_a, step_b, advance_a, advance_b, ratio, lateral_a, lateral_b,
    volume_loss_a, volume_loss_b) at `times` physical times over the common span."""
    (ta, sa, ca), (tb, sb, cb) = a, b
    span = min(ta[-1], tb[-1])
    rows = []
    for t in np.linspace(0, span, times + 1)[1:]:
        pa, pb = at(t, ta, ca), at(t, tb, cb)
        adv = [(p[:, 0] - c[0, :, 0]).mean() for p, c in ((pa, ca), (pb, cb))]
        lat = [(p[:, 1] - c[0, :, 1]).mean() for p, c in ((pa, ca), (pb, cb))]
        loss = [100 * min(0.0, (p[:, 3] / c[0, :, 3] - 1).min()) for p, c in ((pa, ca), (pb, cb))]
        ratio = adv[1] / adv[0] if adv[0] != 0 else float("nan")
        rows.append((t, np.interp(t, ta, sa), np.interp(t, tb, sb), adv[0], adv[1], ratio, lat[0],
                     lat[1], loss[0], loss[1]))
    return rows


def monotone(x):
    """x made non-decreasing (a cell may step back a little at a pillar): a track to interpolate
    over."""
    return np.maximum.accumulate(x)


def common_advance(a, b):
    """Per cell, the downstream distance [um] it has travelled in both runs."""
    return np.minimum(*(monotone(c[:, :, 0] - c[0, :, 0])[-1] for _, _, c in (a, b)))


def compare_by_advance(a, b, times):
    """Rows (advance_um, cells, time_a_ms, time_b_ms, step_a, step_b, lateral_a, lateral_b,
    largest_lateral_difference, volume_loss_a, volume_loss_b) at `times` advances up to the
    median cell's common advance (or either run's mean advance, if less: that dates each row);
    each row over the cells that have travelled that far in both runs (a cell held at a pillar
    would otherwise end the comparison)."""
    reach = common_advance(a, b)
    means = [monotone(c[:, :, 0] - c[0, :, 0]).mean(axis=1)[-1] for _, _, c in (a, b)]
    span = float(min(np.median(reach), *means))
    rows = []
    for s in np.linspace(0, span, times + 1)[1:]:
        lat, when, loss = [], [], []
        cells = np.flatnonzero(reach >= s)
        for t, step, c in (a, b):
            x = monotone(c[:, :, 0] - c[0, :, 0])
            lat.append(np.array([np.interp(s, x[:, k], c[:, k, 1] - c[0, k, 1]) for k in cells]))
            mean_t = np.interp(s, monotone(x.mean(axis=1)), t)
            when.append((mean_t, np.interp(mean_t, t, step)))
            upto = t <= mean_t
            loss.append(100 * min(0.0, (c[upto, :, 3] / c[0, :, 3] - 1).min()))
        rows.append((s, len(cells), when[0][0], when[1][0], when[0][1], when[1][1],
                     lat[0].mean(), lat[1].mean(), float(np.abs(lat[0] - lat[1]).max()), loss[0],
                     loss[1]))
    return rows


def plot_tracks(path, labels, runs):
    """Each cell's lateral against downstream advance, both runs over the common span (top), and
    the difference of its two lateral positions at the same advance (bottom)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    reach = common_advance(*runs)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 8), sharex=True)
    for k, span in enumerate(reach):
        grid = np.linspace(0, span, 200)
        y = []
        for (_, _, c), label, style in zip(runs, labels, ("-", "--")):
            y.append(np.interp(grid, monotone(c[:, k, 0] - c[0, k, 0]), c[:, k, 1]))
            top.plot(grid, y[-1], style, lw=1, color=f"C{k % 10}", label=label if k == 0 else None)
        bottom.plot(grid, y[1] - y[0], lw=1, color=f"C{k % 10}")
    top.set_ylabel("lateral position y [um]")
    top.set_title(f"each cell's track, {labels[0]} (solid) and {labels[1]} (dashed)")
    top.legend()
    bottom.set_xlabel("downstream advance of the cell [um]")
    bottom.set_ylabel(f"y {labels[1]} - y {labels[0]} [um]")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def report_by_advance(rows, la, lb, csv_path):
    print(f"advance [um]  cells  time {la} [ms]  time {lb} [ms]  step {la}  step {lb}  "
          f"lateral {la} [um]  lateral {lb} [um]  largest cell difference [um]  "
          f"volume loss {la} [%]  volume loss {lb} [%]")
    for r in rows:
        print(f"{r[0]:.3f}  {r[1]}  {r[2]:.4g}  {r[3]:.4g}  {r[4]:.0f}  {r[5]:.0f}  {r[6]:.3f}  "
              f"{r[7]:.3f}  {r[8]:.3f}  {r[9]:.3f}  {r[10]:.3f}")
    if csv_path:
        with open(csv_path, "w") as f:
            f.write("advance_um,cells,time_a_ms,time_b_ms,step_a,step_b,lateral_a_um,lateral_b_um,"
                    "largest_lateral_difference_um,volume_loss_a_percent,volume_loss_b_percent\n")
            f.writelines(",".join(f"{v:.6g}" for v in r) + "\n" for r in rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs=2, metavar="LABEL=run.h5")
    ap.add_argument("--times", type=int, default=10, help="how many times to compare at (1..1000)")
    ap.add_argument("--by", choices=("time", "advance"), default="time",
                    help="compare at the same physical time (default) or downstream advance")
    ap.add_argument("--csv", help="the rows as CSV")
    ap.add_argument("--plot", help="with --by advance: each cell's track of both runs (PNG)")
    a = ap.parse_args()
    if a.plot and a.by != "advance":
        sys.exit("--plot: expected --by advance (tracks are drawn over the common advance)")
    if not 1 <= a.times <= 1000:
        sys.exit(f"--times {a.times}: expected 1..1000")
    labels, runs = [], []
    for spec in a.runs:
        if "=" not in spec:
            sys.exit(f"argument '{spec}': expected LABEL=run.h5")
        label, path = spec.split("=", 1)
        labels.append(label)
        runs.append(samples(path))
    na, nb = runs[0][2].shape[1], runs[1][2].shape[1]
    if na != nb:
        sys.exit(f"{labels[0]} has {na} cells and {labels[1]} {nb}: expected the same cells")
    if not np.allclose(runs[0][2][0, :, :3], runs[1][2][0, :, :3], atol=1e-6):
        print(f"warning: {labels[0]} and {labels[1]} start from different cell positions: two "
              "suspensions, not two settings", file=sys.stderr)
    la, lb = labels
    if a.by == "advance":
        report_by_advance(compare_by_advance(runs[0], runs[1], a.times), la, lb, a.csv)
        if a.plot:
            plot_tracks(a.plot, labels, runs)
        return
    rows = compare(runs[0], runs[1], a.times)
    head = (f"time [ms]  step {la}  step {lb}  advance {la} [um]  advance {lb} [um]  ratio  "
            f"lateral {la} [um]  lateral {lb} [um]  volume loss {la} [%]  volume loss {lb} [%]")
    print(head)
    for r in rows:
        print(f"{r[0]:.4g}  {r[1]:.0f}  {r[2]:.0f}  {r[3]:.3f}  {r[4]:.3f}  {r[5]:.4f}  {r[6]:.3f}  "
              f"{r[7]:.3f}  {r[8]:.3f}  {r[9]:.3f}")
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("time_ms,step_a,step_b,advance_a_um,advance_b_um,ratio,lateral_a_um,"
                    "lateral_b_um,volume_loss_a_percent,volume_loss_b_percent\n")
            f.writelines(",".join(f"{v:.6g}" for v in r) + "\n" for r in rows)


if __name__ == "__main__":
    main()
