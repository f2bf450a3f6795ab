#!/usr/bin/env bash
# clang-format over the C++ sources (.clang-format at the root). `scripts/format.sh` rewrites
# them in place; `scripts/format.sh --check` changes nothing and lists the files that differ
# (exit 1), as ctest's format_check does. Exit 77 (skip) when clang-format is not installed.
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
case "${1:-}" in
  --check) check=1 ;;
  "") ;;
  *) echo "format.sh: unknown argument '$1' (expected --check or nothing)" >&2; exit 2 ;;
esac
formatter=$(command -v clang-format || command -v clang-format-14 || true)
if [[ -z $formatter ]]; then
  echo "format.sh: skipped: clang-format not found (apt-get install clang-format)"
  exit 77
fi
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' 2>/dev/null || find src tests bench fuzz examples -name '*.[ch]pp')
if ((check == 0)); then
  "$formatter" -i "${files[@]}"
  echo "format.sh: formatted ${#files[@]} files"
  exit 0
fi
# One clang-format for every file (a process per file took a minute); only on a difference
# are the files checked one by one, to name them.
if "$formatter" --dry-run -Werror "${files[@]}" >/dev/null 2>&1; then
  echo "format.sh: all ${#files[@]} files follow .clang-format"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  "$formatter" --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]} > 0)); then
  echo "format.sh: ${#bad[@]} of ${#files[@]} files differ from .clang-format (run scripts/format.sh):"
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
echo "format.sh: all ${#files[@]} files follow .clang-format"
