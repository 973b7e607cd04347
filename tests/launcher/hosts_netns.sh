#!/usr/bin/env bash
# Issue 14: dld-run places membrane processes on other hosts by itself. dld-run (with the fluid)
# in network namespace A, the two membrane processes on "host" B (a second namespace, a veth pair
# between them), started three ways: through --start-with "ip netns exec {host}", through srun
# inside a SLURM allocation (a stand-in srun that runs its command in the named namespace), and
# printed for the user (this script starts the printed commands in B). Each must give the node
# positions of one K = 1 run over ipc bit for bit. A host that cannot be reached is one line
# naming it and its process, exit 2, and the run's files stay as they were.
# Skipped (exit 77) where namespaces cannot be made.
# Usage: hosts_netns.sh BUILD_DIR PROJECT_SOURCE_DIR [STEPS]
set -euo pipefail
build=$1 src=$2 steps=${3:-400}
run=$build/coupler/launcher/dld-run
dir=$(mktemp -d /tmp/dld-hosts.XXXXXX)
here=$(cd "$(dirname "$0")" && pwd)
. "$here/netns.sh"
make_namespaces
cd "$src"
mkdir -p "$dir/k1"
touching_cells_scene k1 1 60.0 > "$dir/k1/scene.toml"
"$run" "$dir/k1/scene.toml" --membrane cells --steps "$steps" > "$dir/k1/out.txt" 2>&1 ||
  { cat "$dir/k1/out.txt"; exit 1; }

# A stand-in srun: --nodelist=HOST runs the command in namespace HOST (other options dropped).
mkdir -p "$dir/bin"
cat > "$dir/bin/srun" <<'SH'
#!/usr/bin/env bash
host=
while [ $# -gt 0 ] && [ "${1#-}" != "$1" ]; do
  case $1 in --nodelist=*) host=${1#--nodelist=} ;; esac
  shift
done
exec ip netns exec "$host" "$@"
SH
chmod +x "$dir/bin/srun"

place() {  # NAME ARGS...: the touching cells, K = 2 on B, dld-run in A
  local name=$1
  shift
  mkdir -p "$dir/$name"
  touching_cells_scene "$name" 1 60.0 > "$dir/$name/scene.toml"
  ip netns exec "$a" "$run" "$dir/$name/scene.toml" --membrane cells --steps "$steps" \
    --membrane-processes 2 --hosts "$b" --fluid-host 10.203.0.1 --port 5720 "$@"
}
place template --start-with "ip netns exec {host}" > "$dir/template.txt" 2>&1 ||
  { echo "--start-with failed:"; cat "$dir/template.txt"; tail -n 3 "$dir"/template/*.log; exit 1; }
PATH=$dir/bin:$PATH SLURM_JOB_ID=1 SLURMD_NODENAME=$a place srun > "$dir/srun.txt" 2>&1 ||
  { echo "srun failed:"; cat "$dir/srun.txt"; tail -n 3 "$dir"/srun/*.log; exit 1; }
grep -q "srun --nodes=1 --ntasks=1 --nodelist=$b" "$dir/srun.txt" ||
  { echo "inside SLURM, dld-run did not start the membrane processes through srun"; exit 1; }
! grep -q "warning" "$dir/srun.txt" || { echo "a warning on an allocation's node:"; cat "$dir/srun.txt"; exit 1; }
# In an salloc shell (SLURM_JOB_ID but no SLURMD_NODENAME) the fluid would stay on the login node.
SLURM_JOB_ID=1 "$run" "$dir/srun/scene.toml" --membrane cells --hosts "$b" --membrane-processes 2 \
  --dry-run > "$dir/salloc.txt" 2>&1 || true
grep -q "not on one of its nodes (an salloc shell?)" "$dir/salloc.txt" ||
  { echo "no warning outside the allocation's nodes"; exit 1; }

place printed --start-with print > "$dir/printed.txt" 2>&1 &
launcher=$!
for _ in $(seq 100); do
  [ "$(grep -c "^  on $b:" "$dir/printed.txt" || true)" -eq 2 ] && break
  sleep 0.1
done
grep "^  on $b:" "$dir/printed.txt" | sed "s/^  on $b:  //" > "$dir/printed-commands.txt"
[ "$(wc -l < "$dir/printed-commands.txt")" -eq 2 ] ||
  { echo "no two printed commands:"; cat "$dir/printed.txt"; exit 1; }
k=0
while read -r cmd; do
  # shellcheck disable=SC2086  # the printed command, word for word
  ip netns exec "$b" $cmd > "$dir/printed/by-hand-$k.log" 2>&1 &
  k=$((k + 1))
done < "$dir/printed-commands.txt"
wait "$launcher" || { echo "printed run failed:"; cat "$dir/printed.txt"; exit 1; }
wait

for name in template srun printed; do
  grep -h "contact halo" "$dir/$name"/*.log | head -1
done
/usr/bin/python3 "$here/compare_positions.py" "K = 1" "$dir/k1/run-cells-*.ckpt.h5" \
  "K = 2 on another host (template)" "$dir/template/run-cells-*.ckpt.h5" \
  "K = 2 on another host (srun)" "$dir/srun/run-cells-*.ckpt.h5" \
  "K = 2 on another host (printed)" "$dir/printed/run-cells-*.ckpt.h5"

# An unreachable host: one line naming it and its process, exit 2, the run file left alone.
echo "an earlier run" > "$dir/template/run.h5"
status=0
ip netns exec "$a" "$run" "$dir/template/scene.toml" --membrane cells --steps 10 \
  --membrane-processes 2 --hosts "$b,nosuchhost" --fluid-host 10.203.0.1 \
  --start-with "ip netns exec {host}" > "$dir/unreachable.txt" 2>&1 || status=$?
line=$(grep "^error:" "$dir/unreachable.txt" || true)
echo "unreachable host: exit $status: $line"
[ "$status" -eq 2 ] && [[ $line == *"host 'nosuchhost' (membrane process 1)"* ]] ||
  { cat "$dir/unreachable.txt"; exit 1; }
[ "$(cat "$dir/template/run.h5")" = "an earlier run" ] || { echo "run file written over"; exit 1; }
