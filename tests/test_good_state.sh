#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The last good state of a numerical failure is close to it (issue 15). Before the fix the
# driver copied the particles every 50 steps, so a run failing at step 26 saved step 0 as "the
# last good state". Scene: the stability test's half impact (linear, MUSL) at cfl 2, which
# gains energy and stops at step 26 (exit 4). Oracles: crash_<k>.h5 with 1 <= N - k <= 10 for
# the failing step N of the message; its snapshot's step attribute is k, its time that of
# history row k (a row every step), and the centre of mass computed from its particles
# (sum m y / sum m) equals the history's com_y of that row (1e-12 relative; com_x is the full
# ring's, 0 on the mirror plane of this half model). As a particles.h5 snapshot, the crash file
# of this half model holds the whole ring (its mirror image, docs/output.md): the `mirrored`
# group's centre of mass lies on the mirror plane x = mirror_x (1e-12 of the radius) and its
# y equals the history's com_y.
#   usage: TUBEMPM=build/debug/tubempm bash tests/test_good_state.sh SCRATCH
set -u
bin=${TUBEMPM:-bin/tubempm}
scratch=${1:-$(mktemp -d)}
mkdir -p "$scratch"
here=$(cd "$(dirname "$0")" && pwd)
pass=0; fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL [good_state]: $*"; }
export OMP_NUM_THREADS=1

sed -e "s|^&run .*|\&run title = 'fail', t_end = 6.0e-5, history_every = 0.0, output_dir = '$scratch/fail', cfl = 2.0 /|" \
  "$here/scenes/stability_impact.nml" > "$scratch/fail.nml"
"$bin" --quiet "$scratch/fail.nml" > /dev/null 2> "$scratch/fail.err"
rc=$?
[ $rc -eq 4 ] && ok || bad "exit $rc, expected 4 (the scene no longer fails: pick another cfl)"
n=$(sed -n 's/.*instability) at step \([0-9]*\),.*/\1/p' "$scratch/fail.err" | head -1)
k=$(sed -n 's/.*the last good state (step \([0-9]*\),.*/\1/p' "$scratch/fail.err" | head -1)
if [ -z "$n" ] || [ -z "$k" ]; then
  bad "no failing step or last good state in: $(cat "$scratch/fail.err")"
else
  echo "failed at step $n; last good state: step $k"
  [ $((n - k)) -ge 1 ] && [ $((n - k)) -le 10 ] && ok || bad "the last good state (step $k) is $((n - k)) steps before the failure (step $n); at most 10 expected"
  [ -f "$scratch/fail/crash_$k.h5" ] && ok || bad "no crash_$k.h5"
  python3 - "$scratch/fail/crash_$k.h5" "$scratch/fail/history.csv" "$k" <<'PY' && ok || bad "crash_$k.h5 is not the state of step $k"
import sys
import h5py
import numpy as np
crash, hist, k = sys.argv[1], sys.argv[2], int(sys.argv[3])
with h5py.File(crash, "r") as f:
    g = f["snap_000000"]
    step, t = int(g.attrs["step"]), float(np.ravel(g.attrs["time"])[0])
    x, m = g["x"][()], g["mass"][()]
    w = g["mirrored"] if "mirrored" in g else None
    if w is not None:
        xw, mw, cx = w["x"][()], w["mass"][()], float(w.attrs["mirror_x"])
h = np.genfromtxt(hist, delimiter=",", names=True)
row = h[k]                                   # row 0 is t = 0, then one row per step
com = (m[:, None] * x).sum(axis=0) / m.sum()
print("crash step %d t %.6e; history row %d t %.6e; com_y %.15e vs %.15e" % (
    step, t, k, row["time"], com[1], row["com_y"]))
good = (step == k and abs(t - row["time"]) <= 1e-12 * abs(t)
        and abs(com[1] - row["com_y"]) <= 1e-12 * abs(row["com_y"]))
if w is None:
    print("no mirrored group (the whole ring) in the crash file")
    good = False
else:
    comw = (mw[:, None] * xw).sum(axis=0) / mw.sum()
    print("whole ring: %d particles (%d computed); com %.3e, %.15e" % (
        len(mw), len(m), comw[0] - cx, comw[1]))
    good = (good and len(mw) == 2 * len(m) and abs(comw[0] - cx) <= 1e-12 * 0.025
            and abs(comw[1] - row["com_y"]) <= 1e-12 * abs(row["com_y"]))
sys.exit(0 if good else 1)
PY
fi
echo "good_state: $pass passed, $fail failed"
[ $fail -eq 0 ]
