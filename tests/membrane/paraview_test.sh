#!/usr/bin/env bash
# ParaView (Debian's pvpython) opens every XDMF file the programs write, with its default reader
# (issue 18, item 11): a 300-step coupled run of the default scene at the coarse setting with
# meshes every 100 steps and fluid fields, and a fluid-only run of 200 steps with a snapshot every
# 100 (it ends on a snapshot step), then tests/membrane/paraview_reads_xdmf.py. Exit 77 (skipped)
# when pvpython is not installed: scripts/setup --with-paraview installs it.
# Usage: paraview_test.sh DLD_RUN DLD_FLUID SOURCE_DIR
set -euo pipefail
run=$1 fluid=$2 source=$3
command -v pvpython > /dev/null || { echo "pvpython not installed (scripts/setup --with-paraview)"; exit 77; }
dir=$(mktemp -d /tmp/dld-paraview.XXXXXX)
trap 'rm -rf "$dir"' EXIT
sed -e "s|^file = .*|file = \"$dir/run.h5\"|" -e 's/^fields = false/fields = true\nmesh_every = 100/' \
    "$source/configs/single-cell.toml" > "$dir/scene.toml"
"$run" "$dir/scene.toml" --membrane cells --steps 300 > "$dir/run.out" 2>&1 || { cat "$dir/run.out"; exit 1; }
sed -e "s|^file = .*|file = \"$dir/fluid-only.h5\"|" -e 's/^fields = false/fields = true\nsnapshot_every = 100/' \
    -e '/^\[\[cells.cell\]\]/,$d' "$source/configs/single-cell.toml" > "$dir/fluid-only.toml"
"$fluid" "$dir/fluid-only.toml" --steps 200 > "$dir/fluid.out" 2>&1 || { cat "$dir/fluid.out"; exit 1; }
# Offscreen: reading needs no display.
pvpython --force-offscreen-rendering "$source/tests/membrane/paraview_reads_xdmf.py" "$dir" \
  > "$dir/check.out" 2>&1 || true
grep -v "^(" "$dir/check.out" | grep -v "^ *[0-9]* *0x" || true
tail -n 1 "$dir/check.out" | grep -q "paraview_reads_xdmf: ok"
