# SPDX-License-Identifier: MIT
"""Figures of the refinement study (docs/validation.md) from its table and curves.

    python3 -m plots.plot_study [--level quick|full] [--out FOLDER]   (default: quick)

Reads study_<level>.csv and the compact curves curves/<run>.csv that tools/study.py wrote
(docs/study/ for the full level, out/study-quick/ for the quick one), and writes into --out
(default: the same folder):

* accuracy_runtime.png - error against CPU seconds per scene, Pareto front, recommended runs
* error_factors.png    - error against h/t, n_t and particle aspect ratio (sets n_c)
* crush_curves.png     - F(delta) at increasing refinement with DeRuntz-Hodge
* impact_curves.png    - target force against time at increasing refinement
* impact_cor.png       - coefficient of restitution against impact speed, Bao & Yu's band
* wave_arrival.png     - arrival time against angle with the wave-speed lines
* crush_shapes.png     - the reference crush at several stages (needs the run folder)
and advice_<level>.csv: per scene the cheapest run reaching 5 %, 2 % and 1 % error.
"""
from __future__ import annotations

import argparse
import csv
import math
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np

from plots import style  # noqa: F401  (sets the matplotlib defaults)
import matplotlib.pyplot as plt
from plots.mpmplot import namelist, readers, scene, theory
from plots.plot_case import EXPERIMENT_COLUMNS

ROOT = Path(__file__).resolve().parent.parent
SCENES = ("crush", "impact", "wave")
BASIS_STYLE = {"linear": ("C0", "s"), "ugimp": ("C2", "^"), "cpdi1": ("C1", "D"),
               "cpdi2": ("C3", "o")}
TARGETS = (0.05, 0.02, 0.01)
#: The centre point's cfl per scene (as tools/study.py's CENTRE_CFL: the quasi-static crush
#: runs at 0.8)
CENTRE_CFL = {"crush": 0.8, "impact": 0.2, "wave": 0.2, "crush_fixed": 0.8}
HEADLINE = {"crush": "L2 error of F(δ) against FE, δ/D 0.05–0.5",
            "impact": "max rel. error against FE: contact time, COR, 10 us peak",
            "wave": "max arrival error against FE / transit time to 180°"}


def read_table(path: Path) -> list[dict[str, Any]]:
    rows = []
    with open(path, newline="") as fh:
        for r in csv.DictReader(fh):
            for k, v in r.items():
                try:
                    r[k] = float(v) if v not in ("", None) else math.nan
                except ValueError:
                    pass
            rows.append(r)
    return rows


def volumetric(r: dict[str, Any]) -> str:
    """The run's &solver volumetric ('standard' in tables from before that factor)."""
    v = r.get("volumetric")
    return v if isinstance(v, str) and v else "standard"


def penalty(r: dict[str, Any]) -> float:
    """The run's &wall penalty (1 in tables from before that factor)."""
    v = r.get("penalty", math.nan)
    return v if isinstance(v, float) and math.isfinite(v) else 1.0


def cfl_used(r: dict[str, Any]) -> float:
    """The cfl the run used: the table's cfl_used (its input's, or the automatic value for
    cfl = 0), or its cfl in tables from before that column."""
    c = r.get("cfl_used", math.nan)
    return c if isinstance(c, float) and math.isfinite(c) else r["cfl"]


def nominal(r: dict[str, Any]) -> bool:
    """Is r a run as designed (h = h_over_t t), not an alignment variant (h x 0.97, 1.03)?"""
    hs = r.get("h_scale", math.nan)
    return not (isinstance(hs, float) and math.isfinite(hs) and hs != 1.0)


def variants(r: dict[str, Any], rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The alignment variants of run r (its settings at another h_scale: tools/study.py
    ALIGNED), by name."""
    return [v for v in rows if v["scene"] == r["scene"] and not nominal(v)
            and v["name"].rsplit("_hs", 1)[0] == r["name"]]


def grid_errors(r: dict[str, Any], rows: list[dict[str, Any]]) -> list[float]:
    """The errors of r's setting on every grid measured: r's, then its variants'."""
    return [r["error"]] + [v["error"] for v in variants(r, rows)]


def robust_error(r: dict[str, Any], rows: list[dict[str, Any]]) -> float:
    """The error of r's setting: the worst of r's and its alignment variants' (NaN if any of
    them has none), or r's own where it has no variants."""
    errs = grid_errors(r, rows)
    return max(errs) if all(np.isfinite(errs)) else math.nan


def eligible(r: dict[str, Any], rows: list[dict[str, Any]]) -> bool:
    """May the advice and the Pareto front count run r? Where its scene was run at other grid
    alignments (the full level), only the settings measured at them; elsewhere (the quick
    level, which runs none) every run."""
    aligned = any(v["scene"] == r["scene"] and not nominal(v) for v in rows)
    return bool(variants(r, rows)) or not aligned


def centre(r: dict[str, Any], **changes: Any) -> bool:
    """Is r the centre point of the sweeps (CPDI2, MUSL, the scene's centre cfl, aspect 1,
    30 m/s, standard volumetric treatment, h as designed) with ``changes`` applied?"""
    if volumetric(r) != changes.pop("volumetric", "standard") or not nominal(r) or \
            penalty(r) != changes.pop("penalty", 1.0):
        return False
    want = {"basis": "cpdi2", "scheme": "musl", "cfl": CENTRE_CFL.get(r["scene"], 0.2),
            "aspect": 1.0}
    if r["scene"] == "impact":
        want["speed"] = 30.0
    want.update(changes)
    return all((r[k] == v) if isinstance(v, str) else math.isclose(r[k], v) for k, v in
               want.items())


def sweep(rows: list[dict[str, Any]], scene: str, var: str, **fixed: Any
          ) -> list[dict[str, Any]]:
    out = [r for r in rows if r["scene"] == scene and centre(r, **fixed)
           and np.isfinite(r.get(var, math.nan))]
    return sorted(out, key=lambda r: r[var])


def curve(name: str, folder: Path) -> np.ndarray | None:
    p = folder / "curves" / f"{name}.csv"
    return np.loadtxt(p, delimiter=",", skiprows=1, ndmin=2) if p.is_file() else None


def _legend(ax, **kw) -> None:
    """A legend when the axes have labelled artists."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kw)


def pareto(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Lower-left envelope: runs no other run beats in both cost and error."""
    front, best = [], math.inf
    for c, e in sorted(points):
        if e < best:
            front.append((c, e))
            best = e
    return front


def advice(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per scene and target, the cheapest completed run (not the reference, not an alignment
    variant) measured at the other alignments too (tools/study.py ALIGNED) and within the
    target at all three (robust_error); its error as run is ``error``, the worst of the three
    ``robust_error``. A run never measured at another alignment is not advised (eligible): at
    h = t/4 the impact's rebound moves by 5 % with the grid's alignment, which one run cannot
    show. (The quick level runs no alignment variants: there every run counts.)"""
    out = []
    for scene in SCENES:
        ok = [r for r in rows if r["scene"] == scene and r["name"] != r["reference"]
              and nominal(r) and np.isfinite(r["error"]) and np.isfinite(r["cpu_s"])
              and not (scene == "impact" and r["speed"] != 30.0)]
        for tgt in TARGETS:
            within = [r for r in ok if eligible(r, rows) and robust_error(r, rows) <= tgt]
            best = min(within, key=lambda r: r["cpu_s"]) if within else None
            out.append({"scene": scene, "target": tgt,
                        **({k: best[k] for k in ("name", "basis", "scheme", "h_over_t", "n_t",
                                                 "n_c", "aspect", "cfl", "particles", "cpu_s",
                                                 "runtime_ratio", "error")}
                           | {"volumetric": volumetric(best), "penalty": penalty(best),
                              "cfl_used": cfl_used(best),
                              "robust_error": robust_error(best, rows)}
                           if best else {"name": "none within the study"})})
    return out


def settings(r: dict[str, Any]) -> str:
    """Short text of a run's settings."""
    text = f"h/t {r['h_over_t']:g}, n_t {r['n_t']:g}, {r['basis']}"
    if not math.isclose(r["aspect"], 1.0):
        text += f", aspect {r['aspect']:g}"
    if r["cfl"] == 0.0:
        text += f", cfl automatic ({cfl_used(r):g})"
    elif not math.isclose(r["cfl"], 0.2):
        text += f", cfl {r['cfl']:g}"
    if volumetric(r) != "standard":
        text += f", {volumetric(r)}"
    if penalty(r) != 1.0:
        text += f", penalty {penalty(r):g}"
    return text


def fig_accuracy_runtime(rows, adv, out: Path) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(15, 7.0), layout="constrained")
    for ax, scene in zip(axes, SCENES):
        rs = [r for r in rows if r["scene"] == scene and r["name"] != r["reference"]
              and nominal(r) and np.isfinite(r["error"]) and r["error"] > 0
              and not (scene == "impact" and r["speed"] != 30.0)]
        spread = [(r, grid_errors(r, rows)) for r in rs]
        for k, (r, e) in enumerate([x for x in spread if len(x[1]) > 1]):
            ax.plot([r["cpu_s"]] * 2, [100 * min(e), 100 * max(e)], color="0.3", lw=2.5,
                    alpha=0.5, solid_capstyle="butt",
                    label="the same on other grids (h x 0.96 to 1.04)" if k == 0 else None)
        for b, (col, mk) in BASIS_STYLE.items():
            sel = [r for r in rs if r["basis"] == b and volumetric(r) == "standard"
                   and penalty(r) == 1.0]
            if sel:
                ax.loglog([r["cpu_s"] for r in sel], [100 * r["error"] for r in sel], mk,
                          color=col, mfc="none" if b != "cpdi2" else col, ms=6, label=b)
        for vol, mk, col, label in (("fbar", "D", "C4", "fbar (anti-locking)"),
                                    ("fbarwall", "v", "C5", "fbarwall (line through the wall)")):
            sel = [r for r in rs if volumetric(r) == vol]
            if sel:
                ax.loglog([r["cpu_s"] for r in sel], [100 * r["error"] for r in sel], mk,
                          color=col, ms=6, label=label)
        sel = [r for r in rs if penalty(r) != 1.0]
        if sel:
            ax.loglog([r["cpu_s"] for r in sel], [100 * r["error"] for r in sel], "*",
                      color="C6", ms=9, label="stiffer wall penalty (&wall penalty 2, 4)")
        # the front and the advice: the settings measured at three alignments, by the worst
        front = pareto([(r["cpu_s"], robust_error(r, rows)) for r in rs
                        if eligible(r, rows) and np.isfinite(robust_error(r, rows))])
        if front:
            c, e = zip(*front)
            ax.step(c, 100 * np.array(e), where="post", color="k", lw=1.0, alpha=0.6,
                    label="Pareto front (worst over the grids)")
        for a, mk in zip([a for a in adv if a["scene"] == scene], ("*", "P", "X")):
            if "cpu_s" in a:
                ax.plot(a["cpu_s"], 100 * a["robust_error"], mk, color="k", ms=13, mfc="gold",
                        label=f"cheapest ≤ {a['target']:.0%}: {settings(a)}")
        for tgt in TARGETS:
            ax.axhline(100 * tgt, color="0.6", lw=0.7, ls=":")
        ref = next((r for r in rows if r["scene"] == scene and r["name"] == r["reference"]),
                   None)
        if ref is not None and np.isfinite(ref["cpu_s"]):
            ax.axvline(ref["cpu_s"], color="C3", ls="--", lw=0.8,
                       label=f"reference run ({ref['cpu_s']:.0f} s)")
        from matplotlib.ticker import LogFormatter
        ax.xaxis.set_minor_formatter(LogFormatter(labelOnlyBase=False,
                                                  minor_thresholds=(1.5, 0.5)))
        ax.set_xlabel("CPU time [s] (one thread)")
        ax.set_ylabel(f"error [%] ({HEADLINE[scene]})")
        ax.set_title(f"{scene}: accuracy against cost")
        _legend(ax, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13))
    fig.savefig(out / "accuracy_runtime.png", dpi=130)
    plt.close(fig)


def _ticks(ax, axis: str, values: list[float], labels: list[str]) -> None:
    """Fixed ticks with plain labels on a log axis."""
    from matplotlib.ticker import FixedLocator, NullLocator
    a = ax.xaxis if axis == "x" else ax.yaxis
    a.set_major_locator(FixedLocator(values))
    a.set_minor_locator(NullLocator())
    (ax.set_xticklabels if axis == "x" else ax.set_yticklabels)(labels)


def fig_error_factors(rows, out: Path) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), layout="constrained", sharey=True)
    specs = [("h_over_t", "grid spacing h/t (n_t = 16)", {"n_t": 16.0},
              [2, 1, 0.5, 0.25, 0.125], ["2", "1", "1/2", "1/4", "1/8"]),
             ("n_t", "particles through the wall n_t (h = t/4)", {"h_over_t": 0.25},
              [2, 4, 8, 16, 32], ["2", "4", "8", "16", "32"]),
             ("n_c", "particles around: n_c / n_c of square particles (h = t/4, n_t = 8)",
              {"h_over_t": 0.25, "n_t": 8.0}, [0.25, 0.5, 1, 2], ["1/4", "1/2", "1", "2"])]
    for ax, (var, label, fixed, ticks, labels) in zip(axes, specs):
        for k, scene in enumerate(SCENES):
            if var == "n_c":
                rs = sorted([r for r in rows if r["scene"] == scene and centre(
                    r, h_over_t=0.25, n_t=8.0, aspect=r["aspect"])], key=lambda r: -r["aspect"])
                x = [1.0 / r["aspect"] for r in rs]
            else:
                rs = sweep(rows, scene, var, **fixed)
                x = [r[var] for r in rs]
            pts = [(xi, r["error"]) for xi, r in zip(x, rs)
                   if np.isfinite(r["error"]) and r["error"] > 0]
            if pts:
                xs, es = zip(*pts)
                ax.loglog(xs, 100 * np.array(es), "o-", color=f"C{k}", label=scene)
        ax.set_xscale("log")
        _ticks(ax, "x", ticks, labels)
        if var == "h_over_t":
            ax.invert_xaxis()
        ax.set_xlabel(label + (" (finer to the right)" if var != "n_c" else ""))
        ax.grid(True, which="both", alpha=0.3)
        for tgt in TARGETS:
            ax.axhline(100 * tgt, color="0.6", lw=0.7, ls=":")
        _legend(ax)
    axes[0].set_ylabel("error [%] against the finite element\nreferences (static crush, "
                       "dynamic impact and wave)")
    _ticks(axes[0], "y", [1, 2, 5, 10, 20, 50, 100, 200, 500],
           ["1", "2", "5", "10", "20", "50", "100", "200", "500"])
    fig.suptitle("which factor matters: one factor at a time, CPDI2 + MUSL, cfl 0.2 "
                 "(quasi-static crush: 0.8)")
    fig.savefig(out / "error_factors.png", dpi=130)
    plt.close(fig)


def experiment(args_exp: list[str], scene: str) -> tuple[np.ndarray, np.ndarray] | None:
    """The measured curve given as ``--experiment SCENE=FILE`` for this scene, or None
    (columns as for plot_case.py: plots/README.md)."""
    for item in args_exp or []:
        key, _, path = item.partition("=")
        if key == scene and path:
            return readers.read_experiment(path, EXPERIMENT_COLUMNS[scene])
    return None


#: The two sweeps drawn as curves: variable, fixed settings, panel title.
CURVE_SWEEPS = [("h_over_t", {"n_t": 16.0}, "grid spacing (n_t = 16)"),
                ("n_t", {"h_over_t": 0.25}, "particles through the wall (h = t/4)")]


def _sweep_curves(axes, rows, scene: str, folder: Path, xscale: float, note) -> None:
    """Each sweep of CURVE_SWEEPS on its axes: the runs' curves coarse to fine (viridis), x
    scaled by xscale, y in kN/m, labelled with the run's setting and note(run)."""
    cmap = plt.get_cmap("viridis")
    for ax, (var, fixed, _) in zip(axes, CURVE_SWEEPS):
        rs = sweep(rows, scene, var, **fixed)
        order = rs[::-1] if var == "h_over_t" else rs
        for i, r in enumerate(order):
            c = curve(r["name"], folder)
            if c is None:
                continue
            lab = f"h/t = {r['h_over_t']:g}" if var == "h_over_t" else f"n_t = {r['n_t']:g}"
            ax.plot(c[:, 0] * xscale, c[:, 1] * 1e-3, lw=1.1, label=lab + note(r),
                    color=cmap(i / max(len(order) - 1, 1) * 0.9))


def fig_crush(rows, folder: Path, out: Path, exp=None) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), layout="constrained", sharey=True)
    ring = scene.ring_properties(namelist.read_namelist(ROOT / "namelists" / "crush.nml"))
    _sweep_curves(axes, rows, "crush", folder, 1.0,
                  lambda r: f" (L2 error {r['error']:.1%})")
    fe = ROOT / "docs" / "fe_reference" / "crush_fe.csv"
    if fe.is_file():
        a = np.loadtxt(fe, delimiter=",", skiprows=1, ndmin=2)
        for ax in axes:
            ax.plot(a[:, 1], a[:, 2] * 1e-3, color="k", lw=2.0, alpha=0.5,
                    label="FE reference (CalculiX)")
    d = np.linspace(0, 0.6, 200)
    dh = theory.deruntz_hodge(d * ring["D"], ring["D"], ring["t"], ring["sigma_y"],
                               ring["plane"], ring["depth"])
    for ax, (_, _, title) in zip(axes, CURVE_SWEEPS):
        ax.plot(d, dh * 1e-3, "k--", label="DeRuntz–Hodge")
        if exp is not None:
            ax.plot(exp[0] / ring["D"], exp[1] * 1e-3, "o", ms=3, mfc="none", color="k",
                    label="experiment")
        ax.axvspan(0.05, 0.5, color="0.9", zorder=0)
        ax.set_xlim(0, 0.55)
        ax.set_ylim(0, 3.5e-3 * float(np.interp(0.5, d, dh)))
        ax.set_xlabel("δ / D (curves above the frame are cut)")
        ax.set_title(f"quasi-static crush: {title}; shaded: error window", fontsize=10)
        _legend(ax, fontsize=8, loc="upper left")
    axes[0].set_ylabel("platen force per metre [kN/m]")
    fig.savefig(out / "crush_curves.png", dpi=130)
    plt.close(fig)


def fig_fixed(rows, folder: Path, out: Path) -> None:
    """crush_fixed.png: the force at a fixed platen (half model, the bottom platen fixed)
    against the moving platen's of the quarter model, at the same settings: the curves at one
    particle per cell with 'fbarwall' (left) and every pair's error against FE (right)."""
    fixed = [r for r in rows if r["scene"] == "crush_fixed" and np.isfinite(r.get("error",
                                                                                 math.nan))]
    if not fixed:
        return
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, 4.6), layout="constrained",
                                  gridspec_kw={"width_ratios": [1.5, 1]})
    fe = ROOT / "docs" / "fe_reference" / "crush_fe.csv"
    if fe.is_file():
        a = np.loadtxt(fe, delimiter=",", skiprows=1, ndmin=2)
        ax.plot(a[:, 1], a[:, 2] * 1e-3, color="k", lw=2.0, alpha=0.5,
                label="FE reference (CalculiX)")
    twin = {r["name"]: r["name"].replace("crush_fixed_", "crush_", 1) for r in fixed}
    quarter = {r["name"]: r for r in rows if r["scene"] == "crush"}
    one = "cpdi2_musl_h1_4_nt4_a1_cfl0.8_fbarwall"
    for name, label, color in ((f"crush_{one}", "quarter model, moving platen", "C0"),
                               (f"crush_fixed_{one}", "half model, fixed platen", "C3")):
        c = curve(name, folder)
        r = quarter.get(name) or next((x for x in fixed if x["name"] == name), None)
        if c is not None and r is not None:
            ax.plot(c[:, 0], c[:, 1] * 1e-3, color=color, lw=0.9,
                    label=f"{label} (L2 error {r['error']:.1%})")
    ax.axvspan(0.05, 0.5, color="0.9", zorder=0)
    ax.set_xlim(0, 0.55)
    ax.set_ylim(0, None)
    ax.set_xlabel("δ / D")
    ax.set_ylabel("platen force per metre [kN/m]")
    ax.set_title("one particle per cell through the wall (h = t/4, n_t = 4), 'fbarwall'",
                 fontsize=10)
    _legend(ax, fontsize=8, loc="lower right")
    # one place per setting: the run as designed (marker) and the range over the three grid
    # alignments (bar), the fixed platen's left, the quarter's right
    labels, xs = [], []
    for k, r in enumerate(sorted([r for r in fixed if nominal(r)],
                                 key=lambda r: (r["h_over_t"], r["n_t"], volumetric(r)))):
        xs.append(k)
        labels.append(f"h = t/{round(1 / r['h_over_t'])}\nn_t = {r['n_t']:.0f}\n"
                      f"{volumetric(r)}")
        q = quarter.get(twin[r["name"]])
        for run, dx, mk, col, mfc, label in (
                (r, -0.12, "o", "C3", "C3", "half model, fixed platen"),
                (q, 0.12, "s", "C0", "none", "quarter model, moving platen")):
            if run is None or not np.isfinite(run.get("error", math.nan)):
                continue
            e = grid_errors(run, rows)
            if len(e) > 1:
                ax2.plot([k + dx] * 2, [100 * min(e), 100 * max(e)], color=col, lw=2.5,
                         alpha=0.4, solid_capstyle="butt",
                         label="the same on other grids (h x 0.96 to 1.04)" if k == 0 and dx < 0
                         else None)
            ax2.plot(k + dx, 100 * run["error"], mk, color=col, mfc=mfc,
                     label=label if k == 0 else None)
    ax2.axhline(5.0, color="0.5", ls=":", lw=1.0)
    ax2.set_xticks(xs, labels, fontsize=8)
    ax2.set_yscale("log")
    ax2.set_ylabel("L2 error of F(δ) against FE, δ/D 0.05–0.5 [%]")
    ax2.set_title("the same settings, each model (dotted: 5 %)", fontsize=10)
    _legend(ax2, fontsize=8)
    fig.savefig(out / "crush_fixed.png", dpi=130)
    plt.close(fig)


def fig_impact(rows, folder: Path, out: Path, exp=None) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.6), layout="constrained", sharey=True)
    _sweep_curves(axes, rows, "impact", folder, 1e3,
                  lambda r: f": COR {r['cor']:.3f}, contact {r['duration'] * 1e3:.3f} ms")
    for ax, (var, _, title) in zip(axes, CURVE_SWEEPS):
        if exp is not None:
            ax.plot(exp[0] * 1e3, exp[1] * 1e-3, "o", ms=3, mfc="none", color="k",
                    label="experiment")
        ax.set_xlabel("time [ms] (the first spike of h/t = 2 reaches 2200 kN/m, cut)"
                      if var == "h_over_t" else "time [ms]")
        ax.set_title(f"impact at 30 m/s: {title}")
        _legend(ax, fontsize=7)
        ax.set_xlim(0, 0.9)
        ax.set_ylim(0, 700)
    axes[0].set_ylabel("target force per metre [kN/m]")
    fig.savefig(out / "impact_curves.png", dpi=130)
    plt.close(fig)


def fig_cor(rows, out: Path) -> None:
    rs = sorted([r for r in rows if r["scene"] == "impact" and centre(
        r, h_over_t=0.25, n_t=8.0, speed=r["speed"]) and np.isfinite(r["cor"])],
        key=lambda r: r["speed"])
    if not rs:
        return
    inputs = namelist.read_namelist(ROOT / "namelists" / "impact.nml")
    ring = scene.ring_properties(inputs)
    vy = ring["sigma_y"] / math.sqrt(ring["E"] * ring["rho"])
    fig, ax = plt.subplots(figsize=(7.5, 4.6), layout="constrained")
    ax.axhspan(0.75, 0.78, color="C2", alpha=0.25,
               label="Bao & Yu, elastic range: COR 0.75–0.78")
    ax.axvspan(16.5, 125, color="0.92", zorder=0, label="Xu's experiments: 16.5–125 m/s")
    ax.plot([r["speed"] for r in rs], [r["cor"] for r in rs], "o-", color="C3",
            label="MPM (CPDI2, h = t/4, n_t = 8)")
    ax.axvline(vy, color="k", ls=":", lw=1, label=f"$V_Y = σ_y/\\sqrt{{Eρ}}$ = {vy:.1f} m/s")
    ax.set_xscale("log")
    ax.set_xlabel("impact speed [m/s]")
    ax.set_ylabel("coefficient of restitution [-]")
    ax.set_ylim(0, 1)
    ax.set_title("aluminium ring (R/t = 12.5) on a rigid target")
    _legend(ax, fontsize=8)
    fig.savefig(out / "impact_cor.png", dpi=130)
    plt.close(fig)


def fig_wave(rows, folder: Path, out: Path, exp=None) -> None:
    fig, ax = plt.subplots(figsize=(7.5, 4.8), layout="constrained")
    rs = sweep(rows, "wave", "h_over_t", n_t=16.0)[::-1]
    cmap = plt.get_cmap("viridis")
    for i, r in enumerate(rs):
        c = curve(r["name"], folder)
        if c is None:
            continue
        ax.plot(c[:, 0], c[:, 1] * 1e6, "o-", ms=4, lw=1,
                color=cmap(i / max(len(rs) - 1, 1) * 0.9),
                label=f"h/t = {r['h_over_t']:g}, n_t 16: fitted {r['wave_speed']:.0f} m/s")
    inputs = namelist.read_namelist(ROOT / "namelists" / "wave.nml")
    ring = scene.ring_properties(inputs)
    th = np.linspace(0, 180, 50)
    for name, c, ls in (("bar", theory.bar_speed(ring["E"], ring["rho"]), "--"),
                        ("plate", theory.plate_speed(ring["E"], ring["nu"], ring["rho"]), ":")):
        ax.plot(th, np.radians(th) * ring["R"] / c * 1e6, "k", ls=ls,
                label=f"Rθ / c, {name} speed {c:.0f} m/s")
    if exp is not None:
        ax.plot(exp[0], exp[1] * 1e6, "s", ms=5, mfc="none", color="k", label="experiment")
    ax.set_xlabel("angle from the struck point [deg]")
    ax.set_ylabel("arrival time [µs]")
    ax.set_title("wave round the ring: arrival (10 % of the probe's peak)")
    _legend(ax, fontsize=8)
    fig.savefig(out / "wave_arrival.png", dpi=130)
    plt.close(fig)


def fig_shapes(rows, out: Path) -> None:
    ref = next((r for r in rows if r["scene"] == "crush"), None)
    if ref is None:
        return
    finest = ref.get("self_reference")
    run = ROOT / "out" / "study" / str(finest if isinstance(finest, str) and finest
                                       else ref["reference"])
    if not (run / "particles.h5").is_file():
        print(f"  crush_shapes.png: {run} not found (run the study); kept the old figure")
        return
    subprocess.run([sys.executable, "-m", "plots.plot_shapes", "--case",
                    str((run / "case.nml").resolve()), "--out",
                    str((out / "crush_shapes.png").resolve())], check=True, cwd=ROOT,
                   stdout=subprocess.DEVNULL)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--level", default="quick", choices=("quick", "full", "all"),
                    help="whose table (default quick, as tools/study.py): quick reads and "
                         "writes out/study-quick/; full reads docs/study/ and writes its "
                         "figures there (--check's advice table is tools/advice_tables.py's)")
    ap.add_argument("--out", default=None, help="output folder (default docs/study; "
                                                 "out/study-quick for --level quick)")
    ap.add_argument("--experiment", action="append", metavar="SCENE=CSV",
                    help="overlay a measured curve on the crush, impact or wave figure "
                         "(repeatable; columns as for plot_case.py, plots/README.md)")
    args = ap.parse_args(argv)
    folder = ROOT / "out" / "study-quick" if args.level == "quick" else ROOT / "docs" / "study"
    out = Path(args.out) if args.out else folder
    out.mkdir(parents=True, exist_ok=True)
    table = folder / f"study_{args.level}.csv"
    if not table.is_file():
        print(f"ERROR [plot_study]: {table} not found: run tools/study.py --level {args.level}",
              file=sys.stderr)
        return 1
    rows = read_table(table)
    adv = advice(rows)
    with open(out / f"advice_{args.level}.csv", "w", newline="") as fh:
        keys = ["scene", "target", "name", "basis", "scheme", "h_over_t", "n_t", "n_c", "aspect",
                "cfl", "cfl_used", "volumetric", "penalty", "particles", "cpu_s", "runtime_ratio",
                "error",
                "robust_error"]
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for a in adv:
            w.writerow({k: (f"{v:.0f}" if k in ("n_t", "n_c", "particles") and isinstance(v, float)
                            else f"{v:.4g}" if isinstance(v, float) else v)
                        for k, v in a.items()})
    fig_accuracy_runtime(rows, adv, out)
    fig_error_factors(rows, out)
    fig_crush(rows, folder, out, experiment(args.experiment, "crush"))
    fig_fixed(rows, folder, out)
    fig_impact(rows, folder, out, experiment(args.experiment, "impact"))
    fig_cor(rows, out)
    fig_wave(rows, folder, out, experiment(args.experiment, "wave"))
    fig_shapes(rows, out)
    for a in adv:
        if "cpu_s" in a:
            print(f"  {a['scene']:6s} <= {a['target']:.0%}: {a['name']} "
                  f"({a['cpu_s']:.0f} CPU s, error {a['robust_error']:.2%} on the worst "
                  f"grid measured, {a['error']:.2%} as run)")
        else:
            print(f"  {a['scene']:6s} <= {a['target']:.0%}: none within the study")
    print(f"wrote figures to {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
