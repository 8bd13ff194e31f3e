#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The crush against the CalculiX reference (tools/fe_reference/, docs/fe_reference/).

Reads the FE curves of the mesh refinement (docs/fe_reference/crush_nt*_nc*.csv, the finest is
the reference crush_fe.csv), the study's crush curves (docs/study/curves/crush_*.csv: x = delta/D,
y = force [N/m]) and draws docs/fe_reference/crush_fe.png: left, F(delta) of the FE meshes, the
study's reference run (h = t/8, n_t = 16), the h = t/4 runs at n_t = 4, 8, 16 and
DeRuntz-Hodge; right, each curve's difference from the finest FE curve over the study's window.
Writes docs/fe_reference/errors_vs_fe.csv: the relative L2 error (the study's metric, 91 points
over delta/D = 0.05-0.5) of every study crush curve and every FE mesh against the finest FE
mesh, the same after the study's moving average over delta/D = 0.02 of both curves (the mean
response without the MPM force's high-frequency content), the mean force over the window and
its ratio to FE's and to DeRuntz-Hodge's.

    python3 -m plots.plot_fe_reference [--docs docs/fe_reference] [--curves docs/study/curves]
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

from plots.mpmplot import analysis, namelist, scene, theory

ROOT = Path(__file__).resolve().parent.parent

WINDOW = (0.05, 0.5)


def fe_meshes(folder: Path) -> list[tuple[int, int, Path]]:
    """(n_t, n_c, path) of the FE mesh CSVs, coarse to fine."""
    out = []
    for p in folder.glob("crush_nt*_nc*.csv"):
        m = re.fullmatch(r"crush_nt(\d+)_nc(\d+)\.csv", p.name)
        if m:
            out.append((int(m.group(1)), int(m.group(2)), p))
    return sorted(out)


def read_fe(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """delta/D and force [N per depth] of an FE CSV."""
    a = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return a[:, 1], a[:, 2]


def read_curve(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """delta/D and force of a study curve (columns x, y; monotone in x after the ramp)."""
    a = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    order = np.argsort(a[:, 0], kind="stable")
    return a[order, 0], a[order, 1]


def on_window(x: np.ndarray, f: np.ndarray) -> np.ndarray:
    return np.interp(np.linspace(*WINDOW, 91), x, f)


def smooth_on_window(x: np.ndarray, f: np.ndarray) -> np.ndarray:
    """The study's smoothed curve (tools/study.py): F on a grid of delta/D = 0.001, a centred
    moving average over delta/D = 0.02, at the window's 91 points."""
    fine = np.arange(0.0, x.max(), 0.001)
    sm = analysis.moving_average(np.interp(fine, x, f), int(round(0.02 / 0.001)))
    return np.interp(np.linspace(*WINDOW, 91), fine, sm)


def rel_l2(f: np.ndarray, ref: np.ndarray) -> float:
    return float(np.sqrt(np.mean((f - ref) ** 2) / np.mean(ref ** 2)))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--docs", type=Path, default=ROOT / "docs" / "fe_reference")
    ap.add_argument("--curves", type=Path, default=ROOT / "docs" / "study" / "curves")
    ap.add_argument("--case", type=Path, default=ROOT / "namelists" / "crush.nml")
    ap.add_argument("--table", type=Path, default=ROOT / "docs" / "study" / "study_full.csv",
                    help="the study's table: CPU seconds and the self-referenced error per run")
    a = ap.parse_args(argv)
    meshes = fe_meshes(a.docs)
    if not meshes:
        print(f"plot_fe_reference: no FE curves in {a.docs} (make fe-reference)", file=sys.stderr)
        return 2
    r = scene.ring_properties(namelist.read_namelist(a.case))
    xw = np.linspace(*WINDOW, 91)
    dh = theory.deruntz_hodge(xw * r["D"], r["D"], r["t"], r["sigma_y"], r["plane"], r["depth"])
    fx, ff = read_fe(meshes[-1][2])
    ref = on_window(fx, ff)
    ref_s = smooth_on_window(fx, ff)
    rows = []
    study = {}
    curves = [("FE", p.stem, *read_fe(p)) for _, _, p in meshes]
    for p in sorted(a.curves.glob("crush_*.csv")):
        curves.append(("MPM", p.stem, *read_curve(p)))
    for kind, name, x, f in curves:
        if x.max() < WINDOW[1]:
            continue
        w, ws = on_window(x, f), smooth_on_window(x, f)
        if kind == "MPM":
            study[name] = (x, f, w, ws)
        rows.append({"curve": name, "kind": kind, "err": rel_l2(w, ref),
                     "err_s": rel_l2(ws, ref_s), "mean": np.mean(w) / 1e3,
                     "over_fe": np.mean(w) / np.mean(ref), "over_dh": np.mean(w) / np.mean(dh)})
    table = {}
    if a.table.is_file():
        with open(a.table, newline="") as fh:
            table = {r["name"]: r for r in csv.DictReader(fh)}
    with open(a.docs / "errors_vs_fe.csv", "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["curve", "kind", "err_L2_vs_fe", "err_smooth_vs_fe", "force_mean_kN_per_m",
                     "force_mean_over_fe", "force_mean_over_dh", "err_L2_vs_study_ref", "cpu_s"])
        print(f"{'curve':>42s}  {'L2 vs FE':>8s}  {'smoothed':>8s}  {'mean F':>11s}  "
              f"{'/FE':>6s}  {'/DH':>6s}  {'self':>6s}  {'CPU s':>6s}")
        for row in rows:
            st = table.get(row["curve"], {})
            self_err, cpu = st.get("err_self", ""), st.get("cpu_s", "")
            wr.writerow([row["curve"], row["kind"], f"{row['err']:.5f}", f"{row['err_s']:.5f}",
                         f"{row['mean']:.4f}", f"{row['over_fe']:.5f}", f"{row['over_dh']:.5f}",
                         self_err, cpu])
            print(f"{row['curve']:>42s}  {100 * row['err']:7.2f}%  {100 * row['err_s']:7.2f}%  "
                  f"{row['mean']:6.3f} kN/m  {row['over_fe']:.4f}  {row['over_dh']:.4f}  "
                  f"{self_err[:6]:>6s}  {cpu[:6]:>6s}")

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.3))
    xd = np.linspace(0.0, 0.55, 200)
    ax.plot(xd, theory.deruntz_hodge(xd * r["D"], r["D"], r["t"], r["sigma_y"], r["plane"],
                                      r["depth"]) / 1e3, "k:", label="DeRuntz–Hodge")
    greys = plt.cm.Greys(np.linspace(0.45, 1.0, len(meshes)))
    for (n_t, n_c, p), col in zip(meshes, greys):
        x, f = read_fe(p)
        lw = 2.2 if p == meshes[-1][2] else 1.0
        ax.plot(x, f / 1e3, color=col, lw=lw, label=f"FE CPE8R {n_t}×{n_c}")
        if p != meshes[-1][2]:
            bx.plot(xw, 100 * (smooth_on_window(x, f) - ref_s) / ref_s, color=col, lw=1.0,
                    label=f"FE {n_t}×{n_c}")
    # the study's quasi-static crush runs (tools/study.py: centre cfl 0.8)
    picks = [("crush_cpdi2_musl_h1_8_nt16_a1_cfl0.8", "C0"),
             ("crush_cpdi2_musl_h1_4_nt8_a1_cfl0.8", "C1"),
             ("crush_cpdi2_musl_h1_4_nt16_a1_cfl0.8", "C2"),
             ("crush_cpdi2_musl_h1_4_nt4_a1_cfl0.8", "C3"),
             ("crush_cpdi2_musl_h1_4_nt4_a1_cfl0.8_fbar", "C4"),
             ("crush_cpdi2_musl_h1_2_nt4_a1_cfl0.8_fbarwall", "C5")]
    names = {"crush_cpdi2_musl_h1_8_nt16_a1_cfl0.8": "MPM h = t/8, n_t = 16 (study's finest)",
             "crush_cpdi2_musl_h1_4_nt8_a1_cfl0.8": "MPM h = t/4, n_t = 8",
             "crush_cpdi2_musl_h1_4_nt16_a1_cfl0.8": "MPM h = t/4, n_t = 16",
             "crush_cpdi2_musl_h1_4_nt4_a1_cfl0.8": "MPM h = t/4, n_t = 4",
             "crush_cpdi2_musl_h1_4_nt4_a1_cfl0.8_fbar": "MPM h = t/4, n_t = 4, fbar",
             "crush_cpdi2_musl_h1_2_nt4_a1_cfl0.8_fbarwall": "MPM h = t/2, n_t = 4, fbarwall"}
    for name, col in picks:
        if name not in study:
            continue
        x, f, w, ws = study[name]
        e = rel_l2(w, ref)
        thin = name.endswith("nt4_a1_cfl0.8")
        ax.plot(x, f / 1e3, color=col, lw=0.5 if thin else 0.8, alpha=0.5 if thin else 0.85,
                label=f"{names[name]} ({100 * e:.1f} %)")
        if not thin:                   # n_t = 4 (about +30 %) would squash the others
            bx.plot(xw, 100 * (ws - ref_s) / ref_s, color=col, lw=1.0, label=names[name])
    for z in (ax, bx):
        z.axvspan(0.0, WINDOW[0], color="0.9", lw=0)
        z.axvspan(WINDOW[1], 0.6, color="0.9", lw=0)
        z.set_xlabel("platen approach δ / D (D mean diameter)")
    ax.set_xlim(0, 0.55)
    ax.set_ylim(0, 60)
    ax.set_ylabel("platen force per unit depth [kN/m]")
    ax.set_title("crush: CalculiX reference, MPM (L2 error against FE), DeRuntz–Hodge")
    ax.legend(loc="lower right")
    bx.axhline(0.0, color="k", lw=0.8)
    bx.set_xlim(0, 0.55)
    bx.set_ylabel("(F − F_FE) / F_FE [%]")
    bx.set_title(f"smoothed (δ/D 0.02) difference from the finest FE mesh "
                 f"({meshes[-1][0]}×{meshes[-1][1]})")
    bx.legend(loc="upper right", ncol=2)
    fig.tight_layout()
    out = a.docs / "crush_fe.png"
    fig.savefig(out, dpi=130)
    print(f"plot_fe_reference: wrote {out} and {a.docs / 'errors_vs_fe.csv'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
