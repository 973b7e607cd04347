#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The runs to start, least analysed first: the given runs stably sorted by the pillars their
slowest cell had passed in the kept interim analyses (KEPT_CSV, analysis/keep_so_far.py's
summary-unfinished.csv; a run not in it, or no such file: 0).

    analysis/interim_order.py KEPT_CSV RUN [RUN ...]    prints the runs, one line, space-separated

A replaced machine starts every run from step 0, so the run whose committed analysis got furthest
is the last worth repeating: its first pillars are known (scripts/long-runs start).
"""
import sys

from keep_so_far import pillars, read  # the kept analyses' reader (this script's folder)


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: interim_order.py KEPT_CSV RUN [RUN ...]")
    path, runs = sys.argv[1], sys.argv[2:]
    _, rows = read(path, ("run", "slowest_cell_pillars"), "interim_order.py")
    reached = {r["run"]: pillars(r, path, "interim_order.py") for r in rows}
    print(" ".join(sorted(runs, key=lambda run: reached.get(run, 0.0))))


if __name__ == "__main__":
    main()
