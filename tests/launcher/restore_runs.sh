#!/usr/bin/env bash
# Issue 16: a new machine has an empty runs/ folder; scripts/restore-finished-runs marks the runs
# that finished elsewhere as done from the committed summary (docs/results/headline/summary.csv),
# so dld-sweep neither reruns them nor leaves them out (the headline's study file at `fast`, the
# setting those runs were made at): --list shows them done and --summary
# writes the committed summary byte for byte (with a run's exact-coupling stretches, which --list
# shows too). A run folder that holds a checkpoint is left alone,
# and a file that is no sweep summary is refused with one line naming it.
# Usage: restore_runs.sh DLD_SWEEP PROJECT_SOURCE_DIR
set -euo pipefail
sweep=$1 src=$2
dir=$(mktemp -d /tmp/dld-restore.XXXXXX)
trap 'rm -rf "$dir"' EXIT
study=$src/configs/study
sed -e "s|^scene = .*|scene = \"$study/base.toml\"|" -e "s|^output = .*|output = \"$dir/runs\"|" \
    -e "s|^modes = .*|modes = \"$study/dilute_modes_fast.toml\"|" \
    -e "s|^resolutions = .*|resolutions = \"$study/resolutions.toml\"|" \
    -e "s|^default_resolution = .*|default_resolution = \"fast\"|" \
    "$study/headline.toml" > "$dir/headline.toml"
# The committed summary, with exact-coupling stretches (dld-run --exact-coupling-for) given to its
# first run: they must come back in the restored run's summary row.
committed=$src/docs/results/headline/summary.csv
summary=$dir/summary-in.csv
/usr/bin/python3 - "$committed" "$summary" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1], newline="")))
rows[1][rows[0].index("exact_coupling")] = "1000000-1060000;2000000-2050000"
csv.writer(open(sys.argv[2], "w", newline=""), lineterminator="\n").writerows(rows)
PY
cmp -s "$committed" "$summary" && { echo "FAIL: no stretch written into the test's summary"; exit 1; }
done_runs=$(($(wc -l < "$summary") - 1))
# A run under way keeps its folder: a stand-in checkpoint in the first finished run's folder.
first=$(sed -n 2p "$summary" | cut -d, -f1)
mkdir -p "$dir/runs/fast/$first"
touch "$dir/runs/fast/$first/run-fluid.ckpt.h5"
"$src/scripts/restore-finished-runs" "$summary" "$dir/runs/fast" | tee "$dir/restore.txt"
grep -q "^$first: kept (run-fluid.ckpt.h5 present)" "$dir/restore.txt" ||
  { echo "FAIL: $first was not kept"; exit 1; }
[ ! -e "$dir/runs/fast/$first/done.toml" ] || { echo "FAIL: $first overwritten"; exit 1; }
rm -r "${dir:?}/runs/fast/$first"
"$src/scripts/restore-finished-runs" "$summary" "$dir/runs/fast" > /dev/null
# A continuation of the finished run (as hard100-fast makes of Ht45.6-d6) ran a stretch after its
# last step: --list shows it, the finished run's summary row does not.
echo "9000000,9050000,9050000" >> "$dir/runs/fast/$first/run-exact-coupling.csv"
listed=$("$sweep" "$dir/headline.toml" --list | grep -c " done")
[ "$listed" = "$done_runs" ] || { echo "FAIL: $listed runs listed done, expected $done_runs"; exit 1; }
"$sweep" "$dir/headline.toml" --summary > "$dir/summary.txt" 2>&1 || { cat "$dir/summary.txt"; exit 1; }
cmp "$summary" "$dir/runs/fast/summary.csv" ||
  { echo "FAIL: the summary of the restored runs differs from $summary"; exit 1; }
"$sweep" "$dir/headline.toml" --list | grep -q "^  0  $first .*exact coupling over steps 1000000-1060000;2000000-2050000;9000000-9050000" ||
  { echo "FAIL: --list does not show the restored run's exact-coupling stretches"; exit 1; }
echo "restored $done_runs runs: listed done (with their exact-coupling stretches), summary byte for byte"
# Not a sweep summary: one line naming the file and the column, non-zero exit.
echo "a,b" > "$dir/bad.csv"
if "$src/scripts/restore-finished-runs" "$dir/bad.csv" "$dir/x" 2> "$dir/err.txt"; then
  echo "FAIL: a file without the summary's columns was accepted"; exit 1
fi
grep -q "bad.csv: no column 'run'" "$dir/err.txt" || { cat "$dir/err.txt"; exit 1; }
echo "bad summary refused: $(cat "$dir/err.txt")"
