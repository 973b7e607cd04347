#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The runs to start, least analysed first: the given runs stably sorted by the pillars their
slowest cell had passed in the kept interim analyses (KEPT_CSV, analysis/keep_so_far.py's
summary-unfinished.csv; a run not in it, or no such file: 0).

    analysis/interim_order.py KEPT_CSV RUN [RUN ...]    prints the runs, one line, space-separated

A replaced machine starts every run from step 0, so the run whose committed analysis got furthest
is the last worth repeating: its first pillars are known (scripts/long-runs start).
"""
import csv
import os
import sys


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: interim_order.py KEPT_CSV RUN [RUN ...]")
    path, runs = sys.argv[1], sys.argv[2:]
    reached = {}
    if os.path.exists(path):
        try:
            with open(path, newline="") as f:
                reader = csv.DictReader(f)
                rows = list(reader)
        except OSError as e:
            sys.exit(f"interim_order.py: error: {path}: cannot read ({e.strerror})")
        for need in ("run", "slowest_cell_pillars"):
            if rows and need not in (reader.fieldnames or []):
                sys.exit(f"interim_order.py: error: {path}: missing column {need}")
        for r in rows:
            try:
                reached[r["run"]] = float(r["slowest_cell_pillars"])
            except ValueError:
                sys.exit(f"interim_order.py: error: {path}: run {r['run']}: slowest_cell_pillars "
                         f"'{r['slowest_cell_pillars']}' is not a number")
    print(" ".join(sorted(runs, key=lambda run: reached.get(run, 0.0))))


if __name__ == "__main__":
    main()
