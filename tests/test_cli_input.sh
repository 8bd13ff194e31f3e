#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Bad input through the command line: for every tests/bad_inputs/*.nml, `$TUBEMPM --check FILE`
# must exit with status 2 and print on standard error lines starting with "ERROR [" that
# contain each text given in the file's "! expect: <text>" lines. Also a missing file (status 3,
# an I/O error) and an empty file (status 2).
#   usage: TUBEMPM=build/debug/tubempm bash tests/test_cli_input.sh [SCRATCH_DIR]
set -u
here=$(cd "$(dirname "$0")" && pwd)
bin=${TUBEMPM:-build/debug/tubempm}
if [ $# -ge 1 ]; then
  scratch=$1
  mkdir -p "$scratch"
else
  scratch=$(mktemp -d "${TMPDIR:-/tmp}/test_cli_input.XXXXXX")
  trap 'rm -rf "$scratch"' EXIT
fi
pass=0
fail=0

failed() {  # case, reason
  fail=$((fail + 1))
  echo "FAIL [$1]: $2"
}

# check_case FILE EXPECTED_STATUS TEXT...: run --check, compare the status, look for each TEXT
# in the ERROR lines of standard error.
check_case() {
  local file=$1 want=$2 rc err
  shift 2
  err="$scratch/$(basename "$file").stderr"
  "$bin" --check "$file" > /dev/null 2> "$err"
  rc=$?
  if [ "$rc" -ne "$want" ]; then
    failed "$(basename "$file")" "exit status $rc, expected $want; stderr was:"
    sed 's/^/    /' "$err" | head -n 8
    return
  fi
  pass=$((pass + 1))
  local text
  for text in "$@"; do
    if grep -E '^ERROR \[' "$err" | grep -qF -- "$text"; then
      pass=$((pass + 1))
    else
      failed "$(basename "$file")" "no line 'ERROR [...' contains: $text; stderr was:"
      sed 's/^/    /' "$err" | head -n 8
    fi
  done
}

if [ ! -x "$bin" ]; then
  failed setup "no executable at TUBEMPM=$bin (build it, or set TUBEMPM)"
  echo "test_cli_input: $pass passed, $fail failed"
  exit 1
fi

n_files=0
for f in "$here"/bad_inputs/*.nml; do
  [ -f "$f" ] || continue
  n_files=$((n_files + 1))
  expects=()
  while IFS= read -r line; do
    expects+=("$line")
  done < <(sed -n 's/^! expect: //p' "$f")
  if [ ${#expects[@]} -eq 0 ]; then
    failed "$(basename "$f")" "no '! expect: <text>' line in the file"
    continue
  fi
  check_case "$f" 2 "${expects[@]}"
done
if [ "$n_files" -lt 25 ]; then
  failed count "only $n_files files in tests/bad_inputs (25 or more expected)"
fi

# a file that does not exist: I/O error (status 3), the message names the file
check_case "$scratch/does_not_exist.nml" 3 "does_not_exist.nml: cannot open the input file"
# an empty file: bad input (status 2)
: > "$scratch/empty.nml"
check_case "$scratch/empty.nml" 2 "empty.nml: the file is empty"

# a quarter ring in front of a wall that its whole circle would reach behind: no error (the
# wall check takes the modelled part, x >= 0.1, y >= 0.0265); the same wall 0.01 m to the
# right has the quarter ring 0.011 m behind it
wall_case() {  # NAME WALL_X
  cat > "$scratch/$1.nml" <<NML
&run t_end = 1.0e-4 /
&grid h = 0.5e-3 /
&material name = 'al', E = 70.0e9, nu = 0.33, rho = 2700.0, sigma_y = 150.0e6 /
&body center = 0.1, 0.0265, sector = 'quarter', r_inner = 0.024, r_outer = 0.026, n_thick = 4 /
&wall point = $2, 0.0, normal = 1.0, 0.0 /
NML
}
wall_case quarter_front 0.099
"$bin" --check "$scratch/quarter_front.nml" > /dev/null 2> "$scratch/quarter_front.err" \
  && pass=$((pass + 1)) || failed quarter_front "exit $?: $(grep ERROR "$scratch/quarter_front.err" | head -2)"
wall_case quarter_behind 0.111
check_case "$scratch/quarter_behind.nml" 2 "&wall #1: normal = 1.0, 0.0: &body #1 lies up to 0.011 m behind"
# a variable given twice in a group: a warning at the later line that names the first and the
# value used (namelist input keeps the last one)
sed -e 's/^&material name/\&material nu = 0.25, name/' "$scratch/quarter_front.nml" > "$scratch/twice.nml"
"$bin" --check "$scratch/twice.nml" > /dev/null 2> "$scratch/twice.err"
grep -q "^WARNING \[check\]: .*twice.nml:3: &material #1: nu = 0.33: given again (line 3); the last counts" \
  "$scratch/twice.err" && pass=$((pass + 1)) || failed twice "no repeated-variable warning: $(cat "$scratch/twice.err")"

# --check warns of an output folder the run could not make (the run stops with exit 3), and
# makes nothing: a folder under a regular file is warned of; a new nested folder under the
# scratch folder is not, and is not created
touch "$scratch/a_file"
for dir in "$scratch/a_file/run" "$scratch/new/nested/run"; do
  sed -e "s|^&run |\&run output_dir = '$dir', |" "$scratch/quarter_front.nml" > "$scratch/outdir.nml"
  "$bin" --check "$scratch/outdir.nml" > /dev/null 2> "$scratch/outdir.err"
  rc=$?
  warned=no
  grep -q "^WARNING \[check\]: output_dir '$dir' cannot be written here" "$scratch/outdir.err" && warned=yes
  case $dir in */a_file/*) want=yes ;; *) want=no ;; esac
  if [ "$rc" -eq 0 ] && [ "$warned" = "$want" ] && [ ! -e "$dir" ]; then
    pass=$((pass + 1))
  else
    failed outdir "output_dir $dir: exit $rc, warned $warned (expected $want), exists: $([ -e "$dir" ] && echo yes || echo no); $(cat "$scratch/outdir.err")"
  fi
done

# two identical rings crushed by a fast platen: one quasi-static warning for the wall, naming
# the body (it was printed once per ring, word for word); a wall given twice: a warning at the
# second (both act and share the force)
cat > "$scratch/two_fast.nml" <<'NML'
&run t_end = 1.0e-4 /
&grid h = 0.5e-3 /
&material name = 'al', E = 70e9, nu = 0.33, rho = 2700, sigma_y = 150e6 /
&body center = 0.0, 0.025, r_inner = 0.023, r_outer = 0.025, n_thick = 4 /
&body center = 0.0512, 0.025, r_inner = 0.023, r_outer = 0.025, n_thick = 4 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
&wall point = 0.0, 0.0501, normal = 0.0, -1.0, velocity = 0.0, -500.0 /
&wall point = 1.0, 0.0, normal = 0.0, 1.0 /
NML
"$bin" --check "$scratch/two_fast.nml" > /dev/null 2> "$scratch/two_fast.err"
[ "$(grep -c 'D omega_2' "$scratch/two_fast.err")" = 1 ] \
  && grep -q "wall 2: not quasi-static (.* D omega_2 of body 1). Set |velocity| <= " "$scratch/two_fast.err" \
  && pass=$((pass + 1)) || failed two_fast "not one quasi-static warning naming the body: $(grep omega "$scratch/two_fast.err")"
grep -q "two_fast.nml:8: &wall #3: point = 1.0, 0.0: the plane and motion of &wall #1" \
  "$scratch/two_fast.err" && pass=$((pass + 1)) || failed two_fast "no warning of a wall given twice: $(cat "$scratch/two_fast.err")"
# the study's advice for several rings describes the coarsest (it described the first)
sed -e 's/r_inner = 0.023, r_outer = 0.025, n_thick = 4 \/$/r_inner = 0.023, r_outer = 0.025, n_thick = 8 \//' \
    -e '5s/r_inner = 0.023, r_outer = 0.025, n_thick = 8/r_inner = 0.0235, r_outer = 0.025, n_thick = 6/' \
    -e 's/-500.0/-2.5/' "$scratch/two_fast.nml" > "$scratch/two_t.nml"
"$bin" --check "$scratch/two_t.nml" 2>/dev/null | grep -q "this input (body 2, its coarsest ring): h/t 0.333, n_thick 6" \
  && pass=$((pass + 1)) || failed two_t "the advice does not describe the coarsest ring: $("$bin" --check "$scratch/two_t.nml" 2>&1 | grep 'this input')"

# the set-up report counts mirror planes in good English (was "1 mirror planes")
out=$("$bin" --check "$here/../namelists/default.nml" 2> "$scratch/default.err")
echo "$out" | grep -q "walls: 2 (1 mirror plane added by the sector)" && pass=$((pass + 1)) || {
  fail=$((fail + 1)); echo "FAIL [cli]: --check of the half-ring default: $(echo "$out" | grep walls:)"; }
# the default scene (make run) is one the refinement study measured: --check warns of nothing
# (it warned of h = t/2, 25-29 % error, before), and the nearest study run is a close match,
# within 5 % as run and 10 % on the worst of the grids it was run on (its 'fbar' keeps the
# impact's rebound within 2.4-3.7 % on grids up to 4 % finer or coarser, docs/validation.md)
if [ -s "$scratch/default.err" ]; then
  fail=$((fail + 1)); echo "FAIL [cli]: --check warns about the default scene: $(head -c 300 "$scratch/default.err")"
else
  pass=$((pass + 1))
fi
near=$(echo "$out" | grep "nearest study run")
err=$(echo "$near" | sed -nE 's/.*error +([0-9.]+) % on the worst of [0-9]+ grids \(h within [0-9]+ %\), ([0-9.]+) % as run.*/\1 \2/p')
if [ -n "$err" ] && awk -v e="$err" 'BEGIN { split(e, a, " "); exit !(a[1] <= 10.0 && a[2] <= 5.0) }' \
   && ! echo "$near" | grep -q "not a close"; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL [cli]: the default scene is not a study run within 5 % as run, 10 % at worst: $near"
fi

echo "test_cli_input: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
