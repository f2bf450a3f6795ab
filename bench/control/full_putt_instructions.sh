#!/usr/bin/env bash
# Instructions per full-system putt (and per ball-only putt) on each shipped field, counted with
# callgrind, inside full_system_putt / simulate_putt only: (N=3 putts - N=1 putt) / 2, so the
# first putt's cache fill is not counted. Prints a Markdown table [M instructions per putt].
set -euo pipefail
cd "$(dirname "$0")/../.."
loop=./build/bench/control/full_putt_loop
count() {
  local fn='mg::control::full_system_putt*'
  [ "$2" = ball ] && fn='mg::sim::simulate_putt*'
  valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect="$fn" "$loop" "$1" "$2" "$3" 2>&1 |
  sed -n 's/.*I *refs: *//p' | tr -d ','; }
modes=(before exact repeat kinematic at-rest ball)
echo "| field | before | exact | repeat | kinematic | at-rest | ball-only |"
echo "|---|---|---|---|---|---|---|"
for field in flat multiple-hills regular-hill arctan; do
  row="| $field |"
  for mode in "${modes[@]}"; do
    one=$(count "$field" "$mode" 1); three=$(count "$field" "$mode" 3)
    row="$row $(awk -v a="$one" -v b="$three" 'BEGIN { printf "%.1f", (b-a)/2e6 }') |"
  done
  echo "$row"
done
