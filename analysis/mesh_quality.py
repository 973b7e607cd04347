#!/usr/bin/python3
"""Triangle quality of every cell in a membrane checkpoint: are triangles collapsing?

    analysis/mesh_quality.py CHECKPOINT.h5 MESH.off --radius-lu R [--collapsed J]

Reads /membrane/positions (nodes, cell after cell; lattice units) of a dld-membrane checkpoint
(<run>-cells-k.ckpt.h5) and the cells' rest mesh (the .off that cache/meshes holds, in units of
the cell radius; R = the radius in lattice spacings, e.g. 9.75 for 3.9 um at dx 0.4 um, as the
membrane log prints it). For each cell: the smallest and largest triangle angle [deg], the
smallest area ratio J = A / A_rest, and how many triangles have J below --collapsed (default 0.2).
Skalak's area term resists a compressed triangle less and less below J = 1/sqrt(3)
(docs/results-history.md, "Why the dense runs go unstable late"), so collapsed triangles warn
that a run is near a stop.
With --scene (the run's scene.toml: [geometry] and [lattice] dx_um), also where they are: how
many collapsed triangles lie within --film lattice spacings (default 2) of the pillar's surface or
a wall, against that share of all triangles (they collapse in the film there:
docs/results-history.md, "Where the triangles collapse").
Exit code 0; one line naming the file for input it cannot read.
"""
import argparse
import sys
import tomllib

import h5py
import numpy as np


def read_off(path):
    """(vertices[n, 3], faces[m, 3]) of an OFF file."""
    try:
        words = open(path).read().split()
    except OSError as e:
        sys.exit(f"mesh_quality.py: {path}: {e.strerror}")
    if not words or words[0] != "OFF":
        sys.exit(f"mesh_quality.py: {path}: not an OFF file (expected 'OFF' first)")
    nv, nf = int(words[1]), int(words[2])
    v = np.array(words[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    f = np.array(words[4 + 3 * nv:4 + 3 * nv + 4 * nf], dtype=int).reshape(nf, 4)
    if (f[:, 0] != 3).any():
        sys.exit(f"mesh_quality.py: {path}: only triangles expected")
    return v, f[:, 1:]


def read_positions(path):
    try:
        with h5py.File(path, "r", locking=False) as h:
            return h["membrane/positions"][:], int(h["membrane"].attrs.get("step", -1))
    except (OSError, KeyError) as e:
        sys.exit(f"mesh_quality.py: {path}: no /membrane/positions of a dld-membrane checkpoint ({e})")


def areas(x, faces):
    a, b, c = x[faces[:, 0]], x[faces[:, 1]], x[faces[:, 2]]
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)


def angles(x, faces):
    """Corner angles [deg] of every triangle, shape (m, 3)."""
    p = [x[faces[:, k]] for k in range(3)]
    out = []
    for k in range(3):
        u, w = p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]
        cos = (u * w).sum(1) / (np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1))
        out.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.stack(out, 1)


def read_box(path):
    """(spacing, pillar radius, depth, row shift) of a DLD scene, in lattice spacings."""
    try:
        with open(path, "rb") as f:
            t = tomllib.load(f)
        g, dx = t["geometry"], t["lattice"]["dx_um"]
        return tuple(g[k] / dx for k in ("pillar_spacing_um", "pillar_radius_um", "depth_um",
                                          "row_shift_um"))
    except (OSError, tomllib.TOMLDecodeError, KeyError, TypeError) as e:
        sys.exit(f"mesh_quality.py: {path}: no DLD geometry ([geometry] pillar_spacing_um, "
                 f"pillar_radius_um, depth_um, row_shift_um and [lattice] dx_um): {e}")


def distances_to_solids(p, box):
    """Distances [lattice spacings] of points p (n, 3; unwrapped device frame) to the pillar's
    surface (the pillar centred in the box) and to the nearer wall (z = 0, depth). Across the
    shifted x face the next box is lower by the row shift (fluid/immersed_boundary.hpp)."""
    spacing, radius, depth, shift = box
    columns = np.floor(p[:, 0] / spacing)
    x = p[:, 0] - columns * spacing
    y = np.mod(p[:, 1] - columns * shift, spacing)
    return (np.hypot(x - spacing / 2, y - spacing / 2) - radius,
            np.minimum(p[:, 2], depth - p[:, 2]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("checkpoint")
    ap.add_argument("mesh")
    ap.add_argument("--radius-lu", type=float, required=True)
    ap.add_argument("--collapsed", type=float, default=0.2)
    ap.add_argument("--scene")
    ap.add_argument("--film", type=float, default=2.0)
    a = ap.parse_args()
    if not a.radius_lu > 0 or not 0 < a.collapsed < 1:
        sys.exit("mesh_quality.py: --radius-lu must be positive and --collapsed in (0, 1)")
    rest, faces = read_off(a.mesh)
    x, step = read_positions(a.checkpoint)
    n = len(rest)
    if len(x) % n:
        sys.exit(f"mesh_quality.py: {a.checkpoint}: {len(x)} nodes are not cells of {n} ({a.mesh})")
    rest_area = areas(rest * a.radius_lu, faces)
    ang0 = angles(rest, faces)
    print(f"{a.checkpoint}: step {step}, {len(x) // n} cells; rest mesh angles "
          f"{ang0.min():.1f}..{ang0.max():.1f} deg")
    print("cell  angles [deg]      smallest J  largest J  triangles J < %g" % a.collapsed)
    box = read_box(a.scene) if a.scene else None
    near = {"the pillar": [0, 0], "a wall": [0, 0]}  # triangles within --film: all, collapsed
    collapsed = 0
    for c in range(len(x) // n):
        p = x[c * n:(c + 1) * n]
        ang, j = angles(p, faces), areas(p, faces) / rest_area
        print(f"{c:4d}  {ang.min():5.1f}..{ang.max():5.1f}   {j.min():10.3f}  {j.max():9.3f}  "
              f"{(j < a.collapsed).sum():6d}")
        if box:
            collapsed += (j < a.collapsed).sum()
            for name, d in zip(near, distances_to_solids(p[faces].mean(axis=1), box)):
                near[name][0] += (d < a.film).sum()
                near[name][1] += ((d < a.film) & (j < a.collapsed)).sum()
    triangles = len(x) // n * len(faces)
    for name, (every, bad) in near.items() if box else ():
        share = 100 * bad / collapsed if collapsed else 0.0
        print(f"within {a.film:g} spacings of {name}: {bad} of the {collapsed} collapsed "
              f"triangles ({share:.0f} %), {100 * every / triangles:.1f} % of all")

if __name__ == "__main__":
    main()
