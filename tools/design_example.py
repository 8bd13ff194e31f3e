#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Design charts of tube absorbers (`make design-example`): several designs crushed
quasi-statically to half their diameter, compared on one figure (docs/design.md).

    python3 -m tools.design_example [--out out/design_example] [--jobs 2]
                                    [--backend slurm [--partition P] ...] [--collect]

The designs: single tubes of 50 mm outer diameter in steel and in aluminium at D/t = 15, 25
and 35, and a nested pair of steel tubes (50 mm and 40 mm, 2 mm walls, concentric) against the
single 50 mm tube of the same wall (D/t = 25). Each case is written by tools/new_case.py (quarter model,
h = t/4, 8 particles through the wall, a quasi-static platen speed, a stroke of 0.5 D) and run
through tools/batch.py (finished runs are reused; --backend slurm sends them as one job
array, docs/batch.md). Then DIR/designs.csv gets each run's &results (docs/output.md) and
DIR/design_charts.png the charts: specific energy absorption against mean force, crush force
efficiency against D/t, and absorbed energy and force against the stroke, overlaid.
"""
from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

from tools import batch
from tools import new_case

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

D = 50.0e-3
D_OVER_T = (15.0, 25.0, 35.0)
MATERIALS = ("steel", "aluminium")
NESTED_INNER = (40.0e-3, 2.0e-3)           #: inner tube of the nested pair: D, t [m]


def designs(root: Path) -> list[batch.Case]:
    """The cases, cheapest first (thick walls have fewer, larger particles)."""
    bases = root / "bases"
    bases.mkdir(parents=True, exist_ok=True)
    cases = []
    for dt in D_OVER_T:
        for mat in MATERIALS:
            name = f"{mat}_Dt{dt:g}"
            a = new_case.parse(["crush", "--D", str(D), "--t", str(D / dt), "--material", mat,
                                "--stroke", str(0.5 * D), "--title", name])
            _, text = new_case.render(a)
            path = bases / f"{name}.nml"
            path.write_text(text)
            cases.append(batch.Case(name, path, {}, {"material": mat, "D_over_t": dt,
                                                     "design": "single"}))
    # the nested pair: steel_Dt25 (50 mm x 2 mm) with a 40 mm x 2 mm tube inside
    a = new_case.parse(["crush", "--D", str(D), "--t", "2e-3", "--material", "steel",
                        "--stroke", str(0.5 * D), "--title", "steel_nested"])
    _, text = new_case.render(a)
    ro = 0.5 * NESTED_INNER[0]
    text += (f"\n&body                           ! the inner tube, concentric\n"
             f"  shape = 'ring'\n  material = 'steel'\n  center = 0.0, {0.5 * D:.6g}\n"
             f"  r_inner = {ro - NESTED_INNER[1]:.6g}\n  r_outer = {ro:.6g}\n  n_thick = 8\n"
             f"  sector = 'quarter'\n/\n")
    path = bases / "steel_nested.nml"
    path.write_text(text)
    cases.append(batch.Case("steel_nested", path, {}, {"material": "steel", "D_over_t": 25.0,
                                                       "design": "nested"}))
    return cases


def collect(cases: list[batch.Case], root: Path) -> list[dict]:
    from plots.mpmplot import readers  # noqa: PLC0415
    rows = []
    for c in cases:
        folder = root / c.name
        summ = folder / "summary.nml"
        if not summ.is_file():
            print(f"  {c.name}: no summary.nml (not run)")
            continue
        res = readers.read_results(summ)
        status = readers.read_summary(summ).get("status")
        if status != "completed" or not res:
            print(f"  {c.name}: {status}, left out")
            continue
        h = readers.read_history(folder / "history.csv")
        delta = -2.0 * h["wall1_disp"]               # quarter model: the image platen too
        force = h["wall1_force"]
        energy = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) *
                                                  np.diff(delta))])
        rows.append({"name": c.name, **c.labels, **res, "_delta": delta, "_force": force,
                     "_energy": energy})
    with open(root / "designs.csv", "w", newline="") as fh:
        keys = [k for k in rows[0] if not k.startswith("_")] if rows else ["name"]
        w = csv.DictWriter(fh, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()
                        if not k.startswith("_")})
    return rows


def chart(rows: list[dict], out: Path) -> None:
    from plots import style  # noqa: F401,PLC0415  (Agg backend, rcParams)
    import matplotlib.pyplot as plt  # noqa: PLC0415
    colour = {"steel": "C0", "aluminium": "C1"}
    fig, ax = plt.subplots(2, 2, layout="constrained", figsize=(11, 8.5))
    for r in rows:
        nested = r["design"] == "nested"
        kw = dict(color=colour[r["material"]], marker="s" if nested else "o", ms=8,
                  mfc="none" if nested else colour[r["material"]], ls="none")
        ax[0, 0].plot(r["mean_force"] * 1e-3, r["sea"] * 1e-3, **kw)
        ax[0, 0].annotate(r["name"].replace("_", " "), (r["mean_force"] * 1e-3,
                          r["sea"] * 1e-3), fontsize=7, xytext=(4, 3), textcoords="offset points")
        ls = "-." if nested else {15.0: "-", 25.0: "--", 35.0: ":"}.get(r["D_over_t"], "-")
        lab = f"{r['name'].replace('_', ' ')}"
        lw = 2.0 if nested else 1.3
        ax[1, 0].plot(r["_delta"] * 1e3, r["_energy"], color=colour[r["material"]], ls=ls,
                      lw=lw, label=lab)
        ax[1, 1].plot(r["_delta"] * 1e3, r["_force"] * 1e-3, color=colour[r["material"]], ls=ls,
                      lw=0.5 * lw + 0.2, label=lab)
    for mat in MATERIALS:
        sel = sorted((r for r in rows if r["material"] == mat and r["design"] == "single"
                     ), key=lambda r: r["D_over_t"])
        if sel:
            ax[0, 1].plot([r["D_over_t"] for r in sel], [r["cfe"] for r in sel], "o-",
                          color=colour[mat], label=f"{mat}, single")
    nest = [r for r in rows if r["design"] == "nested"]
    if nest:
        ax[0, 1].plot([r["D_over_t"] for r in nest], [r["cfe"] for r in nest], "s",
                      mfc="none", color=colour["steel"], ms=9, label="steel, nested pair")
    ax[0, 0].set(xlabel="mean force [kN] (1 m of tube)", ylabel="SEA [kJ/kg]",
                 title="specific energy absorption against mean force")
    ax[0, 0].plot([], [], "o", color="0.4", label="single tube")
    ax[0, 0].plot([], [], "s", mfc="none", color="0.4", label="nested pair")
    ax[0, 0].legend(loc="lower right")
    ax[0, 1].set(xlabel="D/t", ylabel="CFE = mean / peak force",
                 title="crush force efficiency against D/t")
    ax[0, 1].legend()
    ax[1, 0].set(xlabel=r"stroke $\delta$ [mm]", ylabel="absorbed energy [J] (1 m)",
                 title="energy against stroke")
    ax[1, 0].legend(fontsize=7, ncol=2)
    ax[1, 1].set(xlabel=r"stroke $\delta$ [mm]", ylabel="force [kN] (1 m)",
                 title="force against stroke")
    fig.suptitle(f"tube absorbers of {D * 1e3:g} mm diameter crushed to 0.5 D, quasi-static "
                 "(tools/design_example.py)")
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--out", type=Path, default=ROOT / "out" / "design_example")
    ap.add_argument("--jobs", type=int, default=2, help="runs at a time (local; default 2)")
    ap.add_argument("--collect", action="store_true", help="only collect and chart")
    batch.add_backend_args(ap)
    a = ap.parse_args(argv)
    cases = designs(a.out)
    if not a.collect:
        backend = batch.backend_of(a)
        batch.run_batch(cases, a.out, jobs=a.jobs, threads=a.threads, backend=backend)
    rows = collect(cases, a.out)
    if not rows:
        print("ERROR [design_example]: no finished run to chart", file=sys.stderr)
        return 1
    chart(rows, a.out / "design_charts.png")
    print(f"wrote {a.out / 'designs.csv'} and {a.out / 'design_charts.png'}")
    for r in rows:
        print(f"  {r['name']:18s} SEA {r['sea']:8.1f} J/kg  mean {r['mean_force'] * 1e-3:7.2f} kN"
              f"  CFE {r['cfe']:.3f}  absorbed {r['absorbed_energy']:7.1f} J")
    return 0


if __name__ == "__main__":
    sys.exit(main())
