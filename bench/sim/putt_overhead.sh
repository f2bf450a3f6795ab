#!/usr/bin/env bash
# Instructions of one putt vs the same number of bare mj_step calls, per shipped field, counted
# with callgrind (repeatable whatever else the machine does). Prints a Markdown table.
set -euo pipefail
cd "$(dirname "$0")/../.."
loop=./build/bench/sim/putt_loop
count() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$loop" "$1" "$2" 2>&1 |
  sed -n 's/.*I *refs: *//p' | tr -d ','; }
echo "| field | putt [M instr.] | bare steps [M instr.] | overhead |"
echo "|---|---|---|---|"
for field in flat multiple-hills regular-hill arctan; do
  none=$(count "$field" none); putt=$(count "$field" putt); bare=$(count "$field" bare)
  awk -v f="$field" -v n="$none" -v p="$putt" -v b="$bare" 'BEGIN {
    printf "| %s | %.1f | %.1f | %+.1f %% |\n", f, (p-n)/1e6, (b-n)/1e6, 100*((p-n)/(b-n)-1) }'
done
