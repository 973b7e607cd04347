#!/usr/bin/env bash
# Issue 14, faults across hosts: the fluid on host A (a network namespace), two membrane processes
# on host B over tcp + CURVE; membrane 1 is then killed (SIGKILL) or hung (SIGSTOP) mid-run. The
# fluid and membrane 0 must both stop, non-zero, within the coupler's timeout (5 s here) plus a
# margin, and the fluid's message must name the process, its host and the step. Skipped (77)
# where namespaces cannot be made.
# Usage: fault_netns.sh BUILD_DIR PROJECT_SOURCE_DIR
set -euo pipefail
build=$1 src=$2
fluid=$build/fluid/dld-fluid membrane=$build/membrane/dld-membrane keys=$build/coupler/dld-keys
dir=$(mktemp -d /tmp/dld-fault.XXXXXX)
. "$(dirname "$0")/netns.sh"
make_namespaces
"$keys" "$dir/fluid" "$dir/m0" "$dir/m1" > /dev/null
cd "$src"
port=5720
for signal in KILL STOP; do
  mkdir -p "$dir/f$signal"
  touching_cells_scene "f$signal" 2 5.0 > "$dir/f$signal/scene.toml"
  endpoint=tcp://10.203.0.1:$port
  port=$((port + 2))
  ip netns exec "$a" "$fluid" "$dir/f$signal/scene.toml" --serve "$endpoint" --peers 2 --cells 4 \
    --curve-key "$dir/fluid.key" --curve-clients "$dir/m0.pub" "$dir/m1.pub" \
    > "$dir/f$signal/fluid.log" 2>&1 &
  fluid_pid=$!
  pids=()
  for k in 0 1; do
    ip netns exec "$b" "$membrane" "$dir/f$signal/scene.toml" --connect "$endpoint" --peer "$k" \
      --peers 2 --steps 100000000 --curve-key "$dir/m$k.key" --curve-server "$dir/fluid.pub" \
      > "$dir/f$signal/cells-$k.log" 2>&1 &
    pids+=($!)
  done
  sleep 3  # running: connected and stepping
  kill -0 "$fluid_pid" || { echo "$signal: the fluid ended before the fault"; cat "$dir/f$signal/fluid.log"; exit 1; }
  kill -"$signal" "${pids[1]}"
  start=$(date +%s)
  set +e
  wait "$fluid_pid"; fluid_code=$?
  wait "${pids[0]}"; m0_code=$?
  set -e
  took=$(( $(date +%s) - start ))
  kill -KILL "${pids[1]}" 2>/dev/null || true
  message=$(grep -h "membrane-1@" "$dir/f$signal/fluid.log" | tail -1)
  echo "$signal: fluid exit $fluid_code, membrane 0 exit $m0_code after $took s: $message"
  [ "$fluid_code" -ne 0 ] && [ "$m0_code" -ne 0 ] || { echo "$signal: a process did not fail"; exit 1; }
  [ "$took" -le 15 ] || { echo "$signal: took $took s, the timeout is 5 s"; exit 1; }
  echo "$message" | grep -q "membrane 'membrane-1@$(hostname)'.*step [0-9]" ||
    { echo "$signal: the fluid's message does not name membrane-1, its host and the step"; exit 1; }
  grep -q "membrane-1@" "$dir/f$signal/cells-0.log" ||
    { echo "$signal: membrane 0 was not told which process failed"; cat "$dir/f$signal/cells-0.log"; exit 1; }
done
