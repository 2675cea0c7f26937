#!/usr/bin/env bash
# Consumer.FindPackageFromInstalledPrefix (issue 14): proves that
# find_package(voxplore) works for a project outside this tree.
#   tests/consumer_test.sh BUILD_DIR [CXX_COMPILER]
# 1. cmake --install BUILD_DIR into a temporary prefix;
# 2. configures, builds and runs tests/consumer (SlamIcpParams, OctoMapLayer,
#    DriverParams, RobotInterface) with CMAKE_PREFIX_PATH=<prefix>;
# 3. deletes find_dependency(octomap) from the installed voxploreConfig.cmake
#    and checks that configuring the consumer now fails, naming octomap (so a
#    dependency missing from the config file fails this test).
# About 30 s on 2 cores (one small translation unit). Fails on any error.
set -euo pipefail

REPO=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(realpath -- "${1:?usage: consumer_test.sh BUILD_DIR [CXX_COMPILER]}")
CXX_COMPILER=${2:-c++}
TMP=$(mktemp -d "${TMPDIR:-/tmp}/voxplore_consumer.XXXXXX")
trap 'rm -rf "$TMP"' EXIT

fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$BUILD" --prefix "$TMP/prefix" > "$TMP/install.log" ||
  { cat "$TMP/install.log"; fail "cmake --install $BUILD"; }
config=$(find "$TMP/prefix" -name voxploreConfig.cmake | head -n 1)
[ -n "$config" ] || fail "no voxploreConfig.cmake installed under $TMP/prefix"
echo "consumer: installed into $TMP/prefix ($config)"

launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
configure() {  # configure BUILD_SUBDIR -> the consumer against the prefix
  cmake -S "$REPO/tests/consumer" -B "$TMP/$1" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$TMP/prefix" -DCMAKE_CXX_COMPILER="$CXX_COMPILER" "${launcher[@]}"
}

configure build > "$TMP/configure.log" 2>&1 || { cat "$TMP/configure.log"; fail "configure"; }
cmake --build "$TMP/build" -j"${JOBS:-2}" > "$TMP/build.log" 2>&1 ||
  { cat "$TMP/build.log"; fail "build of the consumer"; }
"$TMP/build/voxplore_consumer" || fail "the consumer ran with an error"

# A config file without one of its dependencies must not pass.
grep -q 'find_dependency(octomap)' "$config" || fail "$config has no find_dependency(octomap)"
sed -i '/find_dependency(octomap)/d' "$config"
if configure build-broken > "$TMP/broken.log" 2>&1; then
  cat "$TMP/broken.log"
  fail "the consumer configured although voxploreConfig.cmake lost find_dependency(octomap)"
fi
grep -q "octomap" "$TMP/broken.log" || { cat "$TMP/broken.log"; fail "the error does not name octomap"; }
echo "consumer: without find_dependency(octomap) the configure fails as it must:"
grep -m 2 "octomap" "$TMP/broken.log"
echo "consumer: OK"
