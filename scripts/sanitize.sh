#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/), and the
# session and console tests under ThreadSanitizer (build-tsan/): the real-time session's core
# thread, I/O thread and user thread with their lock-free channels (a console flood and a viewer
# included), the lockstep session, the console's signals, the core loop. Too slow for every CI run
# on 2 cores; docs/robustness.md has the measured times. Any report fails the run.
#
# `ci` is the part CI runs on every landing (.ci/run, about 15 minutes on 2 cores with a warm
# ccache): the parsers, files, learners and the console session (their unit and CLI tests) and
# every fuzz-corpus replay, under ASan + UBSan, in build-asan-ci/.
#
# usage: scripts/sanitize.sh [asan|tsan|all|ci]  (default all)
set -euo pipefail
cd "$(dirname "$0")/.."
what="${1:-all}"
jobs="${JOBS:-2}"
# ccache (if installed) makes a rerun after a fix cheap.
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1  # a fresh clone elsewhere hits the same cache
fi
asan_flags=(-DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
            -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined")

if [[ $what == ci ]]; then
  start=$(date +%s)
  # -O1 -g: the sanitizers' usual build, faster to compile than RelWithDebInfo's -O2.
  cmake -S . -B build-asan-ci -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" \
    -DMINIGOLF_BUILD_BENCHMARKS=OFF "${launcher[@]}" "${asan_flags[@]}" >/dev/null
  targets=(minigolf test_core test_field test_plant test_learning test_perception test_system test_game test_cli)
  for h in fuzz/*.cpp; do
    case $(basename "$h" .cpp) in replay_main|scratch) ;; *) targets+=("fuzz_$(basename "$h" .cpp)") ;; esac
  done
  nice -n 10 cmake --build build-asan-ci -j"$jobs" --target "${targets[@]}"
  built=$(date +%s)
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
  export LSAN_OPTIONS="suppressions=$PWD/scripts/sanitize.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  suites='Csv|Io|IoSignals|Surface|Field|Situations|Plant|LearningDataset|LearningModel|LearningCli'
  suites+='|VisionMessage|Udp|VisionFeed|NetworkPerception|Session|Robustness|ConsoleCommand|FieldCommand|PlantCommands|Course'
  (cd build-asan-ci && nice -n 10 ctest -j"$jobs" --output-on-failure --timeout 1200 -R "^(($suites)\.|fuzz_)" \
     -E '_NOT_BUILT$')
  echo "sanitize.sh: ci (ASan + UBSan, parsers, session, fuzz replays): build $((built - start)) s," \
       "tests $(( $(date +%s) - built )) s"
  exit 0
fi

if [[ $what == asan || $what == all ]]; then
  start=$(date +%s)
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMINIGOLF_BUILD_BENCHMARKS=OFF "${launcher[@]}" \
    "${asan_flags[@]}" >/dev/null
  nice -n 10 cmake --build build-asan -j"$jobs"
  built=$(date +%s)
  # MuJoCo's and Python's own allocations are not ours: leaks are checked in our tests only
  # through the suppressions file. The Python tests are left out (the interpreter is not
  # instrumented). The viewer/renderer tests run without leak checking: Mesa's GL driver, loaded
  # and unloaded by libGL, leaves 240 bytes per process that no suppression can name (its frames
  # are "<unknown module>" once it is unloaded); they still run under ASan and UBSan.
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
  export LSAN_OPTIONS="suppressions=$PWD/scripts/sanitize.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  (cd build-asan && nice -n 10 ctest -j"$jobs" --output-on-failure --timeout 3000 -E '^(python_|viz_under_xvfb$)')
  (cd build-asan && ASAN_OPTIONS="detect_leaks=0:abort_on_error=1" nice -n 10 ctest --output-on-failure --timeout 3000 \
     -R '^viz_under_xvfb$')
  echo "sanitize.sh: ASan + UBSan: build $((built - start)) s, tests $(( $(date +%s) - built )) s"
fi

if [[ $what == tsan || $what == all ]]; then
  start=$(date +%s)
  cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMINIGOLF_BUILD_BENCHMARKS=OFF "${launcher[@]}" \
    -DCMAKE_CXX_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" >/dev/null
  nice -n 10 cmake --build build-tsan -j"$jobs" --target test_system test_system_realtime test_cli test_control test_core minigolf
  built=$(date +%s)
  tsan_suites='Session|SessionCore|System|Realtime|ConsoleSignalRealtime|Signals/ConsoleSignal|ConsoleCommand|CoreLoop|TimingHistogram|SpscQueue|TripleBuffer'
  (cd build-tsan && TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1" \
     nice -n 10 ctest -j1 --output-on-failure --timeout 3000 -R "^($tsan_suites)\.")
  echo "sanitize.sh: TSan (session and console): build $((built - start)) s, tests $(( $(date +%s) - built )) s"
fi
