#!/usr/bin/env bash
# Issue 14: the split equality of split_equality.sh over tcp with CURVE between two hosts: the
# fluid in one network namespace, two membrane processes in another, a veth pair between them
# (loopback up inside each), made by this test. K = 2 over tcp must give the node positions of
# K = 1 over ipc bit for bit. Skipped (exit 77) where namespaces cannot be made (not root, no
# iproute2, a container without CAP_SYS_ADMIN).
# Usage: split_netns.sh BUILD_DIR PROJECT_SOURCE_DIR [STEPS]
set -euo pipefail
build=$1 src=$2 steps=${3:-400}
fluid=$build/fluid/dld-fluid membrane=$build/membrane/dld-membrane
run=$build/coupler/launcher/dld-run keys=$build/coupler/dld-keys
dir=$(mktemp -d /tmp/dld-netns.XXXXXX)
here=$(cd "$(dirname "$0")" && pwd)
. "$here/netns.sh"
make_namespaces
scene() { touching_cells_scene "k$1" "$1" 60.0; }
mkdir -p "$dir/k1" "$dir/k2"
scene 1 > "$dir/k1/scene.toml"
scene 2 > "$dir/k2/scene.toml"
(cd "$src" && "$run" "$dir/k1/scene.toml" --membrane cells --steps "$steps" > "$dir/k1/out.txt" 2>&1) ||
  { cat "$dir/k1/out.txt"; exit 1; }

"$keys" "$dir/fluid" "$dir/m0" "$dir/m1" > /dev/null
cd "$src"
endpoint=tcp://10.203.0.1:5710
ip netns exec "$a" "$fluid" "$dir/k2/scene.toml" --serve "$endpoint" --peers 2 --cells 4 \
  --curve-key "$dir/fluid.key" --curve-clients "$dir/m0.pub" "$dir/m1.pub" \
  --checkpoint "$dir/k2/fluid.ckpt.h5" > "$dir/k2/fluid.log" 2>&1 &
fluid_pid=$!
pids=()
for k in 0 1; do
  ip netns exec "$b" "$membrane" "$dir/k2/scene.toml" --connect "$endpoint" --peer "$k" --peers 2 \
    --steps "$steps" --curve-key "$dir/m$k.key" --curve-server "$dir/fluid.pub" \
    --checkpoint "$dir/k2/cells-$k.ckpt.h5" > "$dir/k2/cells-$k.log" 2>&1 &
  pids+=($!)
done
status=0
for p in "${pids[@]}" "$fluid_pid"; do wait "$p" || status=1; done
if [ $status -ne 0 ]; then
  tail -n 5 "$dir"/k2/*.log
  exit 1
fi
grep -h "contact halo" "$dir"/k2/cells-*.log
/usr/bin/python3 "$here/compare_positions.py" "K = 1 over ipc" "$dir/k1/run-cells-*.ckpt.h5" \
  "K = 2 over tcp + CURVE between namespaces" "$dir/k2/cells-*.ckpt.h5"
