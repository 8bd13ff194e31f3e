#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The accuracy limit of the time step (``make cfl-accuracy``): for each basis x scheme, at 1 and
2 particles per cell through the wall, the largest cfl at which an elastic ring striking a rigid
frictionless wall keeps its energy within TOL of its initial kinetic energy over the contact and
the rebound. The exact solution conserves energy, so the error is the scheme's alone; it grows
about linearly with the time step (the wall's contact is first order in dt).

The scene is the study's impact ring (namelists/impact.nml: r 24/26 mm, 30 m/s, half model),
elastic, at the stability study's two densities (h = t/2 and t/4, n_thick 4). The scan starts
at the stability study's automatic cfl (0.5 x its stable limit, docs/stability/cfl_limits_ppc*
.csv) and goes down the multiples of STEP below it (from 4 STEP where it found no stable cfl);
the accurate cfl is the first value whose run completes within TOL (0: none down to STEP).

Tables: docs/stability/cfl_accuracy_ppc1.csv, cfl_accuracy_ppc2.csv (basis, scheme,
accurate_cfl, error_at_accurate, next_cfl, error_at_next, stable_auto_cfl) and
cfl_accuracy_runs.csv (every run). tools/advice_tables.py compiles the accurate cfl into
src/method/mpm_time_step_table.inc, where the automatic cfl of a dynamic scene takes it
(docs/stability.md#the-automatic-cfl). Runs go to build/cfl_accuracy/ (reused when the input
is unchanged). About 10 CPU minutes, two runs at a time.

    python3 -m tools.cfl_accuracy [--exe bin/tubempm] [--jobs 2]
"""
from __future__ import annotations

import argparse
import csv
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from tools import batch

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
DOCS = ROOT / "docs" / "stability"
RUNS = ROOT / "build" / "cfl_accuracy"
BASES = ("linear", "ugimp", "cpdi1", "cpdi2")
SCHEMES = ("usl", "usf", "musl")
TOL = 0.01          # energy error of the elastic impact [-]
STEP = 0.0625       # cfl scan step [-]
MARGIN = 0.5        # the stability-based automatic cfl: MARGIN x the stable limit
T_WALL = 2.0e-3     # the ring's wall [m]
DENSITY = {"ppc2": T_WALL / 2, "ppc1": T_WALL / 4}   # h for n_thick 4


def case_text(basis: str, scheme: str, h: float, cfl: float, out: Path) -> str:
    """The elastic impact at one setting."""
    return (f"&run title = 'acc', t_end = 4.0e-4, cfl = {cfl!r}, history_every = 2.0e-6, "
            f"snapshot_every = 1.0, output_dir = '{out}' /\n"
            f"&solver basis = '{basis}', scheme = '{scheme}', plane = 'strain' /\n"
            f"&grid h = {h!r} /\n"
            "&material name = 'al', model = 'elastic', E = 70.0e9, nu = 0.33, rho = 2700.0 /\n"
            "&body shape = 'ring', material = 'al', center = 0.0, 0.0265, r_inner = 24.0e-3, "
            "r_outer = 26.0e-3, n_thick = 4, sector = 'half', velocity = 0.0, -30.0 /\n"
            "&wall point = 0.0, 0.0, normal = 0.0, 1.0, contact = 'frictionless' /\n")


def run_one(exe: str, basis: str, scheme: str, ppc: str, cfl: float) -> tuple[bool, float]:
    """(completed, energy error) of one run; reused when its input is unchanged."""
    folder = RUNS / f"{ppc}_{basis}_{scheme}_cfl{cfl:.4f}"
    folder.mkdir(parents=True, exist_ok=True)
    text = case_text(basis, scheme, DENSITY[ppc], cfl, folder / "out")
    nml = folder / "case.nml"
    summary = folder / "out" / "summary.nml"
    if not (nml.is_file() and nml.read_text() == text and summary.is_file()):
        nml.write_text(text)
        subprocess.run([exe, "--quiet", str(nml)], capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    fields = batch.read_summary(folder / "out")
    if not fields:
        return False, float("nan")
    return fields.get("status") == "completed", float(fields.get("energy_error", "nan"))


def stable_auto(ppc: str) -> dict[tuple[str, str], float]:
    """MARGIN x the stability study's stable cfl (0 where it found none)."""
    with open(DOCS / f"cfl_limits_{ppc}.csv", newline="") as fh:
        return {(r["basis"], r["scheme"]): MARGIN * float(r["stable_cfl"])
                for r in csv.DictReader(fh)}


def scan(exe: str, basis: str, scheme: str, ppc: str, top: float, runs: list) -> dict:
    """The row of the accuracy table: the stability-based automatic value first, then the
    multiples of STEP below it, downwards (from 4 STEP where the study found no stable cfl),
    until a run keeps its energy within TOL."""
    if top > 0.0:
        values = [top] + [STEP * k for k in range(int(top / STEP - 1e-9), 0, -1)]
    else:
        values = [STEP * k for k in range(4, 0, -1)]
    best, best_err, nxt, nxt_err = 0.0, float("nan"), float("nan"), float("nan")
    for cfl in values:
        done, err = run_one(exe, basis, scheme, ppc, cfl)
        runs.append({"ppc": ppc, "basis": basis, "scheme": scheme, "cfl": cfl,
                     "completed": int(done), "energy_error": err})
        if done and err <= TOL:
            best, best_err = cfl, err
            break
        nxt, nxt_err = cfl, err
    return {"basis": basis, "scheme": scheme, "accurate_cfl": best,
            "error_at_accurate": best_err, "next_cfl": nxt, "error_at_next": nxt_err,
            "stable_auto_cfl": top}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--exe", default=str(ROOT / "bin" / "tubempm"))
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args(argv)
    if not Path(a.exe).is_file():
        print(f"ERROR [cfl_accuracy]: {a.exe} not found: build it with make", file=sys.stderr)
        return 2
    runs: list[dict] = []
    for ppc in ("ppc2", "ppc1"):
        auto = stable_auto(ppc)
        combos = [(b, s) for b in BASES for s in SCHEMES]
        with ThreadPoolExecutor(max_workers=a.jobs) as pool:
            rows = list(pool.map(lambda bs: scan(a.exe, bs[0], bs[1], ppc, auto[bs], runs),
                                 combos))
        with open(DOCS / f"cfl_accuracy_{ppc}.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]), lineterminator="\n")
            w.writeheader()
            for r in rows:
                w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
        for r in rows:
            print(f"{ppc} {r['basis']:7s} {r['scheme']:5s} accurate cfl {r['accurate_cfl']:.4f} "
                  f"(error {r['error_at_accurate']:.4f}; next {r['next_cfl']:.4f}: "
                  f"{r['error_at_next']:.4f}; stability-based {r['stable_auto_cfl']:.4f})")
    runs.sort(key=lambda r: (r["ppc"], r["basis"], r["scheme"], r["cfl"]))
    with open(DOCS / "cfl_accuracy_runs.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(runs[0]), lineterminator="\n")
        w.writeheader()
        for r in runs:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
