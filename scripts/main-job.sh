#!/usr/bin/env bash
# The main job: `minigolf reproduce --quick` — the thesis's chapter 6 on the simulated WAM (data
# sets, GPR/GMR/joint GMR, validation MSE, the robot playing random test situations with the
# oracle ceiling, learning curves, figures; beyond the thesis: the robot teaching itself, baselines,
# noise) into out/reproduce/report.md. Then one putt by the arm.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=./build/src/cli/minigolf
out=out/reproduce
$bin reproduce --quick -o "$out" "$@"
echo "== the robot playing (from $out/report.md)"
sed -n '/^## The robot plays/,/^!\[success\]/p' "$out/report.md"
echo "== the robot teaching itself, beside the baselines (from $out/report.md)"
sed -n '/^## Beyond the thesis/,/^### Hindsight/p' "$out/report.md"
echo "== a round of minigolf on every shipped course (from $out/report.md)"
sed -n '/^## Beyond the thesis: a round of minigolf/,/^Mean strokes per hole/p' "$out/report.md"
echo "== one putt by the arm on each field's shipped hole"
$bin putt --field flat --angle 0.01 --speed 1.6
$bin putt --field arctan --angle 0.03 --speed 1.65
