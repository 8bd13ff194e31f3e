#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Error exits print the project's own lines only (issue 15): bad input (2), an output folder
# that cannot be written (3) and a numerical failure (4) each give their exit status and, on
# standard error, nothing but `ERROR [...]` / `WARNING [...]` lines: no "ERROR STOP n" and no
# backtrace (before the fix gfortran printed both after the project's lines). An interrupt is
# not an error (issue 32): SIGTERM (143) and SIGINT (130) give one line `stopped by SIGTERM:
# checkpoint saved, continue with tubempm --restart DIR` (`SIGINT (Ctrl-C)`), no ERROR. Also:
# --help states the exit status that SIGTERM actually gives; a new run into the folder of an
# interrupted one, or into a folder another run writes, is refused; SIGTERM during the set-up;
# a t_end far beyond any run; --check with --scene.
#   usage: TUBEMPM=build/debug/tubempm bash tests/test_exits.sh SCRATCH
set -u
bin=${TUBEMPM:-bin/tubempm}
scratch=${1:-$(mktemp -d)}
mkdir -p "$scratch"
here=$(cd "$(dirname "$0")" && pwd)
pass=0; fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL [exits]: $*"; }
export OMP_NUM_THREADS=1

# stopped NAME WANTED_STATUS STATUS ERRFILE: an interrupt: the status, a `stopped by` line and
# no ERROR line, nothing foreign
stopped() {
  [ "$3" -eq "$2" ] && ok || bad "$1: exit $3, expected $2"
  grep -q '^stopped by SIG' "$4" && ! grep -q '^ERROR' "$4" && ok \
    || bad "$1: not one 'stopped by' line without ERROR: $(head -c 300 "$4")"
  local foreign
  foreign=$(grep -v -E '^((ERROR|WARNING) \[|stopped by SIG)' "$4" | grep -v -E '^\s*$' | head -3)
  [ -z "$foreign" ] && ok || bad "$1: standard error holds more than the project's lines: $foreign"
}

# expect NAME WANTED_STATUS STATUS ERRFILE: the status, at least one ERROR line, nothing foreign
expect() {
  [ "$3" -eq "$2" ] && ok || bad "$1: exit $3, expected $2"
  grep -q '^ERROR \[' "$4" && ok || bad "$1: no ERROR line on standard error"
  local foreign
  foreign=$(grep -v -E '^(ERROR|WARNING) \[' "$4" | grep -v -E '^\s*$' | head -3)
  [ -z "$foreign" ] && ok || bad "$1: standard error holds more than the project's lines: $foreign"
}

ring() {  # NAME EXTRA_RUN: a falling ring, one line per group
  cat > "$scratch/$1.nml" <<NML
&run title = '$1', output_dir = '$scratch/$1', t_end = 2.0e-4 $2 /
&grid h = 1.0e-3 /
&material name = 'alu', model = 'j2', E = 70.0e9, nu = 0.33, rho = 2700.0, sigma_y = 150.0e6 /
&body center = 0.0, 0.0262, r_inner = 0.024, r_outer = 0.026, n_thick = 4, velocity = 0.0, -30.0 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
NML
}

# 2: bad input
"$bin" --check "$here/bad_inputs/13_nu_range.nml" > /dev/null 2> "$scratch/input.err"
expect 'bad input' 2 $? "$scratch/input.err"
# 2: bad command line
"$bin" --no-such-option > /dev/null 2> "$scratch/cli.err"
expect 'command line' 2 $? "$scratch/cli.err"
# 3: output folder that cannot be created (a regular file stands in its way)
touch "$scratch/blocker"
ring io ", output_dir = '$scratch/blocker/out'"
sed -i "s|output_dir = '$scratch/io', ||" "$scratch/io.nml"
"$bin" --quiet "$scratch/io.nml" > /dev/null 2> "$scratch/io.err"
expect 'I/O failure' 3 $? "$scratch/io.err"
# 4: numerical failure (a time step far above the stable limit)
sed -e "/^&run /s|[[:space:]]*/[[:space:]]*\$|, output_dir = '$scratch/numeric', cfl = 1.5 /|" \
  "$here/scenes/stability_impact.nml" > "$scratch/numeric.nml"
"$bin" --quiet "$scratch/numeric.nml" > /dev/null 2> "$scratch/numeric.err"
expect 'numerical failure' 4 $? "$scratch/numeric.err"
# 143: SIGTERM during a run
ring sig ""
sed -i 's/t_end = 2.0e-4/t_end = 5.0e-2/' "$scratch/sig.nml"
"$bin" "$scratch/sig.nml" > "$scratch/sig.out" 2> "$scratch/sig.err" &
pid=$!
sleep 2
kill -TERM $pid 2>/dev/null
wait $pid
stopped 'SIGTERM' 143 $? "$scratch/sig.err"
grep -q '^stopped: ' "$scratch/sig.out" && ! grep -q '^done:' "$scratch/sig.out" && ok \
  || bad "an interrupted run's end line: $(grep -E '^(done|stopped)' "$scratch/sig.out")"
# the stop says which signal, that the checkpoint is saved and how to continue, on one line
grep -q "^stopped by SIGTERM: checkpoint saved, continue with tubempm --restart $scratch/sig\$" "$scratch/sig.err" && ok \
  || bad "the SIGTERM line does not name the signal, the checkpoint and --restart DIR: $(cat "$scratch/sig.err")"
# Ctrl-C: the same line, naming SIGINT (Ctrl-C); exit 130
ring int ""
sed -i 's/t_end = 2.0e-4/t_end = 5.0e-2/' "$scratch/int.nml"
"$bin" "$scratch/int.nml" > "$scratch/int.out" 2> "$scratch/int.err" &
pid=$!
sleep 2
kill -INT $pid 2>/dev/null
wait $pid
stopped 'SIGINT' 130 $? "$scratch/int.err"
grep -q "^stopped by SIGINT (Ctrl-C): checkpoint saved, continue with tubempm --restart $scratch/int\$" "$scratch/int.err" && ok \
  || bad "the SIGINT line: $(cat "$scratch/int.err")"
# one interrupt delivered twice (coreutils timeout signals the child and then its group; a
# shell's Ctrl-C and scancel reach every process of the group): the echo is ignored and the run
# stops cleanly with its checkpoint (before: the second copy killed it outright, no checkpoint)
ring sig2 ""
sed -i 's/t_end = 2.0e-4/t_end = 5.0e-2/' "$scratch/sig2.nml"
"$bin" "$scratch/sig2.nml" > "$scratch/sig2.out" 2> "$scratch/sig2.err" &
pid=$!
sleep 2
kill -TERM $pid 2>/dev/null; kill -TERM $pid 2>/dev/null
wait $pid
stopped 'SIGTERM twice at once' 143 $? "$scratch/sig2.err"
grep -q "status = 'interrupted'" "$scratch/sig2/summary.nml" 2>/dev/null \
  && [ -s "$scratch/sig2/checkpoint.bin" ] && ok \
  || bad "SIGTERM twice at once: no clean stop ($(grep status "$scratch/sig2/summary.nml" 2>&1); $(head -c 200 "$scratch/sig2.err"))"
# a checkpoint of another format version (an earlier tubempm's): refused, the message says so
# and names what to do (before: "not a tubempm checkpoint ... (or is damaged)")
cp -r "$scratch/sig2" "$scratch/oldfmt"
printf '\004\000\000\000' | dd of="$scratch/oldfmt/checkpoint.bin" bs=1 seek=12 conv=notrunc 2>/dev/null
"$bin" --restart "$scratch/oldfmt" > /dev/null 2> "$scratch/oldfmt.err"
rc=$?
[ "$rc" -ne 0 ] && grep -q "was written by another version of tubempm (checkpoint format 4; this one reads format" \
  "$scratch/oldfmt.err" && ok || bad "an old checkpoint format: exit $rc: $(head -c 300 "$scratch/oldfmt.err")"
# --restart of a folder that holds no run: exit 3, says so
"$bin" --restart "$scratch/no_such_run" > /dev/null 2> "$scratch/norun.err"
expect '--restart of no run' 3 $? "$scratch/norun.err"
grep -q "no_such_run is not the output folder of a run" "$scratch/norun.err" && ok \
  || bad "--restart of no run: $(cat "$scratch/norun.err")"
# a new run into the folder of the interrupted one: refused (exit 3), its outputs and checkpoint
# untouched, the message names --restart (before: it ran over them and lost that work)
sum0=$(cksum "$scratch/sig/history.csv" "$scratch/sig/checkpoint.bin" 2>/dev/null)
"$bin" --quiet "$scratch/sig.nml" > /dev/null 2> "$scratch/again.err"
expect 'run over an interrupted run' 3 $? "$scratch/again.err"
grep -q "tubempm --restart $scratch/sig" "$scratch/again.err" && ok \
  || bad "the refusal does not name --restart: $(head -c 300 "$scratch/again.err")"
[ "$(cksum "$scratch/sig/history.csv" "$scratch/sig/checkpoint.bin" 2>/dev/null)" = "$sum0" ] \
  && ok || bad "the refused run changed the interrupted run's outputs"
# two runs into one folder: the second is refused while the first writes (exit 3, before it
# writes anything), the first goes on (before: both wrote, and the first's files were corrupt)
ring lock ""
sed -i 's/t_end = 2.0e-4/t_end = 5.0e-2/' "$scratch/lock.nml"
"$bin" --quiet "$scratch/lock.nml" > /dev/null 2> "$scratch/lock1.err" &
pid=$!
for _ in $(seq 1 100); do [ -s "$scratch/lock/history.csv" ] && break; sleep 0.1; done
"$bin" --quiet "$scratch/lock.nml" > /dev/null 2> "$scratch/lock2.err"
expect 'second run into a busy folder' 3 $? "$scratch/lock2.err"
grep -q "another tubempm run is writing into $scratch/lock" "$scratch/lock2.err" && ok \
  || bad "the second run does not say the folder is busy: $(head -c 300 "$scratch/lock2.err")"
kill -0 $pid 2>/dev/null && ok || bad "the first run did not go on"
kill -TERM $pid 2>/dev/null
wait $pid
stopped 'SIGTERM of the first run' 143 $? "$scratch/lock1.err"
# SIGTERM while the case is being set up (a large one): the project's line and 143, nothing
# written (before: the handlers came after the outputs, and the signal killed it silently)
ring early ", snapshot_every = 1.0"
sed -i 's/n_thick = 4/n_thick = 160/; s/h = 1.0e-3/h = 1.0e-4/' "$scratch/early.nml"
"$bin" --quiet "$scratch/early.nml" > /dev/null 2> "$scratch/early.err" &
pid=$!
sleep 0.3
kill -TERM $pid 2>/dev/null
wait $pid
stopped 'SIGTERM during the set-up' 143 $? "$scratch/early.err"
# (a machine fast enough to be past the set-up stops in the loop, with a checkpoint)
if grep -q 'during the set-up.*nothing written' "$scratch/early.err"; then
  [ ! -e "$scratch/early" ] && ok || bad "a stop during the set-up wrote $scratch/early"
else
  [ -s "$scratch/early/checkpoint.bin" ] && ok || bad "SIGTERM early: neither a stop in the set-up nor a checkpoint: $(cat "$scratch/early.err")"
fi
# a finished run without a checkpoint, then a run into its folder killed outright (SIGKILL)
# after a checkpoint: that run is not taken for the finished one (before: its folder kept the
# old summary, --restart said 'complete' and a new run overwrote the work)
ring kill ""
sed -i 's/t_end = 2.0e-4/t_end = 2.0e-5/' "$scratch/kill.nml"
"$bin" --quiet "$scratch/kill.nml" > /dev/null 2>&1 && ok || bad "the finished run failed"
sed -i "s/t_end = 2.0e-5/t_end = 5.0e-2, checkpoint_every = 0.2/" "$scratch/kill.nml"
"$bin" --quiet "$scratch/kill.nml" > /dev/null 2>&1 &
pid=$!
for _ in $(seq 1 100); do [ -s "$scratch/kill/checkpoint.bin" ] && break; sleep 0.1; done
kill -KILL $pid 2>/dev/null
wait $pid 2>/dev/null
grep -q "status = 'running'" "$scratch/kill/summary.nml" && ok \
  || bad "a killed run's summary.nml: $(cat "$scratch/kill/summary.nml")"
"$bin" --quiet "$scratch/kill.nml" > /dev/null 2> "$scratch/kill_again.err"
expect 'a new run over a killed one' 3 $? "$scratch/kill_again.err"
grep -q "status = 'running': it was killed" "$scratch/kill_again.err" && ok \
  || bad "the refusal does not say the run was killed: $(cat "$scratch/kill_again.err")"
# t_end far beyond any run, at the program's limit of 1e6 s: --check counts the steps as a real
# (more than a default integer holds) and warns of the run's length
ring long ""
sed -i 's/t_end = 2.0e-4/t_end = 1.0e6/' "$scratch/long.nml"
"$bin" --check "$scratch/long.nml" > "$scratch/long.out" 2> "$scratch/long.err"
[ $? -eq 0 ] && ok || bad "--check of t_end = 1e6: exit not 0: $(head -c 300 "$scratch/long.err")"
grep -q -E '^steps: about +[1-9]\.[0-9]+E\+(1[0-9]|2[0-9]) ' "$scratch/long.out" && ok \
  || bad "t_end = 1e6: $(grep '^steps' "$scratch/long.out")"
grep -q 'will take about' "$scratch/long.err" && ok || bad "t_end = 1e6: no long-run warning"
! grep -q -v -E '^(ERROR|WARNING) \[|^\s*$' "$scratch/long.err" && ok \
  || bad "t_end = 1e6: standard error holds more than the project's lines: $(head -3 "$scratch/long.err")"
# one task per call
"$bin" --check --scene "$scratch/long.nml" > /dev/null 2> "$scratch/two.err"
expect '--check with --scene' 2 $? "$scratch/two.err"
# --restart of a completed run: exit 0, says so, touches nothing (before: it ran again from a
# leftover checkpoint)
ring done ", checkpoint_every = 1.0e-9"
sed -i 's/t_end = 2.0e-4/t_end = 2.0e-5/' "$scratch/done.nml"
"$bin" --quiet "$scratch/done.nml" > /dev/null 2>&1 && ok || bad "the short run failed"
sum0=$(cksum "$scratch/done/history.csv" "$scratch/done/particles.h5" 2>/dev/null)
"$bin" --restart "$scratch/done" > "$scratch/done.out" 2> "$scratch/done.err"
[ $? -eq 0 ] && ok || bad "--restart of a completed run does not exit 0"
grep -q "is complete" "$scratch/done.out" && ok || bad "--restart of a completed run does not say it is complete"
[ "$(cksum "$scratch/done/history.csv" "$scratch/done/particles.h5" 2>/dev/null)" = "$sum0" ] && ok \
  || bad "--restart of a completed run changed its outputs"
# --help names what SIGTERM gives
"$bin" --help | grep -q '143' && ok || bad "--help does not name exit status 143 (SIGTERM)"
echo "exits: $pass passed, $fail failed"
[ $fail -eq 0 ]
