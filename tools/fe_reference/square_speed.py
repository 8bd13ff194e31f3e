#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""How fast a square tube may be crushed and still match the static FE curve: the calibration
of `--check`'s quasi-static warning for a 'tube' (docs/validation.md#quasi-static).

Runs namelists/sections/square_tube.nml (release build bin/tubempm, one thread) with the
platens' relative approach at 2, 4, 8 and 16 m/s (`&wall velocity` half of it, the quarter
model's image platen making the other half), the velocity's smooth rise (`ramp`) shortened in
proportion (1 ms at 2 m/s), to the same approach; compares each with the CalculiX static curve
(square_reference.compare: smoothed L2 over delta/H 0-0.5, mean force over FE's, peaks) and
writes docs/fe_reference/square_speed.csv with the approach over H omega_1 (H the tube's outer
height, omega_1 = pi^2 sqrt(E' t^3 / 12 / (rho t L^4)) its side's pinned bending mode, L the
side with the halves of its rounded corners, as mpm_advice's section_speed). Runs are kept in
out/fe_reference/square_speed/ and reused while their input is unchanged. About 5 CPU minutes.

    python3 -m tools.fe_reference.square_speed
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import subprocess
import sys
from pathlib import Path

from plots.mpmplot import namelist
from tools.fe_reference import square_reference as sq

ROOT = Path(__file__).resolve().parent.parent.parent
WORK = ROOT / "out" / "fe_reference" / "square_speed"
OUT = ROOT / "docs" / "fe_reference" / "square_speed.csv"
APPROACH = (2.0, 4.0, 8.0, 16.0)     # [m/s]
RAMP_AT_2 = 1.0e-3                   # [s] the shipped ramp at 2 m/s


def square_h_omega(side: float, t: float, rc: float, e: float, nu: float, rho: float) -> float:
    """H omega_1 of a square tube of centreline side `side`, wall t and centreline corner radius
    rc [m/s] (mpm_advice's section_speed, worked out): H = side + t, omega_1 = pi^2 sqrt(E' I /
    (m L^4)) of a wall pinned at its ends, L its straight part and half of each rounded corner."""
    length = side - 2 * rc + 0.5 * math.pi * rc
    ei = e * t ** 3 / 12 / (1 - nu ** 2)              # plane strain
    omega = math.pi ** 2 * math.sqrt(ei / (rho * t * length ** 4))
    return (side + t) * omega


def h_omega(inputs: dict) -> float:
    """H omega_1 of the shipped square tube [m/s] (square_h_omega of its namelist)."""
    mat, body = inputs["material"][0], inputs["body"][0]
    xs = body["vertices"][0::2]
    return square_h_omega(max(xs) - min(xs), body["thickness"], body.get("corner_radius", 0.0),
                          mat["e"], mat["nu"], mat["rho"])


def main(argv: list[str] | None = None) -> int:
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args(argv)
    base = ROOT / "namelists" / "sections" / "square_tube.nml"
    inputs = namelist.read_namelist(base)
    scale = h_omega(inputs)
    binary = str(ROOT / "bin" / "tubempm")
    rows = []
    for v in APPROACH:
        folder = WORK / f"v{v:g}"
        folder.mkdir(parents=True, exist_ok=True)
        text = namelist.set_values(base.read_text(), {
            "wall.velocity": (0.0, -0.5 * v), "wall.ramp": RAMP_AT_2 * 2.0 / v,
            "run.output_dir": str(folder / "out"), "run.snapshot_every": 1.0})
        case = folder / "case.nml"
        done = (folder / "out" / "history.csv").is_file() and case.is_file() \
            and case.read_text() == text
        if not done:
            case.write_text(text)
            rc = subprocess.call([binary, "--quiet", str(case)],
                                 env=dict(os.environ, OMP_NUM_THREADS="1"))
            if rc != 0:
                print(f"square_speed: the run at {v:g} m/s failed (exit {rc})", file=sys.stderr)
                return 1
        c = sq.compare(folder / "out" / "history.csv", case)
        rows.append({"approach_m_s": v, "ramp_s": RAMP_AT_2 * 2.0 / v,
                     "approach_over_H_omega1": v / scale, "err_smooth": c["err_smooth"],
                     "force_over_fe": c["force_over_fe"],
                     "peak_over_fe": c["peak_mpm_N"] / c["peak_fe_N"]})
        print(f"  {v:5.1f} m/s ({v / scale:.4f} H omega_1): smoothed L2 {c['err_smooth']:.1%}, "
              f"mean force x {c['force_over_fe']:.3f}, peak x {rows[-1]['peak_over_fe']:.2f}")
    with open(OUT, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: f"{x:.6g}" for k, x in r.items()})
    print(f"wrote {OUT.relative_to(ROOT)} (H omega_1 = {scale:.1f} m/s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
