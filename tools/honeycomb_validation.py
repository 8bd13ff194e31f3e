#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Honeycomb panels against Gibson & Ashby's closed forms (``make validate-honeycomb``;
docs/validation.md#honeycomb-cells).

The scene: one cell of a honeycomb panel (`&body shape = 'honeycomb'`, n_cells = 1, 1) between
two 'slip' mirror planes through the centrelines of its vertical walls, compressed along x1 by
moving the right plane; plane strain, E 70 GPa, nu 0.3, rho 2700, wall t = 1 mm. It is the
infinite panel under sigma1 (sigma2 = 0) exactly: the vertical lines through the vertical walls
are planes of symmetry of the panel, and under sigma1 the vertical walls carry no load, so the
free edges above and below the row (the cell's top and bottom vertices, where the next row's
vertical walls would join) are those of the infinite panel. Two roof layers of inclined walls
carry the plane's force over a row of period h + l sin(theta): sigma1 = F / (2 (h + l sin
theta)) per metre of depth; eps1 is the plane's travel over the cell's width 2 l cos(theta);
eps2 the change of the distance between the top and bottom vertices (probes) over 2 (h + l sin
theta). The cell is sized so that the planes lie on grid lines (l cos(theta) a whole number of
cells), so t/l is the nominal value to within h/l.

The loading is quasi-static (LOADING): the plane's travel is reached by a smooth velocity ramp
and easing, each `ramp` estimated periods T0 of the cell (the inclined walls' bending, omega =
1.4 c t / l^2), then held for `hold` periods, with mass-proportional damping 2 zeta omega.
- elastic ('elastic'): a travel of EPS_ELASTIC of the width (small: the walls' rotation changes
  E1 by about 2 eps); E1 = sigma1 / eps1 and nu12 = eps2 / eps1 over the last AVERAGE of the run.
- plastic ('j2', hardening 0, sigma_y / E = 5e-5 so that the collapse comes at small strain):
  a travel of PLASTIC_MULTIPLE times the closed form's yield strain sigma_pl / E1; sigma_pl is
  the fixed plane's mean force over the last PLATEAU of the travel, over 2 (h + l sin theta).
With fe (CalculiX installed), the same cell by static finite elements on the run's own particle
mesh (fe_reference/honeycomb_fe.py): the continuum's values, so that the MPM's error and the
continuum's own departure from the beam formulas are told apart.

Cases (SWEEP: model, volumetric, t/l, n_thick with h = t / n_thick) for the regular panel
(theta = +30, h = l) and a re-entrant one (theta = -30, h = 2 l). The table
docs/honeycomb/gibson_ashby.csv has one row per run: the measured values, the closed forms (E1
and nu12 with Gibson & Ashby's corrections for axial and shear wall deformation,
theory.honeycomb_*), the FE values, the ratios and the CPU seconds. Runs go to
build/honeycomb_validation/ (reused when the input is unchanged); one at a time, about 50 CPU
minutes. tests/test_honeycomb.py runs the coarse cases (t/l = 0.1, n_thick = 4).

    python3 -m tools.honeycomb_validation [--exe bin/tubempm] [--no-fe] [--out CSV]
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import subprocess
import sys
from pathlib import Path

from plots.mpmplot import readers, theory
from tools.fe_reference import honeycomb_fe

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

DOCS = ROOT / "docs" / "honeycomb"
RUNS = ROOT / "build" / "honeycomb_validation"
E, NU, RHO = 70.0e9, 0.3, 2700.0
SIGMA_Y = 3.5e6                 # sigma_y / E = 5e-5 [Pa]
T_WALL = 1.0e-3                 # wall thickness [m]
KINDS = {"regular": (30.0, 1.0), "reentrant": (-30.0, 2.0)}    # theta [deg], h/l
EPS_ELASTIC = 2.0e-4
PLASTIC_MULTIPLE = 5.0
# the loading of each model: ramp and hold in periods T0, damping ratio, volumetric treatment
LOADING = {"elastic": {"ramp": 0.75, "hold": 1.0, "zeta": 0.5, "volumetric": "standard"},
           "j2": {"ramp": 3.0, "hold": 0.0, "zeta": 0.05, "volumetric": "standard"}}
AVERAGE = 0.1       # the held values: the last tenth of the run
PLATEAU = 0.4       # the plastic plateau: the last 40 % of the travel
# the runs of make validate-honeycomb: (model, volumetric, t/l, n_thick, particles per cell
# through the wall), each for both kinds
SWEEP = ([("elastic", "standard", tl, n, 1) for tl, n in ((0.1, 2), (0.1, 4), (0.1, 8),
                                                          (0.1, 16), (0.05, 4), (0.05, 8))]
         + [("elastic", "standard", tl, 8, 2) for tl in (0.1, 0.05)]
         + [("elastic", "fbar", 0.1, n, 1) for n in (4, 8)]
         + [("j2", "standard", tl, n, 1) for tl, n in ((0.1, 4), (0.1, 8), (0.05, 4), (0.05, 8))]
         + [("j2", "standard", tl, 8, 2) for tl in (0.1, 0.05)]
         + [("j2", "fbar", 0.1, n, 1) for n in (4, 8)])


def geometry(kind: str, t_l: float, n_thick: int, ppc: int = 1) -> dict[str, float]:
    """The cell of a case: l with l cos(theta) a whole number of grid cells (h = ppc t /
    n_thick: ppc particles per cell through the wall), and the quantities the scene and the
    measurement need [m, rad]."""
    theta_deg, h_l = KINDS[kind]
    th = math.radians(theta_deg)
    hg = T_WALL / n_thick * ppc
    l = round(T_WALL / t_l * math.cos(th) / hg) * hg / math.cos(th)
    es = E / (1.0 - NU * NU)
    omega = 1.4 * math.sqrt(es / RHO) * T_WALL / l ** 2
    return {"theta_deg": theta_deg, "theta": th, "h_l": h_l, "l": l, "h": h_l * l,
            "t": T_WALL, "t_l": T_WALL / l, "grid": hg, "n_thick": n_thick,
            "width": 2.0 * l * math.cos(th), "period": h_l * l + l * math.sin(th),
            "omega": omega, "t0": 2.0 * math.pi / omega}


def closed_forms(g: dict[str, float]) -> dict[str, float]:
    """Gibson & Ashby at the cell's own t/l: E1 and nu12 with and without the corrections, the
    collapse stress and its yield strain."""
    a = (g["t_l"], g["h_l"], g["theta_deg"])
    e1 = theory.honeycomb_e1(*a, E, NU, "strain")
    spl = theory.honeycomb_sigma_pl1(*a, SIGMA_Y, "strain")
    return {"e1": e1, "e1_thin": theory.honeycomb_e1(*a, E, NU, "strain", corrected=False),
            "nu12": theory.honeycomb_nu12(*a, NU, "strain"),
            "nu12_thin": theory.honeycomb_nu12(*a, NU, "strain", corrected=False),
            "sigma_pl": spl, "eps_y": spl / e1}


def case_text(kind: str, t_l: float, n_thick: int, model: str, out: str,
              volumetric: str | None = None, ramp: float | None = None,
              ppc: int = 1) -> tuple[str, dict]:
    """The namelist of one case (`out` is its output folder; volumetric and the ramp in
    periods: LOADING's unless given) and its geometry."""
    g = geometry(kind, t_l, n_thick, ppc)
    load = dict(LOADING[model])
    if ramp is not None:
        load["ramp"] = ramp
    cf = closed_forms(g)
    eps = EPS_ELASTIC if model == "elastic" else PLASTIC_MULTIPLE * cf["eps_y"]
    stroke = eps * g["width"]
    ramp = load["ramp"] * g["t0"]
    t_end = 2.0 * ramp + load["hold"] * g["t0"]
    v = 1.0001 * stroke / ramp        # the ramps' travel alone just reaches the stroke
    yv = 0.5 * g["h"] + g["l"] * math.sin(g["theta"])
    mat = (f"model = 'elastic', E = {E!r}, nu = {NU!r}, rho = {RHO!r}" if model == "elastic"
           else f"model = 'j2', E = {E!r}, nu = {NU!r}, rho = {RHO!r}, sigma_y = {SIGMA_Y!r}, "
                "hardening = 0.0")
    xw = 0.5 * g["width"]
    text = (f"&run title = 'gibson_ashby', output_dir = '{out}', t_end = {t_end!r},\n"
            f"     history_every = {t_end / 400!r}, snapshot_every = {t_end!r} /\n"
            f"&solver plane = 'strain', damping = {2.0 * load['zeta'] * g['omega']!r}, "
            f"volumetric = '{volumetric or load['volumetric']}' /\n"
            f"&grid h = {g['grid']!r} /\n"
            f"&material name = 'wall', {mat} /\n"
            f"&body shape = 'honeycomb', material = 'wall', n_cells = 1, 1, "
            f"cell_l = {g['l']!r},\n      cell_h = {g['h']!r}, cell_angle = {g['theta_deg']!r}, "
            f"thickness = {T_WALL!r}, n_thick = {n_thick}, center = 0.0, 0.0 /\n"
            f"&wall point = {-xw!r}, 0.0, normal = 1.0, 0.0, contact = 'slip' /\n"
            f"&wall point = {xw!r}, 0.0, normal = -1.0, 0.0, contact = 'slip', "
            f"velocity = {-v!r}, 0.0,\n      ramp = {ramp!r}, stroke = {stroke!r} /\n"
            f"&probe point = 0.0, {yv!r} /\n&probe point = 0.0, {-yv!r} /\n")
    g.update(cf)
    g["stroke"] = stroke
    return text, g


def measure(hist: dict, g: dict) -> dict[str, float]:
    """sigma1 and eps1 (compression positive), eps2 (lateral extension positive), E1, nu12
    held over the last AVERAGE of the run, and how settled it is (the held force's change from
    the AVERAGE before, relative); sigma_plateau: the fixed plane's mean force while the
    moving one travels the last PLATEAU of its stroke, over 2 (h + l sin theta)."""
    n = len(hist["time"])
    k = max(1, int(AVERAGE * n))

    def held(x, back: int = 0):
        return float(sum(x[n - k - back:n - back]) / k)

    force = hist["wall2_fx"]                  # the cell pushes the right plane along +x
    sigma1 = held(force) / (2.0 * g["period"])
    eps1 = -held(hist["wall2_disp"]) / g["width"]
    gap = hist["probe1_y"] - hist["probe2_y"]
    eps2 = held(gap - gap[0]) / (2.0 * g["period"])
    travel = -hist["wall2_disp"] / g["stroke"]
    late = [-f for f, s in zip(hist["wall1_fx"], travel) if s >= 1.0 - PLATEAU]
    return {"sigma1": sigma1, "eps1": eps1, "eps2": eps2, "E1": sigma1 / eps1,
            "nu12": eps2 / eps1, "settle": abs(held(force) - held(force, k)) / abs(held(force)),
            "sigma_plateau": sum(late) / len(late) / (2.0 * g["period"])}


def run_case(exe: str, folder: Path, kind: str, t_l: float, n_thick: int, model: str,
             volumetric: str | None = None, reuse: bool = True, fe: bool = False,
             ramp: float | None = None, ppc: int = 1) -> dict:
    """Run (or reuse) one case in folder; its geometry, closed forms, measurements, ratios and
    CPU seconds ({} when the run failed); with fe, also CalculiX's values on the run's own
    particle mesh (fe_reference/honeycomb_fe.py) and the ratios to them."""
    folder.mkdir(parents=True, exist_ok=True)
    text, g = case_text(kind, t_l, n_thick, model, str(folder / "out"), volumetric, ramp, ppc)
    nml = folder / "case.nml"
    summary = folder / "out" / "summary.nml"
    if not (reuse and nml.is_file() and nml.read_text() == text and summary.is_file()):
        nml.write_text(text)
        c0 = os.times()
        res = subprocess.run([exe, "--quiet", str(nml)], capture_output=True, text=True,
                             env=dict(os.environ, OMP_NUM_THREADS="1"))
        c1 = os.times()
        (folder / "cpu_seconds").write_text(f"{c1.children_user - c0.children_user:.2f}\n")
        if res.returncode != 0:
            (folder / "stderr").write_text(res.stderr)
            return {}
    hist = readers.read_history(folder / "out" / "history.csv")
    summ = readers.read_summary(folder / "out" / "summary.nml")
    m = measure(hist, g)
    row = {"kind": kind, "model": model,
           "volumetric": volumetric or LOADING[model]["volumetric"], "t_l": g["t_l"],
           "n_thick": n_thick,
           "h_over_t": ppc / n_thick, "particles": int(summ.get("particles", 0)),
           "steps": int(summ.get("steps", 0)),
           "cpu_s": float((folder / "cpu_seconds").read_text()), **m}
    if model == "elastic":
        row.update(E1_ga=g["e1"], E1_ratio=m["E1"] / g["e1"], E1_ratio_thin=m["E1"] / g["e1_thin"],
                   nu12_ga=g["nu12"], nu12_ratio=m["nu12"] / g["nu12"],
                   nu12_ratio_thin=m["nu12"] / g["nu12_thin"])
    else:
        row.update(sigma_pl=m["sigma_plateau"], sigma_pl_ga=g["sigma_pl"],
                   sigma_pl_ratio=m["sigma_plateau"] / g["sigma_pl"],
                   eps_end_over_eps_y=m["eps1"] / g["eps_y"])
        for k in ("sigma1", "eps2", "E1", "nu12", "settle"):
            row.pop(k)
    if fe:
        f = honeycomb_fe.run(folder / "out" / "particles.h5", g, model, folder / "fe",
                             g["stroke"], E, NU, SIGMA_Y, PLATEAU)
        if model == "elastic":
            row.update(E1_fe=f["E1"], nu12_fe=f["nu12"], E1_mpm_over_fe=m["E1"] / f["E1"],
                       nu12_mpm_over_fe=m["nu12"] / f["nu12"], E1_fe_over_ga=f["E1"] / g["e1"],
                       nu12_fe_over_ga=f["nu12"] / g["nu12"])
        else:
            row.update(sigma_pl_fe=f["sigma_pl"],
                       sigma_pl_mpm_over_fe=m["sigma_plateau"] / f["sigma_pl"],
                       sigma_pl_fe_over_ga=f["sigma_pl"] / g["sigma_pl"])
        row["fe_cpu_s"] = f["cpu_s"]
    return row


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--exe", default=str(ROOT / "bin" / "tubempm"))
    ap.add_argument("--no-fe", action="store_true", help="no CalculiX reference")
    ap.add_argument("--out", default=str(DOCS / "gibson_ashby.csv"))
    args = ap.parse_args()
    rows = []
    for model, vol, t_l, n, ppc in SWEEP:
        for kind in KINDS:
            name = f"{kind}_{model}_{vol}_tl{t_l:g}_n{n}" + (f"_ppc{ppc}" if ppc != 1 else "")
            row = run_case(args.exe, RUNS / name, kind, t_l, n, model, vol, fe=not args.no_fe,
                           ppc=ppc)
            if not row:
                print(f"{name}: FAILED (see {RUNS / name}/stderr)", flush=True)
                continue
            rows.append(row)
            if model == "elastic":
                print(f"{name}: E1/GA {row['E1_ratio']:.4f}, nu12/GA {row['nu12_ratio']:.4f}, "
                      f"E1/FE {row.get('E1_mpm_over_fe', math.nan):.4f} "
                      f"({row['cpu_s']:.1f} CPU s)", flush=True)
            else:
                print(f"{name}: sigma_pl/GA {row['sigma_pl_ratio']:.4f}, /FE "
                      f"{row.get('sigma_pl_mpm_over_fe', math.nan):.4f} "
                      f"({row['cpu_s']:.1f} CPU s)", flush=True)
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys, restval="")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
