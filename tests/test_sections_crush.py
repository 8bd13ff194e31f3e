#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Sections crushed to densification without welding or crossing (docs/method.md "Sections",
"Self-contact"), run with the binary under test; the oracles are the particle domains of
particles.h5 and the energy balance, not the contact code.

Two coarse scenes, each crushed between a fixed and a moving frictionless platen until the
cells are flat (70 % of the height; the force rises tenfold over the last fifth), with
self-contact:

* a 2 x 2 multi-cell tube (cells of 8 mm, walls 1 mm, read from a walls file: corners, T
  joints and a cross);
* a 2 x 2 auxetic panel (inclined walls of 4 mm at -30 degrees, vertical walls of 8 mm,
  walls 0.8 mm, 4 particles through), with basis 'cpdi1', whose parallelograms cannot fold:
  CPDI2's quadrilaterals fold at its hinges before the cells are flat (the run stops with its
  remedy, docs/stability.md). It is crushed at 10 m/s (the multi-cell tube at 20): at 20 m/s
  its walls cross by 0.11 h in the transient before densification.

Each must complete (exit 0) with its energy balance within 5 % (0.17 % and 0.21 %; two or more
velocity fields meet: the loss of their contact is in `contact_loss`, that of the welds between
a body's own fields is not, docs/output.md), and in no snapshot may a domain
corner lie by more than h/10 inside a particle that is not its neighbour (shares no corner with
its own particles) and was a wall thickness or more from it at t = 0: the walls meet but do
not cross. The crossing measure is itself
checked on two overlapping squares, where it must find the overlap.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_sections_crush SCRATCH
"""
from __future__ import annotations

import sys
from pathlib import Path

import h5py
import numpy as np

from tests.pycheck import Checks
from tests.pyscene import run_scene

T = Checks("test_sections_crush")
check = T.check
H = 0.5e-3
MATERIAL = ("&material name = 'al', model = 'j2', E = 70.0e9, nu = 0.3, rho = 2700.0, "
            "sigma_y = 150.0e6, hardening = 200.0e6 /\n")


def crossing(corners: np.ndarray, quads: np.ndarray, x0: np.ndarray | None = None,
             near: float = 0.0) -> float:
    """The deepest a domain corner lies inside a particle that is not its own or a
    neighbour's (no shared corner), nor one whose centroid at t = 0 (x0) was within `near` of
    its own particle's [m]; 0 when none does."""
    owner = [[] for _ in range(len(corners))]
    for q, row in enumerate(quads):
        for c in row:
            owner[c].append(q)
    deepest = 0.0
    a = corners[quads]                        # (nq, 4, 2)
    b = np.roll(a, -1, axis=1)
    edge = b - a
    length = np.linalg.norm(edge, axis=2)
    lo = a.min(axis=1)
    hi = a.max(axis=1)
    # the (corner, particle) pairs with the corner in the particle's bounding box: the corners
    # sorted by x, each particle's x range a slice of them, then its y range
    order = np.argsort(corners[:, 0], kind="stable")
    xs = corners[order, 0]
    first = np.searchsorted(xs, lo[:, 0], side="left")
    count = np.searchsorted(xs, hi[:, 0], side="right") - first
    qi = np.repeat(np.arange(len(quads)), count)
    ci = order[np.repeat(first - np.cumsum(count) + count, count) + np.arange(count.sum())]
    keep = np.all(corners[ci] >= lo[qi], axis=1) & np.all(corners[ci] <= hi[qi], axis=1)
    ci, qi = ci[keep], qi[keep]
    p = corners[ci]
    # signed distance inside each edge (counter-clockwise: inside on the left)
    cross = (edge[qi, :, 0] * (p[:, None, 1] - a[qi, :, 1])
             - edge[qi, :, 1] * (p[:, None, 0] - a[qi, :, 0]))
    d = cross / length[qi]
    inside = np.all(d > 0.0, axis=1)
    for c, q, depth in zip(ci[inside], qi[inside], d[inside].min(axis=1)):
        nbr = set()
        for o in owner[c]:
            for c2 in quads[o]:
                nbr.update(owner[c2])
        if q in nbr or (x0 is not None and min(np.linalg.norm(x0[q] - x0[o])
                                               for o in owner[c]) < near):
            continue
        deepest = max(deepest, float(depth))
    return deepest


def max_crossing(h5: Path, near: float) -> float:
    """The deepest crossing over the snapshots, of particles that were `near` apart or more
    at t = 0 (CPDI1's parallelograms of a skewed joint particle overlap their next neighbours
    from the start)."""
    with h5py.File(h5, "r") as f:
        snaps = sorted(k for k in f if k.startswith("snap_"))
        x0 = f[snaps[0]]["x"][...]
        return max(crossing(f[k]["corners"][...], f[k]["quads"][...].astype(int), x0, near)
                   for k in snaps)


MULTICELL = "".join(f"{x1},{y1},{x2},{y2},1.0e-3\n" for x1, y1, x2, y2 in [
    (-8e-3, 0.5e-3, 0.0, 0.5e-3), (0.0, 0.5e-3, 8e-3, 0.5e-3),
    (-8e-3, 8.5e-3, 0.0, 8.5e-3), (0.0, 8.5e-3, 8e-3, 8.5e-3),
    (-8e-3, 16.5e-3, 0.0, 16.5e-3), (0.0, 16.5e-3, 8e-3, 16.5e-3),
    (-8e-3, 0.5e-3, -8e-3, 8.5e-3), (-8e-3, 8.5e-3, -8e-3, 16.5e-3),
    (0.0, 0.5e-3, 0.0, 8.5e-3), (0.0, 8.5e-3, 0.0, 16.5e-3),
    (8e-3, 0.5e-3, 8e-3, 8.5e-3), (8e-3, 8.5e-3, 8e-3, 16.5e-3)])


def scene(name: str, body: str, top: float, basis: str, speed: float) -> str:
    stroke = 0.7 * top
    return (f"&run title = '{name}', history_every = 1.0e-5, snapshot_every = 1.0e-4, "
            f"output_dir = 'OUT' /\n&solver basis = '{basis}', mass_scale = 4.0 /\n"
            f"&grid h = {H} /\n{MATERIAL}"
            f"{body}&wall point = 0.0, 0.0, normal = 0.0, 1.0 /\n"
            f"&wall point = 0.0, {top}, normal = 0.0, -1.0, velocity = 0.0, {-speed}, "
            f"ramp = 1.0e-4, stroke = {stroke} /\n")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_sections_crush")
    # the measure finds an overlap: two unit squares, the second's corner (0.7, 0.2) inside
    # the first, 0.2 from its nearest edge
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.7, 0.2], [1.7, 0.2], [1.7, 1.2],
                   [0.7, 1.2]], float)
    found = crossing(sq, np.array([[0, 1, 2, 3], [4, 5, 6, 7]]))
    check(abs(found - 0.2) < 1e-12, f"the crossing measure finds 0.2 in overlapping squares "
                                    f"({found})")
    check(crossing(sq[:4], np.array([[0, 1, 2, 3]])) == 0.0, "and nothing in one square")
    (scratch / "multicell").mkdir(parents=True, exist_ok=True)
    (scratch / "multicell" / "cells.csv").write_text("x1,y1,x2,y2,thickness\n" + MULTICELL)
    cases = {
        "multicell": ("&body shape = 'walls', material = 'al', walls_file = 'cells.csv', "
                      "n_thick = 2, self_contact = .true. /\n", 17.0e-3, "cpdi2", 1.0e-3, 20.0),
        # the panel reaches 7 mm (centrelines) + 0.8 cos 30 mm (the mitred edge joints) from
        # its centre
        "auxetic": ("&body shape = 'honeycomb', material = 'al', n_cells = 2, 2, cell_l = "
                    "4.0e-3, cell_h = 8.0e-3, cell_angle = -30.0, thickness = 0.8e-3, "
                    "n_thick = 4, center = 0.0, 7.69282e-3, self_contact = .true. /\n",
                    15.38564e-3, "cpdi1", 0.8e-3, 10.0),
    }
    for name, (body, top, basis, thick, speed) in cases.items():
        _, s = run_scene(T, scratch, name, scene(name, body, top, basis, speed))
        if not s:
            continue
        err = float(s["energy_error"])
        check(err <= 0.05, f"{name}: energy error {err:.4f} <= 0.05")
        depth = max_crossing(scratch / name / "out" / "particles.h5", near=thick)
        check(depth <= 0.1 * H, f"{name}: walls cross by at most h/10 = {0.1 * H:.1e} m "
                                f"(deepest {depth:.2e} m)")
    return 0


if __name__ == "__main__":
    rc = main()
    sys.exit(max(T.summary(), rc))
