#!/usr/bin/env bash
# [coupling] volume_correction_every with cells in contact across membrane processes is refused
# with one line naming the key (the other processes' contact halos would be made from positions
# before a correction, so the split run would not be the one-process run); with one membrane
# process the same scene runs and its summary gives each cell's volume given back.
# Usage: volume_correction_split.sh DLD_RUN PROJECT_SOURCE_DIR
set -euo pipefail
run=$1 src=$2
dir=$(mktemp -d /tmp/dld-vc-split.XXXXXX)
trap '[ -n "${KEEP:-}" ] || rm -rf "$dir"' EXIT
. "$(dirname "$0")/netns.sh"  # touching_cells_scene
mkdir -p "$dir/split" "$dir/one"
touching_cells_scene split 2 60.0 | sed 's/^membrane_processes = 2/&\nvolume_correction_every = 10/' \
  > "$dir/split/scene.toml"
grep -q "^volume_correction_every = 10" "$dir/split/scene.toml" || { echo "FAIL: scene"; exit 1; }
set +e
(cd "$src" && timeout 120 "$run" "$dir/split/scene.toml" --membrane cells --steps 40) \
  > "$dir/split/out.txt" 2>&1
code=$?
set -e
[ "$code" -ne 0 ] && [ "$code" -ne 124 ] || { cat "$dir/split/out.txt"; echo "FAIL: exit $code"; exit 1; }
grep -q "volume_correction_every: not with cells in contact across 2 membrane processes" \
  "$dir/split/out.txt" || { cat "$dir/split/out.txt"; echo "FAIL: no error naming the key"; exit 1; }
touching_cells_scene one 1 60.0 | sed 's/^membrane_processes = 1/&\nvolume_correction_every = 10/' \
  > "$dir/one/scene.toml"
(cd "$src" && timeout 120 "$run" "$dir/one/scene.toml" --membrane cells --steps 40) \
  > "$dir/one/out.txt" 2>&1 || { cat "$dir/one/out.txt"; echo "FAIL: one process"; exit 1; }
n=$(grep -c "volume given back since this start" "$dir/one/run-cells-0.log" || true)
[ "$n" -eq 4 ] || { cat "$dir/one/run-cells-0.log"; echo "FAIL: $n cells' volume given back"; exit 1; }
echo "ok: refused when split, $n cells corrected in one process"
