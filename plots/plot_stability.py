#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Figures of the stability study (docs/stability.md) from the tables tools/stability.py wrote.

map_impact_ppc*.png (largest stable cfl per basis and scheme), map_crush.png, noise.png,
thinwall.png, distortion.png and flip_pic.png, written next to the tables they are drawn from.

    python3 -m plots.plot_stability                  # tables of the quick level (out/stability-quick/)
    python3 -m plots.plot_stability --level full     # the committed study (docs/stability/)
    python3 -m plots.plot_stability --dir FOLDER     # tables elsewhere
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from plots import style  # noqa: F401  (Agg backend and the shared rcParams, before pyplot)
import matplotlib.pyplot as plt
from tools import stability
from tools.stability import (BASES, D_CRUSH, ENERGY_OK, NOISY, SCHEMES, T_CRUSH, WRONG,
                       fmt)

ROOT = Path(__file__).resolve().parent.parent

#: Folder of the tables and the figures (set by main).
DIR: Path = stability.DOCS


def read_csv(name: str) -> list[dict[str, Any]]:
    """A table of the study from DIR ([] when missing)."""
    return stability.read_csv(name, DIR)

SHORT = {"energy growth": "energy\ngrowth", "det F <= 0": "det F\n<= 0",
         "folded domain": "folded", "left grid": "left\ngrid", "non-finite": "non-\nfinite"}
OUTCOME_COLOURS = {"accurate": "#1a9850", "noisy": "#fee08b", "wrong": "#f46d43",
                   "failed": "#a50026"}


def _legend_outcomes(ax) -> None:
    from matplotlib.patches import Patch
    ax.legend(handles=[Patch(color=c, label=k) for k, c in OUTCOME_COLOURS.items()],
              loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)


def plot_map_impact() -> None:
    for path in sorted(DIR.glob("cfl_runs_ppc*.csv")):
        plot_map_impact_one(path.stem.split("_")[-1])


def plot_map_impact_one(ppc: str) -> None:
    rows = read_csv(f"cfl_runs_{ppc}.csv")
    if not rows:
        return
    methods = [(b, s) for b in BASES for s in SCHEMES]
    lim = {(r["basis"], r["scheme"]): r["stable_cfl"]
           for r in read_csv(f"cfl_limits_{ppc}.csv")}
    fig, ax = plt.subplots(layout="constrained", figsize=(11, 5.4))
    for i, (b, s) in enumerate(methods):
        mine = sorted((r for r in rows if r["basis"] == b and r["scheme"] == s),
                      key=lambda r: r["cfl"])
        c = [r["cfl"] for r in mine]
        # each run colours the cfl range nearer to it than to its neighbours
        edges = [0.5 * (x + y) for x, y in zip(c[:-1], c[1:])]
        lo = [c[0] - 0.125] + edges
        hi = edges + [c[-1] + 0.125]
        for r, x0, x1 in zip(mine, lo, hi):
            ax.add_patch(plt.Rectangle((x0, i - 0.45), x1 - x0, 0.9,
                                       color=OUTCOME_COLOURS[r["outcome"]], lw=0))
            ax.plot([r["cfl"]], [i + 0.38], "|", color="k", ms=4, mew=0.6)
            if not r["scan"]:
                continue
            label = {"failed": SHORT.get(r["reason"], r["reason"]),
                     "wrong": f"E {100 * r['energy_error']:.0f}%"
                     if not r["energy_error"] < ENERGY_OK
                     else f"I {100 * r['impulse_err']:+.0f}%",
                     "noisy": f"n {r['noise']:.2f}", "accurate": ""}[r["outcome"]]
            ax.text(r["cfl"], i, label, ha="center", va="center", fontsize=5.5,
                    color="white" if r["outcome"] == "failed" else "black")
        m = lim.get((b, s), 0.0)
        if m > 0:
            nxt = min((x for x in c if x > m), default=m)
            ax.plot([0.5 * (m + nxt)] * 2, [i - 0.45, i + 0.45], color="k", lw=2.5)
        ax.text(2.17, i, f"{m:g}" if m > 0 else "none", va="center", fontsize=8)
    ax.text(2.17, -0.55, "stable up to", fontsize=7, va="bottom")
    ax.set_yticks(range(len(methods)), [f"{b} {s}" for b, s in methods])
    ax.set_xlim(0.0, 2.15)
    ax.set_ylim(len(methods) - 0.5, -0.5)
    ax.grid(False)
    r0 = rows[0]
    ax.set_xlabel("cfl [-]  (small ticks: the runs; black bar: stability limit found by bisection; "
                  "stable = completes, energy error < 5 %)")
    ax.set_title(f"impact scene (half ring, 30 m/s, h = t/{1 / r0['h_over_t']:g}, "
                 f"n_t = {r0['n_thick']}: {r0['h_over_t'] * r0['n_thick']:g} particle(s) per "
                 "cell through the wall; to 0.4 ms)\nE: energy error, I: impulse error against "
                 "the median of the stable runs at cfl 0.25, n: force noise", fontsize=9)
    from matplotlib.patches import Patch
    ax.legend(handles=[Patch(color=c, label=k) for k, c in OUTCOME_COLOURS.items()],
              loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=4, fontsize=8)
    fig.savefig(DIR / f"map_impact_{ppc}.png", dpi=150)
    plt.close(fig)


def plot_map_crush() -> None:
    rows = read_csv("crush_runs.csv")
    deep = read_csv("distort_runs.csv")
    if not rows:
        return
    cols: list[Any] = sorted({(r["h_over_t"], r["n_thick"]) for r in rows})
    deep_cols = sorted({(r["speed"], r["n_thick"]) for r in deep})
    ncol = len(cols) + len(deep_cols)
    fig, ax = plt.subplots(layout="constrained", figsize=(2.0 + 1.25 * ncol, 3.8))

    def cell(i: int, j: int, outcome: str, txt: str) -> None:
        ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, color=OUTCOME_COLOURS[outcome]))
        ax.text(j, i, txt, ha="center", va="center", fontsize=7,
                color="white" if outcome == "failed" else "black")

    for i, b in enumerate(BASES):
        for j, col in enumerate(cols):
            r = next((r for r in rows if r["basis"] == b and (r["h_over_t"], r["n_thick"])
                      == col), None)
            if r is not None:
                cell(i, j, r["outcome"], SHORT.get(r["reason"], r["reason"])
                     if r["outcome"] == "failed"
                     else f"{100 * r['err_dh']:+.0f}%\nn {r['noise']:.2f}")
        for j, col in enumerate(deep_cols, start=len(cols)):
            r = next((r for r in deep if r["basis"] == b and (r["speed"], r["n_thick"])
                      == col), None)
            if r is None:
                continue
            if r["exit_code"] != 0:
                cell(i, j, "failed", f"{SHORT.get(r['reason'], r['reason'])}\n"
                     f"delta/D {r['delta_reached']:.2f}")
            elif not r["energy_error"] < ENERGY_OK:
                cell(i, j, "wrong", f"E {100 * r['energy_error']:.0f}%")
            else:
                cell(i, j, "accurate", f"E {100 * r['energy_error']:.0f}%\n"
                     f"J {r['min_corner_jacobian']:.2f}" if b == "cpdi2"
                     else f"E {100 * r['energy_error']:.0f}%\ngap {r['mismatch_final']:.2f}h")
    ax.axvline(len(cols) - 0.5, color="k", lw=2)
    labels = [f"h/t {h:g}\nn_t {n}\nppc {h * n:g}" for h, n in cols]
    labels += [f"deep crush\n{v:g} m/s, n_t {n}\nto delta/D {0.8 if v < 10 else 0.95}"
               for v, n in deep_cols]
    ax.set_xticks(range(ncol), labels, fontsize=7)
    ax.set_yticks(range(len(BASES)), BASES)
    ax.set_xlim(-0.5, ncol - 0.5)
    ax.set_ylim(len(BASES) - 0.5, -0.5)
    ax.grid(False)
    ax.set_title("crush scene (quarter ring, MUSL, cfl 0.2; left: to delta/D = 0.29, plateau "
                 "error vs DeRuntz-Hodge and force noise n;\nright: deep crushes, energy "
                 "error E, smallest CPDI2 corner Jacobian J, CPDI1 corner gap: the domains "
                 f"only). accurate: |error| <= {100 * WRONG:.0f} %, n <= {NOISY}, E < 5 %",
                 fontsize=9)
    _legend_outcomes(ax)
    fig.savefig(DIR / "map_crush.png", dpi=150)
    plt.close(fig)


def plot_noise() -> None:
    allrows = read_csv("crush_runs.csv")
    if not allrows:
        return
    fig, axs = plt.subplots(1, 2, layout="constrained", figsize=(11, 4))
    ax = axs[0]
    for k, b in enumerate(BASES):
        rr = sorted((r for r in allrows if r["basis"] == b and r["h_over_t"] == 0.5),
                    key=lambda r: r["ppc_wall"])
        ax.plot([r["ppc_wall"] ** 2 for r in rr], [r["noise"] for r in rr], "o-", color=f"C{k}",
                label=f"{b}, h = t/2 (n_t varies)")
        rr = sorted((r for r in allrows if r["basis"] == b and r["h_over_t"] >= 1.0),
                    key=lambda r: r["ppc_wall"])
        ax.plot([r["ppc_wall"] ** 2 for r in rr], [r["noise"] for r in rr], "o:", mfc="none",
                color=f"C{k}", label=f"{b}, n_t = 4 (h = t, 2t)")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("particles per cell ((n_t h / t)^2 with square particles) [-]")
    ax.set_ylabel("force noise: RMS(F - F_20us) / plateau [-]")
    ax.set_title("cell-crossing noise of the crush force (1 us samples, delta 4-13 mm)")
    ax.legend(fontsize=7, ncol=2)
    ax = axs[1]
    for style, sel, lab in (("o-", lambda r: r["h_over_t"] == 0.5, "h = t/2"),
                            ("o:", lambda r: r["h_over_t"] >= 1.0, "n_t = 4, h = t, 2t")):
        lin = {r["ppc_wall"]: r["noise"] for r in allrows if r["basis"] == "linear" and sel(r)}
        cp2 = {r["ppc_wall"]: r["noise"] for r in allrows if r["basis"] == "cpdi2" and sel(r)}
        x = sorted(set(lin) & set(cp2))
        ax.plot([p ** 2 for p in x], [lin[p] / cp2[p] for p in x], style, color="k", label=lab)
        for p in x:
            ax.annotate(f"{lin[p] / cp2[p]:.1f}", (p ** 2, lin[p] / cp2[p]),
                        textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("particles per cell [-]")
    ax.set_ylabel("noise of linear / noise of CPDI2 [-]")
    ax.set_title("how much noisier the linear basis is")
    ax.legend()
    fig.savefig(DIR / "noise.png", dpi=150)
    plt.close(fig)


def plot_thinwall() -> None:
    rows = read_csv("crush_runs.csv")
    nt_rows = read_csv("nthick_runs.csv")
    stick = read_csv("stick_runs.csv")
    series = read_csv("stick_series.csv")
    if not rows:
        return
    fig, axs = plt.subplots(2, 2, layout="constrained", figsize=(12, 8))
    ax = axs[0, 0]
    nt = max({r["n_thick"] for r in rows}, key=lambda n: sum(1 for r in rows
                                                            if r["n_thick"] == n))
    for b in BASES:
        rr = sorted((r for r in rows if r["basis"] == b and r["n_thick"] == nt),
                    key=lambda r: r["h_over_t"])
        ax.plot([r["h_over_t"] for r in rr], [100 * r["err_dh"] for r in rr], "o-", label=b)
    ax.axvline(1.0, color="k", lw=0.8, ls=":")
    ax.axhspan(-100 * WRONG, 100 * WRONG, color="0.9", zorder=0)
    ax.set_xlabel("h / t [-]")
    ax.set_ylabel("plateau force error vs DeRuntz-Hodge [%]")
    ax.set_title(f"thin-wall limit (MUSL, n_t = {nt}, delta 4-13 mm; grey: +-{100 * WRONG:g} %)")
    ax.legend()
    ax = axs[0, 1]
    if nt_rows:
        rr = sorted(nt_rows, key=lambda r: r["n_thick"])
        ax.plot([r["n_thick"] for r in rr], [1 + r["err_dh"] for r in rr], "o-", color="C3",
                label="CPDI2, h = t/2, n_circ fixed")
        for r in rr:
            ax.annotate(f"{100 * r['err_dh']:+.0f} %", (r["n_thick"], 1 + r["err_dh"]),
                        textcoords="offset points", xytext=(5, 5), fontsize=8)
    aspect = sorted((r for r in rows if r["basis"] == "cpdi2" and r["h_over_t"] == 0.5),
                    key=lambda r: r["n_thick"])
    if aspect:
        ax.plot([r["n_thick"] for r in aspect], [1 + r["err_dh"] for r in aspect], "s--",
                color="C0", label="CPDI2, h = t/2, square particles")
    ax.axhspan(1 - WRONG, 1 + WRONG, color="0.9", zorder=0)
    ax.set_xscale("log", base=2)
    ax.set_yscale("log")
    ax.legend()
    ax.set_xlabel("particles through the wall n_t [-]")
    ax.set_ylabel("plateau force / DeRuntz-Hodge [-]")
    ax.set_title("particles through the wall")
    ax = axs[1, 0]
    for k, r in enumerate(stick):
        path = DIR / f"stick_force_h{fmt(r['h_over_t'])}.csv"
        if not path.is_file():
            continue
        d = np.genfromtxt(path, delimiter=",", names=True)
        end = " (exit 4: energy growth)" if r["exit_code"] == 4 else ""
        ax.plot(d["delta"] * 1e3, np.maximum(d["force"], 1.0) * 1e-3, color=f"C{k}",
                label=f"h/t = {r['h_over_t']:g}{end}")
    ax.axvline((D_CRUSH - 2 * T_CRUSH) * 1e3, color="k", lw=0.8, ls=":")
    ax.set_xlabel("platen approach delta [mm]")
    ax.set_ylabel("platen force (20 us average) [kN/m]")
    ax.set_yscale("log")
    ax.set_ylim(1.0, None)
    ax.set_title("near-full crush of a half ring, then release (CPDI2, n_t = 2)")
    ax.legend(fontsize=7)
    ax = axs[1, 1]
    for k, r in enumerate(stick):
        ss = [x for x in series if x["h_over_t"] == r["h_over_t"]]
        ax.plot([x["delta"] * 1e3 for x in ss], [x["inner_gap"] * 1e3 for x in ss], "o-",
                ms=3, color=f"C{k}", label=f"h/t = {r['h_over_t']:g}")
        ax.axhline(2 * r["h_over_t"] * T_CRUSH * 1e3, color=f"C{k}", lw=0.8, ls="--")
    dd = np.linspace(0, 46e-3, 50)
    ax.plot(dd * 1e3, (D_CRUSH - dd - 2 * T_CRUSH) * 1e3, "k:", lw=1,
            label="flat walls: D - delta - 2t")
    ax.set_xlabel("platen approach delta [mm] (it decreases again on release)")
    ax.set_ylabel("gap between the inner walls at the mid-plane [mm]")
    ax.set_title("inner walls: dashed = 2h, where walls start to share nodes")
    ax.set_ylim(0, 12)
    ax.set_xlim(25, 47)
    ax.legend(fontsize=7)
    fig.savefig(DIR / "thinwall.png", dpi=150)
    plt.close(fig)


def plot_distort() -> None:
    series = read_csv("distort_series.csv")
    if not series:
        return
    fig, axs = plt.subplots(1, 3, layout="constrained", figsize=(13, 4))
    keys = sorted({(s["speed"], s["n_thick"], s["basis"]) for s in series})
    runs = {r["case"]: r for r in read_csv("distort_runs.csv")}
    for i, (v, nt, b) in enumerate(keys):
        ss = [s for s in series if s["basis"] == b and s["n_thick"] == nt and s["speed"] == v]
        d = [s["delta_over_D"] for s in ss]
        ls = "-" if b == "cpdi2" else "--"
        colour = f"C{sorted({(k[0], k[1]) for k in keys}).index((v, nt))}"
        label = f"{b} n_t {nt}, {v:g} m/s"
        axs[0].plot(d, [s["cond_max"] for s in ss], ls, color=colour, label=label)
        if b == "cpdi2":
            axs[1].plot(d, [s["jmin"] for s in ss], ls, color=colour, label=label)
            run = next((r for r in runs.values() if r["basis"] == b and r["n_thick"] == nt
                        and r["speed"] == v), None)
            if run and run["reason"] == "folded domain":
                axs[1].plot([run["delta_fold"]], [0.0], "x", color=colour, ms=9, mew=2)
                axs[1].annotate(f"folded, exit 4\n({run['angle_fold']:.0f} deg)",
                                (run["delta_fold"], 0.0), textcoords="offset points",
                                xytext=(-60, 12 + 14 * i), fontsize=7, color=colour)
        else:
            axs[2].plot(d, [s["mismatch_cells"] for s in ss], ls, color=colour, label=label)
    axs[0].set_yscale("log")
    axs[0].set_ylabel("largest domain distortion sigma_max/sigma_min [-]")
    axs[1].axhline(0.0, color="k", lw=0.8)
    axs[1].set_ylabel("smallest corner Jacobian ratio (<= 0: folded) [-]")
    axs[2].set_ylabel("CPDI1 largest corner gap/overlap [cells]")
    for ax in axs:
        ax.set_xlabel("delta / D [-]")
        ax.legend()
    axs[0].set_title("domain distortion, deep crush (h = t/2)")
    axs[1].set_title("CPDI2: folding (x: caught, angle 0 = equator)")
    axs[2].set_title("CPDI1: neighbours no longer tile")
    fig.savefig(DIR / "distortion.png", dpi=150)
    plt.close(fig)


def plot_flip() -> None:
    rows = read_csv("flip_runs.csv")
    if not rows:
        return
    fig, axs = plt.subplots(1, 2, layout="constrained", figsize=(11, 4))
    ax = axs[0]
    x = [100 * r["energy_lost"] for r in rows]
    y = [r["noise"] for r in rows]
    ax.plot(x, y, "o-")
    for r, xx, yy in zip(rows, x, y):
        ax.annotate(f"flip {r['flip']:g}", (xx, yy), textcoords="offset points",
                    xytext=(4, 4), fontsize=8)
    ax.set_xlabel("energy lost in the elastic impact by 1.2 ms [%]")
    ax.set_ylabel("contact force noise [-]")
    ax.set_title("FLIP against PIC: noise against dissipation")
    ax = axs[1]
    f = [max(1.0 - r["flip"], 1e-4) for r in rows]
    ax.plot(f, [100 * r["energy_lost"] for r in rows], "o-", label="energy lost [%]")
    ax.plot(f, [100 * r["rebound_ratio"] for r in rows], "s-",
            label="rebound speed / impact speed [%]")
    ax.set_xscale("log")
    ax.set_xlabel("PIC fraction 1 - flip (1e-4 stands for pure FLIP) [-]")
    ax.set_ylabel("[%]")
    ax.set_title("elastic half ring, 30 m/s, h = t/2, n_t = 4, MUSL CPDI2")
    ax.legend()
    fig.savefig(DIR / "flip_pic.png", dpi=150)
    plt.close(fig)


def plot_all() -> None:
    for f in (plot_map_impact, plot_map_crush, plot_noise, plot_thinwall, plot_distort,
              plot_flip):
        f()
        print(f"figure: {f.__name__}", flush=True)


def main(argv: list[str] | None = None) -> int:
    global DIR
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--level", choices=("quick", "full"), default="quick",
                    help="whose tables: quick (out/stability-quick/, the default) or full "
                         "(docs/stability/, the committed study)")
    ap.add_argument("--dir", help="folder of the tables, where the figures go too (default: "
                    "by --level)")
    args = ap.parse_args(argv)
    DIR = Path(args.dir) if args.dir else stability.folder_of(args.level)
    if not (DIR / "crush_runs.csv").is_file() and not list(DIR.glob("cfl_runs_ppc*.csv")):
        print(f"ERROR [plot_stability]: no tables in {DIR}: run tools/stability.py --level "
              f"{args.level}", file=sys.stderr)
        return 1
    plot_all()
    print(f"wrote figures to {DIR}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
