#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `make test-slurm`: a real one-node Slurm cluster in a temporary folder (munged, slurmctld and
# slurmd started from a configuration written here, as root), then tests/slurm/check_slurm.py
# runs a small sweep through it and checks it against the local backend (docs/batch.md).
# Every daemon started here is stopped on exit, also on failure. Needs root and Debian's
# slurm-wlm and munge (tools/install-deps.sh --slurm, which make test-slurm calls).
#   usage: tests/slurm/run.sh [BINARY] [-- COMMAND ...]   (default bin/tubempm)
#   With a COMMAND, runs it (SLURM_CONF set) instead of the checks, then stops the cluster:
#     tests/slurm/run.sh -- python3 -m tools.stability --parts flip --backend slurm --poll 1
#   KEEP=1 keeps the temporary folder (logs, run folders) for a look afterwards.
set -u
here=$(cd "$(dirname "$0")/../.." && pwd)
binary=$here/bin/tubempm
if [ $# -gt 0 ] && [ "$1" != "--" ]; then binary=$1; shift; fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
command=("$@")
export PATH="$PATH:/usr/sbin:/sbin"
say() { echo "test-slurm: $*"; }
fail() { echo "ERROR [test-slurm]: $*" >&2; exit 1; }

[ "$(id -u)" = 0 ] || fail "needs root (it starts munged, slurmctld and slurmd as root)"
for c in munged slurmctld slurmd sbatch squeue scancel sinfo; do
  command -v $c >/dev/null 2>&1 || fail "$c not found: run tools/install-deps.sh --slurm"
done
[ -x "$binary" ] || fail "$binary not found: build it with make"

tmp=$(mktemp -d "${TMPDIR:-/tmp}/tubempm-slurm.XXXXXX")
chmod 755 "$tmp"
pids=()
cleanup() {
  local rc=$?
  trap - EXIT INT TERM
  # the jobs of this private cluster first (a failed check may leave some running), then
  # what this script started, by process id, newest first
  if [ -n "${SLURM_CONF:-}" ] && [ ${#pids[@]} -ge 3 ]; then
    scancel --quiet --user=root 2>/dev/null
    for _ in $(seq 40); do
      [ -z "$(squeue --noheader 2>/dev/null)" ] && break; sleep 0.25
    done
  fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill "${pids[$i]}" 2>/dev/null
  done
  for p in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$p" 2>/dev/null
  done
  if [ $rc -ne 0 ]; then
    for f in slurmctld.log slurmd.log munge/munged.log; do
      [ -f "$tmp/$f" ] && { echo "---- $f (last lines)"; tail -n 15 "$tmp/$f"; }
    done
  fi
  if [ "${KEEP:-0}" = 1 ]; then say "kept $tmp"; else rm -rf "$tmp"; fi
  say "daemons stopped"
  exit $rc
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# two free TCP ports for slurmctld and slurmd
read -r port_ctld port_d < <(python3 -c '
import socket
ss = [socket.socket() for _ in range(2)]
for s in ss: s.bind(("127.0.0.1", 0))
print(*[s.getsockname()[1] for s in ss])
for s in ss: s.close()')

# munge: its own key and socket (the socket's folder must be open to all, the key private)
mkdir -p "$tmp/munge" && chmod 755 "$tmp/munge"
head -c 1024 /dev/urandom > "$tmp/munge/munge.key" && chmod 600 "$tmp/munge/munge.key"
munged --foreground --key-file="$tmp/munge/munge.key" --socket="$tmp/munge/munge.socket" \
  --pid-file="$tmp/munge/munged.pid" --log-file="$tmp/munge/munged.log" \
  --seed-file="$tmp/munge/munged.seed" > "$tmp/munge/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$tmp/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$tmp/munge/munge.socket" ] || fail "munged did not start: $(cat "$tmp/munge/munged.out")"

host=$(hostname -s)
mkdir -p "$tmp/state" "$tmp/spool"
cat > "$tmp/slurm.conf" <<EOF
# one node, this machine, everything in $tmp (written by tests/slurm/run.sh)
ClusterName=tubempmtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port_ctld
SlurmdPort=$port_d
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
KillWait=5
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$tmp/slurm.conf
slurmctld -D -c -f "$SLURM_CONF" > "$tmp/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N "$host" -f "$SLURM_CONF" > "$tmp/slurmd.out" 2>&1 &
pids+=($!)
state=""
for _ in $(seq 120); do
  state=$(sinfo --noheader --format=%t 2>/dev/null | head -n 1)
  [ "$state" = idle ] && break
  sleep 0.5
done
[ "$state" = idle ] || fail "the node did not come up (sinfo says '${state:-nothing}')"
say "munged, slurmctld and slurmd up in $tmp (node $host, 2 CPUs, partition test)"

if [ ${#command[@]} -gt 0 ]; then
  "${command[@]}"
else
  binary=$(cd "$(dirname "$binary")" && pwd)/$(basename "$binary")
  (cd "$here" && python3 -m tests.slurm.check_slurm --binary "$binary" --scratch "$tmp/runs")
fi
