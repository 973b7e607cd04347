#!/usr/bin/python3
"""analysis/keep_so_far.py: the kept interim analyses of a study's unfinished runs across
machines. Kept: run A at 6.5 pillars, run B at 2.0, run C at 3.0 (C finished since). The sweep of a
new machine has A at 3.1 pillars (started again), B at 4.0, D at 1.0 (with a volume plot and a
column the kept file lacks) and C again (an older interim file may still name a finished run): A's
kept row and plots must stay, B's and D's be taken with their plots, C's row and plots must go, and
the kept file must have both files' columns. Once every run has finished the kept file goes. A row
whose slowest_cell_pillars is not a number (or nan, or missing), or a CSV without that column, is
refused with one line naming the file. Usage: keep_so_far_test.py PROJECT_SOURCE_DIR"""
import csv
import os
import subprocess
import sys
import tempfile

tool = os.path.join(sys.argv[1], "analysis", "keep_so_far.py")
HEADER = ["run", "state", "p_f_mean", "slowest_cell_pillars"]


def write_csv(path, rows, header=HEADER):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)


def touch(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def read(path):
    with open(path) as f:
        return {r["run"]: r for r in csv.DictReader(f)}


def check(cond, what):
    if not cond:
        sys.exit(f"FAIL: {what}")


with tempfile.TemporaryDirectory() as tmp:
    sweep, kept = os.path.join(tmp, "sweep"), os.path.join(tmp, "kept")
    os.makedirs(sweep)
    os.makedirs(kept)
    write_csv(os.path.join(kept, "summary-unfinished.csv"),
              [["A", "partial", "0.01", "6.5"], ["B", "partial", "0.02", "2.0"],
               ["C", "partial", "0.03", "3.0"]])
    for run in "ABC":
        for p in ("trajectories", "outlets"):
            touch(os.path.join(kept, f"{run}-{p}.png"), f"old {run}")
    write_csv(os.path.join(sweep, "summary-unfinished.csv"),
              [["A", "partial", "0.11", "3.1", "x"], ["B", "partial", "0.12", "4.0", "x"],
               ["C", "partial", "0.13", "3.5", "x"], ["D", "failed", "0.14", "1.0", "wall"]],
              HEADER + ["new_column"])
    write_csv(os.path.join(sweep, "summary.csv"), [["C", "", "0.05", "20.0"]])
    for run in "ABCD":
        for p in ("trajectories", "outlets"):
            touch(os.path.join(sweep, run, "so-far", f"run-{p}.png"), f"new {run}")
    touch(os.path.join(sweep, "D", "so-far", "run-volume-drift.png"), "new D")
    r = subprocess.run([tool, sweep, kept], capture_output=True, text=True)
    check(r.returncode == 0, f"exit {r.returncode}: {r.stderr}")
    rows = read(os.path.join(kept, "summary-unfinished.csv"))
    check(sorted(rows) == ["A", "B", "D"], f"runs {sorted(rows)}")
    check(rows["A"]["p_f_mean"] == "0.01", "A's further row kept")
    check(rows["B"]["p_f_mean"] == "0.12" and rows["D"]["state"] == "failed", "B, D taken")
    for run, text in (("A", "old A"), ("B", "new B"), ("D", "new D")):
        for p in ("trajectories", "outlets"):
            with open(os.path.join(kept, f"{run}-{p}.png")) as f:
                check(f.read() == text, f"{run}-{p}.png: expected '{text}'")
    check(not os.path.exists(os.path.join(kept, "C-trajectories.png")), "C's plots removed")
    check(os.path.exists(os.path.join(kept, "D-volume-drift.png")), "D's volume plot copied")
    check(rows["D"]["new_column"] == "wall" and rows["A"]["new_column"] == ""
          and rows["A"]["state"] == "partial", f"columns of both files: {rows['A']}, {rows['D']}")
    check("kept the earlier analysis" in r.stdout, f"A's line: {r.stdout}")

    write_csv(os.path.join(sweep, "summary-unfinished.csv"), [])
    write_csv(os.path.join(sweep, "summary.csv"), [[run, "", "0", "20"] for run in "ABCD"])
    r = subprocess.run([tool, sweep, kept], capture_output=True, text=True)
    check(r.returncode == 0 and not os.path.exists(os.path.join(kept, "summary-unfinished.csv"))
          and not os.path.exists(os.path.join(kept, "D-volume-drift.png")),
          f"all finished: {r.returncode} {r.stderr} {sorted(os.listdir(kept))}")
    write_csv(os.path.join(sweep, "summary.csv"), [])

    sweep_csv = os.path.join(sweep, "summary-unfinished.csv")
    for bad, said in ((["B", "partial", "0.1", "many"], "'many'"),
                      (["B", "partial", "0.1", "nan"], "'nan'"), (["B", "partial"], "'None'")):
        write_csv(sweep_csv, [bad])
        r = subprocess.run([tool, sweep, kept], capture_output=True, text=True)
        check(r.returncode != 0 and f"{sweep_csv}: run B: slowest_cell_pillars {said}" in r.stderr
              and len(r.stderr.splitlines()) == 1,
              f"a bad number {said}: {r.returncode} {r.stderr}")
    write_csv(sweep_csv, [["B", "partial"]], ["run", "state"])
    r = subprocess.run([tool, sweep, kept], capture_output=True, text=True)
    check(r.returncode != 0 and f"{sweep_csv}: missing column(s) slowest_cell_pillars" in r.stderr
          and len(r.stderr.splitlines()) == 1, f"a missing column: {r.returncode} {r.stderr}")
print("ok")
