#!/usr/bin/env bash
# Configures and builds voxplore (Release) into build/, binaries in build/bin/.
# Extra arguments go to cmake's configure step (e.g. -DVOXPLORE_BENCHMARKS=ON).
set -euo pipefail
cd "$(dirname "$0")/.."
JOBS=${JOBS:-2}
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build build -j"$JOBS"
