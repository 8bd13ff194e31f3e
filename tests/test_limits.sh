#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Cases too big for the machine and values in the wrong unit (issue 15). Before the fix
# `r_outer = 26` (millimetres typed into a metre field) on the crush made --check die allocating
# 33 GB (exit 1, a backtrace) and `h = 1.0e-6` made it grow memory until killed. Now the memory
# is estimated before anything is allocated and the case refused (exit 2) with both numbers and
# what to change. Oracles: exit 2 within 20 s under a 3 GB address-space limit (the old code
# could only die), the project's lines only, the numbers and variables named; the limit given
# by TUBEMPM_MEMORY_LIMIT; the wall-time estimate of --check equal to work / throughput as
# printed, and the warning of a run longer than an hour; values in a likely wrong unit refused
# at their line (r_outer = 26, rho = 7.8), warned of with &run check_units = .false.
#   usage: TUBEMPM=build/debug/tubempm bash tests/test_limits.sh SCRATCH
set -u
bin=${TUBEMPM:-bin/tubempm}
scratch=${1:-$(mktemp -d)}
mkdir -p "$scratch"
here=$(cd "$(dirname "$0")" && pwd)
crush="$here/../namelists/crush.nml"
pass=0; fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL [limits]: $*"; }
export OMP_NUM_THREADS=1

only_ours() {  # ERRFILE: nothing but ERROR/WARNING lines
  local foreign
  foreign=$(grep -v -E '^(ERROR|WARNING) \[' "$1" | grep -v -E '^\s*$' | head -3)
  [ -z "$foreign" ] && ok || bad "$1: more than the project's lines: $foreign"
}

# the address space limit that makes the old behaviour fail at once; not for the sanitizer
# build, whose shadow memory alone needs terabytes of address space
limited() {
  if grep -qa __asan_init "$bin"; then "$@"; else ( ulimit -v 3000000; "$@" ); fi
}

# refused: NAME SED-EXPRESSION PATTERN...: --check exits 2 quickly, under a 3 GB limit
refused() {
  local name=$1 expr=$2; shift 2
  sed -e "$expr" "$crush" > "$scratch/$name.nml"
  limited timeout 20 "$bin" --check "$scratch/$name.nml" \
    > "$scratch/$name.out" 2> "$scratch/$name.err"
  local rc=$?
  [ $rc -eq 2 ] && ok || bad "$name: exit $rc, expected 2: $(head -c 600 "$scratch/$name.err")"
  only_ours "$scratch/$name.err"
  for pat in "$@"; do
    grep -q -- "$pat" "$scratch/$name.err" && ok || bad "$name: no '$pat' in: $(head -c 600 "$scratch/$name.err")"
  done
}
# millimetres typed as metres: refused by the reader at the variable, before the set-up
refused r_outer_26 's/^  r_outer = 25.43e-3 /  r_outer = 26 /' \
  'r_outer_26.nml:49: &body #1: r_outer = 26: over 1 m: the input is in metres' \
  'allowed: a length in metres, at most 1 m (or &run check_units = .false. when the value is meant)'
# the same with check_units = .false. (and no platen, which the 26 m ring would lie behind):
# the memory budget refuses it, with the unit as a hint
refused r_outer_26_budget 's/^  r_outer = 25.43e-3 /  r_outer = 26 /; s/^  title = \(.*\)/  title = \1\n  t_end = 3.25e-3\n  check_units = .false./; /^&wall/,/^\//d' \
  'r_outer' '&body #1: r_outer = 2.6000E+001 m is over 1 m' 'grid of'
refused h_1e-6 's/^  h = 0.37e-3 /  h = 1.0e-6 /' \
  'more than the .* available' 'a larger &grid h' 'GiB'

# the limit from the environment: 20 MiB is less than the 32 MiB base of any run
TUBEMPM_MEMORY_LIMIT=20 "$bin" --check "$crush" > /dev/null 2> "$scratch/limit.err"
rc=$?
[ $rc -eq 2 ] && ok || bad "TUBEMPM_MEMORY_LIMIT=20: exit $rc, expected 2"
grep -q 'more than the 20.0 MiB available (TUBEMPM_MEMORY_LIMIT)' "$scratch/limit.err" && ok \
  || bad "TUBEMPM_MEMORY_LIMIT=20: $(cat "$scratch/limit.err")"
TUBEMPM_MEMORY_LIMIT=4000 "$bin" --check "$crush" > "$scratch/fits.out" 2>&1 && ok \
  || bad "TUBEMPM_MEMORY_LIMIT=4000: the crush (35 MiB) refused: $(tail -3 "$scratch/fits.out")"
grep -q 'of 3.91 GiB available' "$scratch/fits.out" && ok || bad "no 'of 3.91 GiB available' in the report"

# the wall-time estimate is work / throughput; a run beyond an hour is warned of
"$bin" --check "$crush" > "$scratch/crush.out" 2> "$scratch/crush.err"
work=$(sed -n 's/^work estimate: *\([0-9.E+-]*\) particle-steps/\1/p' "$scratch/crush.out")
line=$(grep '^wall-time estimate' "$scratch/crush.out")
python3 - "$work" "$line" <<'PY' && ok || bad "wall time: '$line' is not work $work / rate"
import re, sys
work = float(sys.argv[1])
m = re.search(r'about (\d+):(\d\d):(\d\d) .* at the +([0-9.E+-]+) particle-steps/s', sys.argv[2])
secs = int(m.group(1)) * 3600 + int(m.group(2)) * 60 + int(m.group(3))
want = work / float(m.group(4))
print('wall time %d s, work / rate %.1f s' % (secs, want))
sys.exit(0 if abs(secs - want) <= 0.5 + 0.01 * want else 1)
PY
grep -q 'will take about' "$scratch/crush.err" && bad "the crush (3 min) warned as long" || ok
sed -e 's/^  title = \(.*\)/  title = \1\n  t_end = 0.2/' "$crush" > "$scratch/long.nml"
"$bin" --check "$scratch/long.nml" > /dev/null 2> "$scratch/long.err"
grep -q '^WARNING \[check\]: the run will take about [1-9][0-9]*:[0-9][0-9]:[0-9][0-9]' "$scratch/long.err" \
  && ok || bad "t_end = 0.2 (about 2 h): no long-run warning: $(cat "$scratch/long.err")"

# a density in g/cm^3: refused at its line; with check_units = .false. a warning only
sed -e 's/^  rho = 7800.0 /  rho = 7.8 /' "$crush" > "$scratch/rho.nml"
"$bin" --check "$scratch/rho.nml" > /dev/null 2> "$scratch/rho.err"
rc=$?
[ $rc -eq 2 ] && ok || bad "rho = 7.8: exit $rc, expected 2 (refused)"
grep -q "^ERROR \[input\]: .*rho.nml:39: &material #1: rho = 7.8: outside 10 .. 30000 kg/m^3" "$scratch/rho.err" \
  && ok || bad "rho = 7.8: not refused at its line: $(cat "$scratch/rho.err")"
sed -i 's/^  title = \(.*\)/  title = \1\n  check_units = .false./' "$scratch/rho.nml"
"$bin" --check "$scratch/rho.nml" > /dev/null 2> "$scratch/rho.err"
rc=$?
[ $rc -eq 0 ] && ok || bad "rho = 7.8, check_units = .false.: exit $rc, expected 0 (a warning only)"
grep -q "^WARNING \[check\]: &material #1: rho = 7.8000E+000 kg/m^3 is outside" "$scratch/rho.err" \
  && ok || bad "rho = 7.8, check_units = .false.: no warning: $(cat "$scratch/rho.err")"

echo "limits: $pass passed, $fail failed"
[ $fail -eq 0 ]
