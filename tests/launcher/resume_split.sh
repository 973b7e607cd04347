#!/usr/bin/env bash
# Issue 14: a run resumes with another number of membrane processes. The four touching cells of
# split_equality.sh run STEPS/2 steps with K = 2, then resume with --membrane-processes 3 to
# 3 STEPS/4 and with --membrane-processes 1 to STEPS (the scene file unchanged, so its hash still
# matches every checkpoint). The final node positions and the merged run file's samples must be
# bit for bit those of one K = 1 run of STEPS steps.
# Usage: resume_split.sh DLD_RUN PROJECT_SOURCE_DIR [STEPS]
set -euo pipefail
run=$1 src=$2 steps=${3:-2000}
dir=$(mktemp -d /tmp/dld-resume-split.XXXXXX)
trap 'rm -rf "$dir"' EXIT
. "$(dirname "$0")/netns.sh"  # touching_cells_scene, leg
for name in straight resumed; do
  mkdir -p "$dir/$name"
  touching_cells_scene "$name" "$([ $name = straight ] && echo 1 || echo 2)" 60.0 \
    > "$dir/$name/scene.toml"
done
leg straight "$steps"
leg resumed $((steps / 2))
leg resumed $((3 * steps / 4)) --resume --membrane-processes 3
grep -q "resuming at step $((steps / 2))" "$dir/resumed/out-$((3 * steps / 4)).txt" ||
  { echo "K = 3 did not resume at step $((steps / 2))"; cat "$dir/resumed/out-$((3 * steps / 4)).txt"; exit 1; }
leg resumed "$steps" --resume --membrane-processes 1
grep -q "resuming at step $((3 * steps / 4))" "$dir/resumed/out-$steps.txt" ||
  { echo "K = 1 did not resume at step $((3 * steps / 4))"; cat "$dir/resumed/out-$steps.txt"; exit 1; }
/usr/bin/python3 - "$dir" "$steps" <<'PY'
import sys
import h5py, numpy as np
d, steps = sys.argv[1], int(sys.argv[2])
def final(name):
    with h5py.File(f"{d}/{name}/run-cells-0.ckpt.h5") as f:
        step, x = int(f["membrane"].attrs["step"]), np.asarray(f["membrane/positions"])
    with h5py.File(f"{d}/{name}/run.h5") as f:  # the merged run file: the whole time series
        return step, x, np.asarray(f["membrane-0/cells/samples"])
bad = 0
(s_ref, x_ref, rows_ref), (s, x, rows) = final("straight"), final("resumed")
print(f"steps: straight {s_ref}, resumed {s}; run file samples {rows_ref.shape} and {rows.shape}")
bad += s != steps or s_ref != steps
for what, a, b in (("node positions", x, x_ref), ("samples", rows, rows_ref)):
    diff = float(np.max(np.abs(a - b))) if a.shape == b.shape else float("inf")
    print(f"resumed K = 2 -> 3 -> 1 against K = 1: largest {what} difference {diff:.3g}")
    bad += diff != 0.0
sys.exit(1 if bad else 0)
PY
