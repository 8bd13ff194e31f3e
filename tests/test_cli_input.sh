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
  # the set-up report counts mirror planes in good English (was "1 mirror planes")
out=$("$bin" --check "$here/../namelists/default.nml" 2>/dev/null)
echo "$out" | grep -q "walls: 2 (1 mirror plane added by the sector)" && pass=$((pass + 1)) || {
  fail=$((fail + 1)); echo "FAIL [cli]: --check of the half-ring default: $(echo "$out" | grep walls:)"; }

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

# the set-up report counts mirror planes in good English (was "1 mirror planes")
out=$("$bin" --check "$here/../namelists/default.nml" 2> "$scratch/default.err")
echo "$out" | grep -q "walls: 2 (1 mirror plane added by the sector)" && pass=$((pass + 1)) || {
  fail=$((fail + 1)); echo "FAIL [cli]: --check of the half-ring default: $(echo "$out" | grep walls:)"; }
# the default scene (make run) is one the refinement study calls accurate: --check warns of
# nothing (it warned of h = t/2, 25-29 % error, before), and the nearest study run is a close
# match within 5 % (the study's 5 % impact run, docs/validation.md)
if [ -s "$scratch/default.err" ]; then
  fail=$((fail + 1)); echo "FAIL [cli]: --check warns about the default scene: $(head -c 300 "$scratch/default.err")"
else
  pass=$((pass + 1))
fi
near=$(echo "$out" | grep "nearest study run")
err=$(echo "$near" | sed -nE 's/.*error +([0-9.]+) %.*/\1/p')
if [ -n "$err" ] && awk -v e="$err" 'BEGIN { exit !(e <= 5.0) }' && ! echo "$near" | grep -q "not a close"; then
  pass=$((pass + 1))
else
  fail=$((fail + 1)); echo "FAIL [cli]: the default scene is not a study run within 5 %: $near"
fi

echo "test_cli_input: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
