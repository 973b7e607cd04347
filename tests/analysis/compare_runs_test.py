#!/usr/bin/python3
"""analysis/compare_runs.py on synthetic run files: two cells advancing at 1 um/ms in run A and at
1.1 um/ms in run B, sampled at another time step (B's dt half A's), B's cell 1 losing 1 % of its
volume over the run. The ratio must read 1.1 at every time, B's steps twice A's, B's volume loss
-1 % at the end; runs of different cell counts, a file that is not HDF5 and a bad --times are
refused with one line naming them; runs starting from other positions get a warning. --by advance
on runs whose cells drift sideways (0.1 um per um in A, 0.12 in B for cell 1) at 1 and 2.5 um/ms,
B's cell 1 losing volume, must give B's times 1/2.5 of A's, its steps and volume loss by then,
cell 1's lateral difference 0.02 x the advance while both runs' cell 1 have got that far, the
span the median cell's, and a plot; --plot without --by advance is refused.
Usage: compare_runs_test.py PROJECT_SOURCE_DIR"""
import csv
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

tool = os.path.join(sys.argv[1], "analysis", "compare_runs.py")


def run_file(path, dt_s, speed_um_per_ms, loss, cells=2, start_y=0.0, part=False, drift=(0, 0),
             slow=1.0):
    steps = np.arange(0, 10001, 100, dtype=float)
    t_ms = steps * dt_s * 1e3
    table = [steps]
    for c in range(cells):
        x = speed_um_per_ms * t_ms * (slow if c == 1 else 1.0)
        table += [10.0 * c + x, start_y + drift[min(c, 1)] * x, 2.4 + 0 * t_ms,
                  100.0 * (1 - (loss if c == 1 else 0) * t_ms / t_ms[-1])]
    with h5py.File(path, "w") as f:
        g = f.create_group("cells" if part else "membrane-0/cells")
        g.create_dataset("samples", data=np.column_stack(table))
        g.attrs["dt_s"] = dt_s


def call(*args):
    return subprocess.run([tool, *args], capture_output=True, text=True)


with tempfile.TemporaryDirectory() as d:
    a, b = os.path.join(d, "a.h5"), os.path.join(d, "b-cells-0.h5")
    run_file(a, 1e-6, 1.0, 0.0)
    run_file(b, 0.5e-6, 1.1, 0.01, part=True)  # B's samples span half A's time
    out = os.path.join(d, "cmp.csv")
    r = call(f"A={a}", f"B={b}", "--times", "4", "--csv", out)
    assert r.returncode == 0 and r.stderr == "", r.stdout + r.stderr
    with open(out) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4, rows
    for row in rows:
        assert abs(float(row["ratio"]) - 1.1) < 1e-9, row
        assert abs(float(row["step_b"]) - 2 * float(row["step_a"])) < 1e-6, row
        assert float(row["volume_loss_a_percent"]) == 0.0, row
    assert abs(float(rows[-1]["time_ms"]) - 5.0) < 1e-9, rows[-1]  # B's span: 10 000 x 0.5 us
    assert abs(float(rows[-1]["volume_loss_b_percent"]) + 1.0) < 1e-9, rows[-1]
    assert abs(float(rows[-1]["advance_a_um"]) - 5.0) < 1e-9, rows[-1]

    c = os.path.join(d, "c.h5")
    run_file(c, 1e-6, 1.0, 0.0, cells=3)
    r = call(f"A={a}", f"C={c}")
    assert r.returncode != 0 and r.stderr.strip() == "A has 2 cells and C 3: expected the same cells", r.stderr

    e = os.path.join(d, "elsewhere.h5")
    run_file(e, 1e-6, 1.0, 0.0, start_y=3.0)
    r = call(f"A={a}", f"E={e}")
    assert r.returncode == 0 and r.stderr.startswith("warning: A and E start from different"), r.stderr

    bad = os.path.join(d, "bad.h5")
    with open(bad, "w") as f:
        f.write("not hdf5\n")
    r = call(f"A={a}", f"X={bad}")
    assert r.returncode != 0 and r.stderr.startswith(f"{bad}: cannot open as HDF5"), r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    a2, b2 = os.path.join(d, "a2.h5"), os.path.join(d, "b2.h5")
    run_file(a2, 1e-6, 1.0, 0.0, drift=(0.1, 0.1), slow=0.8)  # cell 1 the slower
    run_file(b2, 1e-6, 2.5, 0.01, drift=(0.1, 0.12), slow=0.8)  # cell 1 loses 1 % by 10 ms
    png = os.path.join(d, "tracks.png")
    r = call(f"A={a2}", f"B={b2}", "--by", "advance", "--times", "4", "--csv", out, "--plot", png)
    # (matplotlib may note its font cache on stderr: only warnings of the tool's own fail it)
    assert r.returncode == 0 and "warning:" not in r.stderr, r.stdout + r.stderr
    with open(out) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 4 and os.path.getsize(png) > 0, rows
    # The cells reach 10 and 8 um (cell 1 the slower): up to the median, 9 um; past 8 um without
    # cell 1, whose drift differs.
    assert abs(float(rows[-1]["advance_um"]) - 9.0) < 1e-9, rows[-1]
    for row in rows:
        s = float(row["advance_um"])
        both = s <= 8.0
        assert int(row["cells"]) == (2 if both else 1), row
        ratio = float(row["time_b_ms"]) * 2.5 / float(row["time_a_ms"])
        assert abs(ratio - 1) < 1e-5, row  # the CSV's 6 digits
        difference = float(row["largest_lateral_difference_um"])
        assert abs(difference - (0.02 * s if both else 0)) < 1e-9, row
        assert abs(float(row["lateral_a_um"]) - 0.1 * s) < 1e-9, row
        # B's mean advance 0.9 x 2.5 um/ms; step = time / dt; volume loss by then t / 10 ms %,
        # to the 0.1 ms between samples.
        t_b = float(row["time_b_ms"])
        assert abs(t_b - s / 2.25) < 1e-5 * t_b, row
        assert abs(float(row["step_b"]) - 1000 * t_b) < 1e-2, row
        assert abs(float(row["volume_loss_b_percent"]) + t_b / 10) <= 0.01 + 1e-9, row
        assert float(row["volume_loss_a_percent"]) == 0.0, row
    r = call(f"A={a}", f"B={b}", "--plot", png)
    assert r.returncode != 0, r.stderr
    assert r.stderr.strip().startswith("--plot: expected --by advance"), r.stderr
    r = call(f"A={a}", f"B={b}", "--times", "0")
    assert r.returncode != 0 and r.stderr.strip() == "--times 0: expected 1..1000", r.stderr
print("compare_runs: ok")
