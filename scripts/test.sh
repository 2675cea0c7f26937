#!/usr/bin/env bash
# The test command: installs dependencies (apt), builds Release with all
# warnings as errors, and runs the whole test suite. Exit code != 0 on failure.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh -DVOXPLORE_BUILD_TESTS=ON -DVOXPLORE_WERROR=ON
cd build
ctest --output-on-failure -j"${JOBS:-2}" --timeout 900
