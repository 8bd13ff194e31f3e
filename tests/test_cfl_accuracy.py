#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The automatic time step of a dynamic scene is chosen by accuracy (docs/stability.md,
"The automatic cfl"): an elastic ring striking a rigid frictionless wall (the study's impact
ring, elastic: tools/cfl_accuracy.py's scene, 0.4 ms of contact) must keep its energy within
1 % of its initial kinetic energy at the automatic cfl (`&run cfl` not given). The exact
solution conserves energy, so the error is the scheme's. At 2 particles per cell through the
wall, for CPDI2 + MUSL (the default, where the stability-based value is accurate) and CPDI1 +
MUSL (where it is not: the accuracy limit is in use; its test must see that):

1. `--check` names the accuracy limit as the reason where it is below the stability-based value
   (0.5 x the stability study's stable cfl), and the run uses that cfl;
2. the run at the automatic cfl keeps the energy within TOL;
3. the oracle can fail: where the accuracy limit is in use, a run at the stability-based value
   (the automatic cfl before it) is outside TOL.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_cfl_accuracy SCRATCH
"""
from __future__ import annotations

import csv
import os
import re
import subprocess
import sys
from pathlib import Path

from tests.pycheck import Checks
from tools import batch
from tools import cfl_accuracy

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

T = Checks("test_cfl_accuracy")
check = T.check
TOL = 0.01


def run(binary: str, nml: Path) -> tuple[int, dict]:
    res = subprocess.run([binary, "--quiet", str(nml)], capture_output=True, text=True,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    return res.returncode, batch.read_summary(nml.parent / "out")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_cfl_accuracy").resolve()
    binary = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
    capped = 0
    for basis, scheme, ppc in (("cpdi2", "musl", "ppc2"), ("cpdi1", "musl", "ppc2")):
        with open(ROOT / "docs" / "stability" / f"cfl_limits_{ppc}.csv", newline="") as fh:
            stable = next(float(r["stable_cfl"]) for r in csv.DictReader(fh)
                          if (r["basis"], r["scheme"]) == (basis, scheme))
        with open(ROOT / "docs" / "stability" / f"cfl_accuracy_{ppc}.csv", newline="") as fh:
            accurate = next(float(r["accurate_cfl"]) for r in csv.DictReader(fh)
                            if (r["basis"], r["scheme"]) == (basis, scheme))
        by_stability = 0.5 * stable
        expect = accurate if 0.0 < accurate < by_stability else by_stability
        ppc_name = ppc
        ppc = f"{basis} + {scheme}, {ppc}"
        folder = scratch / f"auto_{basis}_{scheme}_{ppc_name}"
        folder.mkdir(parents=True, exist_ok=True)
        text = cfl_accuracy.case_text(basis, scheme, cfl_accuracy.DENSITY[ppc_name], 0.0,
                                      folder / "out")
        text = text.replace("cfl = 0.0, ", "")            # the default: automatic
        nml = folder / "case.nml"
        nml.write_text(text)
        res = subprocess.run([binary, "--check", str(nml)], capture_output=True, text=True)
        out = res.stdout + res.stderr
        m = re.search(r"^cfl: ([\d.]+), automatic", out, re.M)
        check(m is not None and abs(float(m[1]) - expect) < 1e-9,
              f"{ppc}: --check's automatic cfl {m and m[1]}, expected {expect} (accuracy "
              f"limit {accurate}, stability-based {by_stability})")
        if expect < by_stability:
            check("kept an elastic impact's energy within 1 %" in out,
                  f"{ppc}: --check names the accuracy limit ({m and m.group(0)})")
        rc, s = run(binary, nml)
        err = float(s.get("energy_error", "nan"))
        print(f"{ppc}: automatic cfl {expect}: exit {rc}, energy error {err:.4f}")
        check(rc == 0 and err <= TOL, f"{ppc}: elastic impact at the automatic cfl {expect}: "
              f"exit {rc}, energy error {err:.4f} (tolerance {TOL})")
        if expect < by_stability:
            capped += 1
            folder = scratch / f"stability_{basis}_{scheme}_{ppc_name}"
            folder.mkdir(parents=True, exist_ok=True)
            nml = folder / "case.nml"
            nml.write_text(cfl_accuracy.case_text(basis, scheme, cfl_accuracy.DENSITY[ppc_name],
                                                  by_stability, folder / "out"))
            rc, s = run(binary, nml)
            err = float(s.get("energy_error", "nan"))
            print(f"{ppc}: stability-based cfl {by_stability}: exit {rc}, energy error "
                  f"{err:.4f}")
            check(rc != 0 or err > TOL, f"{ppc}: the oracle tells the stability-based cfl "
                  f"{by_stability} apart (exit {rc}, energy error {err:.4f})")
    check(capped >= 1, "one case runs at the accuracy limit, so the oracle is seen to tell apart")
    return 0


if __name__ == "__main__":
    rc = main()
    sys.exit(max(T.summary(), rc))
