#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Reliability (issue 8): a run stopped by SIGTERM and continued with --restart gives the same
# history.csv as a continuous run; after SIGKILL history.csv parses and particles.h5 holds every
# snapshot written; an output folder that cannot be written gives exit 3 naming it.
#   usage: TUBEMPM=bin/tubempm bash tests/test_reliability.sh SCRATCH
set -u
bin=${TUBEMPM:-bin/tubempm}
scratch=${1:-$(mktemp -d)}
mkdir -p "$scratch"
pass=0; fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL [reliability]: $*"; }
py=${PYTHON:-python3}

case_file() {  # name, t_end
  cat > "$scratch/$1.nml" <<NML
&run title = '$1', output_dir = '$scratch/$1', t_end = $2, history_every = 2.0e-6,
     snapshot_every = 2.0e-5 /
&solver basis = 'cpdi2' /
&grid h = 1.0e-3 /
&material name = 'alu', model = 'j2', E = 70.0e9, nu = 0.33, rho = 2700.0, sigma_y = 150.0e6,
          hardening = 200.0e6 /
&body center = 0.0, 0.0262, r_inner = 0.024, r_outer = 0.026, n_thick = 4,
      velocity = 0.0, -30.0 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
&probe point = 0.0, 0.0502 /
NML
}

# 1. continuous run
case_file cont 2.0e-4
OMP_NUM_THREADS=1 "$bin" --quiet "$scratch/cont.nml" > "$scratch/cont.log" 2>&1 \
  && ok || bad "continuous run failed: $(tail -3 "$scratch/cont.log")"
wall=$(awk -F' = ' '/wall_seconds/ {print $2}' "$scratch/cont/summary.nml" | tr -d ' ')

# 2. the same case, SIGTERM at about 40 % of the run time, then --restart
case_file part 2.0e-4
OMP_NUM_THREADS=1 "$bin" --quiet "$scratch/part.nml" > "$scratch/part.log" 2>&1 &
pid=$!
sleep "$($py -c "print(max(0.3, 0.4 * float('${wall:-1}')))")"
kill -TERM $pid 2>/dev/null
wait $pid; rc=$?
if [ $rc -eq 143 ]; then ok; else bad "SIGTERM: exit $rc, expected 143 (run ended before the signal?)"; fi
grep -q "status = 'interrupted'" "$scratch/part/summary.nml" 2>/dev/null && ok \
  || bad "summary.nml of the interrupted run does not say 'interrupted'"
[ -f "$scratch/part/checkpoint.bin" ] && ok || bad "no checkpoint after SIGTERM"
grep -q "^stopped by SIGTERM: checkpoint saved" "$scratch/part.log" && ! grep -q "^ERROR" "$scratch/part.log" \
  && ok || bad "no 'stopped by SIGTERM' line (and no ERROR) after SIGTERM"
OMP_NUM_THREADS=1 "$bin" --quiet --restart "$scratch/part" > "$scratch/restart.log" 2>&1 \
  && ok || bad "restart failed: $(tail -3 "$scratch/restart.log")"
$py - "$scratch/cont/history.csv" "$scratch/part/history.csv" <<'PY' && ok || bad "restarted history differs"
import sys, numpy as np
a = np.genfromtxt(sys.argv[1], delimiter=',', names=True)
b = np.genfromtxt(sys.argv[2], delimiter=',', names=True)
if a.dtype.names != b.dtype.names or a.shape != b.shape:
    print('shapes', a.shape, b.shape); sys.exit(1)
worst = 0.0
for n in a.dtype.names:
    scale = max(np.abs(a[n]).max(), 1e-300)
    worst = max(worst, np.abs(a[n] - b[n]).max() / scale)
print('restart: largest relative difference', worst)
sys.exit(0 if worst <= 1e-12 else 1)
PY
$py - "$scratch/cont/particles.h5" "$scratch/part/particles.h5" <<'PY' && ok || bad "restarted snapshots differ"
import sys, h5py, numpy as np
with h5py.File(sys.argv[1]) as a, h5py.File(sys.argv[2]) as b:
    ka = sorted(k for k in a if k.startswith('snap_')); kb = sorted(k for k in b if k.startswith('snap_'))
    if ka != kb: print('snapshots', ka, kb); sys.exit(1)
    for k in ka:
        if abs(a[k].attrs['time'] - b[k].attrs['time']) > 1e-15: sys.exit(1)
        if not np.allclose(a[k]['x'][...], b[k]['x'][...], rtol=1e-12, atol=0): sys.exit(1)
PY

# 3. --restart refuses a changed input
sed -i 's/t_end = /t_end = 9.0e-4 , t_end_was = /' "$scratch/part/input.nml" 2>/dev/null
"$bin" --restart "$scratch/part" > "$scratch/refuse.log" 2>&1; rc=$?
[ $rc -eq 2 ] && ok || bad "changed input.nml: exit $rc, expected 2"

# 4. SIGKILL halfway: history parses, particles.h5 opens with every snapshot written
case_file killed 2.0e-4
OMP_NUM_THREADS=1 "$bin" --quiet "$scratch/killed.nml" > /dev/null 2>&1 &
pid=$!
sleep "$($py -c "print(max(0.3, 0.6 * float('${wall:-1}')))")"
kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
$py - "$scratch/killed" <<'PY' && ok || bad "outputs after SIGKILL are not readable"
import sys, os, numpy as np, h5py
d = sys.argv[1]
h = np.genfromtxt(os.path.join(d, 'history.csv'), delimiter=',', names=True)
assert h.size > 1 and np.all(np.isfinite(h['time']))
with h5py.File(os.path.join(d, 'particles.h5'), 'r') as f:
    snaps = [k for k in f if k.startswith('snap_')]
    assert len(snaps) >= 1
    for k in snaps:
        assert f[k]['x'].shape[1] == 2
print('after SIGKILL:', h.size, 'history rows,', len(snaps), 'snapshots readable')
PY

# 5. an output folder that cannot be created or written: exit 3, the folder named
mkdir -p "$scratch/ro"; chmod 555 "$scratch/ro"
case_file ro 1.0e-5
sed -i "s|output_dir = '$scratch/ro'|output_dir = '$scratch/ro/sub'|" "$scratch/ro.nml"
if [ "$(id -u)" = 0 ]; then   # root ignores permissions: use a path below a regular file
  touch "$scratch/afile"; sed -i "s|output_dir = '$scratch/ro/sub'|output_dir = '$scratch/afile/sub'|" "$scratch/ro.nml"
fi
"$bin" --quiet "$scratch/ro.nml" > "$scratch/ro.log" 2>&1; rc=$?
[ $rc -eq 3 ] && ok || bad "unwritable output folder: exit $rc, expected 3"
grep -q "ERROR \[output\].*sub" "$scratch/ro.log" && ok || bad "the message does not name the folder: $(cat "$scratch/ro.log")"
chmod 755 "$scratch/ro"

echo "test_reliability: $pass passed, $fail failed"
[ $fail -eq 0 ]
