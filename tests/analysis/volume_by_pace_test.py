#!/usr/bin/python3
"""analysis/volume_by_pace.py on a synthetic part file: ten cells along a row between the pillars,
cell k moving at k um per 100 000 steps with a constant volume except cell 0, which stands still
and loses 0.05 % of its volume per 100 000 steps. The slowest tenth of the windows must show that
loss and no other class any; a file without samples is refused with one line naming it.
Usage: volume_by_pace_test.py PROJECT_SOURCE_DIR"""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

src = sys.argv[1]
tool = os.path.join(src, "analysis", "volume_by_pace.py")
with tempfile.TemporaryDirectory() as tmp:
    path = os.path.join(tmp, "run-cells-0.h5")
    steps = np.arange(0, 2_000_001, 1000.0)
    cols = [steps]
    for k in range(10):
        x = 16.0 + k * steps / 1e5   # between the pillar rows (y = 16 with d = 0): never near one
        v = 90.0 * (1 - 0.0005 * steps / 1e5) if k == 0 else np.full_like(steps, 90.0)
        cols += [x, np.full_like(steps, 16.0), np.full_like(steps, 2.4), v]
    with h5py.File(path, "w") as f:
        g = f.create_group("cells")
        g.create_dataset("samples", data=np.column_stack(cols))
        g.attrs["pillar_spacing_um"] = 32.0
        g.attrs["row_shift_um"] = 0.0
    out = subprocess.run([tool, path, "--csv", os.path.join(tmp, "w.csv")], capture_output=True,
                         text=True, check=True).stdout
    rows = [l.split() for l in out.splitlines() if ".." in l]
    slowest, rest = rows[0], rows[1:]
    assert abs(float(slowest[4]) + 0.05) < 1e-9, out
    assert all(abs(float(r[4])) < 1e-12 for r in rest), out
    assert all(float(r[5]) == 0 for r in rows), out  # none near a pillar
    with open(os.path.join(tmp, "w.csv")) as f:
        assert sum(1 for _ in f) == 1 + 10 * 20, "one CSV row per cell and window"
    with h5py.File(os.path.join(tmp, "empty.h5"), "w") as f:
        f.create_group("x")
    bad = subprocess.run([tool, os.path.join(tmp, "empty.h5")], capture_output=True, text=True)
    assert bad.returncode != 0 and "empty.h5: no cells/samples" in bad.stderr, bad.stderr
print("held cell's loss found in the slowest class only; bad file refused")
