#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Stroke-controlled loading (`&wall stroke`, docs/input.md): the prescribed motion eases to rest
over `ramp` once the wall has travelled `stroke`, and without `&run t_end` the run ends when
every moving wall is at rest at its stroke.

A quarter steel ring crushed by a platen at 20 m/s (ramp 0.1 ms, mass_scale 4) to a stroke of
4 mm, with no t_end:
* --check reports the stroke, when the wall comes to rest, and the approach at the end,
  delta = 2 x 4 mm (the quarter model's parallel mirror plane), delta/D = 8 mm / 50 mm;
* the run ends at the closed-form time: rising over the ramp (travel v ramp / 2), at full speed,
  then easing over the ramp (v ramp / 2 again), t_end = stroke / v + ramp = 0.3 ms;
* the platen ends at its stroke within h/10 (and to 1e-9: the law's easing is integrated
  exactly) and comes to rest (its last row's travel under 1 % of v times the row interval);
* &results: stroke = 2 x 4 mm within h/10, and mean_force = absorbed_energy / stroke.
A stroke the motion never reaches (a table that stops first) is refused, naming it.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_stroke SCRATCH
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from tests.pycheck import Checks, close
from tests.pyscene import run_scene, readers

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_stroke")
check = T.check
EXE = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
RI, RO, H = 0.02375, 0.02625, 1.25e-3
V, RAMP, STROKE = 20.0, 1.0e-4, 4.0e-3
CASE = f"""&run title = 'stroke', output_dir = 'OUT', cfl = 0.4, history_every = 4.0e-6 /
&solver basis = 'cpdi2', scheme = 'musl', mass_scale = 4.0 /
&grid h = {H} /
&material name = 'steel', E = 210.0e9, nu = 0.3, rho = 7800.0, sigma_y = 300.0e6,
          hardening = 1.0e6 /
&body shape = 'ring', center = 0.0, {RO}, r_inner = {RI}, r_outer = {RO}, n_thick = 4,
      sector = 'quarter' /
&wall point = 0.0, 0.0525, normal = 0.0, -1.0, velocity = 0.0, {-V}, ramp = {RAMP},
      stroke = {STROKE} /
"""


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_stroke")
    folder = scratch / "stroke"
    folder.mkdir(parents=True, exist_ok=True)
    nml = folder / "check.nml"
    nml.write_text(CASE.replace("OUT", str(folder / "check")))
    r = subprocess.run([EXE, "--check", str(nml)], capture_output=True, text=True)
    stroke_line = next((x for x in r.stdout.splitlines() if "stroke" in x and "wall 1" in x), "")
    approach = next((x for x in r.stdout.splitlines() if x.startswith("approach")), "")
    check(r.returncode == 0 and "4.0000E-03" in stroke_line,
          f"--check reports the stroke ({stroke_line!r})")
    d_over_d = 2 * STROKE / (RI + RO)
    nums = [float(x) for x in approach.replace(",", " ").split() if x[:1].isdigit() and "E" in x]
    check(len(nums) >= 3 and close(nums[1], 2 * STROKE, 1e-4) and close(nums[2], d_over_d, 1e-3),
          f"--check reports delta = 8 mm and delta/D = {d_over_d:.3f} ({approach!r})")
    hist, summ = run_scene(T, scratch, "run", CASE)
    if not hist:
        return T.summary()
    t_end = STROKE / V + RAMP
    check(close(float(summ.get("sim_time", 0.0)), t_end, 1e-9),
          f"the run ends when the platen is at rest: t = {summ.get('sim_time')} s, closed form "
          f"{t_end} s")
    adv = -hist["wall1_disp"]
    check(abs(adv[-1] - STROKE) < H / 10, f"the platen ends at its stroke within h/10 "
                                          f"({adv[-1]:.9g} m, stroke {STROKE} m)")
    check(close(adv[-1], STROKE, 1e-9), f"the platen's travel is the stroke to 1e-9 "
                                        f"({adv[-1]:.12g} m)")
    last = adv[-1] - adv[-2]
    check(abs(last) < 0.01 * V * 4.0e-6, f"the platen comes to rest: it travels {last:.3g} m "
                                         f"over the last row, < 1 % of v x the row interval")
    res = readers.read_results(scratch / "run" / "out" / "summary.nml")
    check(abs(res.get("stroke", 0.0) - 2 * STROKE) < H / 10,
          f"&results stroke {res.get('stroke')} = 2 x {STROKE} m within h/10")
    check(close(res.get("mean_force", 0.0), res.get("absorbed_energy", 1.0) /
                max(res.get("stroke", 1.0), 1e-30), 1e-9),
          "&results mean_force = absorbed_energy / stroke")
    # a table that stops before the stroke
    bad = folder / "short.nml"
    bad.write_text(CASE.replace("OUT", str(folder / "short")).replace(
        f"ramp = {RAMP},", "motion_t = 0.0, 1.0e-4, 2.0e-4, motion_f = 1.0, 1.0, 0.0,"))
    r = subprocess.run([EXE, "--check", str(bad)], capture_output=True, text=True)
    check(r.returncode == 2 and "short.nml:" in r.stderr and "stroke" in r.stderr and
          "not reached" in r.stderr, f"a stroke never reached is refused, naming the file and "
                                     f"stroke ({r.stderr.strip()[:240]!r})")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
