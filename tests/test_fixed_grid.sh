#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# A fixed grid (&grid lower, upper) that validation accepts must not be rejected by the solver
# at step 1 (issue 15). Before the fix validation only asked the bounds to contain the bodies,
# while step 1 needs every particle's node block (its domain plus a cell, nb x nb nodes) inside:
# a ring in a grid equal to its bounding box passed --check and stopped at step 1 ("left the
# grid ... unstable", exit 4). Oracles: for each basis and grids around a ring at rest whose
# upper bounds lie 0 to 2 cells beyond the ring, either --check refuses the grid (exit 2) or a
# run of a few steps completes (exit 0), never exit 4; the bounds the refusal asks for are
# accepted and run; the refusal names &grid, lower, upper and the bounds needed.
#   usage: TUBEMPM=build/debug/tubempm bash tests/test_fixed_grid.sh SCRATCH
set -u
bin=${TUBEMPM:-bin/tubempm}
scratch=${1:-$(mktemp -d)}
mkdir -p "$scratch"
pass=0; fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL [fixed_grid]: $*"; }
export OMP_NUM_THREADS=1

case_file() {  # NAME BASIS LOWER UPPER: an elastic ring at rest, a few steps
  cat > "$scratch/$1.nml" <<NML
&run title = '$1', output_dir = '$scratch/$1', t_end = 1.0e-7 /
&solver basis = '$2' /
&grid h = 1.0e-3, lower = $3, upper = $4 /
&material name = 'alu', model = 'elastic', E = 70.0e9, nu = 0.33, rho = 2700.0 /
&body center = 0.0, 0.0265, r_inner = 0.024, r_outer = 0.026, n_thick = 4 /
NML
}

refused=0; ran=0
for basis in linear ugimp cpdi1 cpdi2; do
  for d in 0.0 0.00025 0.0005 0.001 0.0015 0.002; do
    lo=$(awk -v d="$d" 'BEGIN { printf "%.6g, %.6g\n", -0.026 - d, 0.0005 - d }')
    up=$(awk -v d="$d" 'BEGIN { printf "%.6g, %.6g\n", 0.026 + d, 0.0525 + d }')
    name="g_${basis}_$d"
    case_file "$name" "$basis" "$lo" "$up"
    "$bin" --check "$scratch/$name.nml" > "$scratch/$name.check" 2>&1
    rc=$?
    if [ $rc -eq 2 ]; then
      refused=$((refused + 1))
      grep -qE "&grid: (lower|upper) = .*allowed: (lower <= [^,]*, [^ ]*|upper >= )" "$scratch/$name.check" \
        && ok || bad "$name: refused without the bounds needed: $(grep ERROR "$scratch/$name.check" | head -2)"
      continue
    fi
    [ $rc -eq 0 ] && ok || bad "$name: --check exit $rc"
    "$bin" --quiet "$scratch/$name.nml" > "$scratch/$name.run" 2>&1
    rc=$?
    ran=$((ran + 1))
    [ $rc -eq 0 ] && ok || bad "$name: --check accepted the grid, the run exited $rc: $(grep ERROR "$scratch/$name.run" | head -1)"
  done
done
echo "grids refused by --check: $refused, accepted and run: $ran"
[ $refused -gt 0 ] && ok || bad "no grid refused: the test no longer reaches the grid edge"
[ $ran -gt 0 ] && ok || bad "no grid accepted"

# the bounds the refusal asks for are accepted, and the run completes; it names only the bound
# that falls short (the ring's box holds the lower support of cpdi2 here, not the upper; it
# named both before)
case_file box cpdi2 "-0.026, 0.0005" "0.026, 0.0525"
"$bin" --check "$scratch/box.nml" > /dev/null 2> "$scratch/box.err"
rc=$?
[ $rc -eq 2 ] && ok || bad "grid = the ring's box: --check exit $rc, expected 2"
grep -q "&grid: upper = .*allowed: upper >= " "$scratch/box.err" && ! grep -q "lower" <(sed 's/or lower and upper not given//' "$scratch/box.err") \
  && ok || bad "the refusal names a bound that holds: $(cat "$scratch/box.err")"
lo=$(sed -n 's/.*allowed: lower <= \([^,]*, [^ ]*\)\( and\|,\) .*/\1/p' "$scratch/box.err")
up=$(sed -n 's/.*upper >= \(.*\), plus room.*/\1/p' "$scratch/box.err")
[ -n "$lo" ] || lo="-0.026, 0.0005"
if [ -n "$lo" ] && [ -n "$up" ]; then
  case_file asked cpdi2 "$lo" "$up"
  "$bin" --check "$scratch/asked.nml" > /dev/null 2>&1 && ok || bad "the bounds asked for ($lo; $up) are refused"
  "$bin" --quiet "$scratch/asked.nml" > /dev/null 2> "$scratch/asked.err" && ok \
    || bad "the bounds asked for ($lo; $up): the run failed: $(head -2 "$scratch/asked.err")"
else
  bad "no bounds in the refusal: $(cat "$scratch/box.err")"
fi
echo "fixed_grid: $pass passed, $fail failed"
[ $fail -eq 0 ]
