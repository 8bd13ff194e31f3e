#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The square tube's lateral crush against the CalculiX reference
(tools/fe_reference/square_reference.py).

Reads docs/fe_reference/square_nt*_ns*_na*.csv (the FE meshes; the finest is the reference),
square_shapes.csv (the finest mesh's deformed section) and, where it exists, square_mpm.csv
(tubempm's curve, the same columns), and draws docs/fe_reference/square_fe.png: left, the
platen force per unit depth against the approach over the outer height, delta/H (tubempm's raw
and smoothed); middle, each coarser FE mesh's smoothed difference from the finest (as the
comparison measures it); right,
the deformed section at delta/H = 0, 0.1, ..., 0.5 (the quarter and its mirror images, the
platens as lines).

    python3 -m plots.plot_fe_square [--docs docs/fe_reference]
"""
from __future__ import annotations

import argparse
import csv
import re
import sys
from pathlib import Path

import numpy as np

from plots import style  # noqa: F401  (Agg backend, shared rcParams; before pyplot)
import matplotlib.pyplot as plt

from tools.fe_reference import square_reference as sq


def fe_meshes(docs: Path) -> list[tuple[int, int, int, Path]]:
    """(n_t, n_s, n_a, path) of the FE mesh CSVs, coarse to fine."""
    out = []
    for p in docs.glob("square_nt*_ns*_na*.csv"):
        m = re.fullmatch(r"square_nt(\d+)_ns(\d+)_na(\d+)\.csv", p.name)
        if m:
            out.append((int(m.group(1)), int(m.group(2)), int(m.group(3)), p))
    return sorted(out)


def read_shapes(path: Path) -> dict[float, dict[str, np.ndarray]]:
    """{delta/H: {"inner": (n, 2), "outer": (n, 2)}} [m] of square_shapes.csv."""
    out: dict[float, dict[str, list]] = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            d = out.setdefault(float(r["delta_over_H"]), {"inner": [], "outer": []})
            d[r["surface"]].append((float(r["x_m"]), float(r["y_m"])))
    return {k: {s: np.array(v) for s, v in d.items()} for k, d in sorted(out.items())}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--docs", type=Path, default=sq.DOCS)
    a = ap.parse_args(argv)
    meshes = fe_meshes(a.docs)
    if not meshes:
        print(f"plot_fe_square: no FE curves in {a.docs} (make fe-reference)", file=sys.stderr)
        return 2
    c = sq.read_square()
    H = c.H * sq.MM
    xw = np.linspace(*sq.WINDOW, sq.N_WINDOW)
    d_ref, f_ref = sq.fe.read_csv(meshes[-1][3])
    ref_s = sq.smooth_on_window(d_ref, f_ref, H)

    fig, (ax, bx, cx) = plt.subplots(1, 3, figsize=(15, 4.6),
                                     gridspec_kw={"width_ratios": [1.15, 1.0, 0.85]})
    greys = plt.cm.Greys(np.linspace(0.45, 1.0, len(meshes)))
    for (n_t, n_s, n_a, p), col in zip(meshes, greys):
        d, f = sq.fe.read_csv(p)
        fin = p == meshes[-1][3]
        e = sq.fe.rel_l2(sq.smooth_on_window(d, f, H), ref_s)
        lab = f"FE n_t {n_t}, {n_t * (2 * n_s + n_a)} el." + ("" if fin else
                                                                   f" ({100 * e:.2f} %)")
        ax.plot(d / H, f / 1e3, color=col, lw=2.0 if fin else 1.0, label=lab)
        if not fin:
            bx.plot(xw, 100 * (sq.smooth_on_window(d, f, H) - ref_s) / ref_s, color=col,
                    lw=1.0, label=f"FE n_t {n_t}")
    mpm = a.docs / "square_mpm.csv"
    if mpm.is_file():
        d, f = sq.fe.read_csv(mpm)
        ms = sq.smooth_on_window(d, f, H)
        e = sq.fe.rel_l2(ms, ref_s)
        ax.plot(d / H, f / 1e3, color="C1", lw=0.5, alpha=0.5, label="tubempm")
        ax.plot(xw, ms / 1e3, color="C1", lw=1.5,
                label=f"tubempm smoothed ({100 * e:.1f} %)")
    ax.set_xlim(0, 0.5)
    ax.set_xlabel("platen approach δ / H (H outer height, 49.5 mm)")
    ax.set_ylabel("platen force per unit depth [kN/m]")
    ax.set_title("square tube 48 × 1.5 mm, r_c 3 mm: CalculiX CPE8R meshes, tubempm\n"
                 "(in brackets: smoothed L2 difference from the finest FE mesh)")
    ax.set_ylim(0, 1.3 * float(np.max(f_ref)) / 1e3)
    ax.legend(loc="upper right", fontsize=7)
    inset = ax.inset_axes([0.2, 0.5, 0.36, 0.42])
    for (n_t, n_s, n_a, p), col in zip(meshes, greys):
        d, f = sq.fe.read_csv(p)
        inset.plot(d / H, f / 1e3, color=col, lw=1.5 if p == meshes[-1][3] else 0.8)
    if mpm.is_file():
        d, f = sq.fe.read_csv(mpm)
        inset.plot(d / H, f / 1e3, color="C1", lw=0.8)
    inset.set_xlim(0, 0.04)
    inset.set_ylim(0, 1.1 * float(np.max(f_ref)) / 1e3)
    inset.tick_params(labelsize=7)
    inset.set_title("δ/H 0–0.04: the peak", fontsize=7)
    bx.axhline(0.0, color="k", lw=0.8)
    bx.set_xlim(0, 0.5)
    bx.set_xlabel("δ / H")
    bx.set_ylabel("(F − F_FE) / F_FE, smoothed over δ/H 0.02 [%]")
    bx.set_title(f"FE convergence: difference from the finest mesh (n_t {meshes[-1][0]})")
    if bx.get_legend_handles_labels()[0]:
        bx.legend(loc="best")
    shapes_csv = a.docs / "square_shapes.csv"
    if shapes_csv.is_file():
        shapes = read_shapes(shapes_csv)
        cols = plt.cm.viridis(np.linspace(0.0, 0.9, len(shapes)))
        half = 0.5 * c.H
        for (dh, sh), col in zip(shapes.items(), cols):
            for s in ("inner", "outer"):
                q = sh[s] / sq.MM
                loop = sq.full_loop(q)
                loop = np.vstack([loop, loop[:1]])
                cx.plot(loop[:, 0], loop[:, 1], color=col, lw=0.8,
                        label=f"δ/H = {abs(dh):.1f}" if s == "outer" else None)
            y_p = half - 0.5 * dh * c.H
            cx.plot([-1.35 * half, 1.35 * half], [y_p, y_p], color=col, lw=0.6, ls="--")
            cx.plot([-1.35 * half, 1.35 * half], [-y_p, -y_p], color=col, lw=0.6, ls="--")
        cx.set_aspect("equal")
        cx.set_xlabel("x [mm]")
        cx.set_ylabel("y [mm]")
        cx.set_title("FE deformed section (finest mesh), platens dashed")
        cx.legend(loc="center", fontsize=7)
    fig.tight_layout()
    out = a.docs / "square_fe.png"
    fig.savefig(out, dpi=130)
    print(f"plot_fe_square: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
