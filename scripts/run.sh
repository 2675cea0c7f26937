#!/usr/bin/env bash
# The main job: installs dependencies (apt), builds Release, and runs a scan
# tour of the default world (dlr_test_room) with the simulator. Outputs go to
# out/dlr_test_room/ (run.rawlog, trajectory_gt.tum, topview.png, params.ini).
# Later issues turn this into full autonomous exploration.
set -euo pipefail
cd "$(dirname "$0")/.."
WORLD=${WORLD:-dlr_test_room}
OUT=${OUT:-out/$WORLD}
scripts/install_deps.sh
scripts/build.sh
build/bin/mrpt-sim --world "simulated_worlds/$WORLD.world" \
  --waypoints "simulated_worlds/${WORLD}_tour.txt" --config config/sim.ini --out "$OUT" "$@"
echo "outputs in $OUT:"; ls -l "$OUT"
