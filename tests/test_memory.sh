#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Memory safety at the grid edge (issue 15): a ring with the impact scene's discretisation
# (n_thick 8, h = t/4) moving up at 300 m/s (free flight: no stress, only the speed of leaving matters) out of its fitted grid, which must grow before any
# block reaches past it. Before the fix the bounds check used the width each particle needs
# while the transfers run over the whole nb x nb block: the debug build stopped at the P2G
# scatter and two threads wrote into each other's buffers. Oracles: exit 0 on the debug
# (-fcheck=all) build at 1 and 2 threads (the full ring has 5024 particles, above the
# threshold from which loops run in parallel), and free flight: no force acts on the ring, so
# its centre of mass moves at exactly V: com_vy = V and com_y = y0 + V t (1e-9 relative).
#   usage: TUBEMPM=build/debug/tubempm bash tests/test_memory.sh SCRATCH
set -u
bin=${TUBEMPM:-bin/tubempm}
scratch=${1:-$(mktemp -d)}
mkdir -p "$scratch"
py=${PYTHON:-python3}
pass=0; fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL [memory]: $*"; }

for nt in 1 2; do
  cat > "$scratch/edge$nt.nml" <<NML
&run title = 'edge$nt', output_dir = '$scratch/edge$nt', t_end = 1.8e-05, history_every = 2.0e-7 /
&solver basis = 'cpdi2', scheme = 'musl' /
&grid h = 0.5e-3 /
&material name = 'alu', model = 'j2', E = 70.0e9, nu = 0.33, rho = 2700.0, sigma_y = 150.0e6,
          hardening = 200.0e6 /
&body center = 0.0, 0.0265, r_inner = 0.024, r_outer = 0.026, n_thick = 8, velocity = 0.0, 100.0 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
NML
  OMP_NUM_THREADS=$nt "$bin" --quiet "$scratch/edge$nt.nml" > "$scratch/edge$nt.log" 2>&1
  rc=$?
  [ $rc -eq 0 ] && ok || bad "$nt thread(s): exit $rc: $(grep -m3 -E 'ERROR|Fortran runtime|out of bounds' "$scratch/edge$nt.log")"
  grep -q "grid_grown = [1-9]" "$scratch/edge$nt/summary.nml" 2>/dev/null && ok \
    || bad "$nt thread(s): the grid did not grow (the test no longer reaches the grid edge)"
  $py - "$scratch/edge$nt/history.csv" <<'PY' && ok || bad "$nt thread(s): free flight violated"
import sys, numpy as np
h = np.genfromtxt(sys.argv[1], delimiter=',', names=True)
t, y, vy = h['time'], h['com_y'], h['com_vy']
err_v = np.abs(vy - 100.0).max() / 100.0
err_y = np.abs(y - (y[0] + 100.0 * (t - t[0]))).max() / 0.0265
print('free flight: max |com_vy/V - 1| = %.2e, max |com_y - y0 - V t| / y0 = %.2e' % (err_v, err_y))
sys.exit(0 if err_v < 1e-9 and err_y < 1e-9 else 1)
PY
done
echo "memory: $pass passed, $fail failed"
[ $fail -eq 0 ]
