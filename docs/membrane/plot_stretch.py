#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Plot a dld-membrane stretch CSV against Mills et al. 2004 (mean and ranges).

Usage: plot_stretch.py SIM.csv MILLS_WITH_RANGES.txt OUT.png
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_sim(path):
    rows = [l.strip().split(",") for l in open(path) if l[0].isdigit()]
    return [[float(r[i]) for r in rows] for i in range(3)]


def read_mills(path):
    rows = [list(map(float, l.split())) for l in open(path) if l.strip() and l[0] != "#"]
    return [[r[i] for r in rows] for i in range(7)]


sim_f, sim_a, sim_t = read_sim(sys.argv[1])
f, dt, da, dt_lo, dt_hi, da_lo, da_hi = read_mills(sys.argv[2])
fig, ax = plt.subplots(figsize=(6, 4.5))
ax.errorbar(f, da, yerr=[[a - lo for a, lo in zip(da, da_lo)], [hi - a for a, hi in zip(da, da_hi)]],
            fmt="s", color="tab:blue", mfc="none", capsize=3, label="Mills 2004, axial D_A (mean, range)")
ax.errorbar(f, dt, yerr=[[t - lo for t, lo in zip(dt, dt_lo)], [hi - t for t, hi in zip(dt, dt_hi)]],
            fmt="o", color="tab:red", mfc="none", capsize=3, label="Mills 2004, transverse D_T (mean, range)")
ax.plot(sim_f, sim_a, "-", color="tab:blue", label="dld-membrane D_A")
ax.plot(sim_f, sim_t, "-", color="tab:red", label="dld-membrane D_T")
ax.set_xlabel("stretching force [pN]")
ax.set_ylabel("diameter [um]")
ax.set_title("Optical tweezers, healthy RBC: G_s = 5.3 uN/m, 2000 faces")
ax.legend(fontsize=8, loc="center right")
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(sys.argv[3], dpi=120)
