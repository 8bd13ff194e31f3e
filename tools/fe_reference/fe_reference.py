#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""An independent finite element reference for the quasi-static crush (issue 17, item 1).

Writes a CalculiX (ccx 2.20) deck for a crush namelist (the ring, material and top platen of
namelists/crush.nml), runs ccx and writes the platen force per unit depth against the platen
approach as CSV, in tubempm's quantities and sign conventions (full ring, docs/output.md).

The model (docs/fe_reference/README.md):

- a quarter of the ring (x >= 0, y >= centre) with symmetry on both mirror planes
  (u_x = 0 on x = 0, u_y = 0 on y = y_centre), plane strain, CPE8R (8-node quadratic,
  reduced integration), a structured mapped mesh of n_t x n_c elements (through the wall x
  around the quarter) made here: nodes on circles, midside nodes on the arcs;
- the top platen is a strip of CPE8R elements whose nodes all have prescribed displacements
  (a rigid surface moving down by u); the bottom platen is its mirror image in y = y_centre,
  so the approach is delta = 2 u (docs/output.md);
- frictionless surface-to-surface penalty contact (linear pressure-overclosure);
- NLGEOM, a static step with fixed increments, the J2 model of ccx (*PLASTIC, isotropic
  hardening; see the README for how it differs from tubempm's hypoelastic Jaumann J2);
- units in the deck: mm, N, MPa; the plane-strain thickness is 1 mm, so ccx's reaction is
  N per mm of depth. The CSV is SI: delta [m], force [N] per &run depth, the full platen force
  (twice the quarter's reaction: the mirror x = 0 is perpendicular to the platen).

    python3 -m tools.fe_reference.fe_reference                 # the study's crush, 4 meshes
    python3 -m tools.fe_reference.fe_reference --deck-only     # write the decks, no ccx
    python3 -m tools.fe_reference.fe_reference --meshes 2x26   # one mesh (n_t x n_c)
    python3 -m tools.fe_reference.fe_reference --meshes 4x52 --increments 550 \
        --docs out/fe_sens/docs --work out/fe_sens/work          # a sensitivity check
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from plots.mpmplot import namelist, scene

ROOT = Path(__file__).resolve().parent.parent.parent

#: default case, committed outputs, run folders
CASE = ROOT / "namelists" / "crush.nml"
DOCS = ROOT / "docs" / "fe_reference"
WORK = ROOT / "out" / "fe_reference"
#: the refinement: (elements through the wall, elements around the quarter); element aspect
#: (length around / through the wall) about 2, 4 for the finest (the count around matters
#: little: docs/fe_reference/README.md)
MESHES = ((2, 26), (4, 52), (8, 104), (16, 104))
#: the crush runs to this relative approach delta / D (D the mean diameter; the study's
#: crush stops at 0.53, its error window is 0.05-0.5)
DELTA_END = 0.55
#: number of equal load increments
INCREMENTS = 275
#: penalty stiffness of the contact as a multiple of E per mm [MPa/mm]
PENALTY_OVER_E = 10.0
#: the study's error window (delta / D) and its 91 points
WINDOW = (0.05, 0.5)
MM = 1.0e-3


class InputError(Exception):
    """A crush namelist the FE reference cannot model."""


@dataclass(frozen=True)
class Crush:
    """The crush scene in deck units (mm, N, MPa) and the SI quantities of the outputs."""
    r_inner: float        # [mm]
    r_outer: float        # [mm]
    E: float              # [MPa]
    nu: float
    sigma_y: float        # [MPa]
    hardening: float      # [MPa]
    depth: float          # [m]
    source: str

    @property
    def R(self) -> float:
        return 0.5 * (self.r_inner + self.r_outer)

    @property
    def t(self) -> float:
        return self.r_outer - self.r_inner

    @property
    def D(self) -> float:
        return 2.0 * self.R


def read_crush(path: Path) -> Crush:
    """The ring, material and platens of a crush namelist; InputError names what does not
    fit the FE model (file, group, variable)."""
    inputs = namelist.read_namelist(path)
    where = str(path)
    body = scene.ring_body(inputs)
    if body is None:
        raise InputError(f"{where}: &body: no ring body (shape = 'ring')")
    r = scene.ring_properties(inputs)
    if r["model"] != "j2":
        raise InputError(f"{where}: &material model = '{r['model']}': the FE reference models 'j2'")
    if r["plane"] != "strain":
        raise InputError(f"{where}: &solver plane = '{r['plane']}': the FE reference is "
                         f"plane strain")
    for key in ("E", "nu", "sigma_y"):
        if not math.isfinite(r[key]):
            raise InputError(f"{where}: &material {key}: missing")
    mat = scene.body_material(inputs, body)
    if str(mat.get("rate_law", "none")).lower() != "none":
        raise InputError(f"{where}: &material rate_law = '{mat['rate_law']}': the FE reference "
                         f"is rate independent")
    walls = inputs.get("wall", [])
    moving = [w for w in walls
              if any(abs(float(v)) > 0.0 for v in np.atleast_1d(w.get("velocity", [0.0, 0.0])))]
    if len(moving) != 1:
        raise InputError(f"{where}: &wall: the FE reference needs exactly one moving platen "
                         f"(found {len(moving)})")
    w = moving[0]
    n = np.asarray(w.get("normal", [0.0, 0.0]), dtype=float)
    if not (abs(n[0]) < 1e-12 and n[1] < 0.0):
        raise InputError(f"{where}: &wall normal = {list(n)}: the moving platen must be the top "
                         f"one (normal (0, -1))")
    if str(w.get("contact", "frictionless")).lower() != "frictionless":
        raise InputError(f"{where}: &wall contact = '{w.get('contact')}': the FE reference is "
                         f"frictionless")
    c = np.asarray(body.get("center", [0.0, 0.0]), dtype=float)
    point = np.asarray(w.get("point", [0.0, 0.0]), dtype=float)
    gap = point[1] - (c[1] + float(body["r_outer"]))
    if abs(gap) > 1e-9:
        raise InputError(f"{where}: &wall point: the platen must touch the ring at the start "
                         f"(gap {gap:g} m)")
    sector = str(body.get("sector", "full")).lower()
    if sector not in ("full", "half", "quarter"):
        raise InputError(f"{where}: &body sector = '{sector}'")
    return Crush(r_inner=float(body["r_inner"]) / MM, r_outer=float(body["r_outer"]) / MM,
                 E=r["E"] / 1e6, nu=r["nu"], sigma_y=r["sigma_y"] / 1e6,
                 hardening=r["hardening"] / 1e6, depth=r["depth"],
                 source=os.path.relpath(path, ROOT))


# ----------------------------------------------------------------------------------------------
# The mesh
# ----------------------------------------------------------------------------------------------

def ring_mesh(c: Crush, n_t: int, n_c: int) -> tuple[dict[int, tuple[float, float]],
                                                       list[tuple[int, ...]], dict[str, list]]:
    """Structured quarter ring of CPE8R elements, centre at the origin.

    Node grid (2 n_t + 1) x (2 n_c + 1) in (radius index i, angle index j), angle 0 on the
    y = 0 mirror and pi/2 on the x = 0 mirror; the element centre nodes (i, j both odd) are
    not used. Returns nodes {id: (x, y)}, elements (corner nodes counter-clockwise, then the
    midside nodes of edges 1-2, 2-3, 3-4, 4-1) and the sets: 'outer' faces (element, face
    number 2 = edge 2-3 at r_outer), 'ymirror' and 'xmirror' node ids.
    """
    ni, nj = 2 * n_t + 1, 2 * n_c + 1

    def nid(i: int, j: int) -> int:
        return 1 + i + ni * j

    nodes: dict[int, tuple[float, float]] = {}
    for j in range(nj):
        th = 0.5 * math.pi * j / (nj - 1)
        for i in range(ni):
            if i % 2 == 1 and j % 2 == 1:
                continue
            r = c.r_inner + c.t * i / (ni - 1)
            x, y = r * math.cos(th), r * math.sin(th)
            if j == nj - 1:
                x = 0.0                          # exactly on the mirror
            nodes[nid(i, j)] = (x, y)
    elems: list[tuple[int, ...]] = []
    outer: list[tuple[int, int]] = []
    for jj in range(n_c):
        for ii in range(n_t):
            i, j = 2 * ii, 2 * jj
            elems.append((nid(i, j), nid(i + 2, j), nid(i + 2, j + 2), nid(i, j + 2),
                          nid(i + 1, j), nid(i + 2, j + 1), nid(i + 1, j + 2), nid(i, j + 1)))
            if ii == n_t - 1:
                outer.append((len(elems), 2))
    sets = {"outer": outer,
            "ymirror": [nid(i, 0) for i in range(ni)],
            "xmirror": [nid(i, nj - 1) for i in range(ni)]}
    return nodes, elems, sets


def platen_strip(x0: float, x1: float, y0: float, y1: float, first_node: int, first_elem: int,
                 n: int = 12) -> tuple[dict[int, tuple[float, float]], list[tuple[int, ...]], list]:
    """A top platen: one row of n CPE8R elements over x0 <= x <= x1, y0 <= y <= y1 (all its nodes
    are prescribed: a rigid surface). Returns nodes, elements and the contact faces (face 1 =
    edge 1-2, the bottom)."""
    nx = 2 * n + 1

    def nid(i: int, j: int) -> int:
        return first_node + i + nx * j

    nodes: dict[int, tuple[float, float]] = {}
    for j in range(3):
        for i in range(nx):
            if j == 1 and i % 2 == 1:
                continue
            nodes[nid(i, j)] = (x0 + (x1 - x0) * i / (nx - 1), y0 + (y1 - y0) * j / 2)
    elems: list[tuple[int, ...]] = []
    faces: list[tuple[int, int]] = []
    for k in range(n):
        i = 2 * k
        elems.append((nid(i, 0), nid(i + 2, 0), nid(i + 2, 2), nid(i, 2),
                      nid(i + 1, 0), nid(i + 2, 1), nid(i + 1, 2), nid(i, 1)))
        faces.append((first_elem + k, 1))
    return nodes, elems, faces


# ----------------------------------------------------------------------------------------------
# The deck
# ----------------------------------------------------------------------------------------------

def _num(x: float) -> str:
    return f"{x:.12g}"


def _lines(ids: list[int], per: int = 12) -> str:
    return "\n".join(", ".join(str(i) for i in ids[k:k + per]) for k in range(0, len(ids), per))


def platen_travel(c: Crush) -> float:
    """Travel of the top platen [mm]: half the approach delta = DELTA_END D."""
    return 0.5 * DELTA_END * c.D


def deck_text(header: list[str], nodes: dict[int, tuple[float, float]],
              elems: list[tuple[int, ...]], sets: dict[str, list], c, u: float,
              platen: tuple[float, float, float, float], increments: int = INCREMENTS,
              penalty: float = PENALTY_OVER_E, n_platen: int = 12,
              output: tuple[str, ...] = (),
              amplitude: tuple[tuple[float, float], ...] = ()) -> str:
    """The ccx input of a crush between rigid frictionless platens (deterministic text):
    the body's CPE8R mesh (nodes, elements; sets 'outer' contact faces (element, face),
    'ymirror' and 'xmirror' node ids) in the quarter x >= 0, y >= y_centre = 0, the top
    platen a strip of n_platen CPE8R elements (platen_strip over platen = (x0, x1, y0, y1), its
    bottom y0 touching the body) moving down by u [mm] in `increments` equal increments; c gives
    the material (E, nu, sigma_y, hardening [MPa]); penalty: the contact's penalty over E per
    mm. header: the comment lines that open it; output: more output requests of the step;
    amplitude: (step time, fraction of u) pairs of a piecewise linear travel (none: in
    proportion to the step time), to spend more of the equal increments where the force
    changes fast."""
    first_node = max(nodes) + 1
    pnodes, pelems, pfaces = platen_strip(*platen, first_node, len(elems) + 1, n_platen)
    dt = 1.0 / increments
    out = list(header) + ["*NODE, NSET=NALL"]
    out += [f"{k}, {_num(x)}, {_num(y)}" for k, (x, y) in sorted({**nodes, **pnodes}.items())]
    out.append("*ELEMENT, TYPE=CPE8R, ELSET=ERING")
    out += [f"{e + 1}, " + ", ".join(str(n) for n in conn) for e, conn in enumerate(elems)]
    out.append("*ELEMENT, TYPE=CPE8R, ELSET=EPLATEN")
    out += [f"{len(elems) + 1 + e}, " + ", ".join(str(n) for n in conn)
            for e, conn in enumerate(pelems)]
    out += ["*NSET, NSET=NYMIRROR", _lines(sets["ymirror"]),
            "*NSET, NSET=NXMIRROR", _lines(sets["xmirror"]),
            "*NSET, NSET=NPLATEN", _lines(sorted(pnodes)),
            "*NSET, NSET=NREF", str(first_node),
            "*SURFACE, NAME=SRING, TYPE=ELEMENT"]
    out += [f"{e}, S{f}" for e, f in sets["outer"]]
    out.append("*SURFACE, NAME=SPLATEN, TYPE=ELEMENT")
    out += [f"{e}, S{f}" for e, f in pfaces]
    out += ["*MATERIAL, NAME=STEEL",
            "*ELASTIC", f"{_num(c.E)}, {_num(c.nu)}",
            "*PLASTIC",
            f"{_num(c.sigma_y)}, 0.0",
            f"{_num(c.sigma_y + c.hardening * 2.0)}, 2.0",
            "*SOLID SECTION, ELSET=ERING, MATERIAL=STEEL", "1.0",
            "*SOLID SECTION, ELSET=EPLATEN, MATERIAL=STEEL", "1.0",
            "*SURFACE INTERACTION, NAME=SI",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{_num(penalty * c.E)}",
            "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE",
            "SRING, SPLATEN",
            "*BOUNDARY",
            "NYMIRROR, 2, 2",
            "NXMIRROR, 1, 1",
            "NPLATEN, 1, 2"]
    if amplitude:
        out += ["*AMPLITUDE, NAME=TRAVEL",
                ", ".join(f"{_num(t)}, {_num(v)}" for t, v in amplitude)]
    out += [f"*STEP, NLGEOM, INC={10 * increments}",
            "*STATIC",
            f"{_num(dt)}, 1.0, {_num(dt * 1e-4)}, {_num(dt)}",
            "*BOUNDARY, AMPLITUDE=TRAVEL" if amplitude else "*BOUNDARY",
            f"NPLATEN, 2, 2, {_num(-u)}",
            "*NODE PRINT, NSET=NPLATEN, TOTALS=ONLY",
            "RF",
            "*NODE PRINT, NSET=NREF",
            "U", *output,
            "*END STEP", ""]
    return "\n".join(out)


def write_deck(c: Crush, n_t: int, n_c: int, increments: int = INCREMENTS,
               penalty: float = PENALTY_OVER_E) -> str:
    """The ccx input for one mesh (deterministic text: the test regenerates and compares it);
    increments: equal load increments; penalty: contact penalty over E per mm."""
    nodes, elems, sets = ring_mesh(c, n_t, n_c)
    u = platen_travel(c)
    header = [
        "** tubempm FE reference (tools/fe_reference/fe_reference.py): quasi-static crush",
        f"** case {c.source}: quarter ring, plane strain CPE8R, n_t = {n_t} x n_c = {n_c}",
        f"** r_inner {_num(c.r_inner)} mm, r_outer {_num(c.r_outer)} mm; E {_num(c.E)} MPa, "
        f"nu {_num(c.nu)}, sigma_y {_num(c.sigma_y)} MPa, H {_num(c.hardening)} MPa",
        f"** top platen moves down {_num(u)} mm (approach delta/D = {DELTA_END}); units mm N MPa",
    ]
    return deck_text(header, nodes, elems, sets, c, u,
                     (-0.05 * c.R, 1.3 * c.R, c.r_outer, c.r_outer + c.t), increments, penalty)


def deck_name(n_t: int, n_c: int) -> str:
    return f"crush_nt{n_t}_nc{n_c}"


# ----------------------------------------------------------------------------------------------
# Running ccx and reading its results
# ----------------------------------------------------------------------------------------------

def parse_dat(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Step time, platen reaction R_y (total over the platen's nodes) [N per mm depth] and the
    reference node's u_y [mm] of every converged increment, from ccx's .dat file."""
    times: list[float] = []
    rf: dict[float, float] = {}
    uy: dict[float, float] = {}
    mode = None
    for line in path.read_text().splitlines():
        s = line.strip()
        if not s:
            continue
        if s.startswith("total force"):
            mode, tm = "rf", float(s.split()[-1])
            continue
        if s.startswith("displacements"):
            mode, tm = "u", float(s.split()[-1])
            continue
        parts = s.split()
        try:
            vals = [float(p) for p in parts]
        except ValueError:
            mode = None
            continue
        if mode == "rf" and len(vals) == 3:
            rf[tm] = vals[1]
            times.append(tm)
            mode = None
        elif mode == "u" and len(vals) == 4:
            uy[tm] = vals[2]
            mode = None
    t = np.array(sorted(set(times) & set(uy)))
    return t, np.array([rf[x] for x in t]), np.array([uy[x] for x in t])


def curve_si(c: Crush, rf: np.ndarray, uy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Approach delta [m] and full-ring platen force [N per &run depth] from the quarter's
    platen reaction [N/mm] and travel [mm]: delta = 2 |u| (the bottom platen is the mirror
    image), F = -2 R_y (the x = 0 mirror doubles the platen force; the reaction holds the
    platen against the ring, so the force the ring exerts on it, tubempm's wall force, is
    its negative), R_y per mm of depth."""
    delta = 2.0 * np.abs(uy) * MM
    force = -2.0 * rf / MM * c.depth
    return np.concatenate([[0.0], delta]), np.concatenate([[0.0], force])


def run_ccx(deck: Path, log: Path) -> float:
    """Run ccx on deck (one thread) in its folder; return the CPU seconds (children)."""
    ccx = shutil.which("ccx")
    if ccx is None:
        raise FileNotFoundError("ccx not found: run tools/install-deps.sh --ccx (Debian package "
                                "calculix-ccx) or put CalculiX 2.20's ccx on PATH")
    env = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_STIFFNESS="1",
               CCX_NPROC_EQUATION_SOLVER="1", CCX_NPROC_RESULTS="1")
    t0 = os.times()
    with open(log, "w") as f:
        p = subprocess.run([ccx, "-i", deck.stem], cwd=deck.parent, stdout=f,
                           stderr=subprocess.STDOUT, env=env)
    t1 = os.times()
    if p.returncode != 0:
        raise RuntimeError(f"ccx failed on {deck} (exit {p.returncode}); see {log}")
    return (t1.children_user - t0.children_user) + (t1.children_system - t0.children_system)


def run_cached(text: str, run: Path, name: str, force: bool, label: str, what: str,
               keep_failed: bool = False) -> dict:
    """ccx on the deck `text` as run/name.inp, unless that very deck has finished there before
    (run/result.json) and force is off; the run's {"cpu_s", "wall_s"}. A failed run raises
    FileNotFoundError or RuntimeError, or with keep_failed is said on stderr and recorded with
    cpu_s NaN."""
    deck, done = run / f"{name}.inp", run / "result.json"
    if not (done.is_file() and deck.is_file() and deck.read_text() == text and not force):
        deck.write_text(text)
        done.unlink(missing_ok=True)
        print(f"{label}: running ccx on {what} ...", flush=True)
        t0 = time.time()
        try:
            cpu = run_ccx(deck, run / "ccx.log")
        except (FileNotFoundError, RuntimeError) as e:
            if not keep_failed:
                raise
            print(f"{label}: {e}", file=sys.stderr)
            cpu = math.nan
        done.write_text(json.dumps({"cpu_s": cpu, "wall_s": time.time() - t0}))
    return json.loads(done.read_text())


class StoppedShort(Exception):
    """ccx ended its step before the step time 1 (it could not converge)."""


def run_mesh(text: str, run: Path, name: str, force: bool, label: str, what: str
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
    """run_cached on the deck text in the folder run (made if missing), then parse_dat: step
    times, platen reaction, reference node's u_y and the run's {"cpu_s", "wall_s"}.
    StoppedShort if the step did not reach its end."""
    run.mkdir(parents=True, exist_ok=True)
    info = run_cached(text, run, name, force, label, what)
    tm, rf, uy = parse_dat(run / f"{name}.dat")
    if tm.size == 0 or tm[-1] < 1.0 - 1e-9:
        raise StoppedShort(f"{name}: ccx stopped at step time {tm[-1] if tm.size else 0:g} of 1 "
                           f"(see {run / 'ccx.log'})")
    return tm, rf, uy, info


def window(delta: np.ndarray, force: np.ndarray, D: float) -> np.ndarray:
    """The force at the study's 91 points delta/D = 0.05 ... 0.5 (linear interpolation)."""
    x = np.linspace(*WINDOW, 91) * D
    return np.interp(x, delta, force)


def rel_l2(f: np.ndarray, ref: np.ndarray) -> float:
    """The study's relative L2 error of f against ref on the window points."""
    return float(np.sqrt(np.mean((f - ref) ** 2) / np.mean(ref ** 2)))


def write_curve(path: Path, length: float, delta: np.ndarray, force: np.ndarray,
                column: str = "delta_over_D") -> None:
    """The curve's CSV: delta_m, delta over the length [mm] (column), force_N."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["delta_m", column, "force_N"])
        for d, F in zip(delta, force):
            w.writerow([f"{d:.9e}", f"{d / (length * MM):.9e}", f"{F:.9e}"])


def write_csv(path: Path, c: Crush, delta: np.ndarray, force: np.ndarray) -> None:
    write_curve(path, c.D, delta, force)


def read_csv(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """delta [m] and force [N per depth] of a CSV written by write_csv."""
    a = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return a[:, 0], a[:, 2]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", type=Path, default=CASE, help="crush namelist")
    ap.add_argument("--meshes", nargs="*", default=[f"{a}x{b}" for a, b in MESHES],
                    help="meshes n_t x n_c, coarse to fine (the finest is the reference)")
    ap.add_argument("--docs", type=Path, default=DOCS, help="decks, CSV and summary")
    ap.add_argument("--work", type=Path, default=WORK, help="run folders")
    ap.add_argument("--deck-only", action="store_true", help="write the decks, do not run ccx")
    ap.add_argument("--force", action="store_true", help="re-run meshes that have a result")
    ap.add_argument("--increments", type=int, default=INCREMENTS,
                    help="equal load increments (a sensitivity check; use other --docs/--work)")
    ap.add_argument("--penalty", type=float, default=PENALTY_OVER_E,
                    help="contact penalty over E per mm (a sensitivity check)")
    a = ap.parse_args(argv)
    try:
        c = read_crush(a.case)
        meshes = [tuple(int(v) for v in m.lower().split("x")) for m in a.meshes]
    except (InputError, FileNotFoundError, ValueError) as e:
        print(f"fe_reference: {e}", file=sys.stderr)
        return 2
    a.docs.mkdir(parents=True, exist_ok=True)
    results = []
    for n_t, n_c in meshes:
        name = deck_name(n_t, n_c)
        text = write_deck(c, n_t, n_c, a.increments, a.penalty)
        (a.docs / f"{name}.inp").write_text(text)
        if a.deck_only:
            continue
        try:
            tm, rf, uy, info = run_mesh(text, a.work / name, name, a.force, "fe_reference",
                                        f"{name} ({n_t * n_c} elements)")
        except (FileNotFoundError, RuntimeError) as e:
            print(f"fe_reference: {e}", file=sys.stderr)
            return 3
        except StoppedShort as e:
            print(f"fe_reference: {e}", file=sys.stderr)
            return 4
        delta, force = curve_si(c, rf, uy)
        write_csv(a.docs / f"{name}.csv", c, delta, force)
        results.append({"mesh": name, "n_t": n_t, "n_c": n_c, "elements": n_t * n_c,
                        "increments": int(tm.size), "cpu_s": round(info["cpu_s"], 1),
                        "window": window(delta, force, c.D * MM)})
        print(f"fe_reference: {name}: {tm.size} increments, {info['cpu_s']:.0f} CPU s")
    if a.deck_only or not results:
        return 0
    ref = results[-1]["window"]
    summary = {"case": c.source, "reference": results[-1]["mesh"],
               "window_delta_over_D": list(WINDOW), "delta_end_over_D": DELTA_END,
               "penalty_MPa_per_mm": a.penalty * c.E, "increments": a.increments,
               "meshes": []}
    for r in results:
        w = r.pop("window")
        r["err_L2_vs_finest"] = round(rel_l2(w, ref), 6) if r is not results[-1] else 0.0
        r["force_mean_N"] = round(float(np.mean(w)), 3)
        summary["meshes"].append(r)
        print(f"  {r['mesh']:>18s}: mean force {r['force_mean_N'] / 1e3:.3f} kN/m, "
              f"L2 against the finest {100 * r['err_L2_vs_finest']:.3f} %")
    best = results[-1]["mesh"]
    shutil.copyfile(a.docs / f"{best}.csv", a.docs / "crush_fe.csv")
    (a.docs / "convergence.json").write_text(json.dumps(summary, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
