#!/usr/bin/env bash
# CI stage 3: builds the libFuzzer targets of fuzz/ (clang, -DVOXPLORE_FUZZ=ON:
# ASan + UBSan + libFuzzer) into build-fuzz/, only those targets and the
# libraries they link, and runs each for FUZZ_SECONDS (default 60) from its
# seed corpus fuzz/corpus/<target>/. Any crash, sanitizer report, leak, timeout
# (> 10 s per input) or out-of-memory (> 2048 MB) fails it; the input is saved
# under build-fuzz/artifacts/<target>/. New inputs found go to the scratch
# corpus build-fuzz/corpus/<target>/ (never into the checked-in seeds).
# Usable alone; scripts/test.sh runs it last unless VOXPLORE_SKIP_FUZZ=1.
#   FUZZ_SECONDS=600 FUZZ_TARGETS="rawlog" scripts/fuzz.sh
# Reproduce a crash: build-fuzz/bin/fuzz_<target> <crash-file>
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
JOBS=${JOBS:-2}
BUILD_DIR=${BUILD_DIR:-build-fuzz}
FUZZ_SECONDS=${FUZZ_SECONDS:-60}
FUZZ_TARGETS=${FUZZ_TARGETS:-world_file floor_plan rawlog}
CXX_FUZZ=${CXX_FUZZ:-$(command -v clang++-14 || command -v clang++ || true)}
[ -n "$CXX_FUZZ" ] || { echo "fuzz: clang++ not found (scripts/install_deps.sh installs clang-14)" >&2; exit 1; }

# Largest input per target (bytes): a few times the largest seed.
declare -A MAX_LEN=([world_file]=4096 [floor_plan]=8192 [rawlog]=16384)

export ASAN_OPTIONS="halt_on_error=1:print_stacktrace=1:detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
if [ -z "${ASAN_SYMBOLIZER_PATH:-}" ] && [ -x /usr/lib/llvm-14/bin/llvm-symbolizer ]; then
  export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer
fi
export LSAN_OPTIONS="suppressions=$ROOT/scripts/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"

start=$(date +%s)
cmake -S . -B "$BUILD_DIR" -DCMAKE_CXX_COMPILER="$CXX_FUZZ" -DCMAKE_BUILD_TYPE= -DVOXPLORE_FUZZ=ON \
  -DVOXPLORE_BUILD_TESTS=OFF -DVOXPLORE_BENCHMARKS=OFF "$@"
targets=()
for t in $FUZZ_TARGETS; do targets+=("fuzz_$t"); done
cmake --build "$BUILD_DIR" -j"$JOBS" --target "${targets[@]}"
built=$(date +%s)
echo "fuzz: build took $((built - start)) s"

summary=()
for t in $FUZZ_TARGETS; do
  corpus="$BUILD_DIR/corpus/$t"
  artifacts="$BUILD_DIR/artifacts/$t"
  log="$BUILD_DIR/fuzz_$t.log"
  mkdir -p "$corpus" "$artifacts"
  echo "fuzz: fuzz_$t for ${FUZZ_SECONDS} s (log: $log)"
  if ! "$BUILD_DIR/bin/fuzz_$t" -max_total_time="$FUZZ_SECONDS" -rss_limit_mb=2048 -timeout=10 \
      -max_len="${MAX_LEN[$t]}" -print_final_stats=1 -artifact_prefix="$artifacts/" \
      "$corpus" "fuzz/corpus/$t" >"$log" 2>&1; then
    tail -n 60 "$log" >&2
    echo "fuzz: fuzz_$t FAILED; input saved in $artifacts/ (reproduce: $BUILD_DIR/bin/fuzz_$t <file>)" >&2
    exit 1
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  summary+=("fuzz_$t: ${execs:-?} executions in ${FUZZ_SECONDS} s, corpus $(ls "$corpus" | wc -l) + $(ls "fuzz/corpus/$t" | wc -l) seeds")
done
printf 'fuzz: %s\n' "${summary[@]}"
echo "fuzz: whole stage $(($(date +%s) - start)) s"
