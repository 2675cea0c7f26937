#!/usr/bin/env bash
# CI stage 2: builds voxplore with AddressSanitizer + UndefinedBehaviorSanitizer
# (-DVOXPLORE_SANITIZE=ON, gcc, -O1 -g, asserts on) into build-asan/ and runs
# the whole test suite there. Any ASan/UBSan report or leak in our code fails
# it. Leaks inside third-party libraries are suppressed in scripts/lsan.supp
# (each entry says why). Usable alone; scripts/test.sh runs it after the
# Release tests unless VOXPLORE_SKIP_SANITIZE=1.
#   BUILD_DIR=build-asan  JOBS=2  CTEST_ARGS="-R Rawlog"  scripts/sanitize.sh
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
JOBS=${JOBS:-2}
BUILD_DIR=${BUILD_DIR:-build-asan}

# Exported before the build: gtest_discover_tests runs every test executable
# at build time, so those runs are checked too.
export ASAN_OPTIONS="halt_on_error=1:print_stacktrace=1:detect_leaks=1:check_initialization_order=1:strict_init_order=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$ROOT/scripts/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

start=$(date +%s)
# Empty build type: only the sanitizer flags' -O1 -g, and assert()s stay on.
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE= -DVOXPLORE_SANITIZE=ON -DVOXPLORE_BUILD_TESTS=ON \
  -DVOXPLORE_BENCHMARKS=OFF "$@"
cmake --build "$BUILD_DIR" -j"$JOBS"
built=$(date +%s)
echo "sanitize: build took $((built - start)) s"

cd "$BUILD_DIR"
# shellcheck disable=SC2086
ctest --output-on-failure -j"$JOBS" --timeout 1800 ${CTEST_ARGS:-}
echo "sanitize: ctest took $(($(date +%s) - built)) s; whole stage $(($(date +%s) - start)) s"
