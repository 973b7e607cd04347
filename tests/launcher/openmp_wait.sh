#!/usr/bin/env bash
# dld-run starts its programs with OMP_WAIT_POLICY=PASSIVE and GOMP_SPINCOUNT=20000 (a short spin
# before sleeping: docs/performance.md, "A short spin before sleeping"), and keeps the values a user
# set. Both programs' logs must name the values they ran with: the defaults for a plain run, the
# user's for a run started with GOMP_SPINCOUNT=7 and OMP_WAIT_POLICY=ACTIVE. (Two steps each.)
# Usage: openmp_wait.sh DLD_RUN PROJECT_SOURCE_DIR
set -euo pipefail
run=$1 src=$2
unset OMP_WAIT_POLICY GOMP_SPINCOUNT  # the defaults leg must see dld-run's own
dir=$(mktemp -d /tmp/dld-openmp-wait.XXXXXX)
trap 'rm -rf "$dir"' EXIT
. "$(dirname "$0")/netns.sh"  # touching_runs, leg, programs_said
said() { programs_said "$1" "OpenMP threads (.*)"; }
touching_runs defaults user
leg defaults 2
expect="OpenMP threads (OMP_WAIT_POLICY PASSIVE, GOMP_SPINCOUNT 20000) "
[ "$(said defaults)" = "$expect$expect" ] ||
  { echo "defaults: the programs said '$(said defaults)', expected '$expect' twice"; exit 1; }
GOMP_SPINCOUNT=7 OMP_WAIT_POLICY=ACTIVE leg user 2
expect="OpenMP threads (OMP_WAIT_POLICY ACTIVE, GOMP_SPINCOUNT 7) "
[ "$(said user)" = "$expect$expect" ] ||
  { echo "user's values: the programs said '$(said user)', expected '$expect' twice"; exit 1; }
echo "ok: dld-run's defaults and a user's values reach both programs"
