#!/usr/bin/env bash
# Issue 13: a build copied to another folder, and `cmake --install`, find their data.
# usage: moved_build.sh MINIGOLF_BINARY SOURCE_DATA_DIR BUILD_DIR
set -euo pipefail
binary="$1" data="$2" build="$3"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# 1. Copied: bin/minigolf + share/minigolf/data, with one field only the copy has.
mkdir -p "$tmp/copy/bin" "$tmp/copy/share/minigolf"
cp "$binary" "$tmp/copy/bin/minigolf"
cp -r "$data" "$tmp/copy/share/minigolf/data"
cp "$data/fields/flat.yaml" "$tmp/copy/share/minigolf/data/fields/only-in-the-copy.yaml"
(cd / && "$tmp/copy/bin/minigolf" field list) | grep -q only-in-the-copy ||
  { echo "FAIL: the copied build does not use the data beside it"; exit 1; }
(cd / && "$tmp/copy/bin/minigolf" putt --ball-only --field only-in-the-copy --angle 0 --speed 1 --json) >/dev/null ||
  { echo "FAIL: putt on the copied build"; exit 1; }
# MINIGOLF_DATA_DIR still wins.
(cd / && MINIGOLF_DATA_DIR="$data" "$tmp/copy/bin/minigolf" field list) | grep -q only-in-the-copy &&
  { echo "FAIL: MINIGOLF_DATA_DIR ignored"; exit 1; }

# 2. Installed: cmake --install gives a working tree.
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
test -x "$tmp/prefix/bin/minigolf" && test -f "$tmp/prefix/share/minigolf/data/models/hitting-default.json" ||
  { echo "FAIL: install tree incomplete"; exit 1; }
rm -f "$tmp/prefix/share/minigolf/data/fields/arctan.yaml"  # proves the installed data is the one read
(cd / && "$tmp/prefix/bin/minigolf" field list) | grep -q arctan &&
  { echo "FAIL: the installed build reads the source tree's data"; exit 1; }
(cd / && "$tmp/prefix/bin/minigolf" putt --angle 0 --speed 1 --json) >/dev/null ||
  { echo "FAIL: full-system putt on the installed build"; exit 1; }
# The installed video plugin is the one the installed minigolf loads (not the build tree's).
plugin="$(ls "$tmp"/prefix/lib*/minigolf/libminigolf_video.so 2>/dev/null | head -1)"
[[ -n $plugin ]] || { echo "FAIL: the video plugin is not installed"; exit 1; }
loaded="$(cd / && LD_DEBUG=files "$tmp/prefix/bin/minigolf" vision-cam --fast \
  --video /no/such/a.avi,/no/such/b.avi 2>&1 || true)"
grep -q "no such file" <<<"$loaded" && grep -q "file=$plugin" <<<"$loaded" ||
  { echo "FAIL: the installed minigolf does not load the installed video plugin"; exit 1; }
echo "moved build: copied and installed trees find their data and plugin: 3 passed, 0 failed"
