#!/usr/bin/env bash
# The test command (what CI runs): installs dependencies (apt), then three
# stages, each failing the whole on any error:
#   1. Release build with all warnings as errors into build/, whole test suite;
#   2. scripts/sanitize.sh: ASan + UBSan build into build-asan/, whole test
#      suite again (skip with VOXPLORE_SKIP_SANITIZE=1);
#   3. scripts/fuzz.sh: libFuzzer targets (world loader, floor-plan reader,
#      rawlog reader) into build-fuzz/, each run for FUZZ_SECONDS=60 from its
#      seed corpus; a crash fails (skip with VOXPLORE_SKIP_FUZZ=1).
set -euo pipefail
cd "$(dirname "$0")/.."
t0=$(date +%s)
scripts/install_deps.sh
scripts/build.sh -DVOXPLORE_BUILD_TESTS=ON -DVOXPLORE_WERROR=ON
(cd build && ctest --output-on-failure -j"${JOBS:-2}" --timeout 900)
t1=$(date +%s)
echo "test: stage 1 (Release build + tests) took $((t1 - t0)) s"

if [ "${VOXPLORE_SKIP_SANITIZE:-0}" = 1 ]; then
  echo "test: stage 2 (sanitizers) skipped (VOXPLORE_SKIP_SANITIZE=1)"
else
  scripts/sanitize.sh
fi
t2=$(date +%s)
echo "test: stage 2 (ASan + UBSan build + tests) took $((t2 - t1)) s"

if [ "${VOXPLORE_SKIP_FUZZ:-0}" = 1 ]; then
  echo "test: stage 3 (fuzzing) skipped (VOXPLORE_SKIP_FUZZ=1)"
else
  scripts/fuzz.sh
fi
t3=$(date +%s)
echo "test: stage 3 (fuzzers) took $((t3 - t2)) s; all stages $((t3 - t0)) s"
