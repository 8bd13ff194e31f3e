#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Run every test program in BLD (build/debug) and every tests/test_*.sh, sum their
# "name: N passed, M failed" lines and print the total as the last line. A program that dies
# without its summary line counts as one failure. Exit 1 when anything failed.
#   usage: tools/run-tests.sh BLD
set -u
case "${1:-}" in
  -h|--help) echo "usage: tools/run-tests.sh [BLD]   (default build/debug; make test builds it first;"
             echo "  build/asan: the sanitizer build of make test BUILD=asan)"
             echo "  runs BLD/test_* and tests/test_*.sh, tests/test_*.py; last line: N passed, M failed"
             exit 0 ;;
esac
bld=${1:-build/debug}
[ -d "$bld" ] || { echo "ERROR [run-tests]: $bld is not a build folder (make test builds build/debug)" >&2; exit 2; }
case "$bld" in
  *asan*)  # the sanitizer build: any report stops the program (exit 1, counted as a failure);
           # no leak report: the variables of a Fortran main program live until exit by design
           # and the error exits end through exit(), so every run would report them
    export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:halt_on_error=1}
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1} ;;
esac
scratch=$(mktemp -d "${TMPDIR:-/tmp}/tubempm-tests.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
total_pass=0; total_fail=0; t0=$(date +%s)
# Tests run two at a time (TEST_JOBS, default the core count up to 2), each on one thread;
# those that time themselves or use threads run alone, after the others. The slowest start
# first (longest first: the two queues end together).
jobs=${TEST_JOBS:-$(nproc 2>/dev/null || echo 1)}
[ "$jobs" -gt 2 ] && jobs=2
alone=" test_threads test_memory test_reliability test_batch_slurm test_good_state "
run_one() {  # name, command... : writes $scratch/name.result (the summary lines)
  local name=$1; shift
  local out="$scratch/$name.log" start=$(date +%s.%N) rc
  mkdir -p "$scratch/$name"
  OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} "$@" "$scratch/$name" > "$out" 2>&1; rc=$?
  local line; line=$(grep -E '^[A-Za-z0-9_.-]+: [0-9]+ passed, [0-9]+ failed' "$out" | tail -n 1)
  local p=0 f=0
  if [ -n "$line" ]; then
    p=$(echo "$line" | sed -E 's/.*: ([0-9]+) passed, ([0-9]+) failed.*/\1/')
    f=$(echo "$line" | sed -E 's/.*: ([0-9]+) passed, ([0-9]+) failed.*/\2/')
  fi
  if [ -z "$line" ] || { [ $rc -ne 0 ] && [ "$f" -eq 0 ]; }; then f=$((f + 1)); fi
  local secs; secs=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN{print b-a}')
  {
    if [ "$f" -gt 0 ]; then
      echo "---- $name FAILED (exit $rc); its output:"; sed 's/^/    /' "$out" | tail -n 60
    fi
    printf '%-28s %4d passed, %d failed  (%.1f s)\n' "$name" "$p" "$f" "$secs" 2>/dev/null \
      || echo "$name $p passed, $f failed"
    echo "#counts $p $f"
  } > "$scratch/$name.result"
}
names=(); cmds=()
add() { names+=("$1"); shift; cmds+=("$*"); }
for t in "$bld"/test_*; do
  [ -x "$t" ] && [ -f "$t" ] || continue
  add "$(basename "$t")" "$t"
done
for s in tests/test_*.sh; do
  [ -f "$s" ] || continue
  add "$(basename "$s" .sh)" env TUBEMPM="$bld/tubempm" bash "$s"
done
for s in tests/test_*.py; do
  [ -f "$s" ] || continue
  add "$(basename "$s" .py)" env TUBEMPM="$bld/tubempm" ${PYTHON:-python3} -m "tests.$(basename "$s" .py)"
done
report() {  # print a finished test's result and add its counts
  local r="$scratch/$1.result"
  grep -v '^#counts ' "$r"
  set -- $(grep '^#counts ' "$r")
  total_pass=$((total_pass + $2)); total_fail=$((total_fail + $3))
}
first=" test_scene_matrix test_body_contact test_sections_crush test_filled_square test_honeycomb "
order=()
for i in "${!names[@]}"; do case "$first" in *" ${names[$i]} "*) order+=("$i") ;; esac; done
for i in "${!names[@]}"; do case "$first" in *" ${names[$i]} "*) ;; *) order+=("$i") ;; esac; done
running=()
for i in "${order[@]}"; do
  n=${names[$i]}
  case "$alone" in *" $n "*) continue ;; esac
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
  # shellcheck disable=SC2086
  run_one "$n" ${cmds[$i]} &
  running+=("$n")
done
wait
for n in "${running[@]}"; do report "$n"; done
for i in "${!names[@]}"; do
  n=${names[$i]}
  case "$alone" in *" $n "*) ;; *) continue ;; esac
  # shellcheck disable=SC2086
  run_one "$n" ${cmds[$i]}
  report "$n"
done
echo "all tests took $(( $(date +%s) - t0 )) s"
echo "$total_pass passed, $total_fail failed"
[ "$total_fail" -eq 0 ]
