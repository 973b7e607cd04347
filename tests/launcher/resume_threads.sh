#!/usr/bin/env bash
# dld-run --threads: each program runs on the threads asked for, whatever the scene's [run]
# threads (1 in configs/single-cell.toml), and a run resumes with another number of them. The
# four touching cells of split_equality.sh run STEPS/2 steps with --threads 2 and resume to STEPS
# with --threads 1 (the scene file unchanged, so its hash still matches the checkpoints).
# Threads change the order of some sums only, so the final node positions must match one straight
# run at the scene's threads to within round-off (round_off below, in lattice lengths; 8.7e-13 here,
# and 4e-13 um for the headline's 15 cells after 500 steps).
# Usage: resume_threads.sh DLD_RUN PROJECT_SOURCE_DIR [STEPS]
set -euo pipefail
run=$1 src=$2 steps=${3:-1000}
round_off=1e-10
dir=$(mktemp -d /tmp/dld-resume-threads.XXXXXX)
trap 'rm -rf "$dir"' EXIT
. "$(dirname "$0")/netns.sh"  # touching_runs, leg, programs_said
threads_said() { programs_said "$1" "[0-9]* OpenMP threads"; }  # NAME: each program's threads
touching_runs straight resumed
leg straight "$steps"
leg resumed $((steps / 2)) --threads 2
said=$(threads_said resumed)
[ "$said" = "2 OpenMP threads 2 OpenMP threads " ] ||
  { echo "--threads 2: the programs said '$said'"; exit 1; }
leg resumed "$steps" --resume --threads 1
said=$(threads_said resumed)  # the logs of the resumed leg
[ "$said" = "1 OpenMP threads 1 OpenMP threads " ] ||
  { echo "--threads 1: the programs said '$said'"; exit 1; }
grep -q "resuming at step $((steps / 2))" "$dir/resumed/out-$steps.txt" ||
  { echo "--threads 1 did not resume at step $((steps / 2))"; cat "$dir/resumed/out-$steps.txt"
    exit 1; }
/usr/bin/python3 - "$dir" "$steps" "$round_off" <<'PY'
import sys
import h5py, numpy as np
d, steps, bound = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
def final(name):
    with h5py.File(f"{d}/{name}/run-cells-0.ckpt.h5") as f:
        return int(f["membrane"].attrs["step"]), np.asarray(f["membrane/positions"])
(s_ref, x_ref), (s, x) = final("straight"), final("resumed")
diff = float(np.max(np.abs(x - x_ref)))
print(f"steps: straight {s_ref}, resumed {s}; largest node position difference {diff:.3g} "
      f"lattice lengths (bound {bound:g})")
sys.exit(0 if s == s_ref == steps and diff <= bound else 1)
PY
