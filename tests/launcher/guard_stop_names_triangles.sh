#!/usr/bin/env bash
# A coupled run that the fluid's stability guard stops: the membrane program's error line (which
# dld-run and dld-sweep pass on) ends with the membranes' state at the stop, the smallest triangle
# area ratio and its cell (collapsed triangles came before every late stop of the dense runs,
# docs/results-history.md), at the run's step. A cell 400 times too stiff for the lattice (Ca 0.0005 at
# dx 0.8 um) makes the guard fire within a few steps; its triangles are still near rest.
# Usage: guard_stop_names_triangles.sh DLD_RUN PROJECT_SOURCE_DIR
set -euo pipefail
run=$1 src=$2
dir=$(mktemp -d /tmp/dld-guard-stop.XXXXXX)
trap 'rm -rf "$dir"' EXIT
# The project's single-cell scene (dx 0.8 um), run from the source tree, with the stiff cell.
sed -e "s|^file = .*|file = \"$dir/run.h5\"|" -e 's/^capillary_number = .*/capillary_number = 0.0005/' \
    -e 's/^reynolds = .*/reynolds = 1.0/' "$src/configs/single-cell.toml" > "$dir/scene.toml"
grep -q "^capillary_number = 0.0005" "$dir/scene.toml" || { echo "FAIL: scene"; exit 1; }
set +e
(cd "$src" && timeout 120 "$run" "$dir/scene.toml" --membrane cells --steps 2000) > "$dir/out.txt" 2>&1
code=$?
set -e
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || { cat "$dir/out.txt"; echo "FAIL: exit $code"; exit 1; }
grep -q "dld-fluid stopped with exit code 1: .*the lattice cannot take the forces it sent" \
  "$dir/out.txt" || { cat "$dir/out.txt"; echo "FAIL: not the fluid's guard"; exit 1; }
line=$(grep "cells-0 stopped with exit code 3:" "$dir/out.txt") ||
  { cat "$dir/out.txt"; echo "FAIL: no membrane error line"; exit 1; }
[[ $line =~ \;\ membranes\ at\ step\ ([0-9]+):\ smallest\ triangle\ (0\.9[0-9]+|1\.0[0-9]+)\ of\ rest\ area\ \(cell\ 0\)$ ]] ||
  { echo "$line"; echo "FAIL: no membrane state at the stop"; exit 1; }
step=${BASH_REMATCH[1]}
fluid_step=$(grep -o "after step [0-9]*" "$dir/out.txt" | head -1 | awk '{print $3}')
[ "$step" -le "$fluid_step" ] && [ "$step" -ge $((fluid_step - 1)) ] ||
  { echo "$line"; echo "FAIL: step $step, the fluid's $fluid_step"; exit 1; }
echo "ok: $line"
