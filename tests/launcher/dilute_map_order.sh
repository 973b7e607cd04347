#!/usr/bin/env bash
# scripts/dilute-map runs its cases in the order --only names them (scripts/long-runs puts the case
# under way first), starts no further case after a stopped one (Ctrl-C), keeps each case's earlier
# logs in one history file, and refuses a case that is not one of the nine, or one named twice,
# with one line naming it. A stand-in dld-run records the scenes it is given and writes a log with
# a summary line, as the real one does.
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
# STUB_INTERRUPT=1: a run ended by Ctrl-C (scripts/long-runs stop), as dld-run reports it.
[ -n "${STUB_INTERRUPT:-}" ] && { echo "dld-run: interrupted"; exit 130; }
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
"$src/scripts/dilute-map" --only "$order" --out "$dir/map" --bin "$dir/bin" > "$dir/out2.txt" 2>&1 ||
  { cat "$dir/out2.txt"; exit 1; }
[ "$(wc -l < "$dir/bin/calls.txt")" = 3 ] || { echo "FAIL: a done case ran again"; exit 1; }
# A case run twice more after interrupted attempts keeps both earlier logs, one after the other,
# in the history file (and no file per attempt).
log=$dir/map/cell-d2.0-ca0.5-re0.25-cells-0.log
for attempt in first second; do
  echo "[dld-membrane] step 100 ($attempt attempt, interrupted)" > "$log"
  "$src/scripts/dilute-map" --only 2.0:0.5 --out "$dir/map" --bin "$dir/bin" > "$dir/out3.txt" 2>&1 ||
    { cat "$dir/out3.txt"; exit 1; }
done
[ "$(grep -c "attempt, interrupted" "$log.history")" = 2 ] ||
  { echo "FAIL: the history file does not hold both earlier logs"; cat "$log.history"; exit 1; }
[ "$(find "$dir/map" -name '*.log.[0-9]*' | wc -l)" = 0 ] || { echo "FAIL: a log per attempt"; exit 1; }
# A stopped case (Ctrl-C) stops the map: the next case is not started.
STUB_INTERRUPT=1 "$src/scripts/dilute-map" --only 4.4:1.0,4.4:0.5 --out "$dir/map" \
  --bin "$dir/bin" > "$dir/out4.txt" 2>&1 || true
[ "$(tail -n 1 "$dir/bin/calls.txt")" = cell-d4.4-ca1.0-re0.25 ] &&
  ! grep -q cell-d4.4-ca0.5 "$dir/bin/calls.txt" ||
  { echo "FAIL: after a stopped case the map went on"; cat "$dir/bin/calls.txt"; exit 1; }
calls=$(wc -l < "$dir/bin/calls.txt")
# Not one of the nine cases, or one named twice: one line naming it, exit 2, nothing run.
for bad in "6.0:1.0,5.0:0.2|5.0:0.2: expected D:CA" "6.0:1.0,6.0:1.0|6.0:1.0: named twice"; do
  status=0
  "$src/scripts/dilute-map" --only "${bad%%|*}" --out "$dir/bad" --bin "$dir/bin" \
    2> "$dir/err.txt" || status=$?
  [ "$status" = 2 ] || { echo "FAIL: --only ${bad%%|*}: exit $status, expected 2"; exit 1; }
  grep -q "^dilute-map: --only ${bad#*|}" "$dir/err.txt" || { cat "$dir/err.txt"; exit 1; }
done
[ "$(wc -l < "$dir/bin/calls.txt")" = "$calls" ] || { echo "FAIL: a case ran after an error"; exit 1; }
echo "cases in --only's order, done ones skipped, earlier logs kept in one file, bad cases refused"
