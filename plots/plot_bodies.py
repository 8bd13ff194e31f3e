#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Several bodies in contact (history.csv of a run with more than one body): forces and energies
per body and for the system.

Left: against the travel of the first moving platen (or time when no wall moves), the system's
force (that platen's force) and the normal contact force of every pair of bodies
(contact<i>_<j>_force: what one body passes to the other). Right: the energy absorbed by each
body (plastic dissipation + stored elastic energy, body<k>_plastic + body<k>_strain) and its
kinetic energy.

    python3 -m plots.plot_bodies --case namelists/contact/nested.nml
    python3 -m plots.plot_bodies --dir out/stack --out stack_bodies.png
    python3 -m plots.plot_bodies --case namelists/contact/row3.nml \
        --reference out/row3_single --scale 3

--reference OUTDIR draws the force of another run (its first moving platen against that
platen's travel) times --scale on the force plot: for the row of three tubes, three times one
tube crushed alone.
"""
from __future__ import annotations

import argparse
import os
import re
import sys

import numpy as np

from plots import style  # Agg backend and rcParams, before pyplot
from plots.mpmplot import readers, scene

import matplotlib.pyplot as plt


def bodies(history: dict[str, np.ndarray]) -> int:
    """Number of bodies with their own columns (0 for a one-body run)."""
    return len([c for c in history if re.fullmatch(r"body\d+_x", c)])


def pairs(history: dict[str, np.ndarray]) -> list[tuple[int, int]]:
    """The pairs of bodies (i, j) with contact columns, in file order."""
    out = []
    for c in history:
        m = re.fullmatch(r"contact(\d+)_(\d+)_force", c)
        if m:
            out.append((int(m.group(1)), int(m.group(2))))
    return out


def moving_wall(history: dict[str, np.ndarray]) -> int:
    """The first wall whose travel changes over the run (0: none)."""
    for k in range(1, readers.history_walls(history) + 1):
        d = history[f"wall{k}_disp"]
        if d.size and float(np.max(np.abs(d - d[0]))) > 0.0:
            return k
    return 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description="Forces and energies per body of a tubempm run "
                                "with several bodies in contact.")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--case", metavar="FILE.nml", help="the case file")
    src.add_argument("--dir", metavar="OUTDIR", help="the output folder of a run")
    p.add_argument("--out", metavar="PNG", help="output image (default <outdir>/bodies.png)")
    p.add_argument("--reference", metavar="OUTDIR", help="output folder of a reference run "
                   "whose platen force (times --scale) is drawn over the system's")
    p.add_argument("--scale", type=float, default=1.0, metavar="K",
                   help="factor on the reference force (default 1)")
    args = p.parse_args(argv)
    try:
        outdir, inputs = scene.resolve_case(args.case, args.dir)
        h = readers.read_history(os.path.join(outdir, "history.csv"))
        ref = (readers.read_history(os.path.join(args.reference, "history.csv"))
               if args.reference else None)
    except (OSError, ValueError, KeyError) as exc:
        print(f"ERROR [plot_bodies]: {exc}", file=sys.stderr)
        return 2
    nb = bodies(h)
    if nb == 0:
        print(f"ERROR [plot_bodies]: {outdir}/history.csv has no body<k>_ columns (a run with "
              "one body: use plots/plot_case.py)", file=sys.stderr)
        return 2
    k = moving_wall(h)
    if k:
        x = -h[f"wall{k}_disp"] * 1e3
        xlabel = f"platen travel (wall {k}) [mm]"
    else:
        x = h["time"] * 1e3
        xlabel = "time [ms]"
    fig, (a1, a2) = plt.subplots(1, 2, layout="constrained", figsize=(11.0, 4.2))
    if k:
        a1.plot(x, h[f"wall{k}_force"] * 1e-3, color="k", lw=1.6, label=f"system (wall {k})")
    if ref is not None:
        kr = moving_wall(ref)
        if not kr:
            print(f"ERROR [plot_bodies]: {args.reference}/history.csv: no wall moves",
                  file=sys.stderr)
            return 2
        name = os.path.basename(os.path.normpath(args.reference))
        a1.plot(-ref[f"wall{kr}_disp"] * 1e3, args.scale * ref[f"wall{kr}_force"] * 1e-3,
                color="0.5", ls="--", lw=1.2, label=f"{args.scale:g} x {name} (wall {kr})")
    for i, j in pairs(h):
        a1.plot(x, h[f"contact{i}_{j}_force"] * 1e-3, lw=1.0, label=f"contact {i}-{j}")
    a1.set_xlabel(xlabel)
    a1.set_ylabel("force [kN per m depth]")
    a1.set_title("forces: the system and between bodies")
    a1.legend(fontsize=8)
    for b in range(1, nb + 1):
        line, = a2.plot(x, (h[f"body{b}_plastic"] + h[f"body{b}_strain"]),
                        label=f"body {b}: absorbed (plastic + elastic)")
        a2.plot(x, h[f"body{b}_kinetic"], ls="--", color=line.get_color(), lw=0.8,
                label=f"body {b}: kinetic")
    a2.set_xlabel(xlabel)
    a2.set_ylabel("energy [J per m depth]")
    a2.set_title("energy per body")
    a2.legend(fontsize=8)
    run = (inputs.get("run") or [{}])[0]
    title = str(run.get("title") or os.path.basename(os.path.normpath(outdir)))
    failure = readers.run_failure(outdir)
    if failure:
        style.mark_failed(fig, failure, f"{title}: {nb} bodies")
        print(f"  {failure}")
    else:
        fig.suptitle(f"{title}: {nb} bodies")
    out = args.out or os.path.join(outdir, "bodies.png")
    fig.savefig(out, dpi=style.DPI)
    plt.close(fig)
    print(f"wrote {out}")
    for b in range(1, nb + 1):
        print(f"  body {b}: absorbed {h[f'body{b}_plastic'][-1] + h[f'body{b}_strain'][-1]:.4g} J/m"
              f" (plastic {h[f'body{b}_plastic'][-1]:.4g})")
    for i, j in pairs(h):
        print(f"  contact {i}-{j}: peak {np.max(h[f'contact{i}_{j}_force']):.4g} N/m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
