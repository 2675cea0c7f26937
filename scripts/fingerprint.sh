#!/usr/bin/env bash
# Is a run on this machine the run another machine made? Prints this
# machine's fingerprints of the simulator and of one exploration, to compare
# with the ones recorded in BENCHMARKS.md ("Fingerprints") before pairing a
# campaign with one run elsewhere.
#
#   scripts/fingerprint.sh [--bin DIR] [--out DIR] [--steps N]
#
# 1. mrpt-sim on the dlr_test_room tour (simulated_worlds/dlr_test_room_tour.txt,
#    config/sim.ini, seed 1): the md5 of run.rawlog (the range images the
#    simulator's ray casting made: Embree, sensor noise).
# 2. voxplore-replay of the recorded rawlogs/dlr_test_room/run.rawlog
#    (config/replay.ini): the md5 of trajectory_est.tum and map.bt (SlamIcp
#    and the OctoMap alone, on the same input bytes everywhere).
# 3. voxplore-explore on generated building 4 (voxplore-worldgen --seed 4),
#    compact robot, nbv, seed 1, --max-steps N (default 20): stops, path and
#    the md5 of trajectory_est.tum (SlamIcp and the planner on those images).
# Same md5s: the machines make the same runs, campaigns pair across them;
# which line differs first says where they part (the simulator's images,
# SlamIcp, or the planner and the drive).
# Different: each campaign of a comparison must be run on one machine (a
# single range pixel sends a run another way; BENCHMARKS.md). Takes about
# 15 s on one core. Exit status 0 unless a tool fails.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; }

BIN=build/bin OUT="" STEPS=20
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) BIN=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --steps) STEPS=$2; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "fingerprint.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
for t in mrpt-sim voxplore-replay voxplore-worldgen voxplore-explore; do
  [ -x "$BIN/$t" ] || { echo "fingerprint.sh: $BIN/$t not found (scripts/build.sh first, or --bin DIR)" >&2; exit 2; }
done
if [ -z "$OUT" ]; then
  OUT=$(mktemp -d)
  trap 'rm -rf "$OUT"' EXIT
fi
mkdir -p "$OUT"

echo "cpu: $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1)"
echo "commit: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"

"$BIN/mrpt-sim" --world simulated_worlds/dlr_test_room.world \
  --waypoints simulated_worlds/dlr_test_room_tour.txt --config config/sim.ini \
  --out "$OUT/sim" --seed 1 > "$OUT/sim.log" 2>&1 ||
  { echo "fingerprint.sh: mrpt-sim failed: $(tail -n 1 "$OUT/sim.log")" >&2; exit 1; }
echo "mrpt-sim dlr_test_room tour: rawlog md5 $(md5sum < "$OUT/sim/run.rawlog" | cut -d' ' -f1)"

"$BIN/voxplore-replay" --config config/replay.ini --rawlog rawlogs/dlr_test_room/run.rawlog \
  --out "$OUT/replay" -q > "$OUT/replay.log" 2>&1 ||
  { echo "fingerprint.sh: voxplore-replay failed: $(tail -n 1 "$OUT/replay.log")" >&2; exit 1; }
echo "voxplore-replay dlr_test_room rawlog: trajectory md5 $(md5sum < "$OUT/replay/trajectory_est.tum" | cut -d' ' -f1), map.bt md5 $(md5sum < "$OUT/replay/map.bt" | cut -d' ' -f1)"

"$BIN/voxplore-worldgen" --seed 4 --out "$OUT/b4" --no-topview -q
if ! "$BIN/voxplore-explore" --config config/explore.ini --world "$OUT/b4/building.world" \
  --robot compact --strategy nbv --seed 1 --max-steps "$STEPS" --out "$OUT/explore" -q \
  > "$OUT/explore.log" 2>&1; then
  echo "fingerprint.sh: voxplore-explore failed: $(tail -n 1 "$OUT/explore.log")" >&2
  exit 1
fi
python3 - "$OUT/explore/summary.json" "$STEPS" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"voxplore-explore b4 compact nbv, {sys.argv[2]} steps: {s['stops']} stops, "
      f"path {s['path_length_m']:.4f} m", end="")
EOF
echo ", trajectory md5 $(md5sum < "$OUT/explore/trajectory_est.tum" | cut -d' ' -f1)"
