#!/bin/bash
# replay.sh BIN TAG RUN_DIR [section.key=value ...]: replays a campaign run's
# rawlog with its own SLAM sections (and the overrides) into out/rp/TAG/RUN,
# and prints the run's and the replay's ATE.
set -euo pipefail
BIN=$1; TAG=$2; R=$3; shift 3
N=$(basename "$R"); O=out/rp/$TAG/$N; mkdir -p "$O"
python3 "$(dirname "$0")/mkrp.py" "$R/params.ini" "$O/slam.ini" "$@"
"$BIN/voxplore-replay" -q -r "$R/run.rawlog" -c "$O/slam.ini" -g "$R/trajectory_gt.tum" -o "$O" > "$O/log.txt" 2>&1
cp "$R/trajectory_gt.tum" "$O/"
python3 -c "
import json; d=json.load(open('$O/summary.json')); b=json.load(open('$R/summary.json'))
print('$TAG $N', 'ate', round(b['ate_rmse_m'],4), '->', round(d['ate_rmse_m'],4), 'online', round(d.get('ate_online_rmse_m',0),4), 'closures', b.get('loop_closures'), '->', d.get('loop_closures'), 'prec', d.get('map_precision_above_floor'))
"
