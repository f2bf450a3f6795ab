#!/usr/bin/env bash
# Regenerates the shipped data sets (data/datasets/) with the teacher on the full system:
# <field>.csv at the collection points of the field's `situations` region, and for regions of
# fewer than 24 points <field>-validation.csv at 10 random situations (seed 7). Deterministic:
# the same build gives the same bits for any --threads. Usage: scripts/make-datasets.sh [field...]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=./build/src/cli/minigolf
out=data/datasets
mkdir -p "$out"
fields=("$@")
((${#fields[@]})) || fields=(flat multiple-hills regular-hill arctan)
for f in "${fields[@]}"; do
  $bin collect --field "$f" -o "$out/$f.csv"
  if [[ $f != arctan ]]; then
    $bin collect --field "$f" --random 10 --seed 7 -o "$out/$f-validation.csv"
  fi
done
