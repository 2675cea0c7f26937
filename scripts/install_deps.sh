#!/usr/bin/env bash
# Installs voxplore's build and test dependencies from Debian 12 packages
# (nothing is downloaded from elsewhere). Skips apt entirely when everything
# is already installed. Needs root (or passwordless sudo) for apt-get.
set -euo pipefail

PACKAGES=(
  cmake g++ make pkg-config ccache
  libeigen3-dev
  # MRPT 2.5.8, one -dev package per component we link
  libmrpt-maps-dev libmrpt-slam-dev libmrpt-nav-dev libmrpt-obs-dev libmrpt-poses-dev
  libmrpt-config-dev libmrpt-io-dev libmrpt-serialization-dev libmrpt-system-dev
  libmrpt-math-dev libmrpt-tfest-dev libmrpt-kinematics-dev libmrpt-img-dev
  libmrpt-random-dev libmrpt-tclap-dev
  # loop closure: CNetworkOfPoses (graphs) and the header-only SPA optimiser
  # optimize_graph_spa_levmarq (graphslam; only its headers are used)
  libmrpt-graphs-dev libmrpt-graphslam-dev
  # rawlog-edit, RawLogViewer: the tests check our rawlogs with rawlog-edit --info
  mrpt-apps
  # MRPT's example datasets (2D laser rawlogs, one Kinect frame): bad-input tests
  mrpt-common
  # OctoMap library and tools (bt2vrml)
  liboctomap-dev octomap-tools
  # ray casting, mesh loading, JSON
  libembree-dev libassimp-dev nlohmann-json3-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # CI stage 3 (scripts/fuzz.sh): clang with libFuzzer (libclang_rt.fuzzer in
  # libclang-rt-14-dev) and llvm-symbolizer (llvm-14) for readable stack traces.
  # Stage 2 (scripts/sanitize.sh) uses g++'s libasan/libubsan.
  clang-14 libclang-rt-14-dev llvm-14
  # campaigns (scripts/campaign.sh): GNU parallel runs the grid, gnuplot draws
  # the report's plots (no X: gnuplot-nox), python3 aggregates the CSVs,
  # /usr/bin/time measures each run's CPU time and peak memory
  parallel gnuplot-nox python3 time
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
