#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Mass-proportional damping (`&solver damping`): its energy against what the scheme removes.

Step 3 divides each node velocity by 1 + c dt; the particles receive that change through
G2P, and the `damped` energy is the kinetic energy the particles lose by it (docs/method.md,
"Energies"). Two scenes:

* a free elastic block (10 x 5 mm, 20 x 10 particles) moving at v0 = 5 m/s with damping
  c = 2e4 1/s at a fixed dt, no walls, for c t = 1: every particle's velocity is divided by
  1 + c dt per step, so KE = KE0 (1 + c dt)^(-2 n) after n steps and damped = KE0 - KE
  (both to 1e-9 relative: a conservation law and the scheme's closed form); the velocity
  against exp(-c t) within c^2 t dt (the leading error of the implicit step, c^2 t dt / 2,
  doubled);
* the slow elastic loading of a quarter ring (tests/scenes/damped_quarter.nml: R/t = 10, h =
  t/4, 8 particles through the wall, a platen pressed 0.5 mm over 0.5 ms, c = 1e4 1/s) at the
  automatic cfl: it completes (counted on the nodes, the damped energy ran ahead of what the
  particles lost and the run stopped with exit 4, "energy growth", 5.0 % at 0.19 ms) with an
  energy error under 1 % (measured 0.05 % to 0.1 %).

    TUBEMPM=build/debug/tubempm python3 -m tests.test_damping SCRATCH
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from plots.mpmplot import namelist
from tests.pycheck import Checks
from tests.pyscene import run_scene

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_damping")
check = T.check

V0, C, DT, RHO, W, H = 5.0, 2.0e4, 2.0e-7, 1000.0, 0.01, 0.005
FREE = f"""&run
  title = 'free', output_dir = 'OUT'
  t_end = {1.0 / C}, dt = {DT}, history_every = {10 * DT}, snapshot_every = 1.0
/
&solver damping = {C} /
&grid h = 0.5e-3 /
&material name = 'soft', model = 'elastic', E = 1.0e9, nu = 0.3, rho = {RHO} /
&body shape = 'rect', center = 0.0, 0.0, size = {W}, {H}, n_x = 20, n_y = 10,
      velocity = {V0}, 0.0 /
"""


def free_block(scratch: Path) -> None:
    h, _ = run_scene(T, scratch, "free", FREE)
    if not h:
        return
    ke0 = 0.5 * RHO * W * H * V0 ** 2
    ke, damped, t, n = h["kinetic"], h["damped"], h["time"], h["step"]
    bal = np.max(np.abs(damped + ke - ke0)) / ke0
    check(bal < 1.0e-9, f"free block: damped + kinetic = KE0 to {bal:.2e} (allowed 1e-9)")
    scheme = ke0 * (1.0 + C * DT) ** (-2.0 * n)
    dev = np.max(np.abs(ke - scheme)) / ke0
    check(dev < 1.0e-9, f"free block: KE = KE0 (1 + c dt)^(-2n) to {dev:.2e} (allowed 1e-9)")
    vrel = np.abs(h["com_vx"] / (V0 * np.exp(-C * t)) - 1.0)
    tol = C * C * t * DT
    check(bool(np.all(vrel <= tol + 1e-12)),
          f"free block: v against v0 exp(-c t) within c^2 t dt (largest {np.max(vrel):.3e}, "
          f"allowed {np.max(tol):.3e} at the end)")
    print(f"  free block: damped + KE - KE0 {bal:.1e}, KE vs scheme {dev:.1e}, "
          f"v vs exp(-c t) {np.max(vrel):.3e} (allowed {np.max(tol):.3e}); "
          f"KE/KE0 at c t = 1: {ke[-1] / ke0:.5f} (exp(-2) = {math.exp(-2):.5f})")


def slow_loading(scratch: Path) -> None:
    text = namelist.set_values((ROOT / "tests" / "scenes" / "damped_quarter.nml").read_text(),
                               {"run.output_dir": "OUT"})
    h, s = run_scene(T, scratch, "damped_quarter", text)
    if not h:
        return
    err = float(s.get("energy_error", math.nan))
    check(err < 0.01, f"damped slow loading at the automatic cfl: energy error {err:.4f} < 0.01")
    d = h["damped"]
    check(bool(d[-1] > 0.0 and np.all(np.diff(d) >= 0.0)),
          "damped slow loading: the damped energy grows and is positive")
    check(bool(d[-1] < h["external"][-1]),
          f"damped slow loading: damped {d[-1]:.4g} J below the platen's work "
          f"{h['external'][-1]:.4g} J")
    print(f"  damped slow loading: energy error {100 * err:.3f} %, damped {d[-1]:.4g} J, "
          f"external {h['external'][-1]:.4g} J, dt {np.median(h['dt']):.3e} s")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_damping").resolve()
    free_block(scratch)
    slow_loading(scratch)
    return 0


if __name__ == "__main__":
    main()
    sys.exit(T.summary())
