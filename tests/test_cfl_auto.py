#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The automatic cfl (`&run cfl = 0`, the default; docs/input.md, docs/stability.md), with the
debug build, on tests/scenes/stability_impact.nml (the stability study's impact scene, cut to
60 us: 43 us of contact) for every basis x scheme, at 2 particles per cell through the wall
(h = t/2, n_thick 4, the study's ppc2 scene) and at 1 (h = t/4, n_thick 4, its ppc1 scene):

1. the value `--check` reports is the margin (0.5, stated here independently of the code) times
   the largest stable cfl of docs/stability/cfl_limits_ppc*.csv (stable_cfl), read here from the
   CSV; where the study found no stable cfl, the margin times the smallest cfl it tried
   (cfl_runs_ppc*.csv); but this impact scene takes the accuracy limit of
   docs/stability/cfl_accuracy_ppc*.csv (accurate_cfl, tools/cfl_accuracy.py) where it is lower;
   and the time step the run reports is that cfl;
2. a run at that value stays within its energy tolerance: it completes and its energy error
   (summary.nml) is under 5 %, the run's own guard and the study's line between accurate and
   wrong. Where the study found no stable cfl (linear + usl and ugimp + usl at both densities,
   cpdi2 + usf at 1 per cell) the automatic value promises nothing: there `--check` must warn
   (the method failed at every cfl tried, or usl loses energy at any cfl), and no run is made.

    usage: TUBEMPM=build/debug/tubempm python3 -m tests.test_cfl_auto SCRATCH
"""
from __future__ import annotations

import csv
import os
import re
import subprocess
import sys
from pathlib import Path

from plots.mpmplot import namelist, readers
from tests.pycheck import Checks, close

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_cfl_auto")
check = T.check

MARGIN = 0.5            # docs/stability.md, "The automatic cfl"
ENERGY_TOL = 0.05       # the run's guard and the study's accurate/wrong line
BASES = ("linear", "ugimp", "cpdi1", "cpdi2")
SCHEMES = ("usl", "usf", "musl")
DENSITY = {"ppc2": 1.0e-3, "ppc1": 0.5e-3}   # the cell size h [m]: t = 2 mm, n_thick = 4


def study_limits(ppc: str) -> tuple[dict[tuple[str, str], float], float]:
    """stable_cfl per (basis, scheme) and the smallest cfl tried, from the study's CSVs."""
    folder = ROOT / "docs" / "stability"
    with open(folder / f"cfl_limits_{ppc}.csv", newline="") as fh:
        stable = {(r["basis"], r["scheme"]): float(r["stable_cfl"]) for r in csv.DictReader(fh)}
    tried = []
    for p in ("ppc2", "ppc1"):
        with open(folder / f"cfl_runs_{p}.csv", newline="") as fh:
            tried += [float(r["cfl"]) for r in csv.DictReader(fh)]
    return stable, min(tried)


def accuracy_limits(ppc: str) -> dict[tuple[str, str], float]:
    """accurate_cfl per (basis, scheme): tools/cfl_accuracy.py's table (0: none)."""
    with open(ROOT / "docs" / "stability" / f"cfl_accuracy_{ppc}.csv", newline="") as fh:
        return {(r["basis"], r["scheme"]): float(r["accurate_cfl"]) for r in csv.DictReader(fh)}


def case_file(folder: Path, basis: str, scheme: str, ppc: str) -> Path:
    """The test scene with the basis, scheme and cell size; no cfl (the default)."""
    text = (ROOT / "tests" / "scenes" / "stability_impact.nml").read_text()
    assert "cfl" not in namelist.parse_namelist(text)["run"][0], "the scene sets cfl"
    text = namelist.set_values(text, {"solver.basis": basis, "solver.scheme": scheme,
                                      "grid.h": DENSITY[ppc], "run.output_dir": str(folder)})
    path = folder.with_suffix(".nml")
    path.write_text(text)
    return path


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_cfl_auto").resolve()
    scratch.mkdir(parents=True, exist_ok=True)
    binary = Path(os.environ.get("TUBEMPM", ROOT / "bin" / "tubempm")).resolve()
    env = dict(os.environ, OMP_NUM_THREADS="1")
    for ppc in ("ppc2", "ppc1"):
        stable, tried_min = study_limits(ppc)
        accurate = accuracy_limits(ppc)
        for basis in BASES:
            for scheme in SCHEMES:
                name = f"{basis}_{scheme}_{ppc}"
                limit = stable[(basis, scheme)]
                by_stability = MARGIN * (limit if limit > 0 else tried_min)
                acc = accurate[(basis, scheme)]
                by_accuracy = 0.0 < acc < by_stability     # an impact: the accuracy limit
                expect = acc if by_accuracy else by_stability
                nml = case_file(scratch / name, basis, scheme, ppc)
                # 1. the value chosen, as --check reports it
                res = subprocess.run([str(binary), "--check", str(nml)], env=env,
                                     capture_output=True, text=True)
                out = res.stdout + res.stderr
                m = re.search(r"^cfl: ([\d.]+), automatic \(cfl = 0\): (?:([\d.]+) x ([\d.]+)|"
                              r"the largest cfl at which .* kept an elastic impact's energy "
                              r"within 1 %)", out, re.M)
                if not check(m is not None, f"{name}: --check does not report the automatic "
                             f"cfl:\n{out}"):
                    continue
                chosen = float(m[1])
                check(close(chosen, expect, rtol=1e-9), f"{name}: automatic cfl {chosen}, "
                      f"expected min({MARGIN} x {limit if limit > 0 else tried_min}, accuracy "
                      f"limit {acc}) = {expect}")
                if by_accuracy:
                    check(m[2] is None, f"{name}: the reason should name the accuracy limit: "
                          f"{m[0]}")
                else:
                    check(m[2] is not None and close(float(m[2]), MARGIN, rtol=1e-9)
                          and close(float(m[3]), limit if limit > 0 else tried_min, rtol=1e-9),
                          f"{name}: the reason does not name margin and limit: {m[0]}")
                    why = "stable at no cfl" if limit <= 0 else "the largest cfl at which"
                    check(why in out, f"{name}: the reason should say '{why}': {m[0]}")
                used = re.search(r"used +[\d.E+-]+ s \(cfl +([\d.]+)\)", out)
                check(used is not None and close(float(used[1]), expect, atol=1.0e-3),
                      f"{name}: the time step is not cfl {expect}: {used and used[0]}")
                if limit <= 0:
                    # no stable cfl: the warning instead of a run
                    check(re.search(r"WARNING.*(failed at every cfl|"
                                    r"scheme 'usl' loses)", out) is not None,
                          f"{name}: no stable cfl in the study, but no warning:\n{out}")
                    continue
                # 2. a run at that value
                rc = subprocess.run([str(binary), "--quiet", str(nml)], env=env,
                                    capture_output=True, text=True).returncode
                summ = readers.read_summary(str(scratch / name / "summary.nml"))
                err = float(summ["energy_error"])
                print(f"{name}: cfl {chosen:.6f}, exit {rc}, {summ['status']}, "
                      f"steps {summ['steps']}, energy error {err:.4f}")
                check(rc == 0 and summ["status"] == "completed" and err < ENERGY_TOL,
                      f"{name}: at the automatic cfl {chosen}: exit {rc}, "
                      f"{summ['status']}, energy error {err:.4f} (tolerance {ENERGY_TOL})")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
