#!/usr/bin/env bash
# Installs every build and run dependency from Debian 12's archive. Idempotent; needs root
# (or sudo). Skips apt entirely when everything is already present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libmujoco-dev libeigen3-dev libnlopt-cxx-dev libnlopt-dev libyaml-cpp-dev nlohmann-json3-dev
  libcli11-dev libfmt-dev libspdlog-dev libpng-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  python3 python3-numpy python3-sklearn python3-matplotlib python3-pytest
  valgrind  # bench/sim/putt_overhead.sh counts instructions with callgrind
  libglfw3-dev xvfb xauth ffmpeg  # src/viz: view, render (GLFW windows; xvfb-run without a screen; MP4)
  pybind11-dev python3-dev  # the minigolf Python module (docs/python.md)
  libopenmpi-dev openmpi-bin  # MPI scale-out (docs/scale-out.md)
  clang-14 libfuzzer-14-dev  # scripts/fuzz.sh (libFuzzer harnesses, fuzz/)
  ccache  # build.sh, the wheel and the sanitizer build of CI recompile only what changed
  clang-format  # scripts/format.sh (ctest format_check)
  libopencv-dev  # src/vision: calibration, detection, triangulation (core imgproc calib3d); videoio: the --video plugin
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
