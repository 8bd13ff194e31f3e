#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""'stick' walls: a crush between stick platens, and a block dragged by a stick wall.

The friction's loss (`contact_loss`) is each point's tangential impulse times the slip it
leaves (docs/method.md, "Energies"): 'stick' leaves none and takes nothing.

* A full steel ring crushed between two 'stick' platens (tests/scenes/stick_crush.nml: 2 m/s,
  mass_scale 16, h = t/2, 4 particles through the wall, automatic cfl, 0.5 ms): it completes
  with an energy error under 2 % (measured 0.3 %; counted as the nodes' kinetic energy
  change, contact_loss reached 74 J against 53 J of the platens' work and the error was
  140 %), and contact_loss is non-negative (to 1e-4 of the external work: the Gauss-Seidel
  sweeps end at a relative change of 1e-13) and below the external work.
* An elastic block (10 x 5 mm, E 1 GPa, nu 0.3, rho 1000, 40 x 20 particles) on a 'stick'
  wall that moves along itself at v_w = 0.2 m/s, pressed onto it by a frictionless wall
  moving down at 0.5 m/s (a normal stress of at least rho c_d 0.5 m/s = 0.58 MPa, against
  the shear stress rho c_s v_w = 0.12 MPa that starts the block): with no slip its bottom
  moves with the wall once it is pressed on (the compression reaches the bottom after
  H / c_d = 4.3 us): the particle a quarter cell above the bottom travels as far as the wall
  from 10 us on, within 2 % of that travel (measured 1.1 %). Nothing slips, so
  contact_loss stays under 1 % of the walls' work (measured 1e-5; counted as the nodes'
  kinetic energy change it was 26 % of it) and the energy error under 2 %.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_stick SCRATCH
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

T = Checks("test_stick")
check = T.check

VW, VN, RHO, E, NU, W, H = 0.2, 0.5, 1000.0, 1.0e9, 0.3, 0.01, 0.005
CS = math.sqrt(E / (2.0 * (1.0 + NU)) / RHO)      # shear wave speed [m/s]
PERIOD = 4.0 * H / CS                                # fundamental shear mode, fixed-free [s]
T0 = 10.0e-6                                         # the block is pressed on by then [s]
DRAG = f"""&run
  title = 'drag', output_dir = 'OUT'
  t_end = {4.0 * PERIOD:.6g}, cfl = 0.0, history_every = 2.0e-7, snapshot_every = 1.0
/
&grid h = 0.5e-3 /
&material name = 'soft', model = 'elastic', E = {E}, nu = {NU}, rho = {RHO} /
&body shape = 'rect', center = 0.0, {H / 2}, size = {W}, {H}, n_x = 40, n_y = 20 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0, contact = 'stick', velocity = {VW}, 0.0 /
&wall point = 0.0, {H}, normal = 0.0, -1.0, velocity = 0.0, {-VN} /
&probe point = 0.0, 1.25e-4 /
"""


def crush(scratch: Path) -> None:
    text = namelist.set_values((ROOT / "tests" / "scenes" / "stick_crush.nml").read_text(),
                               {"run.output_dir": "OUT"})
    h, s = run_scene(T, scratch, "stick_crush", text)
    if not h:
        return
    err = float(s.get("energy_error", math.nan))
    check(err < 0.02, f"stick crush: energy error {err:.4f} < 0.02")
    ext = float(h["external"][-1])
    loss = h["contact_loss"]
    check(bool(np.min(loss) >= -1.0e-4 * ext),
          f"stick crush: contact_loss non-negative (least {np.min(loss):.3g} J, allowed "
          f"-1e-4 x {ext:.4g} J)")
    check(bool(loss[-1] < ext), f"stick crush: contact_loss {loss[-1]:.4g} J below the "
                                f"external work {ext:.4g} J")
    print(f"  stick crush: energy error {100 * err:.3f} %, contact_loss {loss[-1]:.4g} J, "
          f"external {ext:.4g} J")


def drag(scratch: Path) -> None:
    h, s = run_scene(T, scratch, "drag", DRAG)
    if not h:
        return
    t = h["time"]
    late = t >= T0
    i0 = int(np.nonzero(late)[0][0])
    travel = VW * (t[late] - t[i0])
    moved = h["probe1_x"][late] - h["probe1_x"][i0]
    dev = float(np.max(np.abs(moved - travel)) / travel[-1])
    check(dev < 0.02, f"drag: the bottom moves with the wall from {T0 * 1e6:g} us on (largest "
                      f"difference {100 * dev:.2f} % of the wall's travel, allowed 2 %)")
    work = float(h["external"][-1])
    loss = float(h["contact_loss"][-1])
    check(abs(loss) < 0.01 * abs(work),
          f"drag: contact_loss {loss:.3g} J under 1 % of the walls' work {work:.4g} J")
    err = float(s.get("energy_error", math.nan))
    check(err < 0.02, f"drag: energy error {err:.4f} < 0.02")
    print(f"  drag: bottom's travel within {100 * dev:.2f} % of the wall's, contact_loss "
          f"{loss:.3g} J of {work:.4g} J external, energy error {100 * err:.2f} %")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_stick").resolve()
    crush(scratch)
    drag(scratch)
    return 0


if __name__ == "__main__":
    main()
    sys.exit(T.summary())
