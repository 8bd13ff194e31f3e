#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A CalculiX reference of the honeycomb cell of tools/honeycomb_validation.py: the same
continuum (the walls with their joints, plane strain) by static finite elements, so that the
MPM's error (against this) and the continuum's own departure from Gibson & Ashby's beam
formulas (this against them) are told apart.

The mesh is the MPM run's own particle layout at t = 0 (particles.h5: the conforming
quadrilaterals of mpm_sections, corners shared), each quadrilateral a CPE8R element (8-node
quadratic, reduced integration; midside nodes added, shared between neighbours). The mirror
planes are applied as tubempm applies them: every node on or behind a plane moves with it
along x (the left plane fixed, the right one moved by -u), free along y; one node of the left
plane is held in y. Elastic: one linear static step; the force is the total x reaction of the
right plane's nodes, eps2 from the nodes nearest the cell's top and bottom vertices.
Plastic (ccx's J2, *PLASTIC at sigma_y, no hardening; small strain): INCREMENTS equal steps of
the travel, the plateau the mean reaction over the last PLATEAU of the travel, as for the MPM.

    from tools.fe_reference import honeycomb_fe
    honeycomb_fe.run(particles_h5, geometry, model, folder)   # {"E1", "nu12"} or {"sigma_pl"}
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from tools.fe_reference import fe_reference as fr   # run_cached: ccx on one thread, reused

INCREMENTS = 40


def _num(x: float) -> str:
    return f"{x:.10g}"


def mesh(particles_h5: Path) -> tuple[np.ndarray, list[list[int]]]:
    """Nodes (n, 2) [m] and CPE8 connectivity (1-based: corners counter-clockwise, then the
    midsides of edges 1-2, 2-3, 3-4, 4-1) from the run's first snapshot."""
    import h5py
    with h5py.File(particles_h5, "r") as f:
        snap = sorted(k for k in f if k.startswith("snap_"))[0]
        corners = np.array(f[snap]["corners"], dtype=float)
        quads = np.array(f[snap]["quads"], dtype=int)
    if quads.min() == 1:
        quads = quads - 1
    nodes = [tuple(p) for p in corners]
    mid: dict[tuple[int, int], int] = {}
    elems = []
    for q in quads:
        p = corners[q]
        area = 0.5 * sum(p[i, 0] * p[(i + 1) % 4, 1] - p[(i + 1) % 4, 0] * p[i, 1]
                         for i in range(4))
        q = list(q) if area > 0 else list(q[::-1])
        ms = []
        for i in range(4):
            a, b = q[i], q[(i + 1) % 4]
            key = (min(a, b), max(a, b))
            if key not in mid:
                mid[key] = len(nodes)
                nodes.append(tuple(0.5 * (corners[a] + corners[b])))
            ms.append(mid[key])
        elems.append([k + 1 for k in q + ms])
    return np.array(nodes), elems


def deck(nodes: np.ndarray, elems: list[list[int]], g: dict, model: str, travel: float,
         E: float, nu: float, sigma_y: float) -> str:
    """The ccx input (SI units; plane strain, 1 m thick)."""
    xw = 0.5 * g["width"]
    tol = 1.0e-6 * g["grid"]
    left = [i + 1 for i, (x, _) in enumerate(nodes) if x <= -xw + tol]
    right = [i + 1 for i, (x, _) in enumerate(nodes) if x >= xw - tol]
    yv = 0.5 * g["h"] + g["l"] * math.sin(g["theta"])
    top = 1 + int(np.argmin(np.hypot(nodes[:, 0], nodes[:, 1] - yv)))
    bot = 1 + int(np.argmin(np.hypot(nodes[:, 0], nodes[:, 1] + yv)))
    hold = min(left, key=lambda k: abs(nodes[k - 1, 1]))
    out = ["** tubempm: honeycomb cell between mirror planes (tools/fe_reference/honeycomb_fe.py)",
           "*NODE, NSET=NALL"]
    out += [f"{i + 1}, {_num(x)}, {_num(y)}" for i, (x, y) in enumerate(nodes)]
    out.append("*ELEMENT, TYPE=CPE8R, ELSET=EALL")
    out += [f"{e + 1}, " + ", ".join(str(n) for n in c) for e, c in enumerate(elems)]
    out += ["*NSET, NSET=NLEFT", fr._lines(left), "*NSET, NSET=NRIGHT", fr._lines(right),
            "*NSET, NSET=NTOP", str(top), "*NSET, NSET=NBOT", str(bot),
            "*NSET, NSET=NHOLD", str(hold),
            "*MATERIAL, NAME=WALL", "*ELASTIC", f"{_num(E)}, {_num(nu)}"]
    if model != "elastic":
        out += ["*PLASTIC", f"{_num(sigma_y)}, 0.0"]
    out += ["*SOLID SECTION, ELSET=EALL, MATERIAL=WALL", "1.0",
            "*BOUNDARY", "NLEFT, 1, 1", "NHOLD, 2, 2", "NRIGHT, 1, 1"]
    if model == "elastic":
        out += ["*STEP", "*STATIC"]
    else:
        dt = 1.0 / INCREMENTS
        out += [f"*STEP, INC={20 * INCREMENTS}", "*STATIC",
                f"{_num(dt)}, 1.0, {_num(dt * 1e-4)}, {_num(dt)}"]
    out += ["*BOUNDARY", f"NRIGHT, 1, 1, {_num(-travel)}",
            "*NODE PRINT, NSET=NRIGHT, TOTALS=ONLY", "RF",
            "*NODE PRINT, NSET=NTOP", "U", "*NODE PRINT, NSET=NBOT", "U", "*END STEP", ""]
    return "\n".join(out)


def parse(dat: Path) -> list[dict[str, float]]:
    """Per converged increment: step time, the right plane's x reaction, u_y of the top and
    bottom vertices (ccx's .dat: one block per quantity and increment)."""
    rows: dict[float, dict[str, float]] = {}
    mode, tm, seen_u = None, 0.0, 0
    for line in dat.read_text().splitlines():
        s = line.strip()
        if not s:
            continue
        if s.startswith("total force"):
            mode, tm = "rf", float(s.split()[-1])
            continue
        if s.startswith("displacements"):
            tm = float(s.split()[-1])
            mode = "top" if seen_u % 2 == 0 else "bot"
            seen_u += 1
            continue
        try:
            vals = [float(p) for p in s.split()]
        except ValueError:
            mode = None
            continue
        r = rows.setdefault(tm, {"time": tm})
        if mode == "rf" and len(vals) == 3:
            r["rf"] = vals[0]
        elif mode in ("top", "bot") and len(vals) == 4:
            r[mode] = vals[2]
        mode = None
    return [rows[k] for k in sorted(rows) if {"rf", "top", "bot"} <= set(rows[k])]


def run(particles_h5: Path, g: dict, model: str, folder: Path, travel: float, E: float,
        nu: float, sigma_y: float, plateau: float = 0.4) -> dict[str, float]:
    """The FE values of one case: elastic {"E1", "nu12"}, plastic {"sigma_pl"} (compression
    positive, as honeycomb_validation.measure), and "cpu_s" of ccx."""
    folder.mkdir(parents=True, exist_ok=True)
    nodes, elems = mesh(particles_h5)
    text = deck(nodes, elems, g, model, travel, E, nu, sigma_y)
    info = fr.run_cached(text, folder, "cell", False, "honeycomb_fe", str(folder))
    rows = parse(folder / "cell.dat")
    if not rows or rows[-1]["time"] < 1.0 - 1e-9:
        raise RuntimeError(f"ccx did not finish the step (see {folder / 'ccx.log'})")
    eps1 = travel / g["width"]
    if model == "elastic":
        r = rows[-1]
        sigma1 = -r["rf"] / (2.0 * g["period"])          # the reaction holds the plane back
        eps2 = (r["top"] - r["bot"]) / (2.0 * g["period"])
        return {"E1": sigma1 / eps1, "nu12": eps2 / eps1, "cpu_s": info["cpu_s"],
                "elements": len(elems)}
    late = [-r["rf"] for r in rows if r["time"] >= 1.0 - plateau - 1e-9]
    return {"sigma_pl": sum(late) / len(late) / (2.0 * g["period"]), "cpu_s": info["cpu_s"],
            "elements": len(elems)}
