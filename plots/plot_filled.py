#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A foam-filled tube against its parts (docs/scenes.md, namelists/foam/): the force and the
absorbed energy against the platens' approach delta of the filled tube, the empty tube of
equal outer size, the empty tube of equal mass (optional) and the foam core alone, with the sum
of the empty tube and the core, and the interaction effect E_filled - (E_empty + E_foam alone)
at equal approach; optionally a second filled tube (`--filled2`, another law between tube and
core) with its own interaction. Prints the table of the &results numbers (mass, absorbed
energy, SEA, mean and peak force, CFE), the bodies' plastic work in the filled tube(s), and
the interaction at the end and at a few approaches (the platens' work integrated along each
curve).

    python3 -m plots.plot_filled --out docs/figures/filled_ring_compare.png
    python3 -m plots.plot_filled --filled out/filled_ring --empty out/empty_ring \\
        --equal-mass out/empty_ring_equal_mass --foam out/foam_disc --at 5 10 20 30
    python3 -m plots.plot_filled --tube "square tube" --filled out/filled_square \\
        --filled2 out/filled_square_bonded --label2 "bonded core" --empty out/square_tube \\
        --equal-mass none --foam out/foam_square --at 5 10 15 20 \\
        --out docs/figures/filled_square_compare.png
"""
from __future__ import annotations

import argparse
import os
import sys

import numpy as np

from plots import style  # noqa: F401  (Agg backend and rcParams, before pyplot)
from plots.mpmplot import readers, scene

import matplotlib.pyplot as plt

RUNS = (("filled", "filled {tube}", "C3"), ("filled2", "filled {tube}, {label2}", "C5"),
        ("empty", "empty {tube}, equal size", "C0"), ("equal_mass", "empty {tube}, equal mass",
                                                     "C2"), ("foam", "foam core alone", "C1"))


def load(outdir: str) -> dict:
    """The run's approach delta [m], platen force [N], the platens' work along the curve [J],
    its &results and &summary."""
    _, inputs = scene.resolve_case(None, outdir)
    history = readers.read_history(os.path.join(outdir, "history.csv"))
    delta, force, _ = scene.crush_displacement(history, inputs)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(delta))])
    summary_path = os.path.join(outdir, "summary.nml")
    return {"delta": delta, "force": force, "work": work,
            "results": readers.read_results(summary_path),
            "summary": readers.read_summary(summary_path),
            "failure": readers.run_failure(outdir)}


def work_at(run: dict, d: float) -> float:
    """The platens' work up to the approach d, on the loading branch [J]; NaN beyond it."""
    delta = run["delta"]
    k = int(np.argmax(delta))
    if d > delta[k]:
        return float("nan")
    return float(np.interp(d, delta[:k + 1], run["work"][:k + 1]))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description="A foam-filled tube against the empty tubes and "
                                "the foam core alone: force and energy against the approach, "
                                "the &results table and the interaction effect.")
    p.add_argument("--tube", default="ring", help="what the tube is, for the labels "
                   "(default ring)")
    p.add_argument("--filled", default="out/filled_ring", help="the filled tube's output folder")
    p.add_argument("--filled2", default="none", help="a second filled tube (another law between "
                   "tube and core), or none (default)")
    p.add_argument("--label2", default="bonded core", help="what the second filled tube is")
    p.add_argument("--empty", default="out/empty_ring",
                   help="the empty tube of equal outer size")
    p.add_argument("--equal-mass", dest="equal_mass", default="out/empty_ring_equal_mass",
                   help="the empty tube of equal mass, or none")
    p.add_argument("--foam", default="out/foam_disc", help="the foam core alone")
    p.add_argument("--at", type=float, nargs="*", default=[5.0, 10.0, 20.0, 30.0], metavar="MM",
                   help="approaches [mm] at which to print the interaction (default 5 10 20 30)")
    p.add_argument("--out", metavar="PNG", help="output image (default <filled>/compare.png)")
    a = p.parse_args(argv)
    labels = {key: label.format(tube=a.tube, label2=a.label2) for key, label, _ in RUNS}
    runs = {key: load(getattr(a, key)) for key, _, _ in RUNS if getattr(a, key) != "none"}
    failed = [f"{key}: {r['failure']}" for key, r in runs.items() if r["failure"]]

    print(f"{'run':<24} {'mass kg':>8} {'stroke mm':>9} {'E J':>8} {'SEA J/kg':>9} "
          f"{'mean kN':>8} {'peak kN':>8} {'CFE':>6}")
    for key, _, _ in RUNS:
        if key not in runs:
            continue
        r = runs[key]["results"]
        print(f"{labels[key]:<24} {r['mass']:8.4f} {r['stroke'] * 1e3:9.2f} "
              f"{r['absorbed_energy']:8.1f} {r['sea']:9.1f} {r['mean_force'] / 1e3:8.2f} "
              f"{r['peak_force'] / 1e3:8.2f} {r['cfe']:6.3f}")
    rf = runs["filled"]["results"]
    e_f, e_e, e_c = (runs[k]["results"]["absorbed_energy"] for k in ("filled", "empty", "foam"))
    inter = e_f - (e_e + e_c)
    print(f"interaction at the end: E_filled - (E_empty + E_foam alone) = {e_f:.1f} - "
          f"({e_e:.1f} + {e_c:.1f}) = {inter:.1f} J ({100.0 * inter / (e_e + e_c):+.1f} % of "
          f"the sum)")
    if "filled2" in runs:
        e_2 = runs["filled2"]["results"]["absorbed_energy"]
        print(f"{labels['filled2']}: interaction at the end {e_2 - (e_e + e_c):.1f} J "
              f"({100.0 * (e_2 - (e_e + e_c)) / (e_e + e_c):+.1f} % of the sum)")
    for key in ("filled", "filled2"):
        rk = runs[key]["results"] if key in runs else {}
        if "body1_energy" in rk and "body2_energy" in rk:
            print(f"{labels[key]}, plastic work by body: {a.tube} {rk['body1_energy']:.1f} J "
                  f"(empty {runs['empty']['results']['body1_energy']:.1f}), core "
                  f"{rk['body2_energy']:.1f} J (alone "
                  f"{runs['foam']['results']['body1_energy']:.1f})")
    for mm in a.at:
        d = 1e-3 * mm
        w = {k: work_at(runs[k], d) for k in runs}
        line = (f"at delta = {mm:g} mm: platens' work filled {w['filled']:.1f} J, empty "
                f"{w['empty']:.1f} J, core alone {w['foam']:.1f} J")
        for k in ("filled2", "equal_mass"):
            if k in w:
                line += f", {labels[k]} {w[k]:.1f} J"
        line += f"; interaction {w['filled'] - w['empty'] - w['foam']:.1f} J"
        if "filled2" in w:
            line += f" ({labels['filled2']}: {w['filled2'] - w['empty'] - w['foam']:.1f} J)"
        print(line)
    for key in runs:
        s = runs[key]["summary"]
        print(f"{key}: {int(s['steps'])} steps, energy error {float(s['energy_error']):.2e}, "
              f"{float(s['wall_seconds']):.0f} s wall")

    fig, (ax_f, ax_e) = plt.subplots(1, 2, layout="constrained", figsize=(12.0, 4.8))
    grid = np.linspace(0.0, min(runs[k]["delta"].max() for k in ("empty", "foam")), 400)
    for key, _, colour in RUNS:
        if key not in runs:
            continue
        r = runs[key]
        ax_f.plot(r["delta"] * 1e3, r["force"] / 1e3, color=colour, lw=1.0, label=labels[key])
        ax_e.plot(r["delta"] * 1e3, r["work"], color=colour, lw=1.2, label=labels[key])
    f_sum = np.array([np.interp(d, runs["empty"]["delta"], runs["empty"]["force"]) +
                      np.interp(d, runs["foam"]["delta"], runs["foam"]["force"]) for d in grid])
    w_sum = np.array([work_at(runs["empty"], d) + work_at(runs["foam"], d) for d in grid])
    w_fil = np.array([work_at(runs["filled"], d) for d in grid])
    ax_f.plot(grid * 1e3, f_sum / 1e3, "k--", lw=1.0, label="empty + foam alone")
    ax_e.plot(grid * 1e3, w_sum, "k--", lw=1.0, label="empty + foam alone")
    ax_e.plot(grid * 1e3, w_fil - w_sum, ":", color="C4", lw=1.6,
              label="interaction: filled − (empty + foam alone)")
    if "filled2" in runs:
        w_2 = np.array([work_at(runs["filled2"], d) for d in grid])
        ax_e.plot(grid * 1e3, w_2 - w_sum, ":", color="C5", lw=1.6,
                  label=f"interaction, {a.label2}")
    ax_f.set_xlabel("approach δ [mm]")
    ax_f.set_ylabel("platen force [kN] (depth 1 m)")
    ax_f.set_title("force against approach")
    ax_f.legend(loc="upper left")
    ax_e.set_xlabel("approach δ [mm]")
    ax_e.set_ylabel("platens' work [J] (depth 1 m)")
    ax_e.set_title(f"energy against approach; at the end: interaction {inter:+.0f} J "
                   f"({100.0 * inter / (e_e + e_c):+.1f} %)")
    ax_e.legend(loc="upper left")
    if failed:
        style.mark_failed(fig, "; ".join(failed))
    out = a.out or os.path.join(a.filled, "compare.png")
    fig.savefig(out)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
