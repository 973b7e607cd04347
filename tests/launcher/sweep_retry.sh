#!/usr/bin/env bash
# dld-sweep --retry-failed --exact-coupling-for N with a stand-in dld-run (beside a copy of
# dld-sweep, where the sweep looks first) whose held coupling always fails, as Ht45.6-d6's did at
# step 4 718 503: the sweep retries a run that fails under it at once with N exact steps first,
# keeps each failed attempt's log, and gives up when the exact steps fail too or after 10 retries,
# so it never loops on a run that gets nowhere. Without --exact-coupling-for a failed run is not
# retried.
# Usage: sweep_retry.sh DLD_SWEEP PROJECT_SOURCE_DIR
set -euo pipefail
sweep=$1 src=$2
dir=$(mktemp -d /tmp/dld-retry.XXXXXX)
trap 'rm -rf "$dir"' EXIT
mkdir -p "$dir/bin"
cp "$sweep" "$dir/bin/dld-sweep"
printf '#!/bin/sh\nexit 0\n' > "$dir/bin/dld-analyze"
# The stand-in: without --exact-coupling-for the guard stops it; with it, STUB_MODE says whether
# the exact steps fail (exact-fails), or pass and the held coupling fails after them (held-fails),
# or the run ends (ok). It appends its arguments to the run's calls file.
cat > "$dir/bin/dld-run" <<'EOF'
#!/usr/bin/env bash
run=$(dirname "$1")
echo "$*" >> "$run/calls"
touch "$run/run-fluid.ckpt.h5"
if [[ " $* " != *" --exact-coupling-for "* ]]; then
  echo "dld-run: dld-fluid stopped with exit code 1: velocity 0.359 (stand-in guard)"; exit 1
fi
[ "$STUB_MODE" = exact-fails ] && { echo "dld-run: velocity 0.25 at exact coupling"; exit 1; }
[ -f "$run/run-exact-coupling.csv" ] || echo "first_step,last_step" > "$run/run-exact-coupling.csv"
n=$(grep -c . "$run/run-exact-coupling.csv")
echo "$((n * 1000)),$((n * 1000 + 500))" >> "$run/run-exact-coupling.csv"
[ "$STUB_MODE" = ok ] && { echo "dld-run: done"; exit 0; }
echo "dld-run: dld-fluid stopped with exit code 1: velocity 0.3 after the exact steps"; exit 1
EOF
chmod +x "$dir/bin/dld-run" "$dir/bin/dld-analyze"
study=$src/configs/study
case_study() {  # case_study NAME: the headline's study file writing under $dir/NAME
  sed -e "s|^scene = .*|scene = \"$study/base.toml\"|" -e "s|^output = .*|output = \"$dir/$1\"|" \
    -e "s|^modes = .*|modes = \"$study/dilute_modes_fast.toml\"|" \
    -e "s|^resolutions = .*|resolutions = \"$study/resolutions.toml\"|" \
    -e "s|^default_resolution = .*|default_resolution = \"fast\"|" \
    "$study/headline.toml" > "$dir/$1.toml"
  echo "$dir/$1.toml"
}
fail() { echo "FAIL: $*"; exit 1; }
sweep_case() {  # sweep_case NAME MODE [ARGS]: the sweep's exit code; its log in $dir/NAME.log
  local name=$1 mode=$2
  shift 2
  local status=0
  STUB_MODE=$mode "$dir/bin/dld-sweep" "$(case_study "$name")" --only Ht8-d4.4 "$@" \
    > "$dir/$name.log" 2>&1 || status=$?
  echo "$status"
}
calls() { grep -c . "$dir/$1/fast/Ht8-d4.4/calls"; }

# Fails, retried with the exact start, ends: done, the stretch in the summary, the failure's log
# kept; the sweep's --threads reaches every attempt.
[ "$(sweep_case ok ok --retry-failed --exact-coupling-for 500 --threads 1)" = 0 ] ||
  { cat "$dir/ok.log"; fail "ok: sweep failed"; }
run=$dir/ok/fast/Ht8-d4.4
[ "$(calls ok)" = 2 ] || fail "ok: $(calls ok) starts, expected 2"
sed -n 2p "$run/calls" | grep -q -- "--resume --exact-coupling-for 500" || fail "ok: retry without the exact start: $(sed -n 2p "$run/calls")"
[ "$(grep -c -- "--threads 1" "$run/calls")" = 2 ] ||
  fail "ok: --threads 1 not passed on: $(cat "$run/calls")"
[ -f "$run/done.toml" ] || fail "ok: the retried run is not done"
grep -q "stand-in guard" "$run/dld-run.failures.log" || fail "ok: the failed attempt's log was not kept"
grep -q "^Ht8-d4.4,.*,1000-1500," "$dir/ok/fast/summary.csv" || fail "ok: no exact_coupling in $(cat "$dir/ok/fast/summary.csv")"
echo "ok: failed, retried with --exact-coupling-for 500, done; summary exact_coupling 1000-1500"

# The exact steps fail too: given up after one retry, listed failed.
[ "$(sweep_case exact exact-fails --retry-failed --exact-coupling-for 500)" = 1 ] || fail "exact: exit code"
[ "$(calls exact)" = 2 ] || fail "exact: $(calls exact) starts, expected 2"
"$dir/bin/dld-sweep" "$dir/exact.toml" --list | grep -q "Ht8-d4.4 *failed" || fail "exact: not listed failed"
echo "exact steps failing too: one retry, then left failed"

# The held coupling fails after every exact stretch: at most 10 retries in one sweep.
[ "$(sweep_case held held-fails --retry-failed --exact-coupling-for 500)" = 1 ] || fail "held: exit code"
[ "$(calls held)" = 11 ] || fail "held: $(calls held) starts, expected 11"
[ "$(grep -c "^==== attempt ended with exit code 1" "$dir/held/fast/Ht8-d4.4/dld-run.failures.log")" = 11 ] ||
  fail "held: not every failed attempt's log kept"
echo "failing after each exact stretch: 10 retries, then left failed"

# Without --exact-coupling-for a failure is final within the sweep.
[ "$(sweep_case plain ok)" = 1 ] || fail "plain: exit code"
[ "$(calls plain)" = 1 ] || fail "plain: $(calls plain) starts, expected 1"
echo "without --exact-coupling-for: not retried"
