#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Node positions of runs against a reference, bit for bit (the split and host tests of issue 14).
The arguments are pairs LABEL GLOB: the membrane checkpoints of one run (`run-cells-*.ckpt.h5`,
taken in process order); the first pair is the reference. Prints the largest difference of each other run
and exits 1 unless all are exactly 0."""
import glob
import re
import sys

import h5py
import numpy as np


def positions(pattern):
    files = sorted(glob.glob(pattern), key=lambda f: int(re.findall(r"(\d+)\.ckpt\.h5$", f)[0]))
    if not files:
        sys.exit(f"compare_positions.py: error: no checkpoint matches {pattern}")
    return np.concatenate([np.asarray(h5py.File(f)["membrane/positions"]) for f in files])


def main():
    args = sys.argv[1:]
    if len(args) < 4 or len(args) % 2:
        sys.exit("usage: compare_positions.py REF_LABEL REF_GLOB LABEL GLOB ...")
    runs = list(zip(args[0::2], args[1::2]))
    ref_label, ref_glob = runs[0]
    ref, bad = positions(ref_glob), 0
    for label, pattern in runs[1:]:
        x = positions(pattern)
        diff = float(np.max(np.abs(x - ref))) if x.shape == ref.shape else float("inf")
        print(f"{label}: largest node position difference to {ref_label}: {diff:.3g} lattice "
              "lengths")
        bad += diff != 0.0
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
