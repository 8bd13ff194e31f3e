#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Deformed shapes of a tubempm run: the particle domains coloured by plastic strain (or, with
``--colour body``, by the body each particle belongs to).

One panel per snapshot of particles.h5 (by default up to six, spread evenly over the run),
each particle drawn as its domain polygon (the CPDI corners) coloured by the equivalent
plastic strain, with the walls that are not mirror planes drawn at their position at that time
(the point moved by the wall's travel, history column wall<k>_disp, along minus its normal;
with the whole tube drawn, also their images in the mirror planes).
A half or quarter model is drawn as the whole tube, from the mirror images that tubempm writes
into particles.h5 (docs/output.md; `--sector` draws the computed part only).

    python3 -m plots.plot_shapes --case namelists/crush.nml
    python3 -m plots.plot_shapes --dir out/impact --frames 0 5 -1 --out impact_shapes.png
    python3 -m plots.plot_shapes --dir out/crush --h5 out/crush/crash_001234.h5
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import textwrap
from typing import Any

import numpy as np

from plots import style  # Agg backend and rcParams, before pyplot
from plots.mpmplot import readers, scene

import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection
from matplotlib.colors import BoundaryNorm, ListedColormap, Normalize

MAX_DEFAULT_FRAMES = 6


def pick_frames(count: int, wanted: list[int] | None) -> list[int]:
    """Snapshot positions to draw: the wanted ones (negative from the end), or up to six
    spread evenly over the run, first and last included."""
    if count == 0:
        return []
    if wanted:
        out = []
        for k in wanted:
            j = k + count if k < 0 else k
            if not 0 <= j < count:
                raise IndexError(f"frame {k} out of range: the file holds {count} snapshots "
                                 f"(0..{count - 1})")
            out.append(j)
        return out
    n = min(count, MAX_DEFAULT_FRAMES)
    return sorted({int(round(x)) for x in np.linspace(0, count - 1, n)})


def wall_positions(walls: list[dict[str, Any]], history: dict[str, np.ndarray] | None,
                   time: float, mirrored: bool = False
                   ) -> list[tuple[np.ndarray, np.ndarray, int]]:
    """(current point [m], unit normal, wall number) of each non-mirror wall at a time: the
    input point moved by wall<k>_disp of the history row nearest the time along -normal. With
    `mirrored` (the whole tube drawn from a half or quarter model) also each wall's images in
    the mirror planes (the lower platen of a quarter crush), each plane drawn once."""
    out = []
    row = None
    if history is not None and history["time"].size:
        row = int(np.argmin(np.abs(history["time"] - time)))
    for w in walls:
        if w["mirror"]:
            continue
        k = w["index"]
        travel = 0.0
        if row is not None and f"wall{k}_disp" in history:
            travel = float(history[f"wall{k}_disp"][row])
        out.append((w["point"] - travel * w["normal"], w["normal"], k))
    if mirrored:
        for m in walls:                         # the planes the sector adds, where the images are
            q, nm = np.asarray(m["point"], float), np.asarray(m["normal"], float)
            if not m["mirror"] or m.get("input") or not np.all(np.isfinite(nm)):
                continue
            out += [(p - 2.0 * np.dot(p - q, nm) * nm, n - 2.0 * np.dot(n, nm) * nm, k)
                    for p, n, k in out]
    seen, unique = set(), []
    for p, n, k in out:                         # a plane is its normal and offset n . p
        key = tuple(np.round(np.append(n, np.dot(n, p)), 12))
        if key not in seen:
            seen.add(key)
            unique.append((p, n, k))
    return unique


def draw_wall(ax: plt.Axes, point: np.ndarray, normal: np.ndarray, size: float,
              scale: float) -> None:
    """A wall as a line with a hatched band on its solid side (behind the normal)."""
    tangent = np.array([-normal[1], normal[0]])
    far = 20.0 * size
    p = point * scale
    a, b = p - far * tangent, p + far * tangent
    band = 0.035 * size
    poly = np.array([a, b, b - band * normal, a - band * normal])
    ax.fill(poly[:, 0], poly[:, 1], facecolor="0.85", edgecolor="0.4", hatch="///", lw=0.0,
            zorder=1)
    ax.plot([a[0], b[0]], [a[1], b[1]], color="0.2", lw=1.5, zorder=3)


def body_colours(nbody: int) -> ListedColormap:
    """One distinct colour per body id 1..nbody (tab10, tab20 beyond ten bodies, cycled
    beyond twenty)."""
    base = plt.get_cmap("tab10" if nbody <= 10 else "tab20")
    return ListedColormap([base(k % base.N) for k in range(nbody)], name="bodies")


def main(argv: list[str] | None = None) -> int:
    """Draw the selected snapshots into one figure."""
    p = argparse.ArgumentParser(description="Deformed particle domains of a tubempm run, "
                                "coloured by equivalent plastic strain, with the walls.")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--case", metavar="FILE.nml", help="the case file")
    src.add_argument("--dir", metavar="OUTDIR", help="the output folder of a run")
    p.add_argument("--frames", type=int, nargs="+", metavar="K",
                   help="snapshot positions (0-based, negative from the end); default: up to "
                        f"{MAX_DEFAULT_FRAMES} spread evenly")
    p.add_argument("--h5", metavar="FILE", help="particle file (default <outdir>/particles.h5; "
                   "a crash_<step>.h5 works too)")
    p.add_argument("--out", metavar="PNG", help="output image (default <outdir>/shapes.png)")
    p.add_argument("--edges", action="store_true", help="outline every particle domain")
    p.add_argument("--sector", action="store_true", help="a half or quarter model: draw the "
                   "computed part only (default: the whole tube, with its mirror images)")
    p.add_argument("--colour", choices=("eqps", "body"), default="eqps",
                   help="colour by equivalent plastic strain (default) or by body")
    args = p.parse_args(argv)

    try:
        outdir, inputs = scene.resolve_case(args.case, args.dir)
        h5 = args.h5 or os.path.join(outdir, "particles.h5")
        names = readers.read_frames(h5)
        chosen = pick_frames(len(names), args.frames)
        if not chosen:
            raise ValueError(f"{h5}: no snapshots")
        frames = [readers.read_frame(h5, names[j], mirrored=not args.sector) for j in chosen]
    except (OSError, ValueError, KeyError, IndexError) as exc:
        print(f"ERROR [plot_shapes]: {exc}", file=sys.stderr)
        return 2
    history = None
    hpath = os.path.join(outdir, "history.csv")
    if os.path.isfile(hpath):
        try:
            history = readers.read_history(hpath)
        except ValueError as exc:
            print(f"warning: {exc}; walls drawn at their initial position", file=sys.stderr)
    walls = scene.wall_table(inputs, readers.history_walls(history) if history else None)

    mm = 1e3
    allc = np.vstack([f["corners"] for f in frames]) * mm
    lo, hi = allc.min(axis=0), allc.max(axis=0)
    size = float(max(hi - lo)) or 1.0
    pad = 0.07 * size
    lo, hi = lo - pad, hi + pad
    key = "eqps" if args.colour == "eqps" else "body"
    vmax = max(float(np.max(f[key])) for f in frames)
    cmap, ticks = style.CMAP, None
    if key == "body":                           # one colour per body id: a discrete scale
        nbody = max(int(round(vmax)), 1)
        ticks = list(range(1, nbody + 1))
        cmap = body_colours(nbody)
        norm = BoundaryNorm(np.arange(0.5, nbody + 1.0), cmap.N)
    else:
        norm = Normalize(vmin=0.0, vmax=vmax if vmax > 0.0 else 1.0)
    tmax = max(float(f.get("time", 0.0)) for f in frames)
    tscale, tunit = (1e3, "ms") if tmax >= 1e-3 else (1e6, "µs")

    n = len(frames)
    ncols = min(n, 3)
    nrows = math.ceil(n / ncols)
    aspect = (hi[1] - lo[1]) / (hi[0] - lo[0])
    fig, axes = plt.subplots(nrows, ncols, layout="constrained", squeeze=False,
                             figsize=(3.6 * ncols + 1.2, (3.6 * aspect + 0.8) * nrows + 0.4))
    pc = None
    for ax, frame in zip(axes.flat, frames):
        verts = frame["corners"][frame["quads"]] * mm
        pc = PolyCollection(verts, array=np.asarray(frame[key], dtype=float), cmap=cmap,
                            norm=norm,
                            edgecolors=(0, 0, 0, 0.35) if args.edges else "face",
                            linewidths=0.15 if args.edges else 0.3, zorder=2)
        ax.add_collection(pc)
        for point, normal, _ in wall_positions(walls, history, float(frame.get("time", 0.0)),
                                               bool(frame["mirrored"])):
            draw_wall(ax, point, normal, size, mm)
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_title(f"t = {float(frame.get('time', 0.0)) * tscale:.4g} {tunit}\n"
                     f"{frame['name']}, max eqps {np.max(frame['eqps']):.3g}", fontsize=9)
        ax.grid(False)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    label = "equivalent plastic strain [-]" if key == "eqps" else "body"
    if key == "eqps" and vmax <= 0.0:
        label += " (zero everywhere)"
    fig.colorbar(pc, ax=axes, label=label, shrink=0.9, ticks=ticks)
    run = (inputs.get("run") or [{}])[0]
    title = str(run.get("title") or os.path.basename(os.path.normpath(outdir)))
    suptitle = f"{title}: deformed particle domains ({frames[0]['np']} particles)"
    if frames[0]["mirrored"]:
        n_img = int(frames[0]["images"]) - 1
        suptitle = (f"{title}: deformed particle domains, the whole tube ({frames[0]['np']} "
                    f"particles: the computed {frames[0]['x'].shape[0] // (n_img + 1)} and "
                    + ("its mirror image)" if n_img == 1 else f"their {n_img} mirror images)"))
    suptitle = textwrap.fill(suptitle, width=max(40, int(10 * fig.get_figwidth())))  # fits
    failure = readers.run_failure(outdir)
    if failure:
        style.mark_failed(fig, failure, suptitle)
        print(f"  {failure}")
    else:
        fig.suptitle(suptitle)
    out = args.out or os.path.join(outdir, "shapes.png")
    fig.savefig(out, dpi=style.DPI)
    plt.close(fig)
    print(f"wrote {out} ({n} frames: {', '.join(f['name'] for f in frames)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
