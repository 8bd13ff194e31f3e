#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A sweep's chart: one column of sweep.csv (tools/sweep.py) against another, one line per
value of a third.

    python3 -m plots.plot_sweep --dir out/chart --x ring.D_over_t --y plastic_end --by ring.speed

Reads DIR/sweep.csv and writes DIR/sweep_<y>.png (or --out). Runs that did not complete
(exit code not 0) are left out and named. --x and --by are any column (the swept keys, labels,
or results), --y a numeric column: the history summaries ``<column>_end``, ``_min``, ``_max``
(``plastic_end`` is the energy absorbed plastically [J], ``wall1_force_max`` the peak force on
wall 1 [N]), the run's &results (``sea``, ``cfe``, ``mean_force``, ``absorbed_energy``, ...),
``cpu_s``, ``energy_error``, ``steps``. ``--list`` prints the columns.
"""
from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

from plots import style  # noqa: F401  (Agg backend, shared rcParams; before pyplot)
import matplotlib.pyplot as plt

#: axis labels of the common columns (others are labelled with their name)
UNITS = {"plastic": "J", "kinetic": "J", "strain": "J", "external": "J", "damped": "J",
         "contact_loss": "J",
         "force": "N", "disp": "m", "com_vx": "m/s", "com_vy": "m/s", "cpu_s": "s",
         "wall_s": "s", "ring.speed": "m/s", "ring.t": "m", "sea": "J/kg", "mean_force": "N",
         "peak_force": "N", "absorbed_energy": "J", "stroke": "m", "mass": "kg",
         "densification_stroke": "m"}
NAMES = {"plastic_end": "plastic dissipation (absorbed energy)", "ring.D_over_t": "D/t",
         "ring.speed": "impact speed", "ring.t": "wall thickness t",
         "sea": "specific energy absorption (SEA)", "cfe": "crush force efficiency (CFE)"}


def label(column: str) -> str:
    """Axis label with its unit."""
    unit = UNITS.get(column, "")
    if not unit:
        for key, u in UNITS.items():
            if column.startswith(key + "_") or f"_{key}_" in column:
                unit = u
                break
    name = NAMES.get(column, column)
    return f"{name} [{unit}]" if unit else name


def number(text: str) -> float:
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def series(rows: list[dict[str, str]], x: str, y: str, by: str | None
           ) -> dict[str, tuple[list[float], list[float]]]:
    """The completed runs' (x, y) points per value of ``by`` (one series '' without), sorted
    by x."""
    out: dict[str, list[tuple[float, float]]] = {}
    for r in rows:
        if r.get("exit_code") != "0":
            continue
        key = r.get(by, "") if by else ""
        out.setdefault(key, []).append((number(r[x]), number(r[y])))
    def order(k: str) -> tuple[float, str]:
        return (number(k), k)
    return {k: ([p[0] for p in sorted(v)], [p[1] for p in sorted(v)])
            for k, v in sorted(out.items(), key=lambda kv: order(kv[0]))}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--dir", type=Path, required=True, help="the sweep's folder (--out of "
                    "tools/sweep.py)")
    ap.add_argument("--x", help="column on the horizontal axis")
    ap.add_argument("--y", default="plastic_end", help="column on the vertical axis "
                    "(default plastic_end)")
    ap.add_argument("--by", help="one line per value of this column")
    ap.add_argument("--logx", action="store_true")
    ap.add_argument("--logy", action="store_true")
    ap.add_argument("--out", type=Path, help="the PNG (default DIR/sweep_<y>.png)")
    ap.add_argument("--list", action="store_true", help="print the columns of sweep.csv")
    args = ap.parse_args(argv)
    path = args.dir / "sweep.csv"
    if not path.is_file():
        print(f"ERROR [plot_sweep]: {path} not found: run tools/sweep.py --out {args.dir} "
              "first (or with --collect)", file=sys.stderr)
        return 2
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    columns = list(rows[0]) if rows else []
    if args.list:
        print("\n".join(columns))
        return 0
    if not args.x:
        ap.error("--x is required (see --list for the columns)")
    for opt, col in (("--x", args.x), ("--y", args.y), ("--by", args.by)):
        if col and col not in columns:
            print(f"ERROR [plot_sweep]: {opt} {col}: no such column in {path}; the columns: "
                  f"{', '.join(columns)}", file=sys.stderr)
            return 2
    lines = series(rows, args.x, args.y, args.by)
    failed = [r["name"] for r in rows if r.get("exit_code") != "0"]
    fig, ax = plt.subplots(layout="constrained", figsize=(6.0, 4.2))
    for key, (xs, ys) in lines.items():
        unit = UNITS.get(args.by, "") if args.by else ""
        ax.plot(xs, ys, "o-", label=f"{NAMES.get(args.by, args.by)} = {key} {unit}".rstrip()
                if args.by else None)
    ax.set_xlabel(label(args.x))
    ax.set_ylabel(label(args.y))
    if args.logx:
        ax.set_xscale("log")
    if args.logy:
        ax.set_yscale("log")
    if args.by:
        ax.legend()
    title = f"{args.dir.name}: {sum(len(v[0]) for v in lines.values())} runs"
    if failed:
        title += f"; not completed: {', '.join(failed[:4])}{' ...' if len(failed) > 4 else ''}"
    ax.set_title(title)
    out = args.out or args.dir / f"sweep_{args.y}.png"
    fig.savefig(out)
    plt.close(fig)
    print(f"wrote {out}")
    if failed:
        print(f"left out {len(failed)} runs that did not complete: {', '.join(failed)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
