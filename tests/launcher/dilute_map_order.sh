#!/usr/bin/env bash
# scripts/dilute-map runs its cases in the order --only names them (scripts/long-runs puts the case
# under way first), keeps each case's earlier log in one history file, and refuses a case that is
# not one of the nine with one line naming it. A stand-in dld-run records the scenes it is given
# and writes a log with a summary line, as the real one does.
# Usage: dilute_map_order.sh PROJECT_SOURCE_DIR
set -euo pipefail
src=$1
dir=$(mktemp -d /tmp/dld-dilute-order.XXXXXX)
trap 'rm -rf "$dir"' EXIT
mkdir -p "$dir/bin"
cat > "$dir/bin/dld-run" <<'STUB'
#!/usr/bin/env bash
scene=$1 name=$(basename "$1" .toml)
echo "$name" >> "$(dirname "$0")/calls.txt"
echo "[dld-membrane] summary: cell 0  mode zigzag  columns 20  lateral shift per column 0.5 um" > "$(dirname "$scene")/$name-cells-0.log"
STUB
chmod +x "$dir/bin/dld-run"
order=4.4:0.2,6.0:1.0,2.0:0.5
"$src/scripts/dilute-map" --only "$order" --out "$dir/map" --bin "$dir/bin" > "$dir/out.txt" 2>&1 ||
  { cat "$dir/out.txt"; exit 1; }
want=$(printf 'cell-d4.4-ca0.2-re0.25\ncell-d6.0-ca1.0-re0.25\ncell-d2.0-ca0.5-re0.25')
[ "$(cat "$dir/bin/calls.txt")" = "$want" ] ||
  { echo "FAIL: cases run in the order"; cat "$dir/bin/calls.txt"; exit 1; }
# Started again: the cases are done (their logs have a certain mode), nothing runs again.
"$src/scripts/dilute-map" --only "$order" --out "$dir/map" --bin "$dir/bin" > "$dir/out2.txt" 2>&1
[ "$(wc -l < "$dir/bin/calls.txt")" = 3 ] || { echo "FAIL: a done case ran again"; exit 1; }
# A case run again keeps its earlier log in the history file (and no file per attempt).
rm "$dir/map/cell-d2.0-ca0.5-re0.25-cells-0.log.history" 2> /dev/null || true
echo "[dld-membrane] step 100 (interrupted)" > "$dir/map/cell-d2.0-ca0.5-re0.25-cells-0.log"
"$src/scripts/dilute-map" --only 2.0:0.5 --out "$dir/map" --bin "$dir/bin" > /dev/null 2>&1
grep -q "step 100 (interrupted)" "$dir/map/cell-d2.0-ca0.5-re0.25-cells-0.log.history" ||
  { echo "FAIL: the earlier log is not in the history file"; exit 1; }
[ "$(find "$dir/map" -name '*.log.[0-9]*' | wc -l)" = 0 ] || { echo "FAIL: a log per attempt"; exit 1; }
# Not one of the nine cases: one line naming it, exit 2, nothing run.
if "$src/scripts/dilute-map" --only 6.0:1.0,5.0:0.2 --out "$dir/bad" --bin "$dir/bin" \
    2> "$dir/err.txt"; then
  echo "FAIL: an unknown case was accepted"; exit 1
fi
grep -q "^dilute-map: --only 5.0:0.2: expected D:CA" "$dir/err.txt" || { cat "$dir/err.txt"; exit 1; }
[ "$(wc -l < "$dir/bin/calls.txt")" = 4 ] || { echo "FAIL: a case ran after the error"; exit 1; }
echo "cases in --only's order, done ones skipped, earlier logs kept in one file, unknown case refused"
