#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A finite element reference for the sheared ring (issue 33): 'bonded' and 'coulomb' platens.

The scene (docs/fe_reference/README.md, "The sheared ring"): the elastic ring of
tests/test_bonded.py (r 7 - 10 mm, E 2 GPa, nu 0.3) between a fixed bottom platen and a top
platen moving down and sideways (sideways / down = 0.5) to an approach delta = 0.2 D (D the mean
diameter, 17 mm), either

- bonded: the ring's outer nodes closer than h/2 to a platen at t = 0 (h = 0.75 mm, the MPM
  grid of the scene: the band tubempm ties, docs/method.md "Bonded walls") move with that
  platen (prescribed displacements); the rest meets the platens without friction; or
- loose: frictional contact (Coulomb, mu = 0.5) on both platens.

CalculiX (ccx 2.20) model: the full ring, plane strain CPE8R, a structured mapped mesh of
n_t x n_c elements (through the wall x around), each platen a strip of CPE8R elements whose
nodes all have prescribed displacements, surface-to-surface penalty contact (the crush
reference's, tools/fe_reference/fe_reference.py, whose helpers this imports), NLGEOM, a static
step of equal increments. Outputs per mesh (SI, per metre of depth, tubempm's signs:
docs/output.md): the approach delta, the normal force and the sideways force the ring exerts on
the top platen (wall1_force, wall1_fx) and on the bottom one, and the sideways motion of the
ring's centroid (com_x).

    python3 -m tools.fe_reference.shear_reference               # both laws, all meshes, tubempm
    python3 -m tools.fe_reference.shear_reference --deck-only   # decks only
    python3 -m tools.fe_reference.shear_reference --laws bonded --meshes 2x48
    python3 -m tools.fe_reference.shear_reference --no-mpm      # FE only
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from tools.fe_reference.fe_reference import _lines, _num, rel_l2, run_cached

HERE = Path(__file__).resolve().parent

ROOT = HERE.parent.parent
DOCS = ROOT / "docs" / "fe_reference"
WORK = ROOT / "out" / "fe_reference" / "shear"

# the scene (SI) -------------------------------------------------------------------------------
R_IN, R_OUT = 7.0e-3, 10.0e-3
E, NU, RHO = 2.0e9, 0.3, 1000.0
H_GRID = 0.75e-3                 #: tubempm's grid spacing; its ties reach h/2 from the wall
N_THICK = 8                      #: tubempm's particles through the wall
RATIO = 0.5                      #: sideways over downward platen speed
DELTA_OVER_D = 0.2               #: the approach at the end, over the mean diameter
MU = 0.5                         #: Coulomb coefficient of the loose ring
V_DOWN = 2.0                     #: tubempm's approach speed [m/s] (quasi-static: --check)
RAMP = 4.0e-4                    #: tubempm's ramp [s]
D_MEAN = R_IN + R_OUT
DELTA_END = DELTA_OVER_D * D_MEAN
LAWS = ("bonded", "coulomb")
#: (elements through the wall, around the ring), coarse to fine
MESHES = ((2, 48), (4, 96), (8, 96))
INCREMENTS = 100
PENALTY_OVER_E = 10.0            #: contact penalty [E per mm]
STICK_OVER_E = 0.1               #: friction's stick slope [E per mm]
WINDOW = (0.02, 0.2)             #: delta / D over which the curves are compared (61 points)
MM = 1.0e-3


# ----------------------------------------------------------------------------------------------
# The mesh (deck units mm; ring centre at the origin)
# ----------------------------------------------------------------------------------------------

def ring_mesh(n_t: int, n_c: int):
    """Full ring of CPE8R elements: node grid (2 n_t + 1) radii x 2 n_c angles (periodic),
    angle index 0 at the top (x = 0, y = r), counter-clockwise. Returns nodes {id: (x, y)},
    elements, the outer faces (element, 2, angle index) and the ordered inner and outer
    boundary node ids (counter-clockwise, corner and midside)."""
    ri, ro = R_IN / MM, R_OUT / MM
    ni, nj = 2 * n_t + 1, 2 * n_c

    def nid(i: int, j: int) -> int:
        return 1 + i + ni * (j % nj)

    nodes = {}
    for j in range(nj):
        th = 0.5 * math.pi + 2.0 * math.pi * j / nj
        for i in range(ni):
            if i % 2 == 1 and j % 2 == 1:
                continue
            r = ri + (ro - ri) * i / (ni - 1)
            nodes[nid(i, j)] = (r * math.cos(th), r * math.sin(th))
    elems, outer = [], []
    for jj in range(n_c):
        for ii in range(n_t):
            i, j = 2 * ii, 2 * jj
            # counter-clockwise: radius grows with i, angle with j
            elems.append((nid(i, j), nid(i + 2, j), nid(i + 2, j + 2), nid(i, j + 2),
                          nid(i + 1, j), nid(i + 2, j + 1), nid(i + 1, j + 2), nid(i, j + 1)))
            if ii == n_t - 1:
                outer.append((len(elems), 2, j))
    inner_ring = [nid(0, j) for j in range(nj)]
    outer_ring = [nid(ni - 1, j) for j in range(nj)]
    return nodes, elems, outer, inner_ring, outer_ring


def platen(first_node: int, first_elem: int, top: bool, n: int = 32):
    """A platen strip of n CPE8R elements, x from -1.4 R_out to 1.4 R_out (+ the sideways
    travel for the top one), thickness t; top: its bottom face at y = r_out (face S1),
    bottom: its top face at y = -r_out (face S3)."""
    ro, t = R_OUT / MM, (R_OUT - R_IN) / MM
    x0 = -1.4 * ro - (0.0 if top else RATIO * DELTA_END / MM)
    x1 = 1.4 * ro + RATIO * DELTA_END / MM
    y0, y1 = (ro, ro + t) if top else (-ro - t, -ro)
    nx = 2 * n + 1

    def nid(i: int, j: int) -> int:
        return first_node + i + nx * j

    nodes = {}
    for j in range(3):
        for i in range(nx):
            if j == 1 and i % 2 == 1:
                continue
            nodes[nid(i, j)] = (x0 + (x1 - x0) * i / (nx - 1), y0 + (y1 - y0) * j / 2)
    elems, faces = [], []
    for k in range(n):
        i = 2 * k
        elems.append((nid(i, 0), nid(i + 2, 0), nid(i + 2, 2), nid(i, 2),
                      nid(i + 1, 0), nid(i + 2, 1), nid(i + 1, 2), nid(i, 1)))
        faces.append((first_elem + k, 1 if top else 3))
    return nodes, elems, faces


def tied(nodes: dict, outer_ring: list[int], top: bool) -> list[int]:
    """Outer nodes closer than h/2 to the platen at t = 0 (tubempm's tie band)."""
    ro = R_OUT / MM
    gap = 0.5 * H_GRID / MM
    return [k for k in outer_ring
            if (ro - nodes[k][1] if top else nodes[k][1] + ro) < gap - 1e-12]


def write_deck(law: str, n_t: int, n_c: int, increments: int = INCREMENTS) -> str:
    nodes, elems, outer, inner_ring, outer_ring = ring_mesh(n_t, n_c)
    ne = len(elems)
    first = max(nodes) + 1
    tn, te, tf = platen(first, ne + 1, True)
    first_b = max(tn) + 1
    bn, be, bf = platen(first_b, ne + 1 + len(te), False)
    u_down = DELTA_END / MM
    u_side = RATIO * u_down
    dt = 1.0 / increments
    # the outer faces of the upper and lower half (two contact pairs)
    nj = 2 * n_c
    up = [(e, f) for e, f, j in outer if math.cos(2.0 * math.pi * (j + 1) / nj) > 0.0]
    low = [(e, f) for e, f, j in outer if math.cos(2.0 * math.pi * (j + 1) / nj) < 0.0]
    out = [
        "** tubempm FE reference (tools/fe_reference/shear_reference.py): the sheared ring",
        f"** law {law}; full ring, plane strain CPE8R, n_t = {n_t} x n_c = {n_c}",
        f"** r_inner {_num(R_IN / MM)} mm, r_outer {_num(R_OUT / MM)} mm; E {_num(E / 1e6)} MPa, "
        f"nu {_num(NU)}; units mm N MPa",
        f"** top platen moves down {_num(u_down)} mm and sideways {_num(u_side)} mm "
        f"(delta/D = {DELTA_OVER_D})",
        "*NODE, NSET=NALL",
    ]
    out += [f"{k}, {_num(x)}, {_num(y)}" for k, (x, y) in sorted({**nodes, **tn, **bn}.items())]
    out.append("*ELEMENT, TYPE=CPE8R, ELSET=ERING")
    out += [f"{e + 1}, " + ", ".join(map(str, c)) for e, c in enumerate(elems)]
    out.append("*ELEMENT, TYPE=CPE8R, ELSET=EPLATEN")
    out += [f"{ne + 1 + e}, " + ", ".join(map(str, c)) for e, c in enumerate(te + be)]
    ntop, nbot = sorted(tn), sorted(bn)
    if law == "bonded":
        ntop = ntop + tied(nodes, outer_ring, True)
        nbot = nbot + tied(nodes, outer_ring, False)
    out += ["*NSET, NSET=NTOP", _lines(ntop), "*NSET, NSET=NBOT", _lines(nbot),
            "*NSET, NSET=NINNER", _lines(inner_ring), "*NSET, NSET=NOUTER", _lines(outer_ring),
            "*SURFACE, NAME=SUP, TYPE=ELEMENT"]
    out += [f"{e}, S{f}" for e, f in up]
    out.append("*SURFACE, NAME=SLOW, TYPE=ELEMENT")
    out += [f"{e}, S{f}" for e, f in low]
    out.append("*SURFACE, NAME=STOP, TYPE=ELEMENT")
    out += [f"{e}, S{f}" for e, f in tf]
    out.append("*SURFACE, NAME=SBOT, TYPE=ELEMENT")
    out += [f"{e}, S{f}" for e, f in bf]
    out += ["*MATERIAL, NAME=RING", "*ELASTIC", f"{_num(E / 1e6)}, {_num(NU)}",
            "*SOLID SECTION, ELSET=ERING, MATERIAL=RING", "1.0",
            "*SOLID SECTION, ELSET=EPLATEN, MATERIAL=RING", "1.0",
            "*SURFACE INTERACTION, NAME=SI",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{_num(PENALTY_OVER_E * E / 1e6)}"]
    if law == "coulomb":
        out += ["*FRICTION", f"{_num(MU)}, {_num(STICK_OVER_E * E / 1e6)}"]
    out += ["*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SUP, STOP",
            "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SLOW, SBOT",
            "*BOUNDARY", "NTOP, 1, 2", "NBOT, 1, 2",
            f"*STEP, NLGEOM, INC={20 * increments}",
            "*STATIC",
            f"{_num(dt)}, 1.0, {_num(dt * 1e-4)}, {_num(dt)}",
            "*BOUNDARY",
            f"NTOP, 1, 1, {_num(u_side)}",
            f"NTOP, 2, 2, {_num(-u_down)}",
            "*NODE PRINT, NSET=NTOP, TOTALS=ONLY", "RF",
            "*NODE PRINT, NSET=NBOT, TOTALS=ONLY", "RF",
            "*NODE PRINT, NSET=NINNER", "U",
            "*NODE PRINT, NSET=NOUTER", "U",
            "*END STEP", ""]
    return "\n".join(out)


def deck_name(law: str, n_t: int, n_c: int) -> str:
    return f"shear_{law}_nt{n_t}_nc{n_c}"


# ----------------------------------------------------------------------------------------------
# Results
# ----------------------------------------------------------------------------------------------

def parse_dat(path: Path):
    """Per converged increment: time, the top and bottom reactions (x, y) [N/mm] and the
    displacements {node: (ux, uy)} of the printed nodes (blocks in deck order: NTOP RF,
    NBOT RF, NINNER U, NOUTER U)."""
    blocks: dict[float, dict] = {}
    cur = None
    for line in path.read_text().splitlines():
        s = line.strip()
        if not s:
            continue
        if s.startswith("total force"):
            tm = float(s.split()[-1])
            b = blocks.setdefault(tm, {"rf": [], "u": {}})
            cur = ("rf", b)
            continue
        if s.startswith("displacements"):
            tm = float(s.split()[-1])
            cur = ("u", blocks.setdefault(tm, {"rf": [], "u": {}}))
            continue
        try:
            vals = [float(p) for p in s.split()]
        except ValueError:
            cur = None
            continue
        if cur is None:
            continue
        if cur[0] == "rf" and len(vals) == 3:
            cur[1]["rf"].append((vals[0], vals[1]))
            cur = None
        elif cur[0] == "u" and len(vals) == 4:
            cur[1]["u"][int(vals[0])] = (vals[1], vals[2])
    return {t: b for t, b in sorted(blocks.items()) if len(b["rf"]) == 2}


def polygon_centroid(p: np.ndarray) -> tuple[float, np.ndarray]:
    """Signed area and centroid of a closed polygon (points in order)."""
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cr = x * yn - xn * y
    a = 0.5 * cr.sum()
    return a, np.array([((x + xn) * cr).sum(), ((y + yn) * cr).sum()]) / (6.0 * a)


def ring_centroid(nodes: dict, inner: list[int], outer: list[int], u: dict) -> np.ndarray:
    """Centroid of the deformed ring [mm]: the outer polygon less the inner one (boundary
    nodes, corner and midside)."""
    po = np.array([[nodes[k][0] + u[k][0], nodes[k][1] + u[k][1]] for k in outer])
    pi = np.array([[nodes[k][0] + u[k][0], nodes[k][1] + u[k][1]] for k in inner])
    ao, co = polygon_centroid(po)
    ai, ci = polygon_centroid(pi)
    return (ao * co - ai * ci) / (ao - ai)

COLUMNS = ["delta_m", "delta_over_D", "side_m", "normal_N", "shear_N", "bottom_normal_N",
           "bottom_shear_N", "center_dx_m"]


def fe_curve(law: str, n_t: int, n_c: int, dat: Path) -> np.ndarray:
    """The curve (rows of COLUMNS) from a ccx .dat: forces the ring exerts on the platens per
    metre of depth (the negative reactions; N/mm -> N/m), normal positive pushing, shear along
    +x; the centroid's sideways motion."""
    nodes, _, _, inner, outer = ring_mesh(n_t, n_c)
    rows = [[0.0] * len(COLUMNS)]
    c0 = ring_centroid(nodes, inner, outer, {k: (0.0, 0.0) for k in nodes})
    for tm, b in parse_dat(dat).items():
        (tx, ty), (bx, by) = b["rf"]
        d = tm * DELTA_END
        c = ring_centroid(nodes, inner, outer, b["u"])
        rows.append([d, d / D_MEAN, RATIO * d, -ty / MM, -tx / MM, by / MM, -bx / MM,
                     (c[0] - c0[0]) * MM])
    return np.array(rows)


def write_curve(path: Path, a: np.ndarray) -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for r in a:
            w.writerow([f"{v:.9e}" for v in r])


def read_curve(path: Path) -> np.ndarray:
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def on_window(a: np.ndarray, col: str) -> np.ndarray:
    """Column col at the 61 points delta/D = 0.02 ... 0.2 (linear interpolation)."""
    x = np.linspace(*WINDOW, 61)
    return np.interp(x, a[:, 1], a[:, COLUMNS.index(col)])

QUANTITIES = ("normal_N", "shear_N", "center_dx_m")


def differences(a: np.ndarray, ref: np.ndarray) -> dict[str, float]:
    """Relative L2 differences of curve a from ref over the window (61 points): normal force,
    shear force, centre motion."""
    return {col: rel_l2(on_window(a, col), on_window(ref, col)) for col in QUANTITIES}


def compare(law: str, mesh: str, fe: np.ndarray, mpm: np.ndarray) -> list[dict]:
    """The comparison rows of one law: per quantity the relative L2 difference of tubempm's
    curve from FE's, the rms difference over the rms of FE's normal force (the measure for the
    loose ring's shear force, which is near zero, so that its relative L2 means little) and
    both curves' values at delta/D = 0.1 and 0.2."""
    rows = []
    scale = float(np.sqrt(np.mean(on_window(fe, "normal_N") ** 2)))
    for col in QUANTITIES:
        f, g = on_window(mpm, col), on_window(fe, col)
        mid = lambda a: float(np.interp(0.1, a[:, 1], a[:, COLUMNS.index(col)]))  # noqa: E731
        rows.append({"law": law, "fe_mesh": mesh, "quantity": col,
                     "rel_L2": f"{rel_l2(f, g):.6f}",
                     "rms_diff_over_fe_normal_rms": f"{np.sqrt(np.mean((f - g) ** 2)) / scale:.6f}"
                     if col != "center_dx_m" else "",
                     "fe_at_0.1": f"{mid(fe):.6e}", "mpm_at_0.1": f"{mid(mpm):.6e}",
                     "fe_at_0.2": f"{g[-1]:.6e}", "mpm_at_0.2": f"{f[-1]:.6e}"})
    return rows


def write_comparison(path: Path, rows: list[dict]) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


# ----------------------------------------------------------------------------------------------
# tubempm
# ----------------------------------------------------------------------------------------------

def namelist_text(law: str, out_dir: str) -> str:
    t_end = DELTA_END / V_DOWN + 0.5 * RAMP
    contact = "'bonded'" if law == "bonded" else f"'coulomb', friction = {MU}"
    return f"""! the sheared ring of docs/fe_reference/README.md (shear_reference.py)
&run
  title = 'shear_{law}', output_dir = '{out_dir}'
  t_end = {t_end:.6e}, cfl = 0.4, history_every = 1.0e-5, snapshot_every = 1.0
/
&grid h = {H_GRID} /
&material name = 'soft', model = 'elastic', E = {E}, nu = {NU}, rho = {RHO} /
&body shape = 'ring', material = 'soft', center = 0.0, {R_OUT}, r_inner = {R_IN},
      r_outer = {R_OUT}, n_thick = {N_THICK} /
&wall point = 0.0, {2 * R_OUT}, normal = 0.0, -1.0, contact = {contact},
      velocity = {RATIO * V_DOWN}, {-V_DOWN}, ramp = {RAMP} /
&wall point = 0.0, 0.0, normal = 0.0, 1.0, contact = {contact} /
"""


def mpm_curve(history: Path) -> np.ndarray:
    from plots.mpmplot import readers
    h = readers.read_history(history)
    d = -np.asarray(h["wall1_disp"])
    rows = np.column_stack([d, d / D_MEAN, RATIO * d, h["wall1_force"], h["wall1_fx"],
                            h["wall2_force"], h["wall2_fx"], h["com_x"] - h["com_x"][0]])
    return rows


def run_mpm(law: str, work: Path) -> np.ndarray:
    run = work / f"mpm_{law}"
    run.mkdir(parents=True, exist_ok=True)
    nml = run / f"shear_{law}.nml"
    nml.write_text(namelist_text(law, str(run / "out")))
    exe = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
    print(f"shear_reference: running tubempm ({law}) ...", flush=True)
    subprocess.run([exe, "--quiet", str(nml)], check=True,
                   env=dict(os.environ, OMP_NUM_THREADS="1"))
    return mpm_curve(run / "out" / "history.csv")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--laws", nargs="*", default=list(LAWS))
    ap.add_argument("--meshes", nargs="*", default=[f"{a}x{b}" for a, b in MESHES])
    ap.add_argument("--docs", type=Path, default=DOCS)
    ap.add_argument("--work", type=Path, default=WORK)
    ap.add_argument("--increments", type=int, default=INCREMENTS)
    ap.add_argument("--deck-only", action="store_true")
    ap.add_argument("--force", action="store_true", help="re-run what has a result")
    ap.add_argument("--no-mpm", action="store_true", help="do not run tubempm")
    a = ap.parse_args(argv)
    meshes = [tuple(int(v) for v in m.lower().split("x")) for m in a.meshes]
    a.docs.mkdir(parents=True, exist_ok=True)
    summary = {"window_delta_over_D": list(WINDOW), "increments": a.increments, "laws": {}}
    sj = a.docs / "shear_convergence.json"
    if sj.is_file():
        summary["laws"] = json.loads(sj.read_text()).get("laws", {})
    comparison: dict[str, list[dict]] = {}
    for law in a.laws:
        curves = []
        info_law = {"meshes": []}
        for n_t, n_c in meshes:
            name = deck_name(law, n_t, n_c)
            text = write_deck(law, n_t, n_c, a.increments)
            if a.deck_only:
                (a.docs / f"{name}.inp").write_text(text)
                continue
            run = a.work / name
            run.mkdir(parents=True, exist_ok=True)
            info = run_cached(text, run, name, a.force, "shear_reference", name,
                              keep_failed=True)
            cur = fe_curve(law, n_t, n_c, run / f"{name}.dat")
            reached = float(cur[-1, 1] / DELTA_OVER_D)
            rec = {"mesh": name, "n_t": n_t, "n_c": n_c, "elements": n_t * n_c,
                   "increments": int(len(cur) - 1), "cpu_s": round(info["cpu_s"], 1),
                   "step_reached": round(reached, 4)}
            print(f"shear_reference: {name}: {len(cur) - 1} increments, step time {reached:.3f},"
                  f" {info['cpu_s']:.0f} CPU s", flush=True)
            if reached < 1.0 - 1e-6:
                rec["converged"] = False
                info_law["meshes"].append(rec)
                continue
            rec["converged"] = True
            (a.docs / f"{name}.inp").write_text(text)
            write_curve(a.docs / f"{name}.csv", cur)
            curves.append((rec, cur))
            info_law["meshes"].append(rec)
        if a.deck_only or not curves:
            continue
        ref_rec, ref = curves[-1]
        info_law["reference"] = ref_rec["mesh"]
        for rec, cur in curves:
            rec["diff_vs_finest"] = {k: round(v, 6) for k, v in differences(cur, ref).items()}
        write_curve(a.docs / f"shear_{law}_fe.csv", ref)
        if not a.no_mpm:
            mpm = run_mpm(law, a.work)
            write_curve(a.docs / f"shear_{law}_mpm.csv", mpm)
            comparison[law] = compare(law, ref_rec["mesh"], ref, mpm)
        summary["laws"][law] = info_law
    if comparison:
        cp = a.docs / "shear_comparison.csv"
        old = {}
        if cp.is_file():
            with open(cp) as f:
                for r in csv.DictReader(f):
                    old.setdefault(r["law"], []).append(r)
        old.update(comparison)
        write_comparison(cp, [r for law in LAWS for r in old.get(law, [])])
        for law, rows in comparison.items():
            for r in rows:
                print(f"  {law:8s} {r['quantity']:12s}: relative L2 "
                      f"{100 * float(r['rel_L2']):.2f} %")
    if not a.deck_only:
        sj.write_text(json.dumps(summary, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
