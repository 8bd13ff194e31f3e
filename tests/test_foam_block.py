#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The crushable foam in a scene: namelists/foam/foam_block.nml, a foam block crushed between
frictionless platens with free sides (plane stress: uniaxial stress), against closed forms.

* The shipped scene (the Alporas-like foam of the hardening law, nu_p = 0, to a logarithmic
  strain of 0.83 eps_d), and the same block with a tabulated curve and nu_p = 0.2 (8 x 8
  particles, one per cell). About 15 s with the debug build.
* Measured: the platen's force per unit width, F / W, from history.csv (averaged over each
  row's interval, like a load cell), against the law averaged over the interval (the mean of Y
  at its ends); the axial and lateral logarithmic strains from the two corner particles (the
  probes: their distance scales with the block's sides, as the deformation is uniform);
  the plastic strain e = eps_axial - sigma / E.
* Checks: |F / W / Y(e) - 1| <= 1 % over the rows with 0.02 <= e <= 0.8 eps_d (for the curve,
  e <= 1.9); the lateral plastic strain ln(W / W0) - nu sigma / E within 0.005 e of -nu_p
  times the axial one, -e (an expansion of nu_p e), from e = 0.1 (after the ramp); the plastic dissipation in
  history.csv at the end within 1 % of A0 int_0^e Y(s) exp(-(1 - nu_p) s) ds (the area shrinks as
  exp(-(1 - nu_p) e) in plane stress; elastic strains, below 0.6 %, neglected); the plastic
  work never decreases; energy_error below 1 %. The penalty's sink-in at the platen (a few
  micrometres, 0.4 % of the height at the end) is why the strain comes from the particles and
  not from the platen's travel.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_foam_block SCRATCH
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

T = Checks("test_foam_block")
check = T.check

E, NU = 1.0e9, 0.3
SP, GAM, A2, BETA, ED = 1.6e6, 2.0e6, 4.0e6, 4.0, 2.46          # the shipped law
CURVE_E = [0.0, 0.5, 1.0, 1.5, 2.0]
CURVE_S = [1.6e6, 2.0e6, 2.5e6, 3.4e6, 5.5e6]
W0 = H0 = 20.0e-3


def y_law(e):
    e = np.clip(e, 0.0, None)
    return SP + GAM * e / ED + A2 * np.log(1.0 / (1.0 - (e / ED) ** BETA))


def y_curve(e):
    return np.interp(e, CURVE_E, CURVE_S)


def case(curve: bool) -> str:
    text = (ROOT / "namelists" / "foam" / "foam_block.nml").read_text()
    values: dict = {"run.output_dir": "OUT", "run.snapshot_every": 1.0}
    if curve:
        base = namelist.parse_namelist(text, "foam_block.nml")
        for key, was, now in (("body.n_x", 16, 8), ("body.n_y", 16, 8),
                              ("material.nu_plastic", 0.0, 0.2)):
            group, var = key.split(".")
            check(base[group][0].get(var) == was,
                  f"namelists/foam/foam_block.nml has {var} = {was}")
            values[key] = now
        law = ("sigma_p", "foam_gamma", "foam_alpha2", "foam_beta", "eps_d")
        n = sum(v in base["material"][0] for v in law)
        check(n == 5, f"the law's five variables replaced by the curve ({n} found)")
        values.update({f"material.{v}": None for v in law})
        values["material.curve_strain"] = [float(x) for x in CURVE_E]
        values["material.curve_stress"] = [float(f"{x:.6e}") for x in CURVE_S]
    return namelist.set_values(text, values)


def block(scratch: Path, curve: bool) -> None:
    name = "curve" if curve else "law"
    nup = 0.2 if curve else 0.0
    h, s = run_scene(T, scratch, name, case(curve))
    if not h:
        return
    law = y_curve if curve else y_law
    dx = h["probe1_x"] - h["probe2_x"]
    dy = h["probe1_y"] - h["probe2_y"]
    width = W0 * dx / dx[0]
    eps_ax = np.log(dy[0] / dy)                        # compression positive
    sig = h["wall1_force"] / width                     # 1 m depth
    e = eps_ax - sig / E
    lat = np.log(dx / dx[0]) - NU * sig / E            # lateral plastic strain
    y_mean = 0.5 * (law(e) + law(np.r_[0.0, e[:-1]]))  # the law averaged over each row
    e_max = 1.9 if curve else 0.8 * ED
    rows = (e >= 0.02) & (e <= e_max)
    rows[0] = False
    err = sig[rows] / y_mean[rows] - 1.0
    worst = float(np.max(np.abs(err))) if rows.any() else math.inf
    at = float(e[rows][np.argmax(np.abs(err))]) if rows.any() else math.nan
    check(bool(rows.sum() > 100) and float(e.max()) > e_max,
          f"{name}: {rows.sum()} rows from e = 0.02 to {e_max:.3f}, reached e = {e.max():.3f}")
    check(worst <= 0.01, f"{name}: F / W follows the law within 1 % (worst {100 * worst:.2f} % "
                         f"at e = {at:.3f})")
    late = rows & (e >= 0.1)                           # after the ramp's transient
    lat_err = np.abs(lat[late] - nup * e[late]) / e[late]
    check(bool(late.sum() > 100 and np.all(lat_err <= 0.005)),
          f"{name}: lateral plastic strain = nu_p e = {nup} e within 0.005 e from e = 0.1 (worst "
          f"{float(np.max(lat_err)):.2e} e)")
    grid = np.linspace(0.0, float(e[-1]), 4001)
    wp = W0 * H0 * np.trapezoid(law(grid) * np.exp(-(1.0 - nup) * grid), grid)
    plastic = float(h["plastic"][-1])
    check(abs(plastic / wp - 1.0) <= 0.01,
          f"{name}: plastic dissipation {plastic:.5g} J vs A0 int Y exp(-(1 - nu_p) e) de "
          f"{wp:.5g} J ({100 * (plastic / wp - 1):+.2f} %)")
    check(bool(np.all(np.diff(h["plastic"]) >= 0.0)), f"{name}: the plastic work never falls")
    ee = float(s.get("energy_error", math.nan))
    check(ee < 0.01, f"{name}: energy_error {ee:.2e} below 1 %")
    print(f"  {name}: worst |F/W/Y - 1| {100 * worst:.3f} % at e = {at:.3f} (e up to {e_max:.3f});"
          f" lateral {float(np.max(lat_err)):.1e} e; plastic {100 * (plastic / wp - 1):+.2f} %;"
          f" energy_error {ee:.1e}; {s.get('steps')} steps")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_foam_block").resolve()
    block(scratch, curve=False)
    block(scratch, curve=True)
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
