#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Plots a fluid-only DLD run file: depth-averaged speed with streamlines, the pillar, and the
gap flux profile with the separation band. Reads only the HDF5 run file."""
import argparse
import sys

import os

os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")  # read a run file while it is written
import h5py  # noqa: E402
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("run", help="run file written by dld-fluid")
    ap.add_argument("-o", "--output", default=None, help="PNG file (default: run file with .png)")
    a = ap.parse_args()
    try:
        f = h5py.File(a.run, "r")
    except OSError as e:
        sys.exit(f"error: {a.run}: cannot open HDF5 run file ({e})")
    with f:
        if "fields" not in f or "results" not in f:
            sys.exit(f"error: {a.run}: no /fields or /results (is this a finished dld-fluid run?)")
        sc = f["scene"].attrs
        lam, radius, d = sc["lambda_um"], sc["pillar_radius_um"], sc["row_shift_um"]
        steps = sorted(k for k in f["fields"] if k.startswith("step_"))
        vel = f["fields"][steps[-1]]["velocity_m_s"][...]  # (nz, ny, nx, 3)
        solid = f["fields"]["solid"][...]
        s_um = f["results"]["separation_distance_um"][0]
        y_um = f["results"]["gap_profile_y_um"][...]
        q = f["results"]["gap_profile_q_m2_s"][...]
    ux = vel[..., 0].mean(axis=0) * 1e3  # mm/s, depth-averaged
    uy = vel[..., 1].mean(axis=0) * 1e3
    speed = np.hypot(ux, uy)
    speed[solid[0] == 1] = np.nan
    ny, nx = ux.shape
    x = (np.arange(nx) + 0.5) * lam / nx
    y = (np.arange(ny) + 0.5) * lam / ny

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.8), gridspec_kw={"width_ratios": [1.1, 1]})
    m = ax.pcolormesh(x, y, speed, shading="auto", cmap="viridis")
    ax.streamplot(x, y, np.nan_to_num(ux), np.nan_to_num(uy), color="w", density=1.2, linewidth=0.6)
    ax.add_patch(plt.Circle((lam / 2, lam / 2), radius, color="0.6"))
    ax.set_aspect("equal")
    ax.set_xlim(0, lam)
    ax.set_ylim(0, lam)
    ax.set_xlabel("x [um]")
    ax.set_ylabel("y [um]")
    ax.set_title(f"depth-averaged speed [mm/s], d = {d} um")
    fig.colorbar(m, ax=ax)

    gap = lam - 2 * radius
    yy = np.concatenate([[0], y_um, [gap]])
    qq = np.concatenate([[0], q, [0]]) * 1e12  # m^2/s to um^2/s
    bx.plot(yy, qq, "o-", ms=3)
    bx.axvspan(0, s_um, color="C1", alpha=0.3, label=f"band with eps = d/lambda of the flux: s = {s_um:.3f} um")
    bx.set_xlabel("distance from the lower pillar across the gap [um]")
    bx.set_ylabel("depth-integrated u_x [um^2/s]")
    bx.set_xlim(0, gap)
    bx.legend(loc="lower center", fontsize=8)
    bx.set_title("flux profile through the gap above the pillar")
    fig.tight_layout()
    out = a.output or a.run.rsplit(".", 1)[0] + ".png"
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main()
