#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The CalculiX crush reference (tools/fe_reference/, docs/fe_reference/).

Checks the committed FE curves against closed forms and the generator against the committed
decks:

- the initial stiffness of the finest FE curve against the thin ring between two line loads,
  P / delta = E' I / ((pi/4 - 2/pi) R^3) (E' = E / (1 - nu^2)), within 2 % (the thin-ring
  formula leaves out shear and normal-force flexibility and the local flattening under the
  load, O((t/R)^2) and less here, R/t = 16.7; the FE gives -0.8 %);
- the plateau: the mean force over delta/D = 0.05-0.5 against DeRuntz-Hodge's (rigid-perfectly
  plastic, P0 / sqrt(1 - (delta/D)^2)) within -5 % ... +5 % (the FE ring is elastic-plastic with
  a 10 MPa linear hardening and its hinges spread: Reid & Reddy's curves lie within a few per
  cent of DeRuntz-Hodge's over this range);
- the mesh refinement: the second-finest mesh within 0.5 % (relative L2 over the window) of
  the finest, and the errors shrinking with the mesh;
- the CSV's columns are consistent (delta/D = delta / D, force positive, delta increasing);
- the generator: the decks regenerated from namelists/crush.nml are identical to the
  committed ones (so generator and decks cannot drift);
- with --ccx (make fe-reference, before it rewrites the CSVs; not in make test, where it cost
  30-40 s): the coarsest deck is run with ccx and its curve must match the committed CSV to 1e-6.

    python3 -m tests.test_fe_reference [--ccx] [SCRATCH]
"""
from __future__ import annotations

import math
import shutil
import sys
import tempfile
import traceback
from pathlib import Path

import numpy as np

from tests.pycheck import Checks
from tools.fe_reference import fe_reference as fe
from plots.mpmplot import namelist, scene, theory

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_fe_reference")
check = T.check
DOCS = ROOT / "docs" / "fe_reference"
WINDOW = np.linspace(0.05, 0.5, 91)


def meshes() -> list[tuple[int, int]]:
    return [tuple(m) for m in fe.MESHES]


def ring() -> dict:
    return scene.ring_properties(namelist.read_namelist(fe.CASE))


def test_columns() -> None:
    r = ring()
    for n_t, n_c in meshes():
        p = DOCS / f"{fe.deck_name(n_t, n_c)}.csv"
        if not check(p.is_file(), f"{p} missing"):
            continue
        a = np.loadtxt(p, delimiter=",", skiprows=1)
        check(np.allclose(a[:, 1], a[:, 0] / r["D"], rtol=1e-8, atol=0.0),
              f"{p.name}: delta_over_D = delta_m / D (D = {r['D']} m)")
        check(bool(np.all(np.diff(a[:, 0]) > 0.0)), f"{p.name}: delta increases")
        check(bool(np.all(a[1:, 2] > 0.0)), f"{p.name}: the force pushes (positive)")
        check(a[-1, 1] >= 0.5, f"{p.name}: reaches delta/D = 0.5 (got {a[-1, 1]:.3f})")
    check((DOCS / "crush_fe.csv").read_bytes() ==
          (DOCS / f"{fe.deck_name(*meshes()[-1])}.csv").read_bytes(),
          "crush_fe.csv is the finest mesh's curve")


def test_elastic_stiffness() -> None:
    r = ring()
    d, f = fe.read_csv(DOCS / "crush_fe.csv")
    k_fe = f[1] / d[1]                       # first increment: delta/D = 0.002, elastic
    k = theory.ring_elastic_stiffness(r["R"], r["t"], r["E"], r["nu"], "strain", r["depth"])
    # the same by hand: E' I / ((pi/4 - 2/pi) R^3)
    e_p = r["E"] / (1.0 - r["nu"] ** 2)
    k_hand = e_p * r["t"] ** 3 / 12.0 * r["depth"] / ((math.pi / 4 - 2 / math.pi) * r["R"] ** 3)
    check(abs(k / k_hand - 1.0) < 1e-12, "mpmplot's ring stiffness is the closed form")
    check(abs(k_fe / k - 1.0) < 0.02,
          f"initial stiffness {k_fe:.4e} N/m/m against the thin ring's {k:.4e} (2 %)")
    # still elastic at the first increment: the second has twice the force within 0.5 %
    check(abs(f[2] / (2.0 * f[1]) - 1.0) < 0.005, "linear over the first two increments")


def test_plateau() -> None:
    r = ring()
    d, f = fe.read_csv(DOCS / "crush_fe.csv")
    fw = np.interp(WINDOW * r["D"], d, f)
    dh = theory.deruntz_hodge(WINDOW * r["D"], r["D"], r["t"], r["sigma_y"], "strain",
                               r["depth"])
    ratio = float(np.mean(fw) / np.mean(dh))
    check(0.95 <= ratio <= 1.05, f"mean force / DeRuntz-Hodge over delta/D 0.05-0.5: "
          f"{ratio:.4f} (band 0.95-1.05)")
    # P0 by hand: 4 M0 / R, M0 = sigma_y t^2 / (2 sqrt 3) (plane strain)
    p0 = 4.0 * r["sigma_y"] * r["t"] ** 2 / (2.0 * math.sqrt(3.0)) / r["R"] * r["depth"]
    check(abs(dh[0] * math.sqrt(1.0 - 0.05 ** 2) / p0 - 1.0) < 1e-12, "DeRuntz-Hodge's P0")
    # pointwise: no point of the window more than 10 % from DeRuntz-Hodge
    worst = float(np.max(np.abs(fw / dh - 1.0)))
    check(worst < 0.10, f"largest pointwise difference from DeRuntz-Hodge {worst:.3f} (< 0.10)")


def test_convergence() -> None:
    r = ring()
    curves = []
    for n_t, n_c in meshes():
        d, f = fe.read_csv(DOCS / f"{fe.deck_name(n_t, n_c)}.csv")
        curves.append(np.interp(WINDOW * r["D"], d, f))
    ref = curves[-1]
    errs = [fe.rel_l2(c, ref) for c in curves[:-1]]
    check(len(curves) >= 3, "at least three meshes")
    check(errs[-1] < 0.005,
          f"second-finest mesh within 0.5 % of the finest ({100 * errs[-1]:.3f} %)")
    check(all(a > b for a, b in zip(errs, errs[1:])), f"errors shrink with the mesh: {errs}")
    # rel_l2 itself: a curve 1 % above is 1 % off
    check(abs(fe.rel_l2(1.01 * ref, ref) - 0.01) < 1e-12, "rel_l2 of a 1 % offset")


def test_decks(scratch: Path) -> None:
    c = fe.read_crush(fe.CASE)
    for n_t, n_c in meshes():
        name = fe.deck_name(n_t, n_c)
        committed = (DOCS / f"{name}.inp").read_text()
        check(fe.write_deck(c, n_t, n_c) == committed,
              f"{name}.inp regenerated from {fe.CASE.name} is identical to the committed deck")
    # the mesh: nodes on their circles, element areas positive (counter-clockwise corners)
    nodes, elems, sets = fe.ring_mesh(c, 2, 6)
    rad = np.array([math.hypot(*xy) for xy in nodes.values()])
    check(bool(np.all((rad > c.r_inner - 1e-9) & (rad < c.r_outer + 1e-9))), "nodes in the wall")
    areas = []
    for e in elems:
        xy = np.array([nodes[n] for n in e[:4]])
        areas.append(0.5 * float(np.sum(xy[:, 0] * np.roll(xy[:, 1], -1)
                                         - np.roll(xy[:, 0], -1) * xy[:, 1])))
    check(min(areas) > 0.0, "every element's corners run counter-clockwise (positive area)")
    area = sum(areas)
    # the corner nodes make n_c trapezoids of angle dth = (pi/2)/n_c between the two circles:
    # area n_c (r_o^2 - r_i^2) sin(dth) / 2 (the annulus' pi/4 (r_o^2 - r_i^2) as dth -> 0)
    dth = 0.5 * math.pi / 6
    exact = 6 * (c.r_outer ** 2 - c.r_inner ** 2) * math.sin(dth) / 2.0
    check(abs(area / exact - 1.0) < 1e-9, f"quarter annulus polygon area {area:.6f} of {exact:.6f}")
    check(len(sets["outer"]) == 6 and len(sets["xmirror"]) == 5, "outer faces and mirror nodes")
    # a namelist the FE reference cannot model is refused with its file and variable
    bad = scratch / "bad.nml"
    bad.write_text(fe.CASE.read_text().replace("plane = 'strain'", "plane = 'stress'"))
    try:
        fe.read_crush(bad)
        check(False, "plane stress refused")
    except fe.InputError as e:
        check("bad.nml" in str(e) and "plane" in str(e), f"plane stress refused: {e}")


def test_ccx(scratch: Path) -> None:
    if shutil.which("ccx") is None:
        check(False, "--ccx: ccx is not on PATH (tools/install-deps.sh --ccx installs it)")
        return
    c = fe.read_crush(fe.CASE)
    n_t, n_c = meshes()[0]
    name = fe.deck_name(n_t, n_c)
    work = scratch / "ccx"
    work.mkdir(parents=True, exist_ok=True)
    deck = work / f"{name}.inp"
    shutil.copyfile(DOCS / f"{name}.inp", deck)
    fe.run_ccx(deck, work / "ccx.log")
    tm, rf, uy = fe.parse_dat(work / f"{name}.dat")
    check(tm.size > 0 and abs(tm[-1] - 1.0) < 1e-9, "ccx ran the coarse deck to the end")
    d, f = fe.curve_si(c, rf, uy)
    dc, fc = fe.read_csv(DOCS / f"{name}.csv")
    same = d.size == dc.size and np.allclose(d, dc, rtol=1e-6) and np.allclose(f, fc, rtol=1e-6)
    check(bool(same), f"ccx's curve of {name} matches the committed CSV (1e-6)")


def main() -> int:
    args = [a for a in sys.argv[1:] if a != "--ccx"]
    scratch = Path(args[0]) if args else Path(tempfile.mkdtemp())
    scratch.mkdir(parents=True, exist_ok=True)
    for test in (test_columns, test_elastic_stiffness, test_plateau, test_convergence):
        try:
            test()
        except Exception:                      # a crash is a failure, the others still run
            traceback.print_exc()
            check(False, f"{test.__name__} raised")
    for test in (test_decks, test_ccx) if "--ccx" in sys.argv[1:] else (test_decks,):
        try:
            test(scratch)
        except Exception:
            traceback.print_exc()
            check(False, f"{test.__name__} raised")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
