#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The sheared ring against the CalculiX reference (tools/fe_reference/shear_reference.py).

Reads docs/fe_reference/shear_<law>_nt*_nc*.csv (the FE meshes) and shear_<law>_mpm.csv
(tubempm) for law = bonded, coulomb and draws docs/fe_reference/shear_fe.png: per law (rows)
the normal force and the sideways force the ring exerts on the moving platen and the sideways
motion of the ring's centre over the platen's sideways travel, against delta/D.

    python3 -m plots.plot_fe_shear [--docs docs/fe_reference]
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import numpy as np

from plots import style  # noqa: F401  (Agg backend, shared rcParams; before pyplot)
import matplotlib.pyplot as plt

from tools.fe_reference import shear_reference as sr

ROOT = Path(__file__).resolve().parent.parent

LABEL = {"bonded": "bonded (fixed group)", "coulomb": f"coulomb, mu {sr.MU} (loose group)"}


def fe_meshes(docs: Path, law: str) -> list[tuple[int, int, Path]]:
    out = []
    for p in docs.glob(f"shear_{law}_nt*_nc*.csv"):
        m = re.match(rf"shear_{law}_nt(\d+)_nc(\d+)\.csv", p.name)
        if m:
            out.append((int(m.group(1)), int(m.group(2)), p))
    return sorted(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--docs", type=Path, default=sr.DOCS)
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    fig, axes = plt.subplots(2, 3, figsize=(13, 7.5), sharex=True)
    greys = ["0.75", "0.5", "0.0"]
    for row, law in enumerate(sr.LAWS):
        meshes = fe_meshes(a.docs, law)
        curves = [(f"FE {n_t}x{n_c}", sr.read_curve(p)) for n_t, n_c, p in meshes]
        styles = [dict(color=greys[max(0, 3 - len(curves) + k)], lw=1.2 + 0.4 * k)
                  for k in range(len(curves))]
        mp = a.docs / f"shear_{law}_mpm.csv"
        if mp.is_file():
            curves.append(("tubempm", sr.read_curve(mp)))
            styles.append(dict(color="C3", lw=1.3, ls="--"))
        for (lab, c), st in zip(curves, styles):
            x = c[:, 1]
            axes[row, 0].plot(x, c[:, 3] / 1e3, label=lab, **st)
            axes[row, 1].plot(x, c[:, 4] / 1e3, label=lab, **st)
            side = np.where(c[:, 2] > 0, c[:, 2], np.nan)
            axes[row, 2].plot(x, c[:, 7] / side, label=lab, **st)
        axes[row, 0].set_ylabel(f"{LABEL[law]}\nnormal force [kN/m]")
        axes[row, 1].set_ylabel("sideways force on the platen [kN/m]")
        axes[row, 2].set_ylabel("centre motion / platen sideways travel")
        axes[row, 2].set_ylim(0.0, 1.0)
        axes[row, 2].axhline(0.5, color="0.6", lw=0.6, ls=":")
        axes[row, 1].axhline(0.0, color="0.6", lw=0.6, ls=":")
        axes[row, 0].legend(loc="upper left", fontsize=8)
    for ax in axes[1]:
        ax.set_xlabel("approach delta / D")
    fig.suptitle(f"Ring r {sr.R_IN * 1e3:g}-{sr.R_OUT * 1e3:g} mm, elastic E "
                 f"{sr.E / 1e9:g} GPa, top platen down and sideways (ratio {sr.RATIO}): "
                 f"CalculiX against tubempm", fontsize=10)
    fig.tight_layout()
    out = a.out or a.docs / "shear_fe.png"
    fig.savefig(out)
    print(f"plot_fe_shear: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
