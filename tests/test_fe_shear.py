#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The sheared ring's CalculiX reference (tools/fe_reference/shear_reference.py,
docs/fe_reference/README.md "The sheared ring"). No ccx, no tubempm run; about a second.

- the committed decks are what the generator writes (generator and decks cannot drift);
- shear_<law>_fe.csv is the finest committed mesh's curve, and every committed mesh reached
  the end of the step (delta/D = 0.2);
- the committed comparison (shear_comparison.csv) is computed from the committed FE and tubempm
  curves (recomputed here to 1e-6);
- the physics the curves must show: the loose ring rolls, carrying almost no shear (rms under
  2 % of the normal force's, in FE and tubempm), the bonded ring's shear force is over 5 times
  the loose ring's, and both rings' centres move half the platen's sideways travel within 1 %
  at delta/D = 0.2 (the scene is symmetric under a half turn about the midpoint between the
  platens: a consistency check, not a sign of rolling).

    python3 -m tests.test_fe_shear
"""
from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

from tests.pycheck import Checks
from tools.fe_reference import shear_reference as sr

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_fe_shear")
check = T.check
DOCS = sr.DOCS


def committed_meshes(law: str) -> list[tuple[int, int]]:
    return [(n_t, n_c) for n_t, n_c in sr.MESHES
            if (DOCS / f"{sr.deck_name(law, n_t, n_c)}.csv").is_file()]


def test_decks_and_curves() -> None:
    for law in sr.LAWS:
        meshes = committed_meshes(law)
        check(len(meshes) >= 2, f"{law}: at least two FE meshes committed ({meshes})")
        for n_t, n_c in meshes:
            name = sr.deck_name(law, n_t, n_c)
            deck = DOCS / f"{name}.inp"
            check(deck.is_file() and deck.read_text() == sr.write_deck(law, n_t, n_c),
                  f"{name}.inp is what the generator writes")
            a = sr.read_curve(DOCS / f"{name}.csv")
            check(abs(a[-1, 1] - sr.DELTA_OVER_D) < 1e-9, f"{name}: reaches delta/D "
                                                           f"{sr.DELTA_OVER_D} ({a[-1, 1]:.4f})")
            check(bool(np.all(np.diff(a[:, 0]) > 0)), f"{name}: delta increases")
        if meshes:
            fin = sr.deck_name(law, *meshes[-1])
            check((DOCS / f"shear_{law}_fe.csv").read_bytes() ==
                  (DOCS / f"{fin}.csv").read_bytes(), f"shear_{law}_fe.csv is {fin}.csv")


def test_comparison() -> None:
    with open(DOCS / "shear_comparison.csv") as f:
        rows = list(csv.DictReader(f))
    for law in sr.LAWS:
        fe = sr.read_curve(DOCS / f"shear_{law}_fe.csv")
        mpm = sr.read_curve(DOCS / f"shear_{law}_mpm.csv")
        mine = [r for r in rows if r["law"] == law]
        again = sr.compare(law, mine[0]["fe_mesh"] if mine else "", fe, mpm)
        check(len(mine) == len(again), f"{law}: {len(again)} comparison rows")
        for r, s in zip(mine, again):
            for key in s:
                if key in ("law", "fe_mesh", "quantity") or not s[key]:
                    check(r[key] == s[key], f"{law} {s['quantity']}: {key} {r[key]} = {s[key]}")
                else:
                    check(abs(float(r[key]) - float(s[key])) <= 1e-6 * max(1.0, abs(float(s[key]))),
                          f"{law} {s['quantity']}: {key} committed {r[key]}, recomputed {s[key]}")


def test_physics() -> None:
    c = sr.COLUMNS.index
    loose_shear = {}
    for law in sr.LAWS:
        for who in ("fe", "mpm"):
            a = sr.read_curve(DOCS / f"shear_{law}_{who}.csv")
            roll = a[-1, c("center_dx_m")] / a[-1, c("side_m")]
            check(abs(roll - 0.5) < 0.01, f"{law} {who}: the centre moves half the platen's "
                                          f"sideways travel ({roll:.4f})")
            s = sr.on_window(a, "shear_N")
            n = sr.on_window(a, "normal_N")
            ratio = float(np.sqrt(np.mean(s ** 2) / np.mean(n ** 2)))
            if law == "coulomb":
                loose_shear[who] = ratio
                check(ratio < 0.02, f"coulomb {who}: shear rms {100 * ratio:.2f} % of the "
                                    f"normal force's (allowed 2 %)")
            else:
                check(ratio > 0.01, f"bonded {who}: shear rms {100 * ratio:.2f} % of the normal "
                                    f"force's")
                loose_shear["b" + who] = float(np.sqrt(np.mean(s ** 2)))
    for who in ("fe", "mpm"):
        a = sr.read_curve(DOCS / f"shear_coulomb_{who}.csv")
        loose = float(np.sqrt(np.mean(sr.on_window(a, "shear_N") ** 2)))
        check(loose_shear["b" + who] > 5 * loose, f"{who}: bonded shear rms "
                                                  f"{loose_shear['b' + who]:.4g} N over 5 times "
                                                  f"the loose ring's {loose:.4g} N")


def main() -> int:
    for t in (test_decks_and_curves, test_comparison, test_physics):
        try:
            t()
        except Exception as e:  # noqa: BLE001
            check(False, f"{t.__name__}: {type(e).__name__}: {e}")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
