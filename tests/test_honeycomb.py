#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Honeycomb panels against Gibson & Ashby's closed forms (Cellular Solids, 2nd ed., ch. 4):
the coarse cases of tools/honeycomb_validation.py (docs/validation.md#honeycomb-cells), run with the
binary under test.

One cell of a regular panel (theta = +30, h = l) and of a re-entrant one (theta = -30, h = 2l)
between two 'slip' mirror planes through its vertical walls, compressed along x1: the infinite
panel under sigma1. t/l = 0.099, n_thick = 4, h = t/4, plane strain, E 70 GPa, nu 0.3. Each
ratio is checked against Gibson & Ashby (E1 and nu12 with their corrections for axial and shear
wall deformation) and against CalculiX on the same mesh (the committed values of
docs/honeycomb/gibson_ashby.csv). At t/l = 0.1 the walls' joints stiffen and strengthen the
continuum itself (the FE on these meshes: E1 +5.8 % regular, +19.6 % re-entrant; sigma_pl +15 %,
+28 %), so the tolerances against Gibson & Ashby are wider than those against the FE.

* Elastic: E1 within 3 % of the FE and within 8 % (regular) / 25 % (re-entrant) of Gibson &
  Ashby; nu12 within 2 % of Gibson & Ashby, positive for the regular cell and negative for
  the re-entrant one; the held force settled (under 1 % change over the last tenth).
  Measured: E1 +4.5 % / +19.7 % of Gibson & Ashby, -1.2 % / +0.1 % of the FE; nu12 +0.5 % /
  +0.8 %.
* Plastic ('j2', no hardening, sigma_y / E = 5e-5; sigma_ys = 2 sigma_y / sqrt 3 in plane
  strain), loaded over 1.5 periods (half the table's time): sigma_pl within 20 % of the FE
  (n_thick = 4 locks in the hinges: +9 % and +15 % in the table; n_thick = 8 is within 2.5 %)
  and within 50 % of Gibson & Ashby. Measured: +8.1 % / +13.7 % of the FE, +24.6 % / +45.4 % of
  Gibson & Ashby.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_honeycomb SCRATCH
"""
from __future__ import annotations

import csv
import math
import os
import sys
import tempfile
import time
from pathlib import Path

from tests.pycheck import Checks
from tools import honeycomb_validation as hv

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_honeycomb")
check = T.check
T_L, N_THICK, PLASTIC_RAMP = 0.1, 4, 1.5
# (kind, model): the tolerances of the ratios to Gibson & Ashby and to the FE on the same mesh
TOL = {("regular", "elastic"): {"E1_ga": 0.08, "E1_fe": 0.03, "nu12_ga": 0.02},
       ("reentrant", "elastic"): {"E1_ga": 0.25, "E1_fe": 0.03, "nu12_ga": 0.02},
       ("regular", "j2"): {"sigma_pl_ga": 0.50, "sigma_pl_fe": 0.20},
       ("reentrant", "j2"): {"sigma_pl_ga": 0.50, "sigma_pl_fe": 0.20}}


def fe_values() -> dict[tuple[str, str], dict[str, float]]:
    """The committed FE values of the cases (docs/honeycomb/gibson_ashby.csv)."""
    out: dict[tuple[str, str], dict[str, float]] = {}
    path = hv.DOCS / "gibson_ashby.csv"
    if not check(path.is_file(), f"{path} exists (make validate-honeycomb)"):
        return out
    with open(path, newline="") as fh:
        for r in csv.DictReader(fh):
            if (int(r["n_thick"]) == N_THICK and abs(float(r["h_over_t"]) * N_THICK - 1) < 1e-6
                    and abs(float(r["t_l"]) - T_L) < 0.005
                    and r["volumetric"] == hv.LOADING[r["model"]]["volumetric"]):
                out[(r["kind"], r["model"])] = {k: float(v) for k, v in r.items()
                                                if k.endswith("_fe") and v}
    return out


def within(name: str, value: float, ref: float, tol: float) -> float:
    """Check |value / ref - 1| <= tol; the ratio."""
    ratio = value / ref
    check(math.isfinite(ratio) and abs(ratio - 1.0) <= tol,
          f"{name} = {value:.5g}, {ratio:.4f} of {ref:.5g} (allowed 1 +- {tol})")
    return ratio


def main() -> int:
    scratch = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    exe = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
    fe = fe_values()
    for (kind, model), tol in TOL.items():
        t0 = time.time()
        row = hv.run_case(exe, scratch / f"{kind}_{model}", kind, T_L, N_THICK, model,
                          reuse=False, ramp=PLASTIC_RAMP if model == "j2" else None)
        if not check(bool(row), f"{kind} {model}: the run completes"):
            continue
        ref = fe.get((kind, model), {})
        check(bool(ref), f"{kind} {model}: its FE values are in gibson_ashby.csv")
        secs = time.time() - t0
        if model == "elastic":
            e_ga = within(f"{kind}: E1 / Gibson & Ashby", row["E1"], row["E1_ga"], tol["E1_ga"])
            e_fe = (within(f"{kind}: E1 / FE", row["E1"], ref["E1_fe"], tol["E1_fe"])
                    if ref else math.nan)
            n_ga = within(f"{kind}: nu12 / Gibson & Ashby", row["nu12"], row["nu12_ga"],
                          tol["nu12_ga"])
            sign = 1.0 if kind == "regular" else -1.0
            check(row["nu12"] * sign > 0.0, f"{kind}: nu12 = {row['nu12']:.4f} has the sign of "
                                            f"cos^2 / sin(theta)")
            check(row["settle"] < 0.01, f"{kind}: the held force is settled (changes "
                                        f"{row['settle']:.2e} over the last tenth, allowed 0.01)")
            print(f"  {kind} elastic: E1 {row['E1']:.4g} Pa = {e_ga:.4f} x Gibson & Ashby, "
                  f"{e_fe:.4f} x FE; nu12 {row['nu12']:.4f} = {n_ga:.4f} x Gibson & Ashby "
                  f"({row['particles']} particles, {row['steps']} steps, {secs:.1f} s)")
        else:
            s_ga = within(f"{kind}: sigma_pl / Gibson & Ashby", row["sigma_pl"],
                          row["sigma_pl_ga"], tol["sigma_pl_ga"])
            s_fe = (within(f"{kind}: sigma_pl / FE", row["sigma_pl"], ref["sigma_pl_fe"],
                           tol["sigma_pl_fe"]) if ref else math.nan)
            print(f"  {kind} plastic: sigma_pl {row['sigma_pl']:.4g} Pa = {s_ga:.4f} x Gibson & "
                  f"Ashby, {s_fe:.4f} x FE ({row['particles']} particles, {row['steps']} steps, "
                  f"{secs:.1f} s)")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
