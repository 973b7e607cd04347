# Sourced by the two-host tests: two network namespaces A (10.203.0.1) and B (10.203.0.2) joined
# by a veth pair, loopback up in each, removed (with every process in them) on exit; and the
# touching four-cell scene of split_equality.sh, and one leg of a resumed run of it. Needs $dir (a
# scratch folder) and $src; leg needs $run (dld-run).
# make_namespaces exits 77 (skipped) where namespaces cannot be made (not root, no iproute2, a
# container without CAP_SYS_ADMIN).
tag=dld$$ a=dld$$a b=dld$$b
cleanup_namespaces() {
  ip netns pids "$a" 2>/dev/null | xargs -r kill -9 2>/dev/null || true
  ip netns pids "$b" 2>/dev/null | xargs -r kill -9 2>/dev/null || true
  ip netns del "$a" 2>/dev/null || true
  ip netns del "$b" 2>/dev/null || true
  rm -rf "$dir"
}
make_namespaces() {
  trap cleanup_namespaces EXIT
  if ! command -v ip > /dev/null || ! ip netns add "$a" 2> /dev/null; then
    echo "skipped: cannot create network namespaces here (needs root and iproute2)"
    exit 77
  fi
  ip netns add "$b"
  ip link add "${tag}x" type veth peer name "${tag}y"
  ip link set "${tag}x" netns "$a"
  ip link set "${tag}y" netns "$b"
  ip -n "$a" addr add 10.203.0.1/24 dev "${tag}x"
  ip -n "$b" addr add 10.203.0.2/24 dev "${tag}y"
  for ns in "$a" "$b"; do ip -n "$ns" link set lo up; done
  ip -n "$a" link set "${tag}x" up
  ip -n "$b" link set "${tag}y" up
}
touching_cells_scene() {  # NAME K TIMEOUT_S: four cells within each other's contact range
  sed -e "s/^name = .*/name = \"$1\"/" -e "s|^file = .*|file = \"$dir/$1/run.h5\"|" \
      -e "s/^range_um = .*/range_um = 1.6/" -e '/^\[\[cells.cell\]\]/,$d' \
      -e "s/^timeout_s = .*/timeout_s = $3\nmembrane_processes = $2/" \
      "$src/configs/single-cell.toml"
  for c in "3.0, 0.0" "11.3, 0.0" "19.6, 0.0" "3.0, 8.4"; do
    printf '[[cells.cell]]\ncentre_um = [%s, 2.4]\n' "$c"
  done
}
touching_runs() {  # NAME...: a folder each with the touching four-cell scene, one membrane process
  local name
  for name in "$@"; do
    mkdir -p "$dir/$name"
    touching_cells_scene "$name" 1 60.0 > "$dir/$name/scene.toml"
  done
}
programs_said() {  # NAME PATTERN: what the fluid's and the membrane's logs of NAME say, one line
  cat "$dir/$1/run-fluid.log" "$dir/$1/run-cells-0.log" | grep -o "$2" | tr '\n' ' '
}
leg() {  # NAME STEPS ARGS...: one leg of a run in $dir/NAME, its output shown if it fails
  local name=$1 n=$2
  shift 2
  (cd "$src" && "$run" "$dir/$name/scene.toml" --membrane cells --steps "$n" \
      --checkpoint-every 250 "$@" > "$dir/$name/out-$n.txt" 2>&1) ||
    { echo "$name to step $n ($*) failed:"; cat "$dir/$name/out-$n.txt"; exit 1; }
}
