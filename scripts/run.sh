#!/usr/bin/env bash
# The main job: installs dependencies (apt), builds Release, and explores the
# default world (dlr_test_room) autonomously with the simulated omniRob until
# nothing is left to see. Outputs go to out/<world>/ (map.bt, map.simplemap,
# metaview.ply, run.rawlog, trajectories, coverage.csv, steps/*.png,
# summary.json). WORLD=office scripts/run.sh explores another world of
# simulated_worlds/; extra arguments go to voxplore-explore (see --help).
set -euo pipefail
cd "$(dirname "$0")/.."
WORLD=${WORLD:-dlr_test_room}
OUT=${OUT:-out/$WORLD}
scripts/install_deps.sh
scripts/build.sh
build/bin/voxplore-explore --config config/explore.ini --world "simulated_worlds/$WORLD.world" \
  --out "$OUT" "$@"
echo "outputs in $OUT:"; ls "$OUT"
echo "summary:"; cat "$OUT/summary.json"
