#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Run the paper's three scenes (namelists/crush.nml, impact.nml, wave.nml) with the release build
# and write their figures to docs/figures/ (PNG) and their key numbers to docs/figures/scenes.txt.
# The scenes of several bodies in contact (namelists/contact/: two_rings, nested,
# nested_eccentric, stack, row3, plates, densify) run when named (row3 also runs its one-tube
# reference row3_single.nml, drawn three times over the row's force); their figures are
# <scene>_bodies.png (forces and energies per body), <scene>_shapes.png (coloured by body) and
# <scene>_eqps.png, their numbers go to build/scenes.txt. densify (a ring crushed to
# delta/D = 0.95 with self-contact) also runs itself without self-contact (densify_weld, one
# velocity field) for docs/figures/densify.png (force against delta/D of both,
# plots/plot_densify.py) and densify_shapes.png.
# The sections (namelists/sections/: square_tube, hex_tube, multicell_2x2, honeycomb,
# auxetic) run when named (or all with `sections`); their figures are <scene>.png (force and
# energies against the platens' approach, with the &results numbers) and <scene>_shapes.png.
# The foam scenes (namelists/foam/: foam_block, filled_ring, empty_ring, empty_ring_equal_mass,
# foam_disc, filled_drop) run when named (or the comparison's four and the drop with `foam`);
# their figures are those docs/scenes.md shows: <scene>.png (force and energies against the
# approach; not for filled_ring), <scene>_shapes.png (filled_ring, foam_disc, filled_drop: the
# start, the middle and the end), <scene>_bodies.png (filled_ring, filled_drop: per body), and,
# once the four crushes are there, filled_ring_compare.png (plots/plot_filled.py: the filled
# ring against the empty rings and the foam alone, with the interaction effect). The filled
# square tube (filled_square, filled_square_bonded, foam_square; `filled_square_all` runs the
# three and sections/square_tube.nml) draws filled_square_compare.png (the filled tube, the
# bonded one, the empty square_tube and the core alone) and <scene>_shapes.png,
# <scene>_bodies.png of the two filled tubes.
# Two runs at once with one thread each (the machine has two cores).
# A subset of the scenes writes its figures but not scenes.txt (the numbers of all three scenes):
# its numbers go to build/scenes.txt instead.
#   usage: tools/run_scenes.sh [scene ...]      (default: crush impact wave)
set -eu
usage() { echo "usage: tools/run_scenes.sh [crush] [crush_fixed] [impact] [wave] [two_rings] [nested] [nested_eccentric] [stack] [row3] [plates] [densify] [square_tube] [hex_tube] [multicell_2x2] [honeycomb] [auxetic] [sections] [foam_block] [filled_ring] [empty_ring] [empty_ring_equal_mass] [foam_disc] [filled_drop] [foam] [filled_square] [filled_square_bonded] [foam_square] [filled_square_all]"
          echo "  (default: crush impact wave) runs namelists/<scene>.nml (namelists/contact/ for the"
          echo "  scenes of several bodies; release build bin/tubempm), writes docs/figures/<scene>.png"
          echo "  and <scene>_shapes.png (several bodies: <scene>_bodies.png, _shapes.png, _eqps.png),"
          echo "  and, for the three paper scenes together, docs/figures/scenes.txt"; }
for a in "$@"; do
  case $a in
    -h|--help) usage; exit 0 ;;
    crush|crush_fixed|impact|wave|two_rings|nested|nested_eccentric|stack|row3|plates|densify) ;;
    square_tube|hex_tube|multicell_2x2|honeycomb|auxetic|sections) ;;
    foam_block|filled_ring|empty_ring|empty_ring_equal_mass|foam_disc|filled_drop|foam) ;;
    filled_square|filled_square_bonded|foam_square|filled_square_all) ;;
    *) echo "ERROR [run_scenes]: unknown scene '$a'" >&2; usage >&2; exit 2 ;;
  esac
done
cd "$(dirname "$0")/.."
py=${PYTHON:-python3}
scenes=${*:-crush impact wave}
scenes=${scenes/sections/square_tube hex_tube multicell_2x2 honeycomb auxetic}
words=; for c in $scenes; do   # the word foam (not foam_block, foam_disc): the five scenes
  [ "$c" = foam ] && c="filled_ring empty_ring empty_ring_equal_mass foam_disc filled_drop"
  [ "$c" = filled_square_all ] && c="filled_square filled_square_bonded foam_square square_tube"
  words="$words $c"; done
scenes=${words# }
numbers=docs/figures/scenes.txt
[ "$scenes" = "crush impact wave" ] || numbers=build/scenes.txt
[ -x bin/tubempm ] || { echo "ERROR [run_scenes]: bin/tubempm not found: run make first" >&2; exit 2; }
mkdir -p docs/figures
nml() { if [ -f "namelists/$1.nml" ]; then echo "namelists/$1.nml"
         elif [ -f "namelists/sections/$1.nml" ]; then echo "namelists/sections/$1.nml"
         elif [ -f "namelists/foam/$1.nml" ]; then echo "namelists/foam/$1.nml"
         elif [ "$1" = densify_weld ]; then echo build/densify_weld.nml
         else echo "namelists/contact/$1.nml"; fi; }
run() {
  local c=$1
  OMP_NUM_THREADS=1 bin/tubempm --quiet "$(nml "$c")" > "build/scene_$c.log" 2>&1 \
    || { echo "scene $c failed:"; tail -5 "build/scene_$c.log"; return 1; }
}
mkdir -p build
case " $scenes " in   # densify without self-contact, for the comparison
  *" densify "*) sed "s/title = 'densify'/title = 'densify_weld'/; s/^ *self_contact = .true.*$//" \
                   namelists/contact/densify.nml > build/densify_weld.nml
                 scenes="$scenes densify_weld" ;;
esac
runs=
for c in $scenes; do runs="$runs $c"; [ "$c" = row3 ] && runs="$runs row3_single"; done
pids=()
for c in $runs; do
  run "$c" & pids+=($!)
  while [ "$(jobs -rp | wc -l)" -ge 2 ]; do sleep 2; done
done
fail=0
for p in "${pids[@]}"; do wait "$p" || fail=1; done
: > "$numbers"
for c in $scenes; do
  [ -f "out/$c/summary.nml" ] || continue
  { echo "== $c"; grep -E "status|steps|particles|wall_seconds|runtime_ratio|updates_per_second|energy_error" "out/$c/summary.nml"
    if [ "$c" = densify ]; then
      $py -m plots.plot_case --case "$(nml "$c")" --out "build/densify_case.png"
      $py -m plots.plot_densify --case "$(nml "$c")" --compare out/densify_weld \
        "one velocity field (welds)" --out docs/figures/densify.png
      $py -m plots.plot_shapes --case "$(nml "$c")" --out "docs/figures/${c}_shapes.png"
    elif [ "$c" = densify_weld ]; then
      $py -m plots.plot_shapes --case "$(nml "$c")" --out "docs/figures/${c}_shapes.png"
    elif [ -f "namelists/foam/$c.nml" ]; then   # the figures docs/scenes.md shows
      kind=(); case $c in foam_block|foam_disc|foam_square|filled_square*) kind=(--kind crush) ;; esac
      case $c in filled_ring) ;; *)
        $py -m plots.plot_case --case "$(nml "$c")" "${kind[@]}" --out "docs/figures/$c.png" ;;
      esac
      case $c in filled_ring|foam_disc|filled_drop|filled_square|filled_square_bonded|foam_square)
        $py -m plots.plot_shapes --case "$(nml "$c")" --frames 0 6 -1 \
          --out "docs/figures/${c}_shapes.png" ;;
      esac
      case $c in filled_ring|filled_drop|filled_square|filled_square_bonded)
        $py -m plots.plot_bodies --case "$(nml "$c")" --out "docs/figures/${c}_bodies.png" ;;
      esac
    elif [ -f "namelists/$c.nml" ] || [ -f "namelists/sections/$c.nml" ]; then
      $py -m plots.plot_case --case "$(nml "$c")" --out "docs/figures/$c.png"
      $py -m plots.plot_shapes --case "$(nml "$c")" --out "docs/figures/${c}_shapes.png"
    else
      ref=(); [ "$c" = row3 ] && ref=(--reference out/row3_single --scale 3)
      $py -m plots.plot_bodies --case "$(nml "$c")" "${ref[@]}" --out "docs/figures/${c}_bodies.png"
      $py -m plots.plot_shapes --case "$(nml "$c")" --colour body --out "docs/figures/${c}_shapes.png"
      $py -m plots.plot_shapes --case "$(nml "$c")" --out "docs/figures/${c}_eqps.png"
    fi
  } >> "$numbers" 2>&1
done
if [ -f out/filled_ring/summary.nml ] && [ -f out/empty_ring/summary.nml ] && \
   [ -f out/empty_ring_equal_mass/summary.nml ] && [ -f out/foam_disc/summary.nml ]; then
  case " $scenes " in *" filled_ring "*|*" empty_ring "*|*" empty_ring_equal_mass "*|*" foam_disc "*)
    { echo "== filled ring against its parts"
      $py -m plots.plot_filled --out docs/figures/filled_ring_compare.png; } >> "$numbers" 2>&1 ;;
  esac
fi
if [ -f out/filled_square/summary.nml ] && [ -f out/filled_square_bonded/summary.nml ] && \
   [ -f out/square_tube/summary.nml ] && [ -f out/foam_square/summary.nml ]; then
  case " $scenes " in *" filled_square "*|*" filled_square_bonded "*|*" foam_square "*|*" square_tube "*)
    { echo "== filled square tube against its parts"
      $py -m plots.plot_filled --tube "square tube" --filled out/filled_square \
        --filled2 out/filled_square_bonded --label2 "bonded core" --empty out/square_tube \
        --equal-mass none --foam out/foam_square --at 5 10 15 20 24 \
        --out docs/figures/filled_square_compare.png; } >> "$numbers" 2>&1 ;;
  esac
fi
cat "$numbers"
exit $fail
