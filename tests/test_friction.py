#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Wall friction against closed forms: a block sliding to rest on a Coulomb wall.

An elastic block (10 x 5 mm, rho 1000, E 1 GPa, 40 x 20 particles, h = 0.5 mm) rests on a fixed
wall with `contact = 'coulomb'`, mu = 0.5, under gravity g = 1e5 m/s^2 (large, so that it stops
within a few hundred steps), and starts sliding at v0 = 5 m/s. Rigid-body Coulomb friction
decelerates it at mu g: it stops after v0 / (mu g) = 0.1 ms, having slid v0^2 / (2 mu g) =
0.25 mm, and friction has taken all of its kinetic energy, m v0^2 / 2 = 0.625 J per m of depth.
At cfl 0.1 (the friction's loss, its impulses times the slip they leave: 0.624, 0.615 and
0.612 J at the automatic cfl, 0.4 and 0.1; docs/method.md, "Energies"):

* the distance slid at t = 0.2 ms (centre of mass) within 3 % of v0^2 / (2 mu g);
* history's `contact_loss` at t = 0.2 ms within 3 % of m v0^2 / 2;
* the energy error (which counts `contact_loss`) under 5 %; without it the friction's loss
  shows as an energy error of about 100 % here.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_friction SCRATCH
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

from tests.pycheck import Checks
from tests.pyscene import run_scene

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_friction")
check = T.check

V0, MU, G, RHO, W, H = 5.0, 0.5, 1.0e5, 1000.0, 0.01, 0.005
CASE = f"""&run
  title = 'slide', output_dir = 'OUT'
  t_end = 2.0e-4, cfl = 0.1, history_every = 1.0e-6, snapshot_every = 1.0e-4
  gravity = 0.0, {-G}
/
&grid
  h = 0.5e-3
/
&material
  name = 'soft', model = 'elastic', E = 1.0e9, nu = 0.3, rho = {RHO}
/
&body
  shape = 'rect', center = 0.0, {H / 2}, size = {W}, {H}, n_x = 40, n_y = 20
  velocity = {V0}, 0.0
/
&wall
  point = 0.0, 0.0
  normal = 0.0, 1.0
  contact = 'coulomb', friction = {MU}
/
"""


def within(a: float, b: float, rtol: float, what: str) -> None:
    ok = math.isfinite(a) and abs(a - b) <= rtol * abs(b)
    check(ok, f"{what}: {a:.6g} vs {b:.6g} ({100 * (a / b - 1):+.2f} %, allowed "
              f"{100 * rtol:g} %)")
    print(f"  {what}: {a:.6g} vs {b:.6g} ({100 * (a / b - 1):+.2f} %)")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_friction").resolve()
    h, s = run_scene(T, scratch, "friction", CASE)
    if not h:
        return 0
    within(float(h["com_x"][-1] - h["com_x"][0]), V0 ** 2 / (2 * MU * G), 0.03,
           "distance slid to rest against v0^2 / (2 mu g) [m]")
    if check("contact_loss" in h, "history.csv has the contact_loss column"):
        within(float(h["contact_loss"][-1]), 0.5 * RHO * W * H * V0 ** 2, 0.03,
               "friction's loss against m v0^2 / 2 [J/m]")
    err = float(s.get("energy_error", math.nan))
    check(err < 0.05, f"energy error {err:.4f} < 0.05 with the friction's loss counted")
    return 0


if __name__ == "__main__":
    main()
    sys.exit(T.summary())
