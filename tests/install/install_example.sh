#!/usr/bin/env bash
# The installed C++ package as an outside project sees it (docs/cpp-api.md): installs the build
# tree into a fresh prefix, configures and builds examples/cpp against it with find_package,
# runs the example and checks its putt against `minigolf putt --json` (the same bits).
#   install_example.sh BUILD_DIR SOURCE_DIR WORK_DIR
# WORK_DIR is removed and made anew; its paths stay the same from run to run, so ccache (if
# installed) serves the example's compilation after the first run.
set -euo pipefail
build=$1 source=$2 work=$3
fail() { echo "install_example: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >"$work/install.log" || fail "cmake --install failed"

# What an outside project needs, and nothing pointing back into the source or build tree.
for f in lib/cmake/minigolf/minigolfConfig.cmake lib/cmake/minigolf/minigolfConfigVersion.cmake \
         lib/cmake/minigolf/minigolfTargets.cmake include/minigolf/minigolf.hpp \
         include/minigolf/system/system.hpp share/minigolf/data/fields/flat.yaml bin/minigolf; do
  [[ -e $prefix/$f ]] || fail "not installed: $f"
done
ls "$prefix"/lib/libmg_*.a >/dev/null 2>&1 || fail "no libraries in $prefix/lib"
# Only the API: headers internal to their library (no entry header reaches them) stay out.
for f in sim_backend/full_system_parts.hpp field/map_reader.hpp \
         experiments/wire.hpp ds/seds_layout.hpp; do
  [[ ! -e $prefix/include/minigolf/$f ]] || fail "an internal header was installed: $f"
done
if grep -rIl -e "$source/src" -e "$build" "$prefix/include" "$prefix/lib/cmake" >/dev/null; then
  fail "installed files name the source or build tree: $(grep -rIl -e "$source/src" -e "$build" \
    "$prefix/include" "$prefix/lib/cmake" | head -3 | tr '\n' ' ')"
fi
subsystems='core|field|plant|sim|robot|stats|learning|ds|perception|control|sim_backend|system'
subsystems+='|teacher'
subsystems+='|selfteach|experiments|game|viz'
if grep -rhE "#include \"($subsystems)/" "$prefix/include" >/dev/null; then
  fail "an installed header includes a subsystem header without the minigolf/ prefix"
fi

launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=$work CCACHE_NOHASHDIR=1
fi
cmake -S "$source/examples/cpp" -B "$work/build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" "${launcher[@]}" >"$work/configure.log" 2>&1 ||
  { cat "$work/configure.log" >&2; fail "the example does not configure against the package"; }
cmake --build "$work/build" -j 2 >"$work/build.log" 2>&1 ||
  { tail -40 "$work/build.log" >&2; fail "the example does not build against the package"; }

# The installed data, as after an install that was moved: MINIGOLF_DATA_DIR names it.
export MINIGOLF_DATA_DIR=$prefix/share/minigolf/data
out=$("$work/build/putt_once" flat 0.02 1.2) || fail "putt_once failed"
echo "$out"
ours=$(tail -1 <<<"$out" | sed 's/,"timing":{[^}]*}//')
theirs=$("$prefix/bin/minigolf" putt --field flat --angle 0.02 --speed 1.2 --json |
  sed 's/,"timing":{[^}]*}//')
[[ $ours == "$theirs" ]] || fail "the example's putt differs from minigolf putt --json:
  example: $ours
  minigolf: $theirs"

# Bad input: one line on standard error, exit 2.
set +e
err=$("$work/build/putt_once" mars 2>&1 >/dev/null)
code=$?
set -e
[[ $code == 2 ]] || fail "putt_once mars: expected exit 2, got $code"
[[ $(wc -l <<<"$err") == 1 && $err == "putt_once: error: "* ]] || fail "putt_once mars: '$err'"
echo "install_example: ok"
