#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Plot the result of a tubempm run against the closed forms (and a measured curve).

The plot is chosen by the kind of scene (the ``scene`` of summary.nml through
mpmplot.scene.scene_kind, which asks ``tubempm --scene`` for an output without it, or --kind; a
wave scene without probes gets the generic plot, and so does a detected impact without a wall
to hit, such as two rings thrown at each other, with a note that names plot_bodies.py when
there are several bodies):

* crush:   platen force vs platen displacement with the DeRuntz-Hodge curve and the elastic
           diametral stiffness; energies vs displacement with kinetic / plastic. The closed
           forms are a single tube's: with more than one &body they are left out, and a line
           says so.
* impact:  target force vs time with the contact phases, contact duration, rebound velocity and
           coefficient of restitution; centre-of-mass velocity vs time.
* wave:    probe velocity disturbances vs time with the arrival times; arrival time vs angle
           from the struck point with the membrane arrival R theta / c for the bar and plate
           wave speeds.
* generic: energies vs time.

The key numbers are printed to standard output.

    python3 -m plots.plot_case --case namelists/impact.nml
    python3 -m plots.plot_case --dir out/crush --experiment xiang.csv --out crush.png

Measured curves (--experiment, CSV with a header line; docs in plots/README.md):
crush ``displacement_m,force_N``; impact ``time_s,force_N``; wave ``angle_deg,arrival_s``.
Forces are in N for the same out-of-plane length as the run's &run depth.
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
from typing import Any

import numpy as np

from plots import style  # noqa: F401  (Agg backend and rcParams, before pyplot)
from plots.mpmplot import analysis, readers, scene, theory

import matplotlib.pyplot as plt

Inputs = dict[str, list[dict[str, Any]]]
History = dict[str, np.ndarray]

#: Columns of the --experiment CSV file for each kind of scene.
EXPERIMENT_COLUMNS: dict[str, tuple[str, str]] = {
    "crush": ("displacement_m", "force_N"),
    "impact": ("time_s", "force_N"),
    "wave": ("angle_deg", "arrival_s"),
}

ENERGY_STYLE: dict[str, dict[str, Any]] = {
    "kinetic": {"color": "C0"},
    "strain": {"color": "C1"},
    "plastic": {"color": "C3"},
    "external": {"color": "k", "linestyle": "--"},
    "damped": {"color": "C7", "linestyle": ":"},
    "contact_loss": {"color": "C4", "linestyle": "-."},   # drawn only when not zero
}


def _text_box(ax: plt.Axes, lines: list[str], loc: str = "upper left") -> None:
    """A block of text in a corner of the axes."""
    x, ha = (0.02, "left") if "left" in loc else (0.98, "right")
    y, va = (0.97, "top") if "upper" in loc else (0.03, "bottom")
    ax.text(x, y, "\n".join(lines), transform=ax.transAxes, ha=ha, va=va, fontsize=8,
            bbox={"boxstyle": "round", "facecolor": "white", "alpha": 0.85, "linewidth": 0.5})


def _left_legend(ax: plt.Axes, title: str | None, loc: str = "upper left") -> None:
    """A legend whose title (a few lines of key numbers) is aligned left."""
    leg = ax.legend(loc=loc, title=title, title_fontsize=8)
    try:
        leg.set_alignment("left")            # matplotlib >= 3.6
    except AttributeError:
        leg._legend_box.align = "left"        # older matplotlib


def _fmt(x: float, spec: str = ".4g") -> str:
    """A number, or 'n/a' for NaN."""
    return "n/a" if x is None or not np.isfinite(x) else format(x, spec)


def _experiment(path: str | None, kind: str) -> tuple[np.ndarray, np.ndarray] | None:
    """The measured curve for this kind of scene, or None."""
    if not path:
        return None
    if kind not in EXPERIMENT_COLUMNS:
        print(f"note: --experiment is not used for a {kind} scene", file=sys.stderr)
        return None
    a, b = readers.read_experiment(path, EXPERIMENT_COLUMNS[kind])
    return a, b


class NoWallError(ValueError):
    """The scene's own plot needs a wall that the case does not have."""


def _ring(inputs: Inputs) -> dict[str, Any] | None:
    """Ring properties, or None when the case has no ring."""
    try:
        return scene.ring_properties(inputs)
    except ValueError:
        return None


def _section_crush(inputs: Inputs) -> bool:
    """A tube, honeycomb or walls body (the scene kinds are a ring's) with a moving wall."""
    shapes = {str(b.get("shape", "ring")).lower() for b in inputs.get("body", [])}
    moving = any(any(float(v) != 0.0 for v in np.atleast_1d(w.get("velocity", [0.0, 0.0])))
                 for w in inputs.get("wall", []))
    return bool(shapes & {"tube", "honeycomb", "walls"}) and moving


def _walls(inputs: Inputs, history: History) -> list[dict[str, Any]]:
    return scene.wall_table(inputs, readers.history_walls(history))


def _energy_lines(ax: plt.Axes, x: np.ndarray, history: History) -> None:
    for name, kw in ENERGY_STYLE.items():
        if name in history and (name != "contact_loss" or np.any(history[name] != 0.0)):
            ax.plot(x, history[name], label=name.replace("_", " "), **kw)


# ----------------------------------------------------------------------------------------------
# crush
# ----------------------------------------------------------------------------------------------

def plot_crush(history: History, inputs: Inputs, outdir: str, experiment: str | None,
               title: str) -> tuple[plt.Figure, list[str]]:
    """Platen force and energies vs platen displacement, with the closed forms."""
    walls = [w for w in _walls(inputs, history) if not w["mirror"]]
    disp, force, k = scene.crush_displacement(history, inputs)
    top = next(w for w in walls if w["index"] == k)
    ring = _ring(inputs)
    depth = scene.depth_of(inputs)
    drop = bool(_drop_weights(inputs))     # a drop's rebound: energies against time
    x2 = history["time"] * 1e3 if drop else disp * 1e3

    fig, (ax, ax2) = plt.subplots(1, 2, layout="constrained", figsize=(11.5, 4.6))
    role = "drop weight" if k in _drop_weights(inputs) else "moving platen"
    ax.plot(disp * 1e3, force * 1e-3, color="C0", label=f"MPM, wall {k} ({role})")
    for w in walls:
        if w is not top:
            j = w["index"]
            ax.plot(disp * 1e3, history[f"wall{j}_force"] * 1e-3,
                    color="C2", lw=0.8, alpha=0.7,
                    label=f"MPM, wall {j} ({'base' if drop else 'fixed platen'})")
    lines = [f"peak force {force.max() * 1e-3:.4g} kN at {disp[np.argmax(force)] * 1e3:.3g} mm"]
    numbers = [f"crush: moving platen = wall {k}, depth {depth:g} m",
               f"peak force        {force.max():.6g} N at displacement "
               f"{disp[np.argmax(force)] * 1e3:.4g} mm"]
    dmax = float(np.nanmax(disp)) if disp.size else 0.0
    nbody = len(inputs.get("body", []))
    if nbody > 1:                              # the closed forms are one tube's
        lines += ["no DeRuntz–Hodge or elastic ring curve: closed forms",
                  f"of a single tube, and this case has {nbody} bodies"]
        numbers.append(f"closed forms      left out: DeRuntz-Hodge and the elastic ring are "
                       f"for a single tube and the case has {nbody} bodies (the force of each "
                       f"pair and each body's energies: plots/plot_bodies.py --dir {outdir})")
    elif ring is not None and np.isfinite(ring["sigma_y"]) and dmax > 0:
        D, t, plane = ring["D"], ring["t"], ring["plane"]
        p0 = theory.plastic_collapse_load(D, t, ring["sigma_y"], plane, depth)
        d = np.linspace(0.0, min(dmax, 0.97 * D), 400)
        ax.plot(d * 1e3, theory.deruntz_hodge(d, D, t, ring["sigma_y"], plane, depth) * 1e-3,
                color="C3", ls="--",
                label=r"DeRuntz–Hodge $P_0/\sqrt{1-(\delta/D)^2}$"
                + f", $P_0$ = {p0 * 1e-3:.3g} kN")
        kel = theory.ring_elastic_stiffness(ring["R"], t, ring["E"], ring["nu"], plane, depth)
        de = np.linspace(0.0, min(dmax, 1.5 * p0 / kel), 50)
        ax.plot(de * 1e3, kel * de * 1e-3, color="C1", ls=":", lw=1.8,
                label=f"thin elastic ring $P = k\\delta$ (closed form), k = {kel * 1e-6:.3g} kN/mm")
        lo, hi = 0.1 * D, 0.3 * D
        sel = (disp >= lo) & (disp <= hi)
        if np.count_nonzero(sel) < 3:           # short stroke: second half of it
            sel = disp >= 0.5 * dmax
        plateau = float(np.mean(force[sel])) if np.any(sel) else float("nan")
        dh_plateau = float(np.mean(theory.deruntz_hodge(disp[sel], D, t, ring["sigma_y"],
                                                         plane, depth))) if np.any(sel) else \
            float("nan")
        rng = f"{disp[sel].min() * 1e3:.3g}–{disp[sel].max() * 1e3:.3g} mm" if np.any(sel) else ""
        lines += [f"plateau {plateau * 1e-3:.4g} kN (DeRuntz–Hodge {dh_plateau * 1e-3:.4g} kN) "
                  f"over {rng}",
                  f"plane {plane}, $\\sigma_0$ = {ring['sigma_y'] * 1e-6:.4g} MPa, "
                  f"D = {D * 1e3:.4g} mm, t = {t * 1e3:.4g} mm"]
        numbers += [f"plateau force     {plateau:.6g} N (mean over {rng})",
                    f"DeRuntz-Hodge     {dh_plateau:.6g} N over the same range; "
                    f"P0 = {p0:.6g} N (plane {plane})"]
        dW = theory.deruntz_hodge_energy(disp, D, t, ring["sigma_y"], plane, depth)
        ax2.plot(x2, dW, color="C3", ls="--", lw=1.0,
                 label=r"DeRuntz–Hodge $P_0\,D\,\arcsin(\delta/D)$")
    exp = _experiment(experiment, "crush")
    if exp is not None:
        ax.plot(exp[0] * 1e3, exp[1] * 1e-3, "o", ms=3, mfc="none", color="k",
                label="experiment")
    ax.set_xlabel(r"platen approach $\delta$ [mm]")
    ax.set_ylabel(f"platen force [kN] (depth {depth:g} m)")
    ax.set_title(f"{title}: force–displacement")
    ax.set_xlim(left=0.0)
    top_force = max(float(np.nanmax(force)), float(np.nanmax(ax.get_ylim()[1])) * 1e3)
    res = _results(outdir)
    support = float(res.get("support_peak_force", 0.0) or 0.0)
    if support > 0.0 and float(np.nanmax(force)) > 2.0 * support:   # the impact's inertia
        top_force = support                # (the run warns of it): the crush at a legible scale
        lines.append("the peak is off the scale: the struck face's inertia,\n"
                     "read support_cfe (docs/output.md#results)")
    ax.set_ylim(min(0.0, float(np.nanmin(force)) * 1e-3), 1.6 * top_force * 1e-3)
    _left_legend(ax, "\n".join(lines))

    _energy_lines(ax2, x2, history)
    for j in _drop_weights(inputs):
        if f"wall{j}_kinetic" in history:
            ax2.plot(x2, history[f"wall{j}_kinetic"], color="k", lw=1.4,
                     label=f"drop weight (wall {j}) kinetic")
    kin, pla = history.get("kinetic"), history.get("plastic")
    ratio_text = None
    if kin is not None and pla is not None and pla.size:
        big = pla > 0.01 * max(float(pla[-1]), 1e-300)
        ratio_end = kin[-1] / pla[-1] if pla[-1] > 0 else float("nan")
        ratio_max = float(np.max(kin[big] / pla[big])) if np.any(big) else float("nan")
        ratio_text = (f"kinetic / plastic: {_fmt(ratio_end, '.3g')} at the end,\n"
                      f"largest {_fmt(ratio_max, '.3g')} once plastic > 1 % of final\n"
                      "(quasi-static when ≪ 1)")
        numbers.append(f"kinetic/plastic   {_fmt(ratio_end, '.4g')} at the end, largest "
                       f"{_fmt(ratio_max, '.4g')}")
    if "plastic" in history:
        absorbed = float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(disp)))
        numbers.append(f"work on platen    {absorbed:.6g} J (integral of F d delta); plastic "
                       f"{history['plastic'][-1]:.6g} J")
    if res:
        metrics = (f"stroke {res['stroke'] * 1e3:.4g} mm, absorbed {res['absorbed_energy']:.4g} J\n"
                   f"mean force {res['mean_force'] * 1e-3:.4g} kN, CFE {res['cfe']:.3f}\n"
                   f"SEA {res['sea'] * 1e-3:.4g} kJ/kg (mass {res['mass']:.4g} kg)")
        if "impactor_rebound" in res:
            metrics += (f"\nimpactor: max stroke {res['impactor_max_stroke'] * 1e3:.4g} mm, "
                        f"rebound {res['impactor_rebound']:.4g} m/s")
            numbers.append(f"impactor          max stroke {res['impactor_max_stroke']:.6g} m, "
                           f"rebound {res['impactor_rebound']:.6g} m/s")
        if "support_peak_force" in res:
            metrics += (f"\nsupport: peak {res['support_peak_force'] * 1e-3:.4g} kN, "
                        f"CFE {res['support_cfe']:.3f}")
            numbers.append(f"support           peak {res['support_peak_force']:.6g} N, CFE "
                           f"{res['support_cfe']:.4g} (the base's load cell)")
        ratio_text = metrics if ratio_text is None else metrics + "\n" + ratio_text
        numbers.append(f"results           stroke {res['stroke']:.6g} m, peak {res['peak_force']:.6g} N, "
                       f"mean {res['mean_force']:.6g} N, CFE {res['cfe']:.4g}, absorbed "
                       f"{res['absorbed_energy']:.6g} J, SEA {res['sea']:.6g} J/kg, densification "
                       f"{res['densification_stroke']:.6g} m (summary.nml &results)")
    ax2.set_xlabel("time [ms]" if drop else r"platen approach $\delta$ [mm]")
    ax2.set_ylabel(f"energy [J] (depth {depth:g} m)")
    ax2.set_title("energies")
    ax2.set_xlim(left=0.0)
    _left_legend(ax2, ratio_text)
    return fig, numbers


def _drop_weights(inputs: Inputs) -> list[int]:
    """The walls with mass (drop weights), 1-based as in history.csv."""
    return [k for k, w in enumerate(inputs.get("wall", []), start=1)
            if float(w.get("mass", 0.0) or 0.0) > 0.0]


def _results(outdir: str) -> dict[str, Any]:
    """summary.nml's &results of the run ({} when absent or unreadable)."""
    try:
        return readers.read_results(os.path.join(outdir, "summary.nml"))
    except (OSError, ValueError):
        return {}


# ----------------------------------------------------------------------------------------------
# impact
# ----------------------------------------------------------------------------------------------

def _total_mass(outdir: str, inputs: Inputs) -> float:
    """Mass of the full structure for depth [kg] from the first snapshot (NaN if unreadable)."""
    h5 = os.path.join(outdir, "particles.h5")
    try:
        frame = readers.read_frame(h5, 0)
    except (OSError, KeyError, ValueError, IndexError, ImportError):
        return float("nan")
    return float(np.sum(frame["mass"])) * scene.depth_of(inputs) * scene.sector_factor(inputs)


def plot_impact(history: History, inputs: Inputs, outdir: str, experiment: str | None,
                title: str) -> tuple[plt.Figure, list[str]]:
    """Target force and centre-of-mass velocity vs time, contact phases, rebound, COR."""
    walls = [w for w in _walls(inputs, history) if not w["mirror"]]
    if not walls:
        raise NoWallError("impact plot: no target wall in the case")
    static = [w for w in walls if not w["moving"]] or walls
    target = max(static, key=lambda w: float(np.nanmax(history[f"wall{w['index']}_force"])))
    k = target["index"]
    n = target["normal"]
    t = history["time"]
    f = history[f"wall{k}_force"]
    vn = history["com_vx"] * n[0] + history["com_vy"] * n[1]
    ph = analysis.contact_phases(t, f, away=vn > 0.0)
    v_imp = analysis.impact_velocity(history, k, n, ph)
    v_reb = analysis.rebound_velocity(history, k, n, ph)
    cor = v_reb / v_imp if v_imp != 0 else float("nan")
    mass = _total_mass(outdir, inputs)
    depth = scene.depth_of(inputs)
    ms = 1e3

    fig, (ax, ax2) = plt.subplots(1, 2, layout="constrained", figsize=(11.5, 4.6))
    ax.plot(t * ms, f * 1e-3, color="C0", label=f"MPM, wall {k} (target)")
    exp = _experiment(experiment, "impact")
    if exp is not None:
        ax.plot(exp[0] * ms, exp[1] * 1e-3, "o", ms=3, mfc="none", color="k", label="experiment")
    if np.isfinite(ph["start"]):
        end = ph["end"] if ph["ended"] else t[-1]
        ax.axvspan(ph["start"] * ms, end * ms, color="C1", alpha=0.12, label="first contact")
        ax.axvline(ph["start"] * ms, color="C1", ls="--", lw=1.0)
        if ph["ended"]:
            ax.axvline(ph["end"] * ms, color="C1", ls="--", lw=1.0)
        ax.plot(ph["peak_time"] * ms, ph["peak"] * 1e-3, "v", color="C3", ms=6,
                label=f"peak {ph['peak'] * 1e-3:.4g} kN")
    def unit(x: float, spec: str, u: str) -> str:
        return "n/a" if not np.isfinite(x) else f"{format(x, spec)} {u}"

    if ph["ended"]:
        contact = (f"contact {ph['start'] * ms:.4g} – {ph['end'] * ms:.4g} ms, "
                   f"duration {ph['duration'] * ms:.4g} ms")
    elif np.isfinite(ph["start"]):
        contact = f"contact from {ph['start'] * ms:.4g} ms to beyond the end of the record"
    else:
        contact = "no contact"
    lines = [contact,
             f"impulse $\\int F\\,dt$ = {unit(ph['impulse'], '.4g', 'N s')}",
             f"$V_{{impact}}$ = {unit(v_imp, '.4g', 'm/s')}, "
             f"$V_{{rebound}}$ = {unit(v_reb, '.4g', 'm/s')}",
             f"COR = $V_{{rebound}}/V_{{impact}}$ = {_fmt(cor, '.3f')}"]
    numbers = [f"impact: target = wall {k}, normal ({n[0]:g}, {n[1]:g}), depth {depth:g} m",
               f"peak force        {_fmt(ph['peak'], '.6g')} N at {_fmt(ph['peak_time'], '.6g')} s",
               f"contact           start {_fmt(ph['start'], '.6g')} s, end "
               f"{_fmt(ph['end'], '.6g')} s, duration {_fmt(ph['duration'], '.6g')} s"
               + ("" if ph["ended"] or not np.isfinite(ph["start"]) else
                  " (contact lasts beyond the record)"),
               f"impact velocity   {_fmt(v_imp, '.6g')} m/s",
               f"rebound velocity  {_fmt(v_reb, '.6g')} m/s",
               f"COR               {_fmt(cor, '.4f')}",
               f"impulse           {_fmt(ph['impulse'], '.6g')} N s"]
    if np.isfinite(mass) and np.isfinite(v_reb):
        dp = mass * (v_imp + v_reb)
        lines.append(f"m($V_i$+$V_r$) = {dp:.4g} N s (m = {mass:.4g} kg)")
        numbers.append(f"momentum change   {dp:.6g} N s = m (V_impact + V_rebound), "
                       f"m = {mass:.6g} kg; impulse/change = {ph['impulse'] / dp:.4f}")
    _text_box(ax, lines, "upper right")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel(f"force on the target [kN] (depth {depth:g} m)")
    ax.set_title(f"{title}: target force")
    ax.legend(loc="center right")

    ax2.plot(t * ms, vn, color="C0", lw=1.8, label="along the target normal $v\\cdot n$")
    ax2.plot(t * ms, history["com_vx"], color="C2", lw=0.9, label="$v_x$")
    ax2.plot(t * ms, history["com_vy"], color="C4", lw=0.9, ls="--", label="$v_y$")
    ax2.axhline(-v_imp, color="0.4", ls=":", lw=1.0)
    if np.isfinite(v_reb):
        ax2.axhline(v_reb, color="C3", ls=":", lw=1.0, label=f"rebound {v_reb:.4g} m/s")
    if np.isfinite(ph["start"]):
        ax2.axvspan(ph["start"] * ms, (ph["end"] if ph["ended"] else t[-1]) * ms, color="C1",
                    alpha=0.12)
    ax2.set_xlabel("time [ms]")
    ax2.set_ylabel("centre-of-mass velocity [m/s]")
    ax2.set_title("centre-of-mass velocity")
    ax2.legend(loc="best")
    return fig, numbers


# ----------------------------------------------------------------------------------------------
# wave
# ----------------------------------------------------------------------------------------------

def probe_angles(history: History, inputs: Inputs) -> tuple[np.ndarray, int, np.ndarray]:
    """(angle of each probe from the struck point [deg], struck probe index (0-based),
    ring centre [m]).

    Angles are measured at the ring centre between the probes' initial positions. The struck
    point is the probe nearest the moving wall (a wall with a velocity or a motion table), or
    probe 1 without one.
    """
    nprobe = readers.history_probes(history)
    pos = np.array([[history[f"probe{j + 1}_x"][0], history[f"probe{j + 1}_y"][0]]
                    for j in range(nprobe)])
    ring = _ring(inputs)
    centre = ring["center"] if ring is not None else pos.mean(axis=0)
    walls = [w for w in _walls(inputs, history) if not w["mirror"] and (w["moving"] or w["table"])]
    struck = 0
    if walls:
        w = walls[0]
        dist = np.abs((pos - w["point"]) @ w["normal"])
        struck = int(np.argmin(dist))
    r = pos - centre
    r0 = r[struck]
    cosang = (r @ r0) / (np.linalg.norm(r, axis=1) * np.linalg.norm(r0))
    return np.degrees(np.arccos(np.clip(cosang, -1.0, 1.0))), struck, centre


def plot_wave(history: History, inputs: Inputs, outdir: str, experiment: str | None,
              title: str, threshold: float = 0.1) -> tuple[plt.Figure, list[str]]:
    """Probe velocity disturbances vs time and arrival time vs angle from the struck point."""
    nprobe = readers.history_probes(history)
    if nprobe == 0:
        raise ValueError("wave plot: the history has no probe columns")
    t = history["time"]
    us = 1e6
    dist = analysis.probe_disturbance(history)
    arrival = np.atleast_1d(analysis.arrival_times(t, dist, threshold))
    angles, struck, _ = probe_angles(history, inputs)
    ring = _ring(inputs)

    fig, (ax, ax2) = plt.subplots(1, 2, layout="constrained", figsize=(11.5, 5.0))
    cmap = plt.get_cmap("viridis")
    order = np.argsort(angles, kind="stable")
    ticks, labels = [], []
    for row, j in enumerate(order):
        peak = float(np.max(dist[:, j])) if dist.size else 0.0
        y = dist[:, j] / peak if peak > 0 else dist[:, j]
        color = cmap(row / max(nprobe - 1, 1) * 0.9)
        ax.plot(t * us, row + 0.8 * y, color=color, lw=1.0)
        if np.isfinite(arrival[j]):
            ax.plot(arrival[j] * us, row + 0.8 * threshold, "o", color="C3", ms=4,
                    label="arrival" if row == 0 else None)
        ticks.append(row)
        labels.append(f"p{j + 1} {angles[j]:.0f}°\n{peak:.2g} m/s")
    ax.set_yticks(ticks, labels, fontsize=7)
    ax.set_xlabel("time [µs]")
    ax.set_ylabel(r"probe: $|v - v(0)|$ / its peak (offset), peak given")
    ax.set_title(f"{title}: probe velocity disturbance (arrival at {threshold:g} × peak)")
    ax.set_ylim(-0.2, nprobe + 0.1)
    ax.legend(loc="lower right")

    ax2.plot(angles, arrival * us, "o", color="C0", label="MPM arrival")
    for j in range(nprobe):
        ax2.annotate(f"p{j + 1}", (angles[j], arrival[j] * us), textcoords="offset points",
                     xytext=(4, -10), fontsize=7)
    numbers = [f"wave: struck point = probe {struck + 1}, threshold {threshold:g} of each peak",
               "probe  angle[deg]  arrival[s]     peak|v-v0|[m/s]"]
    for j in range(nprobe):
        numbers.append(f"{j + 1:5d}  {angles[j]:10.2f}  {_fmt(arrival[j], '12.5e'):>12}  "
                       f"{np.max(dist[:, j]):.4g}")
    if ring is not None and np.isfinite(ring["E"]) and np.isfinite(ring["rho"]):
        R = ring["R"]
        t0 = arrival[struck] if np.isfinite(arrival[struck]) else 0.0
        th = np.linspace(0.0, 180.0, 200)
        speeds = {"bar": theory.bar_speed(ring["E"], ring["rho"]),
                  "plate": theory.plate_speed(ring["E"], ring["nu"], ring["rho"])}
        for (name, c), ls in zip(speeds.items(), ("--", ":")):
            ax2.plot(th, (t0 + R * np.radians(th) / c) * us, color="C3" if name == "bar" else "C1",
                     ls=ls, label=f"$t_0 + R\\theta/c$, {name} c = {c:.0f} m/s")
        numbers.append(f"theory: R = {R:.6g} m, t0 = {t0:.6g} s (arrival at the struck point), "
                       f"bar c = {speeds['bar']:.6g} m/s, plate c = {speeds['plate']:.6g} m/s")
        fit = np.isfinite(arrival) & (angles > 1.0)
        if np.count_nonzero(fit) >= 2:
            s = R * np.radians(angles[fit])
            slope, _ = np.polyfit(s, arrival[fit], 1)
            if slope > 0:
                numbers.append(f"apparent speed    {1.0 / slope:.6g} m/s (fit of arrival vs "
                               f"R theta)")
    exp = _experiment(experiment, "wave")
    if exp is not None:
        ax2.plot(exp[0], exp[1] * us, "s", ms=4, mfc="none", color="k", label="experiment")
    ax2.set_xlabel("angle from the struck point [deg]")
    ax2.set_ylabel("arrival time [µs]")
    ax2.set_xlim(0.0, 185.0)
    ax2.set_ylim(bottom=0.0)
    ax2.set_title("arrival time around the ring")
    ax2.legend(loc="upper left")
    return fig, numbers


# ----------------------------------------------------------------------------------------------
# generic
# ----------------------------------------------------------------------------------------------

def plot_generic(history: History, inputs: Inputs, outdir: str, experiment: str | None,
                 title: str) -> tuple[plt.Figure, list[str]]:
    """Energies vs time."""
    t = history["time"]
    scale, unit = (1e3, "ms") if t[-1] >= 1e-3 else (1e6, "µs")
    fig, ax = plt.subplots(layout="constrained", figsize=(7.0, 4.6))
    _energy_lines(ax, t * scale, history)
    if all(k in history for k in ("kinetic", "strain", "plastic", "external")):
        damped = history.get("damped", np.zeros_like(t))
        loss = history.get("contact_loss", np.zeros_like(t))
        total = history["kinetic"] + history["strain"] + history["plastic"] + damped + loss
        ax.plot(t * scale, total - history["external"], color="C5", lw=1.0,
                label="kinetic + strain + plastic + damped + contact loss − external")
    ax.set_xlabel(f"time [{unit}]")
    ax.set_ylabel(f"energy [J] (depth {scene.depth_of(inputs):g} m)")
    ax.set_title(f"{title}: energies")
    ax.legend(loc="best")
    numbers = [f"generic: {len(t)} rows to t = {t[-1]:.6g} s"]
    for k in ENERGY_STYLE:
        if k in history:
            numbers.append(f"{k:9s} at the end {history[k][-1]:.6g} J, largest "
                           f"{np.max(history[k]):.6g} J")
    return fig, numbers


PLOTTERS = {"crush": plot_crush, "impact": plot_impact, "wave": plot_wave,
            "generic": plot_generic}


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """Command line."""
    p = argparse.ArgumentParser(
        description="Plot a tubempm run (crush, impact, wave or generic) against the closed "
                    "forms; prints the key numbers.",
        epilog="experiment CSV columns (header line, SI units, forces for the run's depth): "
               "crush displacement_m,force_N; impact time_s,force_N; wave angle_deg,arrival_s")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--case", metavar="FILE.nml", help="the case file (its output folder is "
                     "the &run output_dir, or out/<title>)")
    src.add_argument("--dir", metavar="OUTDIR", help="the output folder of a run")
    p.add_argument("--out", metavar="PNG", help="output image (default <outdir>/<kind>.png)")
    p.add_argument("--experiment", metavar="CSV", help="measured curve to overlay")
    p.add_argument("--kind", choices=sorted(PLOTTERS), help="override the detected scene kind")
    p.add_argument("--threshold", type=float, default=0.1,
                   help="wave: arrival when |v - v(0)| exceeds this fraction of its peak "
                        "(default 0.1)")
    return p.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    """Read the run, draw the plot for its kind of scene, print the key numbers."""
    args = parse_args(argv)
    try:
        outdir, inputs = scene.resolve_case(args.case, args.dir)
        history = readers.read_history(os.path.join(outdir, "history.csv"))
    except (OSError, ValueError) as exc:
        print(f"ERROR [plot_case]: {exc}", file=sys.stderr)
        return 2
    if history["time"].size < 2:
        print(f"ERROR [plot_case]: {outdir}/history.csv has fewer than two rows; nothing to plot",
              file=sys.stderr)
        return 2
    try:
        kind = args.kind or scene.scene_kind(outdir, args.case)
    except (OSError, ValueError, subprocess.SubprocessError) as exc:
        print(f"ERROR [plot_case]: the kind of scene: {exc}; or give --kind", file=sys.stderr)
        return 2
    if kind == "wave" and not args.kind and readers.history_probes(history) == 0:
        kind = "generic"                       # a platen pulse without probes: energies
    failure = readers.run_failure(outdir)
    run = (inputs.get("run") or [{}])[0]
    title = str(run.get("title") or os.path.basename(os.path.normpath(outdir)))
    plotter = PLOTTERS[kind]
    if kind == "impact" and not args.kind and _drop_weights(inputs):
        plotter = plot_crush                   # a drop test: force and energy vs the approach
    if kind == "generic" and not args.kind and _section_crush(inputs):
        kind, plotter = "crush", plot_crush    # a section between platens (no ring theory)
    kwargs = {"threshold": args.threshold} if kind == "wave" else {}
    try:
        try:
            fig, numbers = plotter(history, inputs, outdir, args.experiment, title, **kwargs)
        except NoWallError as exc:
            if args.kind:                      # --kind asked for this plot: the error stands
                raise
            nbody = len([c for c in history if re.fullmatch(r"body\d+_x", c)])
            print(f"note: {exc}; the generic plot instead"
                  + (f" (forces and energies per body: plots/plot_bodies.py --dir {outdir})"
                     if nbody > 1 else ""))
            kind = "generic"
            fig, numbers = plot_generic(history, inputs, outdir, args.experiment, title)
    except (OSError, ValueError, KeyError) as exc:
        print(f"ERROR [plot_case]: {kind} plot of {outdir}: {exc}", file=sys.stderr)
        return 2
    out = args.out or os.path.join(outdir, f"{kind}.png")
    if failure:
        style.mark_failed(fig, failure)
    fig.savefig(out, dpi=style.DPI)
    plt.close(fig)
    weight = " (a drop weight)" if kind == "crush" and _drop_weights(inputs) else ""
    print(f"{title}: {kind} scene{weight}, {history['time'].size} history rows, t_end "
          f"{history['time'][-1]:.6g} s")
    if failure:
        print(f"  {failure}")
    for line in numbers:
        print("  " + line)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
