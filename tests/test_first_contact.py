#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Wall contact from the first instant: a wall that touches the material surface at t = 0.

* Plane impact of a block: an aluminium block (4 x 20 mm, E 70 GPa, nu 0.33, rho 2700, 32 x
  160 particles, h = 0.25 mm) between two 'slip' side walls (lateral confinement: uniaxial
  strain), struck from below by a wall that touches it at t = 0 and moves at v = 1 m/s. Until
  the wave comes back from the top (2 L / c_d = 6.45 us) the contact stress is rho c_d v
  (c_d = sqrt((lambda + 2 mu) / rho)): the wall's force is nonzero from the second step on
  (the penalty acts on the gap at the start of a step, zero in the first), its impulse over
  the first 5 us is rho c_d v A T within 5 % (the penalty's compliance, a layer of about
  2 to 4 h / alpha of the material, delays the rise by tau = int (1 - f / F) dt, measured
  0.18 us, about 4.5 h / c_d; the test allows 6 h / c_d), and it equals the block's
  momentum (to 1e-9).
* A ring touching a wall at one corner at t = 0 (namelists/wave.nml at h = t/8, n_thick = 8,
  the wall's velocity a half-sine pulse of 1 m/s over 5 us, the first 0.5 us): the force is
  nonzero from the second step on (the surface curve passes through the corners; through
  the B-spline of the corners, inside the circle by R dtheta^2 / 8, the wall pushed nothing
  for 1.09 us), and the impulse equals the ring's momentum (to 1e-9).

* A bar striking a rigid wall: an elastic aluminium bar in uniaxial strain (two particles across
  between 'slip' side walls, one particle per cell, h = 0.5 mm) strikes a frictionless wall at
  10 m/s. The contact lasts 2 L / c_d (the wave's round trip) plus the delay of the penalty
  (a layer 2 h deep at one particle per cell, loaded and unloaded) and of the first step, the
  same whatever the length (6.1 h / c_d at L = 100 h and at 400 h). At L = 400 h the contact
  time (from the start of the first step with a force to the end of the last) is within 1 % of
  2 L / c_d (+0.77 %; +3.1 % at L = 100 h, and +4.8 % at 80 cells with two particles per cell,
  whose penalty is twice as deep: docs/method.md), the rebound within 1 % of the impact speed
  (-0.64 %); and the wave speed from the two lengths, 2 (L2 - L1) / (T2 - T1), free of the
  delay, is c_d within 0.2 % (-0.005 %).

    TUBEMPM=build/debug/tubempm python3 -m tests.test_first_contact SCRATCH
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

T = Checks("test_first_contact")
check = T.check

V, RHO, E, NU, W, L, HC = 1.0, 2700.0, 70.0e9, 0.33, 4.0e-3, 20.0e-3, 0.25e-3
CD = math.sqrt(E * (1.0 - NU) / (RHO * (1.0 + NU) * (1.0 - 2.0 * NU)))
TW = 5.0e-6                                          # window, before 2 L / c_d [s]
BLOCK = f"""&run
  title = 'block', output_dir = 'OUT'
  t_end = {TW}, cfl = 0.0, history_every = 1.0e-9, snapshot_every = 1.0
/
&solver basis = 'cpdi2', scheme = 'musl', plane = 'strain' /
&grid h = {HC} /
&material name = 'al', model = 'elastic', E = {E}, nu = {NU}, rho = {RHO} /
&body shape = 'rect', material = 'al', center = 0.0, 0.0, size = {W}, {L}, n_x = 32,
      n_y = 160 /
&wall point = 0.0, {-L / 2}, normal = 0.0, 1.0, velocity = 0.0, {V} /
&wall point = {-W / 2}, 0.0, normal = 1.0, 0.0, contact = 'slip' /
&wall point = {W / 2}, 0.0, normal = -1.0, 0.0, contact = 'slip' /
"""


def step_impulse(h: dict, upto: float) -> float:
    """Sum of force x dt over the steps that end at or before `upto` (one row per step)."""
    m = (h["step"] >= 1) & (h["time"] <= upto * (1.0 + 1e-12))
    return float(np.sum(-h["wall1_fy"][m] * h["dt"][m]))


def block(scratch: Path) -> None:
    h, _ = run_scene(T, scratch, "block", BLOCK)
    if not h:
        return
    check(bool(np.all(np.diff(h["step"]) == 1)), "block: one history row per step")
    f = -h["wall1_fy"]                                # the wall's force on the block
    check(bool(f[1] == 0.0 and np.all(f[2:12] > 0.0)),
          "block: no force in the first step (gap 0), a force from the second on")
    force = RHO * CD * V * W                          # rho c_d v A per unit depth [N/m]
    imp = step_impulse(h, TW)
    tau = TW - imp / force
    check(abs(imp / (force * TW) - 1.0) < 0.05,
          f"block: impulse over 5 us {imp:.5g} N s/m vs rho c_d v A T {force * TW:.5g} "
          f"({100 * (imp / (force * TW) - 1):+.2f} %, allowed 5 %)")
    check(0.0 <= tau < 6.0 * HC / CD,
          f"block: the penalty's lag {tau * 1e6:.3f} us under 6 h / c_d = "
          f"{6e6 * HC / CD:.3f} us")
    mom = RHO * W * L * h["com_vy"][-1]
    check(abs(mom - imp) <= 1e-9 * abs(imp), f"block: impulse {imp:.12g} = momentum {mom:.12g}")
    print(f"  block: impulse / (rho c_d v A T) = {imp / (force * TW):.4f}, lag {tau * 1e6:.3f} us"
          f" ({tau * CD / HC:.2f} h / c_d), force of steps 2-4 / rho c_d v A: "
          f"{', '.join(f'{x / force:.3f}' for x in f[2:5])}")


def ring(scratch: Path) -> None:
    ts = np.linspace(0.0, 5.0e-6, 26)
    values = {"run.title": "ring", "run.output_dir": "OUT", "run.t_end": 5.0e-7, "run.cfl": 0.0,
              "run.history_every": 1.0e-10, "run.snapshot_every": 1.0, "grid.h": 0.25e-3,
              "wall.velocity": [0.0, 1.0], "wall.penalty": 1.0,
              "wall.motion_t": [float(f"{x:.6g}") for x in ts],
              "wall.motion_f": [float(f"{x:.6g}") for x in np.abs(np.sin(np.pi * ts / 5.0e-6))]}
    text = namelist.set_values((ROOT / "namelists" / "wave.nml").read_text(), values)
    got = namelist.parse_namelist(text, "ring")
    check(all(got[k.split(".")[0]][0][k.split(".")[1]] == v for k, v in values.items()),
          "ring: namelists/wave.nml with the test's values")
    h, s = run_scene(T, scratch, "ring", text)
    if not h:
        return
    f = -h["wall1_fy"]                                # on the ring (the full ring's)
    first = int(np.nonzero(f > 0.0)[0][0]) if np.any(f > 0.0) else -1
    when = (f"step {h['step'][first]:.0f}, t = {h['time'][first] * 1e6:.3f} us" if first >= 0
            else "none in 0.5 us")
    check(first == 2 and bool(np.all(f[2:] > 0.0)),
          f"ring: a force from the second step on (first: {when})")
    imp = step_impulse(h, 1.0)
    # the full ring's mass: its particles are quadrilaterals between the corner circles,
    # 8 through the wall, n_k = 2 particles / 8 around the full ring (the half model's twice)
    nk = 2 * int(s.get("particles", 0)) // 8
    mass = RHO * 0.5 * (0.026 ** 2 - 0.024 ** 2) * nk * math.sin(2.0 * math.pi / nk)
    mom = mass * h["com_vy"][-1]
    check(abs(mom - imp) <= 1e-9 * abs(imp),
          f"ring: impulse {imp:.12g} = momentum {mom:.12g} (mass {mass:.6g} kg/m)")
    print(f"  ring: first force: {when}; impulse over 0.5 us {imp:.4g} N s/m")


BAR = """&run
  title = 'bar', output_dir = 'OUT'
  t_end = {t_end}, cfl = 0.0, history_every = 1.0e-8, snapshot_every = 1.0
/
&solver basis = 'cpdi2', scheme = 'musl', plane = 'strain' /
&grid h = {h} /
&material name = 'al', model = 'elastic', E = {E}, nu = {NU}, rho = {RHO} /
&body shape = 'rect', material = 'al', center = 0.0, {yc}, size = {w}, {L}, n_x = 2, n_y = {ny},
      velocity = 0.0, -{v} /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
&wall point = {xl}, 0.0, normal = 1.0, 0.0, contact = 'slip' /
&wall point = {xr}, 0.0, normal = -1.0, 0.0, contact = 'slip' /
"""


def bar(scratch: Path) -> None:
    hb, v, gap = 0.5e-3, 10.0, 1.0e-8
    times = {}
    for cells in (100, 400):
        L = cells * hb
        text = BAR.format(t_end=f"{2.0 * L / CD + 20.0 * hb / CD + gap / v:.4g}", h=hb, E=E,
                          NU=NU, RHO=RHO, yc=gap + 0.5 * L, w=2.0 * hb, L=L, ny=cells, v=v,
                          xl=-hb, xr=hb)
        h, _ = run_scene(T, scratch, f"bar{cells}", text)
        if not h:
            return
        f = -h["wall1_fy"]
        on = np.nonzero(f > 0.01 * f.max())[0]
        check(on.size > 0 and on[-1] < len(f) - 1, f"bar{cells}: contact begins and ends")
        if on.size == 0 or on[-1] >= len(f) - 1:
            return
        times[cells] = float(h["time"][on[-1]] - h["time"][on[0] - 1])
        delay = (times[cells] - 2.0 * L / CD) * CD / hb
        print(f"  bar, L = {cells} h: contact {times[cells] * 1e6:.4f} us, 2 L / c_d "
              f"{2e6 * L / CD:.4f} us ({100 * (times[cells] * CD / (2 * L) - 1):+.2f} %, delay "
              f"{delay:.2f} h / c_d), rebound {h['com_vy'][-1]:.4f} m/s")
        if cells == 400:
            check(abs(times[cells] * CD / (2.0 * L) - 1.0) < 0.01,
                  f"bar, L = 400 h: contact {times[cells]:.6e} s vs 2 L / c_d {2 * L / CD:.6e} s "
                  "(1 %)")
            check(abs(h["com_vy"][-1] / v - 1.0) < 0.01,
                  f"bar, L = 400 h: rebound {h['com_vy'][-1]:.5f} m/s vs {v} m/s (1 %)")
    speed = 2.0 * 300 * hb / (times[400] - times[100])
    check(abs(speed / CD - 1.0) < 0.002, f"bar: the wave speed from two lengths {speed:.2f} m/s "
          f"vs c_d {CD:.2f} m/s (0.2 %)")
    print(f"  bar: wave speed from L = 100 h and 400 h {speed:.2f} m/s, c_d {CD:.2f} m/s "
          f"({100 * (speed / CD - 1):+.3f} %)")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_first_contact").resolve()
    block(scratch)
    ring(scratch)
    bar(scratch)
    return 0


if __name__ == "__main__":
    main()
    sys.exit(T.summary())
