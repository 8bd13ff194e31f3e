#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Cross-checks of the project's explicit FE code (xfe) against CalculiX (ccx 2.20) in dynamics.

1. ``block``: an elastic plane-strain block (half of it, mirror x = 0; 10 mm x 20 mm,
   aluminium E 70 GPa, nu 0.33, rho 2700) whose base y = 0 is moved up by the wave scene's
   platen pulse (10 m/s times the table 0, 1, 1, 0 at 0, 2, 10, 12 us), the base nodes tied
   to it (u_y prescribed, u_x free). ccx: *DYNAMIC (implicit, alpha = 0), CPE8 (full
   integration: ccx 2.20's CPE8R carries half the mass in *DYNAMIC, its 1-D wave runs at
   sqrt(2) c_d; CPE8 gives the 1-D plane-strain wave to 0.4 %), fixed increments;
   xfe: Q4 mean dilatation, explicit, the tied wall. Compared: v_y at four points
   (their arrival times at 10 % of the peak, tools/study.py's rule, and the RMS difference of
   the histories over the largest value).
2. ``crush``: xfe on the quasi-static crush (the bottom quarter of namelists/crush.nml's ring,
   mirrors x = 0 and y = y_c, the platen at the study's 2.5 m/s approach after its 0.5 ms
   ramp) against the static CalculiX curve docs/fe_reference/crush_fe.csv: mean force and
   relative L2 difference over delta/D = 0.05-0.5 (tools/fe_reference/fe_reference.py's).

An elastic ring impact in ccx 2.20 (*DYNAMIC with a penalty contact on a rigid strip) did not
get past the first contact: its increments fell below 1e-11 s or it stopped on "too many
cutbacks" (penalties 10 E and 1 E per mm, alpha -0.05 and -0.2), so the contact of the impact
is checked against closed forms only (tests/test_fe_dynamic.py).

Runs go to out/fe_dynamic/ccx/, the numbers to docs/fe_reference/ccx_dynamic.json.

    python3 -m tools.fe_reference.ccx_dynamic [--cases block crush] [--crush-nt 2 4 8]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from plots.mpmplot import analysis, namelist, readers, scene
from tools.fe_reference import fe_dynamic
from tools import study

ROOT = Path(__file__).resolve().parent.parent.parent

WORK = ROOT / "out" / "fe_dynamic" / "ccx"
DOCS = ROOT / "docs" / "fe_reference"
E, NU, RHO = 70.0e9, 0.33, 2700.0
TABLE_T = [0.0, 2.0e-6, 1.0e-5, 1.2e-5]
TABLE_F = [0.0, 1.0, 1.0, 0.0]
SPEED = 10.0
#: block: half width, height [m]; probes [m]
BLOCK = (10.0e-3, 20.0e-3)
BLOCK_PROBES = [(0.0, 10.0e-3), (0.0, 20.0e-3), (5.0e-3, 20.0e-3), (10.0e-3, 10.0e-3)]
BLOCK_T_END = 2.0e-5


def _num(x: float) -> str:
    return f"{x:.12g}"


def wall_position(t: float) -> float:
    """The table's platen travel [m] at t (exact integral of the piecewise-linear velocity)."""
    y = 0.0
    for i in range(1, len(TABLE_T)):
        a, b = TABLE_T[i - 1], min(t, TABLE_T[i])
        if b > a:
            fa = TABLE_F[i - 1]
            fb = TABLE_F[i - 1] + (TABLE_F[i] - TABLE_F[i - 1]) * (b - a) / (TABLE_T[i] - a)
            y += 0.5 * (b - a) * SPEED * (fa + fb)
    return y


def quad8_grid(nx: int, ny: int, x0: float, x1: float, y0: float, y1: float):
    """Structured CPE8R mesh of a rectangle (mm): nodes {id: (x, y)}, elements, node index."""
    ni, nj = 2 * nx + 1, 2 * ny + 1

    def nid(i: int, j: int) -> int:
        return 1 + i + ni * j

    nodes = {}
    for j in range(nj):
        for i in range(ni):
            if i % 2 == 1 and j % 2 == 1:
                continue
            nodes[nid(i, j)] = (x0 + (x1 - x0) * i / (ni - 1), y0 + (y1 - y0) * j / (nj - 1))
    elems = []
    for jj in range(ny):
        for ii in range(nx):
            i, j = 2 * ii, 2 * jj
            elems.append((nid(i, j), nid(i + 2, j), nid(i + 2, j + 2), nid(i, j + 2),
                          nid(i + 1, j), nid(i + 2, j + 1), nid(i + 1, j + 2), nid(i, j + 1)))
    return nodes, elems, nid, ni, nj


def _lines(ids, per: int = 12) -> str:
    ids = list(ids)
    return "\n".join(", ".join(str(i) for i in ids[k:k + per]) for k in range(0, len(ids), per))


def block_deck(nx: int, ny: int, dt: float) -> tuple[str, list[int]]:
    """The ccx deck of the block (mm, N, s, tonne); returns the deck and the probe node ids."""
    w, hgt = BLOCK[0] * 1e3, BLOCK[1] * 1e3
    nodes, elems, nid, ni, nj = quad8_grid(nx, ny, 0.0, w, 0.0, hgt)
    probes = []
    for px, py in BLOCK_PROBES:
        i = round(px * 1e3 / w * (ni - 1))
        j = round(py * 1e3 / hgt * (nj - 1))
        probes.append(nid(i, j))
    amp = []
    tt = np.linspace(0.0, TABLE_T[-1], 241)
    for t in list(tt) + [BLOCK_T_END]:
        amp.append(f"{_num(t)}, {_num(wall_position(t) * 1e3)}")
    out = ["** tubempm: ccx cross-check of xfe (tools/fe_reference/ccx_dynamic.py): block wave",
           "*NODE, NSET=NALL"]
    out += [f"{k}, {_num(x)}, {_num(y)}" for k, (x, y) in sorted(nodes.items())]
    out.append("*ELEMENT, TYPE=CPE8, ELSET=EALL")
    out += [f"{e + 1}, " + ", ".join(map(str, c)) for e, c in enumerate(elems)]
    out += ["*NSET, NSET=NBASE", _lines(nid(i, 0) for i in range(ni)),
            "*NSET, NSET=NMIRROR", _lines(nid(0, j) for j in range(nj)),
            "*NSET, NSET=NPROBE", _lines(probes),
            "*AMPLITUDE, NAME=PULSE", *amp,
            "*MATERIAL, NAME=AL", "*ELASTIC", f"{_num(E / 1e6)}, {_num(NU)}",
            "*DENSITY", f"{_num(RHO * 1e-12)}",
            "*SOLID SECTION, ELSET=EALL, MATERIAL=AL", "1.0",
            "*BOUNDARY", "NMIRROR, 1, 1",
            f"*STEP, INC={int(BLOCK_T_END / dt) + 10}",
            "*DYNAMIC, ALPHA=0.0, DIRECT",
            f"{_num(dt)}, {_num(BLOCK_T_END)}",
            "*BOUNDARY, AMPLITUDE=PULSE", "NBASE, 2, 2, 1.0",
            "*NODE PRINT, NSET=NPROBE", "U",
            "*END STEP", ""]
    return "\n".join(out), probes


def parse_velocities(path: Path, probes: list[int]) -> tuple[np.ndarray, np.ndarray]:
    """Times and v_y [m/s] of the probe nodes from ccx's .dat: ccx 2.20 prints zero
    velocities in *DYNAMIC, so the displacement blocks are read and differentiated (central
    differences on the fixed increments)."""
    times, rows = [], []
    cur: dict[int, float] = {}
    tm = None
    for line in path.read_text().splitlines():
        s = line.strip()
        if s.startswith("displacements"):
            if tm is not None:
                times.append(tm)
                rows.append([cur.get(p, math.nan) for p in probes])
            tm = float(s.split()[-1])
            cur = {}
            continue
        parts = s.split()
        if tm is not None and len(parts) == 4:
            try:
                cur[int(parts[0])] = float(parts[2]) * 1e-3
            except ValueError:
                pass
    if tm is not None:
        times.append(tm)
        rows.append([cur.get(p, math.nan) for p in probes])
    t = np.concatenate([[0.0], np.array(times)])
    u = np.vstack([np.zeros((1, len(probes))), np.array(rows)])
    return t, np.gradient(u, t, axis=0)


def run_ccx(folder: Path, name: str, deck: str) -> float:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.inp").write_text(deck)
    r0 = os.times()
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1")
    subprocess.run(["ccx", "-i", name], cwd=folder, check=True, env=env,
                   stdout=open(folder / "ccx.log", "w"), stderr=subprocess.STDOUT)
    r1 = os.times()
    return (r1.children_user - r0.children_user) + (r1.children_system - r0.children_system)


def block_xfe(binary: Path, folder: Path, nx: int, ny: int) -> dict:
    vals = {"shape": "rect", "lower": [0.0, 0.0], "upper": list(BLOCK), "nx": nx, "ny": ny,
            "mirror_x": True, "E": E, "nu": NU, "rho": RHO, "sigma_y": 0.0, "hardening": 0.0,
            "wall_tied": True, "wall_speed": SPEED, "motion_t": TABLE_T, "motion_f": TABLE_F,
            "t_end": BLOCK_T_END, "cfl": fe_dynamic.CFL, "history_every": 2.0e-8,
            "probe_x": [p[0] for p in BLOCK_PROBES], "probe_y": [p[1] for p in BLOCK_PROBES],
            "output": str(folder / "history.csv")}
    fe_dynamic.run_case(binary, folder, vals)
    return readers.read_history(folder / "history.csv")


def compare_block(binary: Path) -> dict:
    res: dict = {"case": "block", "probes_m": BLOCK_PROBES, "ccx": {}, "xfe": {}}
    curves = {}
    for nx, ny in ((10, 20), (20, 40)):
        dt = 2.0e-8
        deck, probes = block_deck(nx, ny, dt)
        name = f"block_{nx}x{ny}"
        folder = WORK / name
        cpu = run_ccx(folder, name, deck)
        t, vy = parse_velocities(folder / f"{name}.dat", probes)
        arr = analysis.arrival_times(t, np.abs(vy), study.ARRIVAL_THRESHOLD)
        res["ccx"][f"CPE8 {nx}x{ny}"] = {"dt": dt, "cpu_s": round(cpu, 1),
                                          "arrivals_us": [float(a * 1e6) for a in arr]}
        curves[f"ccx{nx}"] = (t, vy)
    for nx, ny in ((20, 40), (40, 80)):
        h = block_xfe(binary, WORK / f"xfe_block_{nx}x{ny}", nx, ny)
        vy = np.column_stack([h[f"probe{k}_vy"] for k in range(1, 5)])
        arr = analysis.arrival_times(h["time"], np.abs(vy), study.ARRIVAL_THRESHOLD)
        res["xfe"][f"Q4 {nx}x{ny}"] = {"arrivals_us": [float(a * 1e6) for a in arr]}
        curves[f"xfe{nx}"] = (h["time"], vy)
    tr, vr = curves["ccx20"]
    for key in ("ccx10", "xfe20", "xfe40"):
        t, v = curves[key]
        diff = [float(np.sqrt(np.mean((np.interp(tr, t, v[:, k]) - vr[:, k]) ** 2))
                      / np.max(np.abs(vr[:, k]))) for k in range(vr.shape[1])]
        res.setdefault("rms_vs_ccx_20x40", {})[key] = diff
    return res


#: the quasi-static crush with xfe: relative approach speed [m/s] and ramp [s] (tools/study.py)
CRUSH_SPEED = study.CRUSH_APPROACH
CRUSH_RAMP = study.CRUSH_RAMP


def crush_xfe(binary: Path, n_t: int, delta_end: float = 0.52) -> dict:
    """xfe on the crush's bottom quarter (mirrors x = 0 and y = y_c), the bottom platen moving
    up at half the study's approach speed after its ramp (the top one is its mirror image),
    against the static CalculiX curve docs/fe_reference/crush_fe.csv over delta/D 0.05-0.5."""
    from tools.fe_reference import fe_reference as fr
    c = fr.read_crush(fr.CASE)
    r_in, r_out = c.r_inner * 1e-3, c.r_outer * 1e-3
    D = c.D * 1e-3
    inputs = namelist.read_namelist(fr.CASE)
    rho = float(scene.ring_properties(inputs)["rho"])
    t_end = 0.5 * CRUSH_RAMP + 0.5 * delta_end * D / (0.5 * CRUSH_SPEED)
    folder = WORK / f"xfe_crush_nt{n_t}"
    vals = {"shape": "ring", "sector": "quarter", "r_inner": r_in, "r_outer": r_out,
            "center": [0.0, r_out], "n_t": n_t, "E": c.E * 1e6, "nu": c.nu, "rho": rho,
            "sigma_y": c.sigma_y * 1e6, "hardening": c.hardening * 1e6, "wall_y": 0.0,
            "wall_speed": 0.5 * CRUSH_SPEED, "motion_t": [0.0, CRUSH_RAMP],
            "motion_f": [0.0, 1.0], "t_end": t_end, "cfl": fe_dynamic.CFL,
            "history_every": 1.0e-5, "output": str(folder / "history.csv")}
    cpu = fe_dynamic.run_case(binary, folder, vals)
    h = readers.read_history(folder / "history.csv")
    delta = -2.0 * h["wall1_disp"]
    force = h["wall1_force"]
    ref_d, ref_f = fr.read_csv(DOCS / "crush_fe.csv")
    w = fr.window(delta, force, D)
    wr = fr.window(ref_d, ref_f, D)
    # the dynamic run's inertia oscillation removed: tools/study.py's moving average over
    # delta/D = SMOOTH_WIDTH
    step = float(np.median(np.diff(delta[delta > 0.05 * D]))) / D
    smooth = fr.window(delta, analysis.moving_average(force, int(round(study.SMOOTH_WIDTH / step))),
                       D)
    inw = (delta >= 0.05 * D) & (delta <= 0.5 * D)
    ratio = float(np.max(h["kinetic"][inw] / np.maximum(h["plastic"][inw], 1e-30)))
    return {"n_t": n_t, "cpu_s": round(cpu, 1), "t_end": t_end,
            "force_mean_N": float(np.mean(w)), "force_mean_ccx_N": float(np.mean(wr)),
            "mean_over_ccx": float(np.mean(w) / np.mean(wr)),
            "err_L2_vs_ccx": fr.rel_l2(w, wr), "err_L2_smoothed_vs_ccx": fr.rel_l2(smooth, wr),
            "max_kinetic_over_plastic": ratio}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="+", default=["block", "crush"], choices=["block", "crush"])
    ap.add_argument("--crush-nt", type=int, nargs="+", default=[2, 4, 8])
    args = ap.parse_args(argv)
    binary = fe_dynamic.build()
    path = DOCS / "ccx_dynamic.json"
    out = json.loads(path.read_text()) if path.is_file() else {}
    for case in args.cases:
        t0 = time.time()
        if case == "block":
            out["block"] = compare_block(binary)
        elif case == "crush":
            out["crush"] = {"case": "crush", "xfe": [crush_xfe(binary, n) for n in args.crush_nt]}
        print(json.dumps(out[case], indent=1), f"({time.time() - t0:.0f} s)")
    path.write_text(json.dumps(out, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
