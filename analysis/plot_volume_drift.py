#!/usr/bin/python3
"""Cell volumes over a run, for comparing the stability of runs side by side.

    analysis/plot_volume_drift.py out.png LABEL=run.h5 [LABEL=run.h5 ...] [--x step] [--csv out.csv]

Reads /membrane-k/cells/samples of each run file, or /cells/samples of a membrane part file
(columns: step, then per cell centroid x y z [um] and volume [um^3]) and the time step (its dt_s
attribute); plots the smallest and the mean cell volume change [% of the first sample] against
physical time [ms], or with --x step against the time step (a numerical effect tied to the step
shows there as one curve whatever the time step). The CSV has one row per run and sample.
"""
import argparse
import sys

from compare_runs import samples  # the reader of run and part files (this script's folder)


def volumes(path):
    """(step, time_ms, volumes[sample, cell]) of a run file (all membrane parts side by side) or of
    a membrane part file (run-cells-k.h5: a running run's, which holds every sample so far)."""
    time_ms, step, cells = samples(path)
    return step, time_ms, cells[:, :, 3]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("png")
    ap.add_argument("runs", nargs="+", metavar="LABEL=run.h5")
    ap.add_argument("--x", choices=["time", "step"], default="time")
    ap.add_argument("--csv")
    a = ap.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.2))
    rows = ["label,step,time_ms,min_volume_change_percent,mean_volume_change_percent"]
    for spec in a.runs:
        if "=" not in spec:
            sys.exit(f"argument '{spec}': expected LABEL=run.h5")
        label, path = spec.split("=", 1)
        step, t_ms, vol = volumes(path)
        change = 100 * (vol / vol[0] - 1)
        lo, mean = change.min(axis=1), change.mean(axis=1)
        x = t_ms if a.x == "time" else step
        (line,) = ax.plot(x, lo, label=label)
        ax.plot(x, mean, ls=":", color=line.get_color())
        rows += [f"{label},{s:.0f},{t:.6g},{x:.5g},{m:.5g}" for s, t, x, m in zip(step, t_ms, lo, mean)]
    ax.axhline(-1, color="grey", lw=0.8, ls="--")
    ax.set_xlabel("time [ms]" if a.x == "time" else "time step")
    ax.set_ylabel("cell volume change [%]")
    ax.set_title("solid: the smallest cell, dotted: the mean over the cells", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.png, dpi=120)
    if a.csv:
        with open(a.csv, "w") as out:
            out.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
