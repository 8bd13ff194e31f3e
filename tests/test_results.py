#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""summary.nml's &results and results.csv of a crush (docs/output.md, "Results"), recomputed
here from the run's history.csv and the input alone, by a separate implementation:
- stroke: the platen's largest advance, doubled by the quarter model's parallel mirror plane;
- peak_force: the largest wall1_force of the rows;
- absorbed_energy + the stored elastic energy at the end: the platen's work, integral of
  F d(delta) over the rows (trapezoids), within 2 % (the rows are the mean force of each
  interval; the code accumulates the work every step);
- mass: rho pi (r_outer^2 - r_inner^2) for depth, within 0.1 % (the particles tile a polygon);
- mean_force = absorbed / stroke, cfe = mean / peak, sea = absorbed / mass, to round-off;
- results.csv holds the same numbers as the group, with the title; a scene without a
  loading wall (a ring flying into a fixed target) has neither.
    usage: test_results.py [SCRATCH]   (TUBEMPM: the binary under test)
"""
import csv
import math
import sys
from pathlib import Path

from tests.pycheck import Checks, close
from tests.pyscene import run_scene, readers

T = Checks("test_results")
RI, RO, RHO = 0.02375, 0.02625, 7800.0
CRUSH = f"""&run title = 'res', output_dir = 'OUT', t_end = 4.0e-4, cfl = 0.4, history_every = 4.0e-6 /
&solver basis = 'cpdi2', scheme = 'musl', mass_scale = 4.0 /
&grid h = 1.25e-3 /
&material name = 'steel', E = 210.0e9, nu = 0.3, rho = {RHO}, sigma_y = 300.0e6, hardening = 1.0e6 /
&body shape = 'ring', center = 0.0, {RO}, r_inner = {RI}, r_outer = {RO}, n_thick = 4,
      sector = 'quarter' /
&wall point = 0.0, 0.0525, normal = 0.0, -1.0, velocity = 0.0, -20.0, ramp = 1.0e-4 /
"""
IMPACT = """&run title = 'fly', output_dir = 'OUT', t_end = 2.0e-5 /
&grid h = 1.0e-3 /
&material name = 'al', E = 70e9, nu = 0.33, rho = 2700, sigma_y = 200e6 /
&body r_inner = 23e-3, r_outer = 25e-3, n_thick = 4, velocity = 0, -30 /
&wall point = 0, -25.5e-3, normal = 0, 1 /
"""


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_results")
    hist, summ = run_scene(T, scratch, "crush", CRUSH)
    if not hist:
        return T.summary()
    out = scratch / "crush" / "out"
    res = readers.read_results(out / "summary.nml")
    T.check(bool(res), "a crush has &results")
    adv = [-d for d in hist["wall1_disp"]]
    delta = [2.0 * a for a in adv]                     # the lower half approaches the mirror
    force = hist["wall1_force"]
    stroke = max(delta)
    T.check(close(res.get("stroke", 0.0), stroke, 1e-12), f"stroke {res.get('stroke')} = {stroke}")
    T.check(close(res.get("peak_force", 0.0), max(force), 1e-12),
            f"peak_force {res.get('peak_force')} = {max(force)}")
    work = sum(0.5 * (force[i] + force[i - 1]) * (delta[i] - delta[i - 1])
               for i in range(1, len(delta)))
    stored = hist["strain"][-1]
    T.check(close(res.get("absorbed_energy", 0.0) + stored, work, 0.02),
            f"absorbed + stored {res.get('absorbed_energy', 0.0) + stored:.4g} J = the platen's "
            f"work from the rows {work:.4g} J within 2 %")
    mass = RHO * math.pi * (RO**2 - RI**2)
    T.check(close(res.get("mass", 0.0), mass, 1e-3), f"mass {res.get('mass')} = {mass} (unscaled)")
    e = res.get("absorbed_energy", 0.0)
    T.check(close(res.get("mean_force", 0.0), e / stroke, 1e-12), "mean_force = absorbed / stroke")
    T.check(close(res.get("cfe", 0.0), e / stroke / max(force), 1e-12), "cfe = mean / peak")
    T.check(close(res.get("sea", 0.0), e / res.get("mass", 1.0), 1e-12), "sea = absorbed / mass")
    T.check(0.0 < res.get("densification_stroke", -1.0) <= stroke, "densification within the stroke")
    T.check(close(res.get("body1_energy", 0.0), hist["plastic"][-1], 1e-12),
            "body1_energy = the plastic dissipation at the end")
    with open(out / "results.csv") as f:
        rows = list(csv.DictReader(f))
    T.check(len(rows) == 1 and rows[0]["title"] == "res", f"results.csv: one row, titled ({rows})")
    if rows:
        for key in ("stroke", "peak_force", "mean_force", "cfe", "absorbed_energy", "mass", "sea",
                    "densification_stroke", "body1_energy"):
            T.check(close(float(rows[0][key]), res.get(key, math.nan), 1e-12),
                    f"results.csv {key} = &results {key}")
    hist2, _ = run_scene(T, scratch, "fly", IMPACT)
    if hist2:
        out2 = scratch / "fly" / "out"
        T.check(readers.read_results(out2 / "summary.nml") == {} and not (out2 / "results.csv").exists(),
                "a ring flying into a fixed target: no loading wall, no &results")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
