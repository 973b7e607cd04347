#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Keeps the furthest interim analysis of each unfinished run of a sweep, across machines.

    analysis/keep_so_far.py SWEEP_DIR KEPT_DIR

SWEEP_DIR is a sweep's output (runs/<study>/<setting>, after dld-sweep --summary --unfinished):
its summary-unfinished.csv, each unfinished run's plots in RUN/so-far/ and the finished runs'
summary.csv. KEPT_DIR (docs/results/headline/<setting>/so-far, committed) holds the rows and
plots kept so far. A replaced machine starts its runs from step 0, so a row here replaces the kept
row of the same run only if its slowest cell has passed at least as many pillars; a run that has
finished since (in SWEEP_DIR/summary.csv) leaves KEPT_DIR. Writes KEPT_DIR/summary-unfinished.csv
(the study's rule does not apply to these rows: each cell over the pillars it passed so far) and
copies RUN/so-far/run-{trajectories,outlets,volume-drift}.png (those there) to
KEPT_DIR/RUN-{...}.png.
"""
import argparse
import csv
import math
import os
import shutil
import sys

CSV = "summary-unfinished.csv"
PLOTS = ("trajectories", "outlets", "volume-drift")  # the last one: scripts/long-runs interim


def read(path, required, tool="keep_so_far.py"):
    """(header, rows) of a CSV, ([], []) if it does not exist; a one-line error if it lacks a
    required column."""
    if not os.path.exists(path):
        return [], []
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            header = reader.fieldnames or []
    except OSError as e:
        sys.exit(f"{tool}: error: {path}: cannot read ({e.strerror})")
    missing = [c for c in required if rows and c not in header]
    if missing:
        sys.exit(f"{tool}: error: {path}: missing column(s) {', '.join(missing)}")
    return header, rows


def pillars(row, path, tool="keep_so_far.py"):
    """The pillars the run's slowest cell had passed, or a one-line error naming the file."""
    value = row.get("slowest_cell_pillars")
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not math.isfinite(number):
        sys.exit(f"{tool}: error: {path}: run {row.get('run')}: slowest_cell_pillars '{value}' "
                 f"is not a number")
    return number


def drop_plots(kept_dir, run):
    for p in PLOTS:
        path = os.path.join(kept_dir, f"{run}-{p}.png")
        if os.path.exists(path):
            os.remove(path)


def write(path, header, rows):
    try:
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=header, extrasaction="ignore", lineterminator="\n")
            w.writeheader()
            w.writerows(rows)
    except OSError as e:
        sys.exit(f"keep_so_far.py: error: {path}: cannot write ({e.strerror})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sweep_dir")
    ap.add_argument("kept_dir")
    a = ap.parse_args()
    new_path, kept_path = os.path.join(a.sweep_dir, CSV), os.path.join(a.kept_dir, CSV)
    need = ("run", "slowest_cell_pillars")
    new_header, new_rows = read(new_path, need)
    kept_header, kept_rows = read(kept_path, need)
    _, finished = read(os.path.join(a.sweep_dir, "summary.csv"), ("run",))
    done = {r["run"] for r in finished}
    try:
        os.makedirs(a.kept_dir, exist_ok=True)
    except OSError as e:
        sys.exit(f"keep_so_far.py: error: {a.kept_dir}: cannot make it ({e.strerror})")
    kept = {r["run"]: r for r in kept_rows if r["run"] not in done}
    for run in {r["run"] for r in kept_rows} & done:
        drop_plots(a.kept_dir, run)
        print(f"{run}: finished, its interim analysis removed")
    for r in new_rows:
        run, old = r["run"], kept.get(r["run"])
        if run in done:  # an older summary-unfinished.csv may still name it
            continue
        if old is not None and pillars(old, kept_path) > pillars(r, new_path):
            print(f"{run}: kept the earlier analysis ({pillars(old, kept_path):.2f} pillars for "
                  f"its slowest cell, here {pillars(r, new_path):.2f})")
            continue
        kept[run] = r
        drop_plots(a.kept_dir, run)
        for p in PLOTS:
            src = os.path.join(a.sweep_dir, run, "so-far", f"run-{p}.png")
            if os.path.exists(src):
                try:
                    shutil.copyfile(src, os.path.join(a.kept_dir, f"{run}-{p}.png"))
                except OSError as e:
                    sys.exit(f"keep_so_far.py: error: {src}: cannot copy ({e.strerror})")
        print(f"{run}: {r.get('state', '')}, {pillars(r, new_path):.2f} pillars for its slowest "
              f"cell (kept)")
    header = new_header + [c for c in kept_header if c not in new_header]  # kept rows' own too
    if not kept:
        if os.path.exists(kept_path):
            os.remove(kept_path)
        return
    write(kept_path, header, [kept[run] for run in sorted(kept)])
    print(f"{kept_path}: {len(kept)} unfinished run(s)")


if __name__ == "__main__":
    main()
