#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The square tube's CalculiX reference (tools/fe_reference/square_reference.py,
docs/fe_reference/README.md "The square tube"). No ccx, no tubempm run; about a second.

- the committed decks are what the generator writes (generator and decks cannot drift);
- the mesh: corner areas positive, the quarter's polygon area against the closed form of its
  straight walls and chorded corner, nodes on the mirrors, the outer top at H / 2;
- the curves: delta_over_H = delta_m / H, delta increasing, force positive, every mesh to
  delta/H = 0.5; square_fe.csv is the finest mesh's curve;
- the refinement: at least three meshes, the smoothed differences from the finest shrinking,
  the second-finest within 1 %; the convergence summary recomputed from the committed curves;
- the physics: past the peak the force lies within 0.9-1.3 times the rigid-plastic three-hinge
  mechanism of the side walls, P = 4 M0 / (L sin theta) (L = a/2 the half side,
  2 L (1 - cos theta) = delta, M0 = sigma_y t^2 / (2 sqrt 3) in plane strain), over
  delta/H = 0.2-0.5; the inner surface never comes nearer to touching itself than 1 mm;
- compare() on the reference's own curve written as a history gives zero error, and a force
  1 % higher gives 1 %; the committed square_comparison.json is computed from the committed
  curves (square_mpm.csv, square_fe.csv).

    python3 -m tests.test_fe_square [SCRATCH]
"""
from __future__ import annotations

import json
import math
import sys
import tempfile
import traceback
from pathlib import Path

import numpy as np

from tests.pycheck import Checks
from tools.fe_reference import square_reference as sq

T = Checks("test_fe_square")
check = T.check
DOCS = sq.DOCS


def committed() -> list[tuple[int, int, int]]:
    return [m for m in sq.MESHES if (DOCS / f"{sq.deck_name(*m)}.csv").is_file()]


def test_decks_and_mesh() -> None:
    c = sq.read_square()
    for m in sq.MESHES:
        deck = DOCS / f"{sq.deck_name(*m)}.inp"
        check(deck.is_file() and deck.read_text() == sq.write_deck(c, *m),
              f"{deck.name} is what the generator writes")
    n_t, n_s, n_a = 2, 5, 3
    nodes, elems, sets = sq.square_mesh(c, n_t, n_s, n_a)
    areas = []
    for e in elems:
        xy = np.array([nodes[k] for k in e[:4]])
        areas.append(0.5 * float(np.sum(xy[:, 0] * np.roll(xy[:, 1], -1)
                                         - np.roll(xy[:, 0], -1) * xy[:, 1])))
    check(min(areas) > 0.0, "every element's corners run counter-clockwise")
    r_o, r_i = c.rc + 0.5 * c.t, c.rc - 0.5 * c.t
    exact = c.t * (c.a - 2.0 * c.rc) + n_a * (r_o ** 2 - r_i ** 2) * math.sin(
        0.5 * math.pi / n_a) / 2.0
    check(abs(sum(areas) / exact - 1.0) < 1e-12,
          f"quarter polygon area {sum(areas):.9f} of {exact:.9f} (straight walls, chorded corner)")
    check(all(nodes[k][1] == 0.0 for k in sets["ymirror"]), "y-mirror nodes on y = 0")
    check(all(nodes[k][0] == 0.0 for k in sets["xmirror"]), "x-mirror nodes on x = 0")
    top = max(y for _, y in nodes.values())
    check(abs(top - 0.5 * c.H) < 1e-12, f"outer top at H/2 ({top})")
    check(len(sets["outer"]) == 2 * n_s + n_a, "one outer face per element along")


def test_curves() -> None:
    c = sq.read_square()
    meshes = committed()
    check(len(meshes) >= 3, f"at least three FE meshes committed ({meshes})")
    for m in meshes:
        p = DOCS / f"{sq.deck_name(*m)}.csv"
        a = np.loadtxt(p, delimiter=",", skiprows=1)
        check(np.allclose(a[:, 1], a[:, 0] / (c.H * sq.MM), rtol=1e-8, atol=0.0),
              f"{p.name}: delta_over_H = delta_m / H")
        check(bool(np.all(np.diff(a[:, 0]) > 0.0)), f"{p.name}: delta increases")
        check(bool(np.all(a[1:, 2] > 0.0)), f"{p.name}: the force pushes (positive)")
        check(abs(a[-1, 1] - sq.DELTA_END) < 1e-6, f"{p.name}: reaches delta/H = 0.5")
    if meshes:
        check((DOCS / "square_fe.csv").read_bytes() ==
              (DOCS / f"{sq.deck_name(*meshes[-1])}.csv").read_bytes(),
              "square_fe.csv is the finest mesh's curve")


def test_convergence() -> None:
    c = sq.read_square()
    H = c.H * sq.MM
    meshes = committed()
    curves = [sq.fe.read_csv(DOCS / f"{sq.deck_name(*m)}.csv") for m in meshes]
    ref_s = sq.smooth_on_window(*curves[-1], H)
    errs = [sq.fe.rel_l2(sq.smooth_on_window(d, f, H), ref_s) for d, f in curves[:-1]]
    check(all(x > y for x, y in zip(errs, errs[1:])), f"differences shrink with the mesh: {errs}")
    check(errs[-1] < 0.01, f"second-finest within 1 % of the finest ({100 * errs[-1]:.3f} %)")
    summary = json.loads((DOCS / "square_convergence.json").read_text())
    for row, e in zip(summary["meshes"], errs):
        check(abs(row["err_smooth_vs_finest"] - e) < 1e-6,
              f"{row['mesh']}: square_convergence.json's smoothed difference {e:.6f}")
    for row in summary["meshes"]:
        check(row["inner_clearance_min_mm"] > 1.0,
              f"{row['mesh']}: the inner surface keeps {row['inner_clearance_min_mm']} mm "
              f"from itself (no self-contact by delta/H = 0.5)")


def test_mechanism() -> None:
    c = sq.read_square()
    d, f = sq.fe.read_csv(DOCS / "square_fe.csv")
    x = np.linspace(0.2, 0.5, 31)
    delta = x * c.H                                         # [mm]
    L = 0.5 * c.a
    theta = np.arccos(1.0 - delta / (2.0 * L))
    m0 = c.sigma_y * c.t ** 2 / (2.0 * math.sqrt(3.0))       # [N mm / mm]
    p = 4.0 * m0 / (L * np.sin(theta)) * 1e3 * c.depth      # [N per depth]
    ratio = np.interp(delta * sq.MM, d, f) / p
    check(bool(np.all((ratio > 0.9) & (ratio < 1.3))),
          f"FE over the three-hinge mechanism, delta/H 0.2-0.5: {ratio.min():.3f}-"
          f"{ratio.max():.3f} (band 0.9-1.3)")


def test_committed_comparison() -> None:
    """square_comparison.json is what compare() gives for the committed tubempm curve."""
    js, mpm = DOCS / "square_comparison.json", DOCS / "square_mpm.csv"
    if not (js.is_file() and mpm.is_file()):
        print("test_fe_square: no committed tubempm comparison")
        return
    c = sq.read_square()
    H = c.H * sq.MM
    e = json.loads(js.read_text())
    d, f = sq.fe.read_csv(mpm)
    d0, f0 = sq.fe.read_csv(DOCS / "square_fe.csv")
    err = sq.fe.rel_l2(sq.smooth_on_window(d, f, H), sq.smooth_on_window(d0, f0, H))
    check(abs(err - e["err_smooth"]) < 1e-5,
          f"square_comparison.json's err_smooth {e['err_smooth']} from square_mpm.csv ({err:.6f})")


def test_compare(scratch: Path) -> None:
    """compare() reads a history.csv through scene.crush_displacement: the FE curve written as a
    quarter model's history (a top platen moving down, the mirror doubling the approach)."""
    d, f = sq.fe.read_csv(DOCS / "square_fe.csv")
    case = scratch / "square.nml"
    case.write_text("&body\n shape = 'ring', r_inner = 1.0, r_outer = 2.0, sector = 'quarter' /\n"
                    "&wall\n point = 0.0, 2.0, normal = 0.0, -1.0, velocity = 0.0, -1.0 /\n")
    for scale, want in ((1.0, 0.0), (1.01, 0.01)):
        hist = scratch / "history.csv"
        with open(hist, "w") as fh:
            fh.write("time,wall1_disp,wall1_force,wall2_disp,wall2_force,wall3_disp,"
                     "wall3_force\n")
            for k, (dk, fk) in enumerate(zip(d, f)):
                fh.write(f"{k},{-0.5 * dk:.12e},{scale * fk:.12e},0,0,0,0\n")
        e = sq.compare(hist, case)
        check(abs(e["err_smooth"] - want) < 1e-6 and abs(e["err_L2"] - want) < 1e-6,
              f"compare of the FE curve x {scale}: {e['err_L2']:.6f}, {e['err_smooth']:.6f}")


def main() -> int:
    scratch = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    scratch.mkdir(parents=True, exist_ok=True)
    for test in (test_decks_and_mesh, test_curves, test_convergence, test_mechanism,
                 test_committed_comparison):
        try:
            test()
        except Exception:
            traceback.print_exc()
            check(False, f"{test.__name__} raised")
    try:
        test_compare(scratch)
    except Exception:
        traceback.print_exc()
        check(False, "test_compare raised")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
