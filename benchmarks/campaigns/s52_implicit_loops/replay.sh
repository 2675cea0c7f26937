#!/bin/bash
# replay.sh BIN TAG RUN_DIR [key=value ...]: the fifty-second session's form,
# whose keys are [loop_closure] keys; runs ../s53_metaview_dup/replay.sh
# (section.key=value) with them.
set -euo pipefail
BIN=$1; TAG=$2; R=$3; shift 3
args=()
for kv in "$@"; do args+=("loop_closure.$kv"); done
exec "$(dirname "$0")/../s53_metaview_dup/replay.sh" "$BIN" "$TAG" "$R" "${args[@]}"
