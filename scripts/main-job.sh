#!/usr/bin/env bash
# The main job (for now): demonstration putts on each shipped field (ball only), putts hit by
# the simulated arm, a scripted console session with a recording, the launch-accuracy study;
# outcomes printed, trajectories drawn in out/demo/fields.png, the study in out/demo/study/.
# The launch parameters below are example inputs; what happens is simulated when this runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=./build/src/cli/minigolf
out=out/demo
mkdir -p "$out"

echo "== shipped fields"
$bin field list

# field  angle[rad]  speed[m/s]
putts=(
  "flat 0.00 2.5"
  "flat 0.01 2.6"
  "multiple-hills -0.03 2.8"
  "multiple-hills 0.00 2.9"
  "regular-hill 0.00 2.8"
  "regular-hill 0.01 2.6"
  "arctan 0.00 2.7"
  "arctan 0.01 2.8"
)
echo "== demo putts (ball only)"
i=0
for p in "${putts[@]}"; do
  read -r field angle speed <<<"$p"
  $bin putt --ball-only --field "$field" --angle "$angle" --speed "$speed" \
    --trajectory "$out/putt_${i}_${field}.csv" --json >"$out/putt_${i}_${field}.json"
  $bin putt --ball-only --field "$field" --angle "$angle" --speed "$speed"
  i=$((i + 1))
done
echo "== the arm hits (full system, fast lockstep mode)"
$bin putt --field flat --angle 0.01 --speed 1.6
$bin putt --field flat --hole 1.2,0.3 --angle 0.25 --speed 1.25
$bin putt --field flat --angle 0.01 --speed 1.6 --json >"$out/arm_putt_flat.json"
$bin putt --field multiple-hills --angle 0.01 --speed 1.8
$bin putt --field regular-hill --angle 0.01 --speed 1.65
$bin putt --field arctan --angle 0.03 --speed 1.65
echo "== a scripted console session (lockstep), recorded to $out/console_recording.csv"
$bin console --echo <<EOF
record on $out/console_recording.csv
angle 0.25
speed 1.25
hole 1.2 0.3
hit
wait 3
reset
angle 0.01
speed 1.6
hole 2.0 0.0
hit
wait 4
status
record off
quit
EOF
echo "== launch accuracy (thesis 6.1): 10 hits at -10, 0, +10 deg with execution noise"
$bin study launch-error --torque-noise 0.001 --out "$out/study" --plot
for field in flat multiple-hills regular-hill arctan; do
  $bin field heights "$field" -o "$out/heights_${field}.csv" --cell 0.02
  $bin field show "$field" --json >"$out/field_${field}.json"
done
/usr/bin/python3 scripts/plot_demo.py "$out"
echo "== figure: $out/fields.png"
