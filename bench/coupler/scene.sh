# Sourced by the coupler benchmarks: the RBC scene they time (configs/single-cell.toml at
# dx = 0.4 um, 2000-face cells, Re 0.1, SPEC's viscosity ratio 5), without its cells; callers
# append a [cells] table (packed at random: any count up to the study's 17).
# bench_scene NAME OUT_DIR [EXTRA_SED_ARGS...]   (prints the scene; the run file goes to OUT_DIR)
bench_scene() {
  local name=$1 dir=$2
  shift 2
  sed -e "s/^name = .*/name = \"$name\"/" -e 's/^dx_um = .*/dx_um = 0.4/' \
      -e 's/^mesh_faces = .*/mesh_faces = 2000/' -e 's/^reynolds = .*/reynolds = 0.1/' \
      -e "s|^file = .*|file = \"$dir/$name.h5\"|" "$@" \
      -e '/^\[\[cells.cell\]\]/,$d' "$here/configs/single-cell.toml"
}
