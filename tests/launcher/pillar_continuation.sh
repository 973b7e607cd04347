#!/usr/bin/env bash
# A run ended by its pillar rule, resumed with more pillars, is the straight run (the hard case's
# fast run continues the headline's run so: scripts/hard100-fast). One cell of
# configs/single-cell.toml (dx 0.8 um) with the forces held 3 steps and the viscosity field 2 (Re 0.1: stable so): the
# first leg (--pillars 1) must end at a multiple of 6 (CouplingParams::exact_resume_every), and
# the continued run (--resume --pillars 2) must end with the node positions and the run file's
# samples of one --pillars 2 run, bit for bit. (Before runs ended at such steps, the resumed run
# recomputed the held forces there and differed.)
# Usage: pillar_continuation.sh DLD_RUN PROJECT_SOURCE_DIR
set -euo pipefail
run=$1 src=$2
dir=$(mktemp -d /tmp/dld-pillar-continuation.XXXXXX)
trap 'rm -rf "$dir"' EXIT
for name in straight continued; do
  mkdir -p "$dir/$name"
  sed -e "s|^file = .*|file = \"$dir/$name/run.h5\"|" \
      -e "s|^timeout_s = .*|timeout_s = 60.0\nforce_every = 3\nviscosity_field_every = 2|" \
      -e "s|^reynolds = .*|reynolds = 0.1|" "$src/configs/single-cell.toml" > "$dir/$name/scene.toml"
done
leg() {  # NAME PILLARS ARGS...: one leg, its output shown if it fails
  local name=$1 n=$2
  shift 2
  (cd "$src" && "$run" "$dir/$name/scene.toml" --membrane cells --pillars "$n" \
      --steps 1000000 --checkpoint-every 5000 "$@" > "$dir/$name/out-$n.txt" 2>&1) ||
    { echo "$name to $n pillars ($*) failed:"; cat "$dir/$name/out-$n.txt"; exit 1; }
}
leg straight 2
leg continued 1
leg continued 2 --resume
/usr/bin/python3 - "$dir" <<'PY'
import re, sys
import h5py, numpy as np
d = sys.argv[1]
first = open(f"{d}/continued/out-2.txt").read()
m = re.search(r"resuming at step (\d+)", first)
bad = 0
if not m:
    print("the continued run did not say where it resumed"); sys.exit(1)
resumed_at = int(m.group(1))
print(f"first leg ended at step {resumed_at} ({resumed_at % 6} past a multiple of 6)")
bad += resumed_at % 6 != 0 or resumed_at == 0
def final(name):
    with h5py.File(f"{d}/{name}/run-cells-0.ckpt.h5") as f:
        step, x = int(f["membrane"].attrs["step"]), np.asarray(f["membrane/positions"])
    with h5py.File(f"{d}/{name}/run.h5") as f:
        return step, x, np.asarray(f["membrane-0/cells/samples"])
(s_ref, x_ref, rows_ref), (s, x, rows) = final("straight"), final("continued")
print(f"steps: straight {s_ref}, continued {s}")
bad += s != s_ref
for what, a, b in (("node positions", x, x_ref), ("samples", rows, rows_ref)):
    diff = float(np.max(np.abs(a - b))) if a.shape == b.shape else float("inf")
    print(f"continued against straight: largest {what} difference {diff:.3g}")
    bad += diff != 0.0
sys.exit(1 if bad else 0)
PY
