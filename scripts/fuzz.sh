#!/usr/bin/env bash
# Coverage-guided fuzzing of every parser with libFuzzer (clang 14, ASan + UBSan): builds the
# harnesses of fuzz/ in build-fuzz/ (-DMG_FUZZ=ON) and runs each for RUNS executions (default
# 10^6), starting from fuzz/corpus/<harness>/ (new inputs go to build-fuzz/corpus/<harness>/).
# Any crash, sanitizer report, leak, non-mg exception or input slower than 10 s stops the run
# and leaves the input as build-fuzz/crash-*. See docs/robustness.md for the measured times.
#
# usage: [JOBS=2] scripts/fuzz.sh [RUNS] [HARNESS...]
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-1000000}"
shift || true
all=(field_yaml heightmap_csv heightmap_png dataset_csv learner_json hitting_json demos_csv module_config
     console_line vision_datagram plant_yaml)
harnesses=("${@:-${all[@]}}")
if [[ $# -eq 0 ]]; then harnesses=("${all[@]}"); fi

launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMG_FUZZ=ON "${launcher[@]}" \
  -DMINIGOLF_BUILD_TESTS=OFF -DMINIGOLF_BUILD_BENCHMARKS=OFF >/dev/null
targets=()
for h in "${harnesses[@]}"; do targets+=("fuzz_$h"); done
nice -n 10 cmake --build build-fuzz -j2 --target "${targets[@]}"

# One harness: RUNS executions, its log and its line of the summary.
run_one() {
  local h=$1 start execs
  mkdir -p "build-fuzz/corpus/$h"
  start=$(date +%s)
  # max_len: libFuzzer's default (the largest seed, at least 4096 bytes).
  if ! (cd build-fuzz && nice -n 10 "./fuzz/fuzz_$h" -runs="$runs" -timeout=10 -rss_limit_mb=4096 \
          -print_final_stats=1 -artifact_prefix="crash-$h-" "corpus/$h" "../fuzz/corpus/$h" 2>"fuzz-$h.log"); then
    echo "fuzz.sh: $h FAILED (see build-fuzz/fuzz-$h.log and build-fuzz/crash-$h-*)"; tail -30 "build-fuzz/fuzz-$h.log"
    return 1
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "build-fuzz/fuzz-$h.log" | grep -o '[0-9]*$' || echo "?")
  echo "fuzz.sh: $h: $execs executions, 0 crashes, 0 hangs, $(( $(date +%s) - start )) s"
}
export -f run_one
export runs
# JOBS harnesses at a time (default 2, one per core).
printf '%s\n' "${harnesses[@]}" | xargs -P "${JOBS:-2}" -I{} bash -c 'run_one "$@"' _ {}
