#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Run the paper's three scenes (namelists/crush.nml, impact.nml, wave.nml) with the release build
# and write their figures to docs/figures/ (PNG) and their key numbers to docs/figures/scenes.txt.
# Two runs at once with one thread each (the machine has two cores).
#   usage: tools/run_scenes.sh [scene ...]      (default: crush impact wave)
set -eu
cd "$(dirname "$0")/.."
py=${PYTHON:-python3}
scenes=${*:-crush impact wave}
mkdir -p docs/figures
run() {
  local c=$1
  OMP_NUM_THREADS=1 bin/tubempm --quiet "namelists/$c.nml" > "build/scene_$c.log" 2>&1 \
    || { echo "scene $c failed:"; tail -5 "build/scene_$c.log"; return 1; }
}
mkdir -p build
pids=()
for c in $scenes; do
  run "$c" & pids+=($!)
  while [ "$(jobs -rp | wc -l)" -ge 2 ]; do sleep 2; done
done
fail=0
for p in "${pids[@]}"; do wait "$p" || fail=1; done
: > docs/figures/scenes.txt
for c in $scenes; do
  [ -f "out/$c/summary.nml" ] || continue
  { echo "== $c"; grep -E "status|steps|particles|wall_seconds|runtime_ratio|updates_per_second|energy_error" "out/$c/summary.nml"
    $py plots/plot_case.py --case "namelists/$c.nml" --out "docs/figures/$c.png"
    $py plots/plot_shapes.py --case "namelists/$c.nml" --out "docs/figures/${c}_shapes.png"
  } >> docs/figures/scenes.txt 2>&1
done
cat docs/figures/scenes.txt
exit $fail
