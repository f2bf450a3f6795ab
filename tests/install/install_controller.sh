#!/usr/bin/env bash
# The controller as a program that drives another arm sees it (docs/cpp-api.md): installs the
# build tree into a fresh prefix, builds examples/cpp_controller against the package's
# `controller` component with MuJoCo and GLFW made unusable (their headers shadowed by ones that
# fail to compile, their CMake packages disabled), checks that nothing of the simulator is on the
# link line or in the program, and runs it: the module on a fake arm through Rest, Hitting,
# Braking.
#   install_controller.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build=$1 source=$2 work=$3
fail() { echo "install_controller: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >"$work/install.log" || fail "cmake --install failed"
[[ -e $prefix/lib/cmake/minigolf/minigolfControllerTargets.cmake ]] ||
  fail "not installed: lib/cmake/minigolf/minigolfControllerTargets.cmake"

# Any include of MuJoCo or GLFW by a controller header stops the compilation here.
poison=$work/poison
mkdir -p "$poison/mujoco" "$poison/GLFW"
echo '#error "the controller includes MuJoCo"' >"$poison/mujoco/mujoco.h"
echo '#error "the controller includes GLFW"' >"$poison/GLFW/glfw3.h"

launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=$work CCACHE_NOHASHDIR=1
fi
cmake -S "$source/examples/cpp_controller" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_FLAGS="-I$poison" \
  -DCMAKE_DISABLE_FIND_PACKAGE_glfw3=ON -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_mujoco=ON "${launcher[@]}" >"$work/configure.log" 2>&1 ||
  { cat "$work/configure.log" >&2; fail "the example does not configure against the controller"; }
cmake --build "$work/build" -j 2 >"$work/build.log" 2>&1 ||
  { tail -40 "$work/build.log" >&2; fail "the example does not build against the controller"; }

# The link line names only the controller's libraries and their dependencies.
link=$work/build/CMakeFiles/module_ticks.dir/link.txt
[[ -e $link ]] || fail "no link command at $link"
if grep -Eio 'mujoco|glfw|libmg_(sim|sim_backend|system|plant|belief|learning|viz)\.a' "$link"; then
  fail "the controller's link line holds the simulator: $(cat "$link")"
fi
if nm -C "$work/build/module_ticks" | grep -E ' (mj_|mjv_|mjr_|glfw)' | head -3 | grep .; then
  fail "the program references MuJoCo or GLFW symbols"
fi

export MINIGOLF_DATA_DIR=$prefix/share/minigolf/data
out=$("$work/build/module_ticks") || { echo "$out"; fail "module_ticks failed"; }
echo "$out"
for state in "Idle -> Rest" "Rest -> Hitting" "Hitting -> Braking"; do
  grep -q -- "$state" <<<"$out" || fail "module_ticks: no '$state'"
done

# Bad input: one line on standard error, exit 2.
set +e
err=$("$work/build/module_ticks" /nonexistent-model.json 2>&1 >/dev/null)
code=$?
set -e
[[ $code == 2 ]] || fail "module_ticks /nonexistent-model.json: expected exit 2, got $code"
[[ $(wc -l <<<"$err") == 1 && $err == "module_ticks: error: "* ]] || fail "bad input: '$err'"
echo "install_controller: ok"
