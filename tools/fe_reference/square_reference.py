#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A finite element reference for a square tube crushed laterally between flat platens
(issue 34).

The section: a square tube, centreline side a = 48 mm, wall t = 1.5 mm, corners rounded on the
centreline to r_c = 3 mm (outer corner radius 3.75 mm, inner 2.25 mm; outer height
H = a + t = 49.5 mm), of the crush's steel (namelists/crush.nml: E 210 GPa, nu 0.3, J2
sigma_y 310 MPa, linear hardening 10 MPa), in plane strain between two rigid frictionless
platens that approach each other by half the outer height (delta = 24.75 mm).

The CalculiX (ccx 2.20) model is the ring reference's (tools/fe_reference/fe_reference.py,
whose deck writer, runner and readers this imports): a quarter (x >= 0, y >= centre) with
mirrors u_x = 0 on x = 0 and u_y = 0 on y = centre, CPE8R elements on a structured mapped mesh
made here (n_t through the wall; along the centreline n_s on each straight half-wall and n_a
on the corner arc; nodes on the offsets of the centreline, the corner's on arcs), the top
platen a strip of CPE8R elements whose nodes all have prescribed displacements, frictionless
surface-to-surface penalty contact (10 E per mm), NLGEOM, a static step of equal increments
(automatic cut-back allowed) moving the platen down by H / 4 = 12.375 mm, a fifth of the
increments over the first 4 % of the travel (the force's peak, TRAVEL). The deformed shape
of every increment goes to the .frd file (ccx has one output frequency for the .dat and the
.frd files): the self-contact check (the inner walls must not touch by delta = H / 2) and the
figure's shapes.

Outputs (docs/fe_reference/, SI, tubempm's conventions: docs/output.md): per mesh
square_nt<n_t>_ns<n_s>_na<n_a>.inp and .csv (delta_m the relative approach of the platens,
delta_over_H over the outer height, force_N the full tube's platen force per &run depth),
square_fe.csv (the finest mesh: the reference), square_shapes.csv (the finest mesh's deformed
quarter at a few approaches), square_convergence.json.

    python3 -m tools.fe_reference.square_reference                  # the meshes, coarse to fine
    python3 -m tools.fe_reference.square_reference --deck-only      # the decks only
    python3 -m tools.fe_reference.square_reference --meshes 2x14x4  # one mesh (n_t x n_s x n_a)
    python3 -m tools.fe_reference.square_reference --compare out/square_tube/history.csv
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import shutil
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from plots.mpmplot import analysis, namelist, readers, scene
from tools.fe_reference import fe_reference as fe
from tools.fe_reference.fe_reference import MM, _num

ROOT = Path(__file__).resolve().parent.parent.parent

DOCS = ROOT / "docs" / "fe_reference"
WORK = ROOT / "out" / "fe_reference" / "square"
#: the material's namelist (the crush's steel)
MATERIAL_CASE = ROOT / "namelists" / "crush.nml"
#: tubempm's scene of the same tube
SCENE = ROOT / "namelists" / "sections" / "square_tube.nml"
#: the section [mm]: centreline side, wall thickness, centreline corner radius
SIDE, THICKNESS, CORNER = 48.0, 1.5, 3.0
#: the approach at the end over the outer height
DELTA_END = 0.5
#: the comparison window (delta / H) and its points (spacing 0.005, the ring's)
WINDOW = (0.0, 0.5)
N_WINDOW = 101
#: where the ring's window starts (delta / D there, delta / H here): the second set of errors
RING_WINDOW_START = 0.05
#: the smoothed error's moving average [delta / H] (the ring's, tools/study.py SMOOTH_WIDTH)
SMOOTH_WIDTH = 0.02
#: the refinement (n_t, n_s, n_a): element length along about 2 t / n_t (aspect 2)
MESHES = ((2, 14, 4), (4, 28, 7), (8, 56, 13))
INCREMENTS = 300
#: the platen's travel over the step: (step time, fraction), piecewise linear; the first fifth
#: of the increments goes to delta/H 0-0.02, where the force rises to its peak and falls
TRAVEL = ((0.0, 0.0), (0.2, 0.04), (1.0, 1.0))
#: the deformed shapes kept in square_shapes.csv (delta / H, the nearest increments)
SHAPES_AT = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5)
#: self-contact: surface points closer along the boundary than this [mm] are neighbours (a
#: quarter of the side: points of different walls, or of the two arms of a folded side wall
#: 6 mm or more from its hinge)
NEIGHBOUR_ARC = 0.25 * SIDE


@dataclass(frozen=True)
class Square:
    """The square tube in deck units (mm, N, MPa)."""
    a: float              # centreline side [mm]
    t: float              # wall [mm]
    rc: float             # centreline corner radius [mm]
    E: float              # [MPa]
    nu: float
    sigma_y: float        # [MPa]
    hardening: float      # [MPa]
    depth: float          # [m]
    source: str

    @property
    def H(self) -> float:
        """Outer height (= width) [mm]."""
        return self.a + self.t


def read_square(material_case: Path = MATERIAL_CASE) -> Square:
    """The section above with the material and depth of the ring crush's namelist (checked as
    fe_reference.read_crush checks it: j2, plane strain, rate independent)."""
    c = fe.read_crush(material_case)
    return Square(a=SIDE, t=THICKNESS, rc=CORNER, E=c.E, nu=c.nu, sigma_y=c.sigma_y,
                  hardening=c.hardening, depth=c.depth, source=c.source)


# ----------------------------------------------------------------------------------------------
# The mesh (deck units mm, the tube's centre at the origin)
# ----------------------------------------------------------------------------------------------

def centreline(c: Square, n_s: int, n_a: int, j: int) -> tuple[float, float, float, float]:
    """Point (x, y) and outward normal (nx, ny) of the quarter's centreline at the half-element
    index j = 0 ... 2 (2 n_s + n_a): from the y = 0 mirror up the side wall (n_s elements),
    round the corner (n_a), along the top wall to the x = 0 mirror (n_s)."""
    h = 0.5 * c.a
    straight = h - c.rc
    u = 0.5 * j                                   # in elements
    if u <= n_s:
        return h, straight * u / n_s, 1.0, 0.0
    if u <= n_s + n_a:
        phi = 0.5 * math.pi * (u - n_s) / n_a
        cs, sn = math.cos(phi), math.sin(phi)
        if u == n_s + n_a:
            cs, sn = 0.0, 1.0
        return straight + c.rc * cs, straight + c.rc * sn, cs, sn
    x = straight * (1.0 - (u - n_s - n_a) / n_s)
    return (0.0 if j == 2 * (2 * n_s + n_a) else x), h, 0.0, 1.0


def square_mesh(c: Square, n_t: int, n_s: int, n_a: int
                ) -> tuple[dict[int, tuple[float, float]], list[tuple[int, ...]], dict[str, list]]:
    """Structured quarter square tube of CPE8R elements: node grid (2 n_t + 1) through the
    wall (inner to outer) x (2 n_l + 1) along (n_l = 2 n_s + n_a; centreline()), element centre
    nodes left out. Returns nodes {id: (x, y)}, elements (corners counter-clockwise, then the
    midside nodes of edges 1-2, 2-3, 3-4, 4-1) and the sets: 'outer' faces (element, 2),
    'ymirror', 'xmirror' node ids, and 'inner' / 'outer_nodes': the boundary node ids in order
    along (corner and midside)."""
    n_l = 2 * n_s + n_a
    ni, nj = 2 * n_t + 1, 2 * n_l + 1

    def nid(i: int, j: int) -> int:
        return 1 + i + ni * j

    nodes: dict[int, tuple[float, float]] = {}
    for j in range(nj):
        x, y, nx, ny = centreline(c, n_s, n_a, j)
        for i in range(ni):
            if i % 2 == 1 and j % 2 == 1:
                continue
            o = c.t * (i / (ni - 1) - 0.5)
            nodes[nid(i, j)] = (x + o * nx, y + o * ny)
    elems: list[tuple[int, ...]] = []
    outer: list[tuple[int, int]] = []
    for jj in range(n_l):
        for ii in range(n_t):
            i, j = 2 * ii, 2 * jj
            elems.append((nid(i, j), nid(i + 2, j), nid(i + 2, j + 2), nid(i, j + 2),
                          nid(i + 1, j), nid(i + 2, j + 1), nid(i + 1, j + 2), nid(i, j + 1)))
            if ii == n_t - 1:
                outer.append((len(elems), 2))
    sets = {"outer": outer,
            "ymirror": [nid(i, 0) for i in range(ni)],
            "xmirror": [nid(i, nj - 1) for i in range(ni)],
            "inner": [nid(0, j) for j in range(nj)],
            "outer_nodes": [nid(ni - 1, j) for j in range(nj)]}
    return nodes, elems, sets


def platen_travel(c: Square) -> float:
    """Travel of the top platen [mm]: half the approach delta = DELTA_END H."""
    return 0.5 * DELTA_END * c.H


def deck_name(n_t: int, n_s: int, n_a: int) -> str:
    return f"square_nt{n_t}_ns{n_s}_na{n_a}"


def write_deck(c: Square, n_t: int, n_s: int, n_a: int, increments: int = INCREMENTS,
               penalty: float = fe.PENALTY_OVER_E) -> str:
    """The ccx input for one mesh (deterministic text)."""
    nodes, elems, sets = square_mesh(c, n_t, n_s, n_a)
    u = platen_travel(c)
    h = 0.5 * c.a
    header = [
        "** tubempm FE reference (tools/fe_reference/square_reference.py): square tube crushed "
        "laterally",
        f"** material of {c.source}: quarter square tube, plane strain CPE8R, n_t = {n_t}, "
        f"n_s = {n_s}, n_a = {n_a}",
        f"** centreline side {_num(c.a)} mm, wall {_num(c.t)} mm, centreline corner radius "
        f"{_num(c.rc)} mm; E {_num(c.E)} MPa, nu {_num(c.nu)}, sigma_y {_num(c.sigma_y)} MPa, "
        f"H {_num(c.hardening)} MPa",
        f"** top platen moves down {_num(u)} mm (approach delta/H = {DELTA_END}, H the outer "
        f"height); units mm N MPa",
    ]
    y0 = h + 0.5 * c.t
    return fe.deck_text(header, nodes, elems, sets, c, u,
                        (-0.05 * h, 1.3 * h, y0, y0 + c.t), increments, penalty,
                        output=("*NODE FILE, NSET=NALL", "U"), amplitude=TRAVEL)


# ----------------------------------------------------------------------------------------------
# Results
# ----------------------------------------------------------------------------------------------

def parse_frd(path: Path) -> list[tuple[float, dict[int, tuple[float, float]]]]:
    """The displacement frames of a ccx .frd file: [(step time, {node: (u_x, u_y)})]."""
    frames: list[tuple[float, dict[int, tuple[float, float]]]] = []
    tm, cur = math.nan, None
    for line in path.read_text().splitlines():
        if line.startswith("  100C"):
            tm = float(line[12:24])
        elif line.startswith(" -4  DISP"):
            cur = {}
        elif cur is not None and line.startswith(" -1"):
            cur[int(line[3:13])] = (float(line[13:25]), float(line[25:37]))
        elif cur is not None and line.startswith(" -3"):
            frames.append((tm, cur))
            cur = None
    return frames


def boundary(nodes: dict[int, tuple[float, float]], ids: list[int],
             u: dict[int, tuple[float, float]]) -> np.ndarray:
    """The deformed positions of the nodes ids, in order (n, 2) [mm]."""
    return np.array([(nodes[k][0] + u[k][0], nodes[k][1] + u[k][1]) for k in ids])


def full_loop(q: np.ndarray) -> np.ndarray:
    """The whole closed curve from its quarter q (ordered from the y = 0 mirror to the x = 0
    mirror): the four mirror images, counter-clockwise, each shared mirror point once."""
    q2 = (q * [-1.0, 1.0])[::-1][1:]             # x < 0, from the x = 0 mirror down
    top = np.vstack([q, q2])
    bottom = (top * [1.0, -1.0])[::-1][1:-1]
    return np.vstack([top, bottom])


def self_clearance(loop: np.ndarray, neighbour: float = NEIGHBOUR_ARC) -> float:
    """The least distance between two points of a closed polyline that are more than
    `neighbour` apart along it: how near the surface comes to touching itself [mm]."""
    seg = np.hypot(*np.diff(np.vstack([loop, loop[:1]]), axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
    total = float(np.sum(seg))
    d = np.hypot(loop[:, None, 0] - loop[None, :, 0], loop[:, None, 1] - loop[None, :, 1])
    ds = np.abs(s[:, None] - s[None, :])
    ds = np.minimum(ds, total - ds)
    return float(np.min(np.where(ds > neighbour, d, np.inf)))


def shapes_of(c: Square, n_t: int, n_s: int, n_a: int, frd: Path) -> list[dict]:
    """Per .frd frame and the start: the approach [mm], the inner and outer surfaces of the quarter (n, 2)
    [mm], the inner surface's self-clearance, the inner gap between the top and bottom walls
    (twice the least y of the top wall's inner surface, x <= a/2 - r_c) and the side wall's
    largest outward bulge [mm]."""
    nodes, _, sets = square_mesh(c, n_t, n_s, n_a)
    ref = max(nodes) + 1                          # the platen's first node (deck_text's NREF)
    out = []
    for tm, u in [(0.0, {k: (0.0, 0.0) for k in [*nodes, ref]})] + parse_frd(frd):
        inner = boundary(nodes, sets["inner"], u)
        outer = boundary(nodes, sets["outer_nodes"], u)
        top = inner[2 * (n_s + n_a):]
        out.append({"time": tm, "delta_mm": -2.0 * u[ref][1], "inner": inner,
                    "outer": outer, "clearance_mm": self_clearance(full_loop(inner)),
                    "wall_gap_mm": 2.0 * float(np.min(top[:, 1])),
                    "bulge_mm": float(np.max(outer[:, 0]) - 0.5 * c.H)})
    return out


def write_shapes(path: Path, shapes: list[dict], c: Square) -> None:
    """The deformed quarter's surfaces at the frames nearest to SHAPES_AT: delta_m,
    delta_over_H, surface (inner or outer), k (order along), x_m, y_m (tube centre at the
    origin)."""
    d = np.array([sh["delta_mm"] for sh in shapes]) / c.H
    keep = sorted({int(np.argmin(np.abs(d - x))) for x in SHAPES_AT})
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["delta_m", "delta_over_H", "surface", "k", "x_m", "y_m"])
        for sh in (shapes[i] for i in keep):
            d = sh["delta_mm"] * MM
            for name in ("inner", "outer"):
                for k, (x, y) in enumerate(sh[name]):
                    w.writerow([f"{d:.6e}", f"{sh['delta_mm'] / c.H:.6f}", name, k,
                                f"{x * MM:.6e}", f"{y * MM:.6e}"])


def on_window(delta: np.ndarray, force: np.ndarray, H: float) -> np.ndarray:
    """The force at the window's points delta/H (H [m]; linear interpolation)."""
    return np.interp(np.linspace(*WINDOW, N_WINDOW) * H, delta, force)


def smooth_on_window(delta: np.ndarray, force: np.ndarray, H: float) -> np.ndarray:
    """The smoothed force at the window's points (tools/study.py's crush_curve_metrics): F on
    a grid of delta/H = 0.001, a centred moving average over SMOOTH_WIDTH, interpolated."""
    order = np.argsort(delta, kind="stable")
    fine = np.arange(0.0, delta.max(), 0.001 * H)
    sm = analysis.moving_average(np.interp(fine, delta[order], force[order]),
                                 int(round(SMOOTH_WIDTH / 0.001)))
    return np.interp(np.linspace(*WINDOW, N_WINDOW) * H, fine, sm)


# ----------------------------------------------------------------------------------------------
# tubempm against the reference
# ----------------------------------------------------------------------------------------------

def mpm_curve(history_csv: Path, case: Path | None = None) -> tuple[np.ndarray, np.ndarray]:
    """tubempm's crush curve: the platens' relative approach [m] and the full tube's platen
    force [N per &run depth] of a run's history.csv (scene.crush_displacement: mirror images
    of a quarter model counted); the namelist `case`, by default the one beside history.csv
    or namelists/sections/square_tube.nml."""
    history_csv = Path(history_csv)
    if case is None:
        beside = sorted(history_csv.parent.glob("*.nml"))
        case = beside[0] if beside else SCENE
    delta, force, _ = scene.crush_displacement(readers.read_history(history_csv),
                                               namelist.read_namelist(case))
    return delta, force


def compare(history_csv: Path, case: Path | None = None, reference: Path | None = None
            ) -> dict[str, float]:
    """tubempm's square tube crush (mpm_curve of its history.csv) against the FE reference
    (square_fe.csv): relative L2 errors of the platen force over delta/H = 0-0.5 (H the outer
    height), raw (err_L2) and both curves smoothed over delta/H = 0.02 as the ring's
    (err_smooth, the headline); the same over the ring's window, delta/H = 0.05-0.5, past the
    peak (err_L2_005, err_smooth_005); the mean force over FE's (force_over_fe), the peak
    force of each (peak_fe_N, peak_mpm_N) and how far the run got (delta_end_over_H). A run
    short of delta/H = 0.5 is measured over what it has."""
    delta, force = mpm_curve(history_csv, case)
    H = read_square().H * MM
    d_fe, f_fe = fe.read_csv(reference or DOCS / "square_fe.csv")
    end = min(float(np.max(delta)) / H, WINDOW[1])
    keep = np.linspace(*WINDOW, N_WINDOW) <= end + 1e-12
    w, ws = on_window(delta, force, H)[keep], smooth_on_window(delta, force, H)[keep]
    r, rs = on_window(d_fe, f_fe, H)[keep], smooth_on_window(d_fe, f_fe, H)[keep]
    late = np.linspace(*WINDOW, N_WINDOW)[keep] >= RING_WINDOW_START - 1e-12
    return {"err_L2": fe.rel_l2(w, r), "err_smooth": fe.rel_l2(ws, rs),
            "err_L2_005": fe.rel_l2(w[late], r[late]),
            "err_smooth_005": fe.rel_l2(ws[late], rs[late]),
            "force_over_fe": float(np.mean(w) / np.mean(r)),
            "peak_fe_N": float(np.max(f_fe[d_fe <= end * H])),
            "peak_mpm_N": float(np.max(force[delta <= end * H])),
            "delta_end_over_H": end}


# ----------------------------------------------------------------------------------------------

def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--meshes", nargs="*", default=[f"{a}x{b}x{c}" for a, b, c in MESHES],
                    help="meshes n_t x n_s x n_a, coarse to fine (the finest is the reference)")
    ap.add_argument("--docs", type=Path, default=DOCS, help="decks, CSV and summary")
    ap.add_argument("--work", type=Path, default=WORK, help="run folders")
    ap.add_argument("--deck-only", action="store_true", help="write the decks, do not run ccx")
    ap.add_argument("--force", action="store_true", help="re-run meshes that have a result")
    ap.add_argument("--increments", type=int, default=INCREMENTS,
                    help="equal load increments (a sensitivity check; use other --docs/--work)")
    ap.add_argument("--penalty", type=float, default=fe.PENALTY_OVER_E,
                    help="contact penalty over E per mm (a sensitivity check)")
    ap.add_argument("--compare", type=Path, metavar="HISTORY_CSV",
                    help="only compare a tubempm run's history.csv with the committed reference")
    ap.add_argument("--write", action="store_true",
                    help="with --compare: write its curve (square_mpm.csv) and errors "
                         "(square_comparison.json) to --docs")
    a = ap.parse_args(argv)
    if a.compare:
        e = {k: round(v, 6) for k, v in compare(a.compare).items()}
        print(json.dumps(e, indent=1))
        if a.write:
            delta, force = mpm_curve(a.compare)
            fe.write_curve(a.docs / "square_mpm.csv", read_square().H, delta, force,
                           "delta_over_H")
            (a.docs / "square_comparison.json").write_text(json.dumps(e, indent=1) + "\n")
        return 0
    try:
        c = read_square()
        meshes = [tuple(int(v) for v in m.lower().split("x")) for m in a.meshes]
    except (fe.InputError, FileNotFoundError, ValueError) as e:
        print(f"square_reference: {e}", file=sys.stderr)
        return 2
    a.docs.mkdir(parents=True, exist_ok=True)
    H = c.H * MM
    results = []
    for n_t, n_s, n_a in meshes:
        name = deck_name(n_t, n_s, n_a)
        text = write_deck(c, n_t, n_s, n_a, a.increments, a.penalty)
        (a.docs / f"{name}.inp").write_text(text)
        if a.deck_only:
            continue
        n_el = n_t * (2 * n_s + n_a)
        try:
            tm, rf, uy, info = fe.run_mesh(text, a.work / name, name, a.force,
                                           "square_reference", f"{name} ({n_el} elements)")
        except (FileNotFoundError, RuntimeError, fe.StoppedShort) as e:
            print(f"square_reference: {e}", file=sys.stderr)
            return 3
        delta, force = fe.curve_si(c, rf, uy)
        fe.write_curve(a.docs / f"{name}.csv", c.H, delta, force, "delta_over_H")
        shapes = shapes_of(c, n_t, n_s, n_a, a.work / name / f"{name}.frd")
        last = shapes[-1]
        i_pk = int(np.argmax(force))
        i_cl = int(np.argmin([sh["clearance_mm"] for sh in shapes]))
        results.append({"mesh": name, "n_t": n_t, "n_s": n_s, "n_a": n_a, "elements": n_el,
                        "increments": int(tm.size), "cpu_s": round(info["cpu_s"], 1),
                        "peak_force_N": round(float(force[i_pk]), 2),
                        "peak_delta_over_H": round(float(delta[i_pk]) / H, 5),
                        "inner_clearance_end_mm": round(last["clearance_mm"], 4),
                        "inner_clearance_min_mm": round(shapes[i_cl]["clearance_mm"], 4),
                        "inner_clearance_min_delta_over_H":
                            round(shapes[i_cl]["delta_mm"] / c.H, 5),
                        "wall_gap_end_mm": round(last["wall_gap_mm"], 4),
                        "bulge_end_mm": round(last["bulge_mm"], 4),
                        "frame_end_delta_over_H": round(last["delta_mm"] / c.H, 5),
                        "curve": (delta, force), "shapes": shapes})
        print(f"square_reference: {name}: {tm.size} increments, {info['cpu_s']:.0f} CPU s, "
              f"peak {force[i_pk] / 1e3:.2f} kN/m at delta/H {delta[i_pk] / H:.4f}, inner "
              f"clearance at the end {last['clearance_mm']:.3f} mm")
    if a.deck_only or not results:
        return 0
    ref_d, ref_f = results[-1]["curve"]
    ref, ref_s = on_window(ref_d, ref_f, H), smooth_on_window(ref_d, ref_f, H)
    summary = {"material": c.source, "section_mm": {"a": c.a, "t": c.t, "r_c": c.rc, "H": c.H},
               "reference": results[-1]["mesh"], "window_delta_over_H": list(WINDOW),
               "smooth_width_delta_over_H": SMOOTH_WIDTH, "delta_end_over_H": DELTA_END,
               "penalty_MPa_per_mm": a.penalty * c.E, "increments": a.increments, "meshes": []}
    for r in results:
        d, f = r.pop("curve")
        shapes = r.pop("shapes")
        w, ws = on_window(d, f, H), smooth_on_window(d, f, H)
        r["err_L2_vs_finest"] = round(fe.rel_l2(w, ref), 6)
        r["err_smooth_vs_finest"] = round(fe.rel_l2(ws, ref_s), 6)
        r["force_mean_N"] = round(float(np.mean(w)), 3)
        summary["meshes"].append(r)
        print(f"  {r['mesh']:>22s}: mean force {r['force_mean_N'] / 1e3:.3f} kN/m, L2 against "
              f"the finest {100 * r['err_L2_vs_finest']:.3f} % (smoothed "
              f"{100 * r['err_smooth_vs_finest']:.3f} %)")
    best = results[-1]["mesh"]
    shutil.copyfile(a.docs / f"{best}.csv", a.docs / "square_fe.csv")
    write_shapes(a.docs / "square_shapes.csv", shapes, c)
    (a.docs / "square_convergence.json").write_text(json.dumps(summary, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
