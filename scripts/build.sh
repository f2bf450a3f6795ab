#!/usr/bin/env bash
# Configures and builds the project into ./build (Release). Extra args go to CMake configure.
set -euo pipefail
cd "$(dirname "$0")/.."
# ccache (if installed) makes a rebuild cheap, also in a fresh clone (as scripts/sanitize.sh).
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1  # a fresh clone elsewhere hits the same cache
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "$@" >/dev/null
cmake --build build -j "$(nproc)"
