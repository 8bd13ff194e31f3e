#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""tubempm's impact and wave against the dynamic finite element references.

Runs tubempm (bin/tubempm, one thread, one run at a time; finished runs in
out/fe_dynamic/mpm/ are reused while their input is unchanged) at:

- ``default``: namelists/default.nml as shipped (h = t/4, n_t = 8, CPDI2, MUSL, F-bar,
  cfl 0.8; history every 1 us as the study's impact, so that the 10 us mean peak is measured on
  the same sampling as the FE's);
- ``impact``: namelists/impact.nml with tools/study.py's overrides (t_end 0.9 ms);
- ``wave``: namelists/wave.nml with the study's overrides (t_end 30 us, history every 0.1 us);
- ``wave_default``: the same with default.nml's solver settings (F-bar, cfl 0.8);
- ``impact_p4``, ``wave_p1``: default.nml with `&wall penalty = 4`, wave.nml with the default
  penalty (1);

measures them with tools/study.py's impact_metrics and wave_metrics, exactly as the FE runs
are measured (tools/fe_reference/fe_dynamic.py), prints the errors against the finest FE mesh
and writes docs/fe_reference/dynamic_errors.csv. With ``--study`` it also measures every
impact and wave run of the committed refinement study (docs/study/study_full.csv and the
arrival curves docs/study/curves/wave_*.csv) against the FE reference:
docs/fe_reference/dynamic_errors_study.csv.

    python3 -m tools.fe_reference.compare_dynamic [--study] [--only default wave]
    python3 -m tools.fe_reference.compare_dynamic --wave out/wave   # your own wave run
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import sys
from pathlib import Path

import numpy as np

from plots.mpmplot import namelist, readers
from tools import batch
from tools import study

ROOT = Path(__file__).resolve().parent.parent.parent

DOCS = ROOT / "docs" / "fe_reference"
WORK = ROOT / "out" / "fe_dynamic" / "mpm"
CONVERGENCE = DOCS / "dynamic_convergence.json"
#: the issue's target for the arrival times [s]
ARRIVAL_TARGET = 0.3e-6
IMPACT_KEYS = ("duration", "v_rebound", "cor", "plastic_end", "peak_10us")


def cases() -> dict[str, batch.Case]:
    imp = dict(study.SCENES["impact"]["set"], **{"run.threads": 1})
    wav = dict(study.SCENES["wave"]["set"], **{"run.threads": 1})
    return {
        "default": batch.Case("default", ROOT / "namelists" / "default.nml",
                              {"run.history_every": 1.0e-6, "run.threads": 1}),
        "impact": batch.Case("impact", study.SCENES["impact"]["base"], imp),
        "wave": batch.Case("wave", study.SCENES["wave"]["base"], wav),
        "wave_default": batch.Case("wave_default", study.SCENES["wave"]["base"],
                                   dict(wav, **{"solver.volumetric": "fbar", "run.cfl": 0.8})),
        # the shipped settings with the other wall penalty: the impact with penalty 4, the wave
        # with the default (1)
        "impact_p4": batch.Case("impact_p4", ROOT / "namelists" / "default.nml",
                                {"run.history_every": 1.0e-6, "run.threads": 1,
                                 "wall.penalty": 4.0}),
        "wave_p1": batch.Case("wave_p1", study.SCENES["wave"]["base"],
                              dict(wav, **{"wall.penalty": 1.0})),
    }


def fe_reference() -> dict:
    if not CONVERGENCE.is_file():
        raise SystemExit(f"{CONVERGENCE} missing: run tools/fe_reference/fe_dynamic.py first")
    return json.loads(CONVERGENCE.read_text())


def impact_of(folder: Path, base: Path) -> dict:
    inputs = namelist.read_namelist(base)
    m = study.impact_metrics(folder, inputs)
    h = readers.read_history(folder / "history.csv")
    return {"duration": m["duration"], "cor": m["cor"], "v_rebound": m["cor"] * m["v_impact"],
            "peak_10us": m["peak_10us"], "plastic_end": float(h["plastic"][-1])}


def wave_of(folder: Path, base: Path) -> list[float]:
    inputs = namelist.read_namelist(base)
    return [float(a) for a in study.wave_metrics(folder, inputs)["arrivals"]]


def impact_rows(setting: str, mpm: dict, fe: dict) -> list[dict]:
    est = fe["impact"]["estimate"]
    rows = []
    for k in IMPACT_KEYS:
        ref = est[k]["finest"] if k in est else fe["impact"]["meshes"][-1][k]
        err = mpm[k] - ref
        rows.append({"setting": setting, "quantity": k, "probe": "", "mpm": mpm[k], "fe": ref,
                     "fe_error": est[k]["error"] if k in est else math.nan,
                     "error": err, "rel_error": err / ref if ref else math.nan, "target": "",
                     "within_target": ""})
    return rows


def wave_rows(setting: str, arrivals: list[float], fe: dict) -> list[dict]:
    est = fe["wave"]["estimate"]
    angles = fe["wave"]["meshes"][-1]["angles"]
    rows = []
    for j, a in enumerate(arrivals):
        ref = est[f"arrival_{j + 1}"]["finest"]
        err = a - ref
        rows.append({"setting": setting, "quantity": "arrival", "probe": f"{angles[j]:.0f}",
                     "mpm": a, "fe": ref, "fe_error": est[f"arrival_{j + 1}"]["error"],
                     "error": err, "rel_error": err / ref if ref else math.nan,
                     "target": ARRIVAL_TARGET,
                     "within_target": int(abs(err) <= ARRIVAL_TARGET)})
    return rows


def write_rows(path: Path, rows: list[dict]) -> None:
    keys = list(rows[0].keys())
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def print_rows(rows: list[dict]) -> None:
    for r in rows:
        if r["quantity"] == "arrival":
            print(f"  {r['setting']:13s} arrival {r['probe']:>4s} deg: MPM {r['mpm'] * 1e6:8.3f} "
                  f"us, FE {r['fe'] * 1e6:8.3f} +- {r['fe_error'] * 1e6:.3f} us, error "
                  f"{r['error'] * 1e6:+7.3f} us {'ok' if r['within_target'] else 'OVER 0.3 us'}")
        else:
            print(f"  {r['setting']:13s} {r['quantity']:11s}: MPM {r['mpm']:.6g}, FE {r['fe']:.6g}"
                  f" (+- {r['fe_error']:.2g}), error {r['rel_error'] * 100:+.2f} %")


def study_rows(fe: dict) -> list[dict]:
    """Every committed impact and wave run of the refinement study against the FE."""
    rows = []
    est_i = fe["impact"]["estimate"]
    est_w = fe["wave"]["estimate"]
    with open(ROOT / "docs" / "study" / "study_full.csv", newline="") as fh:
        table = list(csv.DictReader(fh))
    for r in table:
        if r["scene"] == "impact" and r["status"] == "completed" and \
                float(r["speed"] or 0.0) == 30.0:          # the FE reference's speed
            out = {"name": r["name"], "cpu_s": r["cpu_s"]}
            for k in ("duration", "cor", "peak_10us"):
                v = float(r[k]) if r[k] else math.nan
                out[f"err_{k}"] = v / est_i[k]["finest"] - 1.0
            rows.append(out)
        elif r["scene"] == "wave" and r["status"] == "completed":
            path = ROOT / "docs" / "study" / "curves" / f"{r['name']}.csv"
            if not path.is_file():
                continue
            arr = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)[:, 1]
            ref = np.array([est_w[f"arrival_{j + 1}"]["finest"] for j in range(len(arr))])
            d = arr - ref
            rows.append({"name": r["name"], "cpu_s": r["cpu_s"],
                         "max_abs_arrival_error_us": float(np.nanmax(np.abs(d)) * 1e6),
                         "mean_arrival_error_us": float(np.nanmean(d) * 1e6),
                         "probes_within_0.3us": int(np.sum(np.abs(d) <= ARRIVAL_TARGET))})
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", nargs="+", default=list(cases()),
                    help=f"the settings to run and compare (default all: {', '.join(cases())})")
    ap.add_argument("--study", action="store_true",
                    help="also every impact and wave run of the committed refinement study")
    ap.add_argument("--wave", metavar="OUTDIR",
                    help="time a wave run of your own (OUTDIR with its history.csv and "
                         "input.nml; the probes of namelists/wave.nml) at the FE reference's "
                         "levels, print its arrival errors and stop (runs nothing)")
    args = ap.parse_args(argv)
    fe = fe_reference()
    if args.wave:
        out = Path(args.wave)
        rows = wave_rows(out.name, wave_of(out, out / "input.nml"), fe)
        print_rows(rows)
        return 0
    cs = cases()
    todo = [cs[k] for k in args.only]
    batch.run_batch(todo, WORK, jobs=1, threads=1)
    rows: list[dict] = []
    for c in todo:
        folder = WORK / c.name
        if c.name.startswith("wave"):
            rows += wave_rows(c.name, wave_of(folder, c.base), fe)
        else:
            rows += impact_rows(c.name, impact_of(folder, c.base), fe)
    print_rows(rows)
    path = DOCS / "dynamic_errors.csv"
    if path.is_file():          # the settings not run this time keep their committed rows
        with open(path, newline="") as fh:
            kept = [r for r in csv.DictReader(fh) if r["setting"] not in args.only]
        rows = kept + [{k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()}
                       for r in rows]
        order = list(cases())
        rows.sort(key=lambda r: order.index(r["setting"]) if r["setting"] in order else 99)
    write_rows(path, rows)
    print(f"wrote {DOCS / 'dynamic_errors.csv'}")
    if args.study:
        srows = study_rows(fe)
        imp = [r for r in srows if "err_duration" in r]
        wav = [r for r in srows if "max_abs_arrival_error_us" in r]
        write_rows(DOCS / "dynamic_errors_study_impact.csv", imp)
        write_rows(DOCS / "dynamic_errors_study_wave.csv", wav)
        print(f"wrote {len(imp)} impact and {len(wav)} wave rows of the study")
    return 0


if __name__ == "__main__":
    sys.exit(main())
