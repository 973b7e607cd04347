#!/usr/bin/python3
"""analysis/mesh_quality.py on a synthetic checkpoint: two cells of a small rest mesh (an
octahedron, radius 1) at radius 10; in cell 1 the top node is pushed onto the midpoint of an
edge of one of its triangles, which collapses to zero area (its neighbours flatten, J 0.58-1.15). Cell 0 must read J = 1 and no collapsed triangle,
cell 1 one, which --scene places within 2 spacings of a pillar of radius 34 and of none of
radius 30; a scene without a DLD geometry and a checkpoint of the wrong node count are refused
with one line naming them.
Usage: mesh_quality_test.py PROJECT_SOURCE_DIR"""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

tool = os.path.join(sys.argv[1], "analysis", "mesh_quality.py")
v = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
faces = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
with tempfile.TemporaryDirectory() as tmp:
    off = os.path.join(tmp, "octa.off")
    with open(off, "w") as f:
        f.write("OFF\n6 8 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in v)
                + "".join(f"3 {a} {b} {c}\n" for a, b, c in faces))
    cell0 = 10 * v + [50, 50, 5]
    cell1 = 10 * v + [80, 50, 5]
    cell1[4] = (cell1[0] + cell1[2]) / 2  # on edge 0-2: triangle (0, 2, 4) has no area
    ck = os.path.join(tmp, "run-cells-0.ckpt.h5")
    with h5py.File(ck, "w") as h:
        g = h.create_group("membrane")
        g.create_dataset("positions", data=np.vstack([cell0, cell1]))
        g.attrs["step"] = 1000
    out = subprocess.run([tool, ck, off, "--radius-lu", "10"], capture_output=True, text=True,
                         check=True).stdout
    rows = {int(l.split()[0]): l.split() for l in out.splitlines() if l.strip()[:1].isdigit()}
    assert float(rows[0][-3]) == 1.0 and rows[0][-1] == "0", out  # smallest J 1, none collapsed
    assert float(rows[1][-3]) == 0.0 and rows[1][-1] == "1", out
    # With a scene: the collapsed triangle's centroid (85, 55, 5) is 35.36 from the pillar's axis
    # at (50, 50) and 5 from the walls: within 2 spacings of a pillar of radius 34, not of one of
    # radius 30, never of a wall (depth 10).
    def film(radius):
        scene = os.path.join(tmp, "scene.toml")
        with open(scene, "w") as f:
            f.write(f"[geometry]\npillar_spacing_um = 100.0\npillar_radius_um = {radius}\n"
                    "depth_um = 10.0\nrow_shift_um = 5.0\n[lattice]\ndx_um = 1.0\n")
        out = subprocess.run([tool, ck, off, "--radius-lu", "10", "--scene", scene],
                             capture_output=True, text=True, check=True).stdout
        return [l for l in out.splitlines() if l.startswith("within")]
    near = film(34.0)
    assert "the pillar: 1 of the 1 collapsed" in near[0] and "a wall: 0 of the 1" in near[1], near
    assert "the pillar: 0 of the 1 collapsed" in film(30.0)[0], film(30.0)
    bad = subprocess.run([tool, ck, off, "--radius-lu", "10", "--scene", off], capture_output=True,
                         text=True)
    assert bad.returncode != 0 and "no DLD geometry" in bad.stderr, bad.stderr
    with h5py.File(ck, "w") as h:
        h.create_group("membrane").create_dataset("positions", data=cell0[:5])
    bad = subprocess.run([tool, ck, off, "--radius-lu", "10"], capture_output=True, text=True)
    assert bad.returncode != 0 and "5 nodes are not cells of 6" in bad.stderr, bad.stderr
print("collapsed triangles counted per cell and placed by the pillar; bad input refused")
