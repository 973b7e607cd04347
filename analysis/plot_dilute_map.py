#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The dilute-limit map as one figure: the trajectory of the single cell of each (d, Ca) run
(y/lambda against x/lambda from its start, array inclination d/lambda dashed, horizontal dotted),
one panel per case, rows d and columns Ca. Usage:
    plot_dilute_map.py runs/dilute/cell-d*-cells-0.h5 -o map.png"""
import argparse
import os
import sys

os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")
import h5py  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("files", nargs="+", help="cells run files of one-cell runs")
    p.add_argument("-o", "--output", required=True, help="PNG to write")
    a = p.parse_args()
    runs = {}
    for path in a.files:
        try:
            with h5py.File(path, "r") as f:
                attrs = f["cells"].attrs
                d = float(attrs["row_shift_um"])
                ca = float(attrs["capillary_number"])
                lam = float(attrs["pillar_spacing_um"])
                rows = f["cells/samples"][...]
        except (OSError, KeyError) as e:
            sys.exit(f"plot_dilute_map.py: error: {path}: not a cells run file with "
                     f"row_shift_um and capillary_number ({e})")
        runs[(d, ca)] = (lam, rows[:, 1], rows[:, 2], os.path.basename(path))
    ds = sorted({k[0] for k in runs})
    cas = sorted({k[1] for k in runs})
    fig, axes = plt.subplots(len(ds), len(cas), figsize=(4.2 * len(cas), 2.8 * len(ds)),
                             squeeze=False)
    for i, d in enumerate(ds):
        for j, ca in enumerate(cas):
            ax = axes[i][j]
            ax.set_title(f"d = {d:g} um, Ca = {ca:g}", fontsize=10)
            if (d, ca) not in runs:
                ax.text(0.5, 0.5, "not run", ha="center", transform=ax.transAxes)
                continue
            lam, x, y, _ = runs[(d, ca)]
            xs, ys = (x - x[0]) / lam, (y - y[0]) / lam
            ax.plot(xs, ys, lw=1.2)
            ax.plot([0, xs[-1]], [0, xs[-1] * d / lam], "k--", lw=0.8)
            ax.plot([0, xs[-1]], [0, 0], "k:", lw=0.8)
            ax.grid(alpha=0.3)
            if i == len(ds) - 1:
                ax.set_xlabel("x / lambda")
            if j == 0:
                ax.set_ylabel("y / lambda")
    fig.tight_layout()
    fig.savefig(a.output, dpi=110)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
