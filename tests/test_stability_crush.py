#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Stability study checks on the crush scene (issue 7, docs/stability.md), with the debug build.

Both cases are built exactly as tools/stability.py builds them (namelists/crush.nml with the
study's overrides), only shorter:

1. cell-crossing noise: the linear basis gives more crush-force noise than CPDI2 at h = t/2,
   n_t = 4, cfl 0.4. The noise (RMS of the force minus its 20 us moving average, relative to the
   plateau, over an approach of 3-5 mm) is compared with the ratio the study found for the same
   runs (docs/stability/noise_test.csv): it must lie within a factor 1.5 of it and above 2;
2. a deep crush whose CPDI2 domains fold (the study's fast crush to delta/D = 0.95) is stopped:
   exit 4, a message naming the folded domain, the time step and the remedy, a readable last
   good state, and the approach at the fold within 0.03 D of the study's.

    usage: TUBEMPM=build/debug/tubempm python3 -m tests.test_stability_crush SCRATCH
"""
from __future__ import annotations

import glob
import os
import sys
from pathlib import Path

import numpy as np
from plots.mpmplot import namelist, readers, scene
from tools import stability
from tools.batch import run_batch
from tests.pycheck import Checks

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_stability_crush")
check = T.check


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_stability")
    binary = Path(os.environ.get("TUBEMPM", ROOT / "bin" / "tubempm")).resolve()
    study = {r["basis"]: r for r in stability.read_csv("noise_test.csv")}

    # 1. noise: linear against CPDI2
    cases = stability.noise_test_cases()
    fold = None
    for r in stability.read_csv("distort_runs.csv"):
        if r["case"] == "fastcrush_cpdi2_h0p5_nt2":
            fold = r
    fast = stability.crush_case("cpdi2", 0.5, 2, t_end=0.95 * stability.D_CRUSH / 2
                                / stability.FAST, prefix="fastcrush",
                                extra={"run.history_every": 1.0e-6, "run.snapshot_every": 0.0,
                                       "wall.velocity": [0.0, -stability.FAST],
                                       "wall.ramp": 0.0})
    res = run_batch(cases + [fast], scratch, jobs=1, threads=1, binary=binary,
                    log=lambda m: print(m, flush=True))
    noise = {}
    for c, r in zip(cases, res):
        folder = scratch / c.name
        check(r["exit_code"] == 0, f"{c.name}: exit {r['exit_code']}")
        h = readers.read_history(folder / "history.csv")
        disp, force, _ = scene.crush_displacement(h, namelist.read_namelist(folder /
                                                                             "input.nml"))
        dt_row = float(np.median(np.diff(h["time"])))
        noise[c.labels["basis"]] = stability.force_noise(disp, force, stability.TEST_WINDOW,
                                                         dt_row)
    ratio = noise["linear"] / noise["cpdi2"]
    ref = study["linear"]["noise_test_window"] / study["cpdi2"]["noise_test_window"]
    print(f"noise over 3-5 mm: linear {noise['linear']:.3f}, cpdi2 {noise['cpdi2']:.3f}, "
          f"ratio {ratio:.2f} (study {ref:.2f})")
    check(ratio > 2.0, f"linear/cpdi2 noise ratio {ratio:.2f} not above 2")
    check(ref / 1.5 <= ratio <= ref * 1.5,
          f"linear/cpdi2 noise ratio {ratio:.2f} not within a factor 1.5 of the study's {ref:.2f}")

    # 2. the fold is caught
    r = res[-1]
    folder = scratch / fast.name
    log = (folder / "run.log").read_text(errors="replace")
    check(r["exit_code"] == 4, f"fast deep crush: exit {r['exit_code']}, expected 4")
    check("folded CPDI2 domain" in log and "time step dt =" in log and "Remedy" in log,
          "fast deep crush: the message does not name the fold, the time step and the remedy")
    summ = readers.read_summary(folder / "summary.nml")
    check(summ.get("status") == "unstable" and summ.get("min_corner_jacobian", 1.0) <= 0.0,
          f"fast deep crush: summary {summ.get('status')}, "
          f"min_corner_jacobian {summ.get('min_corner_jacobian')}")
    crash = glob.glob(str(folder / "crash_*.h5"))
    ok = len(crash) == 1
    if ok:
        fr = readers.read_frame(crash[0])
        m = stability.quad_measures(fr)
        ok = bool(np.all(np.isfinite(fr["corners"])) and np.min(m["jmin"]) > 0.0)
        print(f"last good state {os.path.basename(crash[0])}: smallest corner Jacobian ratio "
              f"{np.min(m['jmin']):.3f} (not folded)")
    check(ok, "fast deep crush: no readable, unfolded last good state")
    h = readers.read_history(folder / "history.csv")
    disp, _, _ = scene.crush_displacement(h, namelist.read_namelist(folder / "input.nml"))
    d_fold = float(disp[-1]) / stability.D_CRUSH
    print(f"fold at delta/D = {d_fold:.3f} (study: {fold['delta_fold'] if fold else 'none'})")
    check(fold is not None and abs(d_fold - fold["delta_fold"]) <= 0.03,
          "fast deep crush: fold not where the study found it")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
