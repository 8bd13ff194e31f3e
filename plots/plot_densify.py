#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A ring crushed to densification: force against delta/D (D the outer diameter, log scale) of
runs with and without self-contact, with the closed forms of docs/method.md ("Self-contact"):
DeRuntz-Hodge P0 / sqrt(1 - (delta/D_m)^2) (the four-hinge mechanism with geometry change) and,
once the platen gap H = D - delta is below 2t, the densification bound (2/sqrt 3) sigma_y
(pi D_m / 2 - pi H / 2) (the flattened double wall pressed as a plane-strain strip).

    python3 -m plots.plot_densify --case namelists/contact/densify.nml \\
        --compare out/densify_weld "one velocity field (welds)" --out densify.png
"""
from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np

from plots import style  # noqa: F401  (Agg backend and rcParams, before pyplot)
from plots.mpmplot import readers, scene, theory

import matplotlib.pyplot as plt


def curve(outdir: str, inputs: dict) -> tuple[np.ndarray, np.ndarray]:
    """delta [m] and the platen force [N] of a run."""
    history = readers.read_history(os.path.join(outdir, "history.csv"))
    disp, force, _ = scene.crush_displacement(history, inputs)
    return disp, force


def densification_bound(delta: np.ndarray, d_out: float, d_mean: float, t: float,
                        sigma_y: float, depth: float) -> np.ndarray:
    """(2/sqrt 3) sigma_y (pi D_m / 2 - pi H / 2) for H = D - delta < 2t, NaN before [N]."""
    gap = d_out - delta
    f = 2.0 / math.sqrt(3.0) * sigma_y * (0.5 * math.pi * d_mean - 0.5 * math.pi * gap) * depth
    return np.where(gap < 2.0 * t, f, np.nan)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description="Force against delta/D of a ring crushed to "
                                "densification, with and without self-contact, and the closed "
                                "forms (DeRuntz-Hodge, the densification bound).")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--case", metavar="FILE.nml", help="the case file")
    src.add_argument("--dir", metavar="OUTDIR", help="the output folder of a run")
    p.add_argument("--label", default="self-contact", help="label of that run")
    p.add_argument("--compare", nargs=2, action="append", default=[],
                   metavar=("OUTDIR", "LABEL"), help="another run of the same ring to overlay")
    p.add_argument("--out", metavar="PNG", help="output image (default <outdir>/densify.png)")
    a = p.parse_args(argv)
    outdir, inputs = scene.resolve_case(a.case, a.dir)
    ring = scene.ring_properties(inputs)
    d_mean, t, depth = ring["D"], ring["t"], ring["depth"]
    d_out = d_mean + t
    fig, ax = plt.subplots(layout="constrained", figsize=(7.5, 4.8))
    runs = [(outdir, a.label)] + [(d, lab) for d, lab in a.compare]
    print(f"ring D = {d_out * 1e3:.4g} mm (outer), t = {t * 1e3:.4g} mm; inner walls flat "
          f"against each other at delta/D = {1.0 - 2.0 * t / d_out:.3f}")
    for i, (d, lab) in enumerate(runs):
        disp, force = curve(d, inputs)
        ax.semilogy(disp / d_out, np.maximum(force, 1e-3), color=f"C{i}", lw=1.0, label=lab)
        for x in (0.5, 0.8, 0.9, 0.95):
            m = (disp >= (x - 0.01) * d_out) & (disp <= (x + 0.01) * d_out)
            if np.count_nonzero(m) > 2:
                mean = float(np.trapezoid(force[m], disp[m]) / (disp[m][-1] - disp[m][0]))
                print(f"{lab}: mean force over delta/D {x - 0.01:.2f}-{x + 0.01:.2f}: "
                      f"{mean:.4g} N")
    x = np.linspace(0.0, 0.97, 500)
    ax.semilogy(x, theory.deruntz_hodge(x * d_out, d_mean, t, ring["sigma_y"], ring["plane"],
                                        depth), "--", color="C3",
                label=r"DeRuntz–Hodge $P_0/\sqrt{1-(\delta/D_m)^2}$")
    ax.semilogy(x, densification_bound(x * d_out, d_out, d_mean, t, ring["sigma_y"], depth),
                ":", color="k", lw=1.8,
                label=r"densification bound $\frac{2}{\sqrt{3}}\sigma_y(\pi D_m/2 - \pi H/2)$, $H < 2t$")
    ax.set_xlabel(r"$\delta/D$ (D outer diameter)")
    ax.set_ylabel(f"platen force [N] (depth {depth:g} m)")
    title = str(inputs.get("run", [{}])[0].get("title", os.path.basename(outdir))).strip()
    ax.set_title(f"{title}: crush to densification")
    ax.set_xlim(0.0, 1.0)
    p0 = theory.plastic_collapse_load(d_mean, t, ring["sigma_y"], ring["plane"], depth)
    ax.set_ylim(bottom=0.3 * p0)
    ax.legend(loc="upper left", fontsize=8)
    out = a.out or os.path.join(outdir, "densify.png")
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
