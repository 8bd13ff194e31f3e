#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The stability study (issue 7, ``make stability``): where each method breaks.

Six parts, each a batch of tubempm runs (tools/batch.py, one thread, one run at a time) on
cheap variants of the shipped scenes (namelists/impact.nml, crush.nml), set by overrides:

  cfl       largest stable cfl per basis x scheme on the impact scene: a scan of cfl values,
            then bisection between the last stable and the first unstable one; "stable" =
            the run completes, no failure detected, energy error < 5 %
  noise     cell-crossing noise of the crush force (RMS of the force minus its 20 us moving
            average, relative to the plateau) against particles per cell, every basis
  thinwall  crush force error against DeRuntz-Hodge as h/t goes from 1/4 to 2, every basis;
            and a near-full crush and release of a half ring with both platens (the inner
            walls meet): for h >= t they interact through shared nodes before they touch
  nthick    particles through the wall n_t = 1..32 (CPDI2, n_circ fixed)
  distort   CPDI1 and CPDI2 domains at deep crush (delta/D up to 0.8): distortion over time
            and where domains fold or invert
  flip      FLIP against PIC in an elastic impact: force noise against the energy lost

Results: one table per part, plus the time series the figures need, in docs/stability/ for
the full level (the committed study) and out/stability-quick/ for the quick level, or --out;
the figures are drawn from them by plots/plot_stability.py (``make stability`` runs both).
Run folders: build/stability/<case>/ (reused when the input is unchanged, so an interrupted
study continues where it stopped).

    python3 -m tools.stability                # quick level (< 10 min on one core)
    python3 -m tools.stability --level full   # full level, into docs/stability/
    python3 -m tools.stability --backend slurm --partition short   # each batch a Slurm job
                                              # array, waited for (docs/batch.md)
    python3 -m plots.plot_stability --level full   # the figures again from the tables
"""
from __future__ import annotations

import argparse
import csv
import math
import re
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from tools import batch
from tools.batch import Case, run_batch, read_summary
from plots.mpmplot import analysis, namelist, readers, scene, theory

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

RUNS = ROOT / "build" / "stability"
DOCS = ROOT / "docs" / "stability"       #: tables of the full level (the committed study)
QUICK = ROOT / "out" / "stability-quick"  #: tables of the quick level
OUT = QUICK                              #: where write_csv writes (set by main)
CRUSH = ROOT / "namelists" / "crush.nml"
IMPACT = ROOT / "namelists" / "impact.nml"

BASES = ("linear", "ugimp", "cpdi1", "cpdi2")
SCHEMES = ("usl", "usf", "musl")
T_CRUSH = 1.48e-3          #: wall thickness of crush.nml [m]
T_IMPACT = 2.0e-3          #: wall thickness of impact.nml [m]
D_CRUSH = 50.86e-3         #: outer diameter of crush.nml [m]
ENERGY_OK = 0.05           #: stable: energy error below this [-]
SMOOTH = 20.0e-6           #: moving-average window of the smoothed force [s]
HIST = 1.0e-6              #: history interval of the noise measurements [s]
PLATEAU = (4.0e-3, 13.0e-3)  #: crush approach window of the plateau [m]
TEST_WINDOW = (3.0e-3, 5.0e-3)  #: approach window of the noise test in make test [m]
TEST_T_END = 0.77e-3       #: end of the noise test's runs (approach 5.2 mm) [s]
TEST_CFL = 0.4             #: cfl of the noise test's runs (stable: cfl_limits_ppc2.csv) [-]
NOISY = 0.25               #: crush: force noise above this is "noisy" [-]
NOISY_IMPACT = 0.15        #: impact: force noise above this is "noisy" [-]
WRONG = 0.10               #: crush: plateau error against DeRuntz-Hodge above this is "wrong"

LEVELS: dict[str, dict[str, Any]] = {
    "quick": {
        "cfl_configs": ((1.0e-3, 4),), "cfl_bisect": 2,
        "noise_nt": (2, 4), "thin_h": (0.5, 1.0, 2.0), "thin_nt": 4,
        "stick_h": (0.5, 1.0, 2.0), "nthick": (1, 2, 4, 8), "distort_nt": (2,),
        "fast_nt": (2, 4),
        "flip": (0.0, 0.9, 0.99, 0.999, 1.0),
    },
    "full": {
        "cfl_configs": ((1.0e-3, 4), (0.5e-3, 4)), "cfl_bisect": 3,
        "noise_nt": (2, 4, 8), "thin_h": (0.25, 0.5, 1.0, 1.5, 2.0), "thin_nt": 4,
        "stick_h": (0.5, 1.0, 2.0), "nthick": (1, 2, 4, 8, 16, 32), "distort_nt": (2, 4),
        "fast_nt": (2, 4, 8),
        "flip": (0.0, 0.5, 0.9, 0.99, 0.999, 1.0),
    },
}
CFL_SCAN = (0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0)


def say(msg: str) -> None:
    print(msg, flush=True)


# ----------------------------------------------------------------------------------------------
# helpers
# ----------------------------------------------------------------------------------------------

def fmt(x: float) -> str:
    """A number for a case name (no dots or signs that confuse a shell)."""
    return f"{x:g}".replace(".", "p").replace("-", "m")


#: where the runs go: None = local processes, one at a time; or a batch.Slurm (set by main)
BACKEND: batch.Slurm | None = None


def batch_run(cases: list[Case]) -> list[dict[str, Any]]:
    """Run ``cases`` (one thread each) and return their results; on Slurm, stop the study
    where a run did not end on its own, since each part's next runs depend on these."""
    res = run_batch(cases, RUNS, jobs=1, threads=1, log=say, backend=BACKEND)
    if BACKEND is not None and BACKEND.dry_run:
        raise SystemExit("dry run: the script of the first batch only (the later batches "
                         "depend on its results)")
    lost = [r["name"] for r in res if r.get("exit_code") is None]
    if lost:
        raise SystemExit(f"{len(lost)} runs did not end on their own (cancelled, or out of "
                         f"time), e.g. {lost[0]}; run the study again to re-run them")
    return res


def run_reason(folder: Path, summary: dict[str, Any], exit_code: int | None) -> str:
    """Short reason of a failed run: the cause named in the ERROR line."""
    if exit_code == 0:
        return ""
    msg = str(summary.get("message", ""))
    if not msg:
        log = folder / "run.log"
        msg = log.read_text(errors="replace") if log.is_file() else ""
    low = msg.lower()
    for key, short in (("energy growth", "energy growth"), ("energy blow-up", "energy growth"),
                       ("det f", "det F <= 0"),
                       ("folded", "folded domain"), ("left the grid", "left grid"),
                       ("non-finite", "non-finite"), ("did not converge", "return map"),
                       ("not positive", "dt <= 0")):
        if key in low:
            return short
    return f"exit {exit_code}"


smooth = analysis.moving_average


def common(result: dict[str, Any], folder: Path) -> dict[str, Any]:
    s = read_summary(folder)
    code = result.get("exit_code")
    return {"exit_code": code, "status": s.get("status", ""),
            "reason": run_reason(folder, s, code), "steps": s.get("steps", 0),
            "sim_time": s.get("sim_time", float("nan")),
            "energy_error": s.get("energy_error", float("nan")),
            "cpu_s": round(float(result.get("cpu_s", float("nan"))), 2),
            "min_corner_jacobian": s.get("min_corner_jacobian", float("nan"))}


def crush_metrics(folder: Path) -> dict[str, Any]:
    """Plateau force, its error against DeRuntz-Hodge and the force noise of a crush run."""
    out = {"plateau_N": float("nan"), "err_dh": float("nan"), "noise": float("nan"),
           "delta_max": float("nan")}
    try:
        h = readers.read_history(folder / "history.csv")
        inputs = namelist.read_namelist(folder / "input.nml")
    except (OSError, ValueError):
        return out
    disp, force, _ = scene.crush_displacement(h, inputs)
    out["delta_max"] = float(np.nanmax(disp)) if disp.size else float("nan")
    dt_row = float(np.median(np.diff(h["time"]))) if len(h["time"]) > 2 else HIST
    fs = smooth(force, round(SMOOTH / dt_row) + 1)
    sel = (disp >= PLATEAU[0]) & (disp <= PLATEAU[1])
    if np.count_nonzero(sel) < 10 or not np.all(np.isfinite(force[sel])):
        return out
    ring = scene.ring_properties(inputs)
    dh = theory.deruntz_hodge(disp[sel], ring["D"], ring["t"], ring["sigma_y"],
                               ring["plane"], ring["depth"])
    plateau = float(np.mean(fs[sel]))
    out.update(plateau_N=plateau, err_dh=plateau / float(np.mean(dh)) - 1.0,
               noise=float(np.sqrt(np.mean((force[sel] - fs[sel]) ** 2)) / plateau))
    out["noise_test_window"] = force_noise(disp, force, TEST_WINDOW, dt_row)
    return out


def force_noise(disp: np.ndarray, force: np.ndarray, window: tuple[float, float],
                dt_row: float) -> float:
    """RMS of the force minus its SMOOTH moving average, over the approach window, relative to
    the mean of the smoothed force there (tests/test_stability.py uses the same function)."""
    fs = smooth(force, round(SMOOTH / dt_row) + 1)
    sel = (disp >= window[0]) & (disp <= window[1])
    if np.count_nonzero(sel) < 10:
        return float("nan")
    return float(np.sqrt(np.mean((force[sel] - fs[sel]) ** 2)) / np.mean(fs[sel]))


def crush_outcome(row: dict[str, Any]) -> str:
    if row["exit_code"] != 0:
        return "failed"
    if not (abs(row["err_dh"]) <= WRONG) or not (row["energy_error"] < ENERGY_OK):
        return "wrong"
    if row["noise"] > NOISY:
        return "noisy"
    return "accurate"


def folder_of(level: str) -> Path:
    """Folder of the tables of a level: docs/stability/ (full) or out/stability-quick/."""
    return DOCS if level == "full" else QUICK


def write_csv(name: str, rows: list[dict[str, Any]]) -> Path:
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / name
    keys: list[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with path.open("w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    say(f"wrote {path}")
    return path


def read_csv(name: str, folder: Path | None = None) -> list[dict[str, Any]]:
    """A table of the study ([] when missing), from folder (default docs/stability/)."""
    path = (DOCS if folder is None else Path(folder)) / name
    if not path.is_file():
        return []
    rows = []
    with path.open() as f:
        for r in csv.DictReader(f):
            row: dict[str, Any] = {}
            for k, v in r.items():
                try:
                    row[k] = int(v)
                except (TypeError, ValueError):
                    try:
                        row[k] = float(v)
                    except (TypeError, ValueError):
                        row[k] = v
            rows.append(row)
    return rows


# ----------------------------------------------------------------------------------------------
# 1. largest stable cfl (impact)
# ----------------------------------------------------------------------------------------------

def impact_overrides(h: float, nt: int) -> dict[str, Any]:
    return {"grid.h": h, "body.n_thick": nt, "run.t_end": 4.0e-4,
            "run.history_every": HIST, "run.snapshot_every": 0.0}


def ppc_tag(h: float, nt: int) -> str:
    """'ppc2' for 2 particles per cell through the impact ring's wall (n_t h / t)."""
    return f"ppc{fmt(nt * h / T_IMPACT)}"


def impact_metrics(folder: Path) -> dict[str, Any]:
    out = {"impulse": float("nan"), "noise": float("nan")}
    try:
        h = readers.read_history(folder / "history.csv")
    except (OSError, ValueError):
        return out
    t, f = h["time"], h["wall1_force"]
    if len(t) < 30 or not np.all(np.isfinite(f)):
        return out
    out["impulse"] = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t)))
    dt_row = float(np.median(np.diff(t)))
    fs = smooth(f, round(SMOOTH / dt_row) + 1)
    on = f > 0.05 * np.max(f)
    if np.count_nonzero(on) > 20:
        i0 = int(np.argmax(on)) + round(SMOOTH / dt_row)      # past the first impact spike
        sel = np.zeros_like(on)
        sel[i0:] = True
        sel &= fs > 0.05 * np.max(f)
        if np.count_nonzero(sel) > 10:
            out["noise"] = float(np.sqrt(np.mean((f[sel] - fs[sel]) ** 2)) / np.mean(fs[sel]))
    return out


def part_cfl(lv: dict[str, Any]) -> None:
    """Scan, then bisect, the cfl of every basis x scheme on the impact scene, at each
    resolution of the level."""
    for h, nt in lv["cfl_configs"]:
        cfl_config(lv, h, nt)


def cfl_config(lv: dict[str, Any], h: float, nt: int) -> None:
    base = impact_overrides(h, nt)
    tag = f"h{fmt(h * 1e3)}_nt{nt}"
    ppc = ppc_tag(h, nt)
    rows: dict[tuple[str, str, float], dict[str, Any]] = {}

    def case(b: str, s: str, cfl: float) -> Case:
        ov = dict(base, **{"solver.basis": b, "solver.scheme": s, "run.cfl": cfl})
        return Case(f"cfl_{tag}_{b}_{s}_{fmt(cfl)}", IMPACT, ov,
                    {"basis": b, "scheme": s, "cfl": cfl})

    def run(cases: list[Case]) -> None:
        for c, r in zip(cases, batch_run(cases)):
            folder = RUNS / c.name
            row = {"basis": c.labels["basis"], "scheme": c.labels["scheme"],
                   "cfl": c.labels["cfl"], "h_over_t": h / T_IMPACT,
                   "n_thick": nt, "scan": int(c.labels["cfl"] in CFL_SCAN)}
            row.update(common(r, folder))
            row.update(impact_metrics(folder))
            row["stable"] = int(row["exit_code"] == 0 and row["energy_error"] < ENERGY_OK)
            rows[(row["basis"], row["scheme"], row["cfl"])] = row

    combos = [(b, s) for b in BASES for s in SCHEMES]
    run([case(b, s, c) for c in CFL_SCAN for b, s in combos])
    brackets = {}
    for b, s in combos:
        ok = [c for c in CFL_SCAN if rows[(b, s, c)]["stable"]]
        bad = [c for c in CFL_SCAN if not rows[(b, s, c)]["stable"]]
        lo = max([c for c in ok if not bad or c < min(bad)], default=0.0)
        hi = min(bad, default=None)
        brackets[(b, s)] = [lo, hi]
    for _ in range(lv["cfl_bisect"]):
        todo = []
        for (b, s), (lo, hi) in brackets.items():
            # no stable cfl in the scan: the method is not stable on this scene (USL with
            # linear weights) or too inaccurate at any cfl; only the full level looks lower
            if hi is not None and (lo > 0.0 or (lv["cfl_bisect"] > 2 and hi > 0.2)):
                todo.append(case(b, s, round(0.5 * (lo + hi), 6)))
        run(todo)
        for c in todo:
            key = (c.labels["basis"], c.labels["scheme"])
            if rows[(key[0], key[1], c.labels["cfl"])]["stable"]:
                brackets[key][0] = c.labels["cfl"]
            else:
                brackets[key][1] = c.labels["cfl"]
    # reference impulse: the median over the runs at the smallest cfl that completed with an
    # energy error under 5 % (one method's own error does not become the reference)
    ref = float(np.median([r["impulse"] for (b, s, c), r in rows.items()
                           if c == CFL_SCAN[0] and r["stable"]]))
    out = []
    for key in sorted(rows, key=lambda k: (BASES.index(k[0]), SCHEMES.index(k[1]), k[2])):
        r = rows[key]
        r["impulse_err"] = r["impulse"] / ref - 1.0 if r["exit_code"] == 0 else float("nan")
        if r["exit_code"] != 0:
            r["outcome"] = "failed"
        elif not (r["energy_error"] < ENERGY_OK) or not (abs(r["impulse_err"]) < 0.05):
            r["outcome"] = "wrong"
        elif r["noise"] > NOISY_IMPACT:
            r["outcome"] = "noisy"
        else:
            r["outcome"] = "accurate"
        out.append(r)
    write_csv(f"cfl_runs_{ppc}.csv", out)
    limits = []
    for (b, s), (lo, hi) in brackets.items():
        mine = sorted((c, r) for (bb, ss, c), r in rows.items() if (bb, ss) == (b, s))
        first_fail = min((c for c, r in mine if r["exit_code"] != 0), default=float("nan"))
        no_fail = max((c for c, r in mine if r["exit_code"] == 0 and not c > first_fail),
                      default=0.0)
        limits.append({"basis": b, "scheme": s, "stable_cfl": lo,
                       "unstable_cfl": hi if hi is not None else float("nan"),
                       "completes_cfl": no_fail, "caught_cfl": first_fail,
                       "first_failure": next((rows[(b, s, c)]["reason"] or "energy error "
                                              f"{rows[(b, s, c)]['energy_error']:.3f}"
                                              for c in sorted(c for (bb, ss, c) in rows
                                                              if (bb, ss) == (b, s))
                                              if not rows[(b, s, c)]["stable"]), "")})
    write_csv(f"cfl_limits_{ppc}.csv", limits)


# ----------------------------------------------------------------------------------------------
# 2.-4. crush: noise against particles per cell, thin-wall limit, particles through the wall
# ----------------------------------------------------------------------------------------------

def crush_case(basis: str, h_over_t: float, nt: int, t_end: float = 1.75e-3,
               n_circ: int = 0, extra: dict[str, Any] | None = None, prefix: str = "crush",
               base: Path = CRUSH) -> Case:
    ov = {"grid.h": h_over_t * T_CRUSH, "body.n_thick": nt, "body.n_circ": n_circ,
          "solver.basis": basis, "run.t_end": t_end, "run.history_every": HIST,
          "run.snapshot_every": 0.0, "wall[1].velocity": (0.0, -5.0), "wall[1].stroke": 0.0}
    if extra:
        ov.update(extra)
    name = f"{prefix}_{basis}_h{fmt(h_over_t)}_nt{nt}" + (f"_nc{n_circ}" if n_circ else "")
    return Case(name, base, ov, {"basis": basis, "h_over_t": h_over_t, "n_thick": nt,
                                 "n_circ": n_circ})


def crush_rows(cases: list[Case], part: str) -> list[dict[str, Any]]:
    rows = []
    for c, r in zip(cases, batch_run(cases)):
        folder = RUNS / c.name
        row = {"part": part, "case": c.name, **c.labels}
        ppc_t = c.labels["n_thick"] * c.labels["h_over_t"]   # particles per cell through the wall
        row["ppc_wall"] = ppc_t
        row.update(common(r, folder))
        row.update(crush_metrics(folder))
        row["outcome"] = crush_outcome(row)
        rows.append(row)
    return rows


def part_crush(lv: dict[str, Any]) -> None:
    """Noise against particles per cell and the h/t sweep, every basis (MUSL)."""
    cases = []
    for nt in lv["noise_nt"]:
        for b in BASES:
            cases.append(crush_case(b, 0.5, nt))
    for ht in lv["thin_h"]:
        for b in BASES:
            c = crush_case(b, ht, lv["thin_nt"])
            if c.name not in [x.name for x in cases]:
                cases.append(c)
    cases.sort(key=lambda c: c.labels["n_thick"] ** 2 / c.labels["h_over_t"])
    write_csv("crush_runs.csv", crush_rows(cases, "crush"))
    write_csv("noise_test.csv", crush_rows(noise_test_cases(), "noise_test"))


def noise_test_cases() -> list[Case]:
    """The noise check of make test (tests/test_stability_crush.py): linear and CPDI2 at
    h = t/2, n_t = 4, cfl 0.4, to an approach of 5.2 mm; noise over 3-5 mm."""
    return [crush_case(b, 0.5, 4, t_end=TEST_T_END, extra={"run.cfl": TEST_CFL},
                       prefix="noisetest") for b in ("linear", "cpdi2")]


def part_nthick(lv: dict[str, Any]) -> None:
    """n_t from 1 to 32 at h = t/2, CPDI2; n_circ fixed (that of n_t = 4 at aspect 1)."""
    cases = [crush_case("cpdi2", 0.5, nt, n_circ=420, prefix="nthick") for nt in lv["nthick"]]
    write_csv("nthick_runs.csv", crush_rows(cases, "nthick"))


# near-full crush of a half ring between two platens, then release: the inner walls meet
STICK_DELTA = 46.0e-3      #: approach at the end of loading [m] (inner walls 1.9 mm apart if flat)
STICK_V = 5.0              #: speed of each platen [m/s]
STICK_RAMP = 5.0e-4        #: ramp of the motion table [s]
STICK_RELEASE = 4.0e-4     #: time the platens withdraw at the end [s]


def stick_base() -> Path:
    """crush.nml as a half model with a bottom platen moving up (written under build/)."""
    text = CRUSH.read_text()
    text += ("\n&wall\n  point = 0.0, 0.0\n  normal = 0.0, 1.0\n  contact = 'frictionless'\n"
             "  velocity = 0.0, 5.0\n/\n")
    path = RUNS / "bases" / "crush_half_two_platens.nml"
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)
    return path


def part_stick(lv: dict[str, Any]) -> None:
    base = stick_base()
    t_load = STICK_RAMP / 2 + STICK_DELTA / 2 / STICK_V
    table_t = [0.0, STICK_RAMP, t_load, t_load + 5.0e-5]
    table_f = [0.0, 1.0, 1.0, -1.0]
    t_end = t_load + STICK_RELEASE
    cases = []
    for ht in lv["stick_h"]:
        extra = {"body.sector": "half", "run.snapshot_every": 2.0e-4,
                 "wall[1].ramp": 0.0, "wall[1].motion_t": table_t, "wall[1].motion_f": table_f,
                 "wall[2].motion_t": table_t, "wall[2].motion_f": table_f}
        cases.append(crush_case("cpdi2", ht, 2, t_end=t_end, extra=extra, prefix="stick",
                                base=base))
    rows = []
    series = []
    for c, r in zip(cases, batch_run(cases)):
        folder = RUNS / c.name
        row = {"part": "stick", "case": c.name, **c.labels}
        row.update(common(r, folder))
        row.update(stick_metrics(folder, t_load, series, c.labels["h_over_t"]))
        rows.append(row)
    write_csv("stick_runs.csv", rows)
    write_csv("stick_series.csv", series)


def inner_gap(frame: dict[str, Any], center: np.ndarray, half_width: float) -> float:
    """Gap between the inner surfaces of the top and bottom walls near the mid-plane x = cx,
    from the particle domains' corners [m]."""
    xc = frame["corners"]
    near = np.abs(xc[:, 0] - center[0]) < half_width
    top = xc[near & (xc[:, 1] > center[1])]
    bot = xc[near & (xc[:, 1] <= center[1])]
    if len(top) == 0 or len(bot) == 0:
        return float("nan")
    return float(top[:, 1].min() - bot[:, 1].max())


def stick_metrics(folder: Path, t_load: float, series: list[dict[str, Any]],
                  ht: float) -> dict[str, Any]:
    out = {"gap_at_39mm": float("nan"), "gap_flat_39mm": float("nan"),
           "gap_loaded": float("nan"), "gap_released": float("nan"),
           "springback": float("nan"), "force_loaded": float("nan")}
    try:
        h = readers.read_history(folder / "history.csv")
        inputs = namelist.read_namelist(folder / "input.nml")
        names = readers.read_frames(folder / "particles.h5")
    except (OSError, ValueError, KeyError):
        return out
    t = h["time"]
    delta = -(h["wall1_disp"] + h["wall2_disp"])
    f = smooth(h["wall1_force"], round(SMOOTH / HIST) + 1)
    ring = scene.ring_properties(inputs)
    center = ring["center"]
    gaps = []
    for name in names:
        fr = readers.read_frame(folder / "particles.h5", name)
        g = inner_gap(fr, center, 3.0e-3)
        k = min(int(np.searchsorted(t, fr["time"] - 1e-12)), len(t) - 1)
        gaps.append((float(fr["time"]), float(delta[k]), g, float(f[k])))
    for tt, d, g, ff in gaps:
        series.append({"h_over_t": ht, "time": tt, "delta": d, "inner_gap": g, "force": ff})
    # force against approach (1 row per 10 us) for the figure
    step = max(1, round(1.0e-5 / HIST))
    with (OUT / f"stick_force_h{fmt(ht)}.csv").open("w") as fh:
        fh.write("time,delta,force\n")
        for i in range(0, len(t), step):
            fh.write(f"{t[i]:.6g},{delta[i]:.6g},{f[i]:.6g}\n")
    # the inner walls near the mid-plane, 39.5 mm into the crush: a flat wall pair would still
    # be D_outer - delta - 2 t apart; walls that share nodes stop approaching about 2 h apart
    near = [g for tt, d, g, ff in gaps if abs(d - 39.5e-3) < 1.0e-3 and tt <= t_load]
    if near:
        out["gap_at_39mm"] = near[0]
    out["gap_flat_39mm"] = D_CRUSH - 39.5e-3 - 2.0 * T_CRUSH
    loaded = [(g, ff) for tt, d, g, ff in gaps if tt <= t_load + 1e-9]
    if loaded:
        out["gap_loaded"], out["force_loaded"] = loaded[-1]
    if gaps and gaps[-1][0] > t_load + 1e-9:
        out["gap_released"] = gaps[-1][2]
        out["springback"] = out["gap_released"] - out["gap_loaded"]
    return out


# ----------------------------------------------------------------------------------------------
# 5. large distortion at deep crush
# ----------------------------------------------------------------------------------------------

def quad_measures(frame: dict[str, Any]) -> dict[str, np.ndarray]:
    """Per particle: smallest corner Jacobian ratio (cross product of the two edges at a corner
    over the area: 1 for a parallelogram, <= 0 folded), condition number of the half-vector
    map [r1 r2] (1 for a square), and the domain's extent in cells."""
    xc = frame["corners"]
    q = frame["quads"].astype(int)
    x = xc[q]                                   # (np, 4, 2)
    e_next = np.roll(x, -1, axis=1) - x
    e_prev = np.roll(x, 1, axis=1) - x
    cross = e_next[..., 0] * e_prev[..., 1] - e_next[..., 1] * e_prev[..., 0]
    xs, ys = x[..., 0], x[..., 1]
    area = 0.5 * np.sum(xs * np.roll(ys, -1, axis=1) - np.roll(xs, -1, axis=1) * ys, axis=1)
    jmin = np.min(cross, axis=1) / np.where(area != 0, area, np.nan)
    r1 = 0.25 * (x[:, 1] + x[:, 2] - x[:, 0] - x[:, 3])
    r2 = 0.25 * (x[:, 2] + x[:, 3] - x[:, 0] - x[:, 1])
    m = np.stack([r1, r2], axis=2)
    sv = np.linalg.svd(m, compute_uv=False)
    cond = sv[:, 0] / np.maximum(sv[:, 1], 1e-300)
    extent = np.max(np.ptp(x, axis=1), axis=1)
    return {"jmin": jmin, "cond": cond, "extent": extent}


def corner_pairs(frame: dict[str, Any], tol: float) -> np.ndarray:
    """CPDI1: pairs (i, j) of corners of different particles that coincide (within tol) in the
    first frame: the corners neighbouring parallelograms share while they tile the ring."""
    xc = frame["corners"]
    q = frame["quads"].astype(int)
    owner = np.empty(len(xc), dtype=int)
    for k in range(4):
        owner[q[:, k]] = np.arange(len(q))
    pairs = []
    for i0 in range(0, len(xc), 512):
        blk = xc[i0:i0 + 512]
        d2 = np.sum((blk[:, None, :] - xc[None, :, :]) ** 2, axis=2)
        d2[owner[i0:i0 + 512, None] == owner[None, :]] = np.inf
        i, j = np.nonzero(d2 < tol * tol)
        pairs.append(np.column_stack([i + i0, j]))
    pr = np.concatenate(pairs) if pairs else np.zeros((0, 2), dtype=int)
    return pr[pr[:, 0] < pr[:, 1]]


def corner_mismatch(frame: dict[str, Any], pairs: np.ndarray) -> float:
    """CPDI1: largest distance between corners that coincided at the start (0 while the
    parallelograms tile the ring; gaps and overlaps make it grow) [m]."""
    if len(pairs) == 0:
        return 0.0
    xc = frame["corners"]
    return float(np.max(np.linalg.norm(xc[pairs[:, 0]] - xc[pairs[:, 1]], axis=1)))

FAST = 50.0                #: platen speed of the fast deep crush [m/s]


def part_distort(lv: dict[str, Any]) -> None:
    """Quasi-static crush (5 m/s per platen) to delta/D = 0.8, and a fast one (50 m/s per
    platen, no ramp) to delta/D = 0.95 (near full crush: the side hinges close)."""
    t_end = 2.5e-4 + 0.8 * D_CRUSH / 2 / 5.0         # delta/D = 0.8
    cases = []
    for nt in lv["distort_nt"]:
        for b in ("cpdi1", "cpdi2"):
            cases.append(crush_case(b, 0.5, nt, t_end=t_end, prefix="distort",
                                    extra={"run.snapshot_every": 1.0e-4,
                                           "run.history_every": 1.0e-5}))
    t_fast = 0.95 * D_CRUSH / 2 / FAST
    for nt in lv["fast_nt"]:
        for b in ("cpdi1", "cpdi2"):
            c = crush_case(b, 0.5, nt, t_end=t_fast, prefix="fastcrush",
                           extra={"run.snapshot_every": t_fast / 40, "run.history_every": 1.0e-6,
                                  "wall.velocity": [0.0, -FAST], "wall.ramp": 0.0})
            c.labels["speed"] = FAST
            cases.append(c)
    rows, series = [], []
    for c, r in zip(cases, batch_run(cases)):
        folder = RUNS / c.name
        row = {"part": "distort", "case": c.name, "speed": 5.0, **c.labels}
        row.update(common(r, folder))
        row.update(distort_metrics(folder, c, series))
        if row["reason"] == "folded domain":
            row["delta_fold"] = row["delta_reached"]
            m = re.search(r"at \(([-+0-9.E]+), ([-+0-9.E]+)\) m folded",
                          (folder / "run.log").read_text(errors="replace"))
            if m:   # where: angle from the ring centre (0 = equator, 90 = under the platen)
                row["angle_fold"] = math.degrees(math.atan2(float(m.group(2)) - 25.43e-3,
                                                            float(m.group(1))))
        rows.append(row)
    write_csv("distort_runs.csv", rows)
    write_csv("distort_series.csv", series)


def distort_metrics(folder: Path, c: Case, series: list[dict[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {"jmin_final": float("nan"), "cond_max_final": float("nan"),
                           "delta_fold": float("nan"), "delta_cond4": float("nan"),
                           "angle_worst": float("nan"), "mismatch_final": float("nan"),
                           "delta_reached": float("nan")}
    try:
        h = readers.read_history(folder / "history.csv")
        inputs = namelist.read_namelist(folder / "input.nml")
        names = readers.read_frames(folder / "particles.h5")
    except (OSError, ValueError, KeyError):
        return out
    disp, _, _ = scene.crush_displacement(h, inputs)
    ring = scene.ring_properties(inputs)
    cx, cy = ring["center"]
    h_cell = c.labels["h_over_t"] * T_CRUSH
    first = readers.read_frame(folder / "particles.h5", names[0])
    angle0 = np.degrees(np.arctan2(first["x"][:, 1] - cy, first["x"][:, 0] - cx))
    basis = c.labels["basis"]
    pairs = corner_pairs(first, 1.0e-3 * h_cell) if basis == "cpdi1" else np.zeros((0, 2), int)
    speed = c.labels.get("speed", 5.0)
    for name in names:
        fr = readers.read_frame(folder / "particles.h5", name)
        k = min(int(np.searchsorted(h["time"], fr["time"] - 1e-12)), len(disp) - 1)
        d = float(disp[k]) / D_CRUSH
        m = quad_measures(fr)
        iw = int(np.nanargmin(m["jmin"])) if basis == "cpdi2" else int(np.nanargmax(m["cond"]))
        row = {"basis": basis, "n_thick": c.labels["n_thick"], "speed": speed,
               "time": float(fr["time"]),
               "delta_over_D": d, "jmin": float(np.nanmin(m["jmin"])),
               "cond_max": float(np.nanmax(m["cond"])),
               "cond_p99": float(np.nanpercentile(m["cond"], 99)),
               "extent_max_cells": float(np.nanmax(m["extent"])) / h_cell,
               "angle_worst": float(angle0[iw]),
               "mismatch_cells": corner_mismatch(fr, pairs) / h_cell}
        series.append(row)
    out["delta_reached"] = float(disp[-1]) / D_CRUSH
    mine = [s for s in series if s["basis"] == basis and s["n_thick"] == c.labels["n_thick"]
            and s["speed"] == speed]
    if mine:
        last = mine[-1]
        out.update(jmin_final=last["jmin"], cond_max_final=last["cond_max"],
                   angle_worst=last["angle_worst"], mismatch_final=last["mismatch_cells"])
        folded = [s["delta_over_D"] for s in mine if s["jmin"] <= 0.0]
        out["delta_fold"] = folded[0] if folded else float("nan")
        c4 = [s["delta_over_D"] for s in mine if s["cond_max"] >= 4.0]
        out["delta_cond4"] = c4[0] if c4 else float("nan")
    return out


# ----------------------------------------------------------------------------------------------
# 6. FLIP against PIC in an elastic impact
# ----------------------------------------------------------------------------------------------

def part_flip(lv: dict[str, Any]) -> None:
    cases = []
    for fl in lv["flip"]:
        ov = {"grid.h": 1.0e-3, "body.n_thick": 4, "run.t_end": 1.2e-3,
              "run.history_every": HIST, "run.snapshot_every": 0.0, "material.model": "elastic",
              "solver.flip": fl}
        cases.append(Case(f"flip_{fmt(fl)}", IMPACT, ov, {"flip": fl}))
    rows = []
    for c, r in zip(cases, batch_run(cases)):
        folder = RUNS / c.name
        row = {"part": "flip", "case": c.name, **c.labels}
        row.update(common(r, folder))
        try:
            h = readers.read_history(folder / "history.csv")
        except (OSError, ValueError):
            rows.append(row)
            continue
        e = h["kinetic"] + h["strain"]
        row["energy_lost"] = 1.0 - float(e[-1] / e[0])
        row["rebound_ratio"] = float(h["com_vy"][-1] / 30.0)
        row.update({k: v for k, v in impact_metrics(folder).items() if k == "noise"})
        # particle-velocity noise: kinetic energy minus that of the centre-of-mass motion is
        # vibration plus noise; its high-frequency part (minus its 20 us average) is noise
        dt_row = float(np.median(np.diff(h["time"])))
        kin = h["kinetic"]
        row["kin_noise"] = float(np.sqrt(np.mean((kin - smooth(kin, round(SMOOTH / dt_row)
                                                                 + 1)) ** 2)) / e[0])
        rows.append(row)
    write_csv("flip_runs.csv", rows)

PARTS = {"cfl": part_cfl, "crush": part_crush, "nthick": part_nthick, "stick": part_stick,
         "distort": part_distort, "flip": part_flip}


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """The command line (the level defaults to quick, as in ``make stability``)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--level", choices=tuple(LEVELS), default="quick",
                    help="quick (the default, < 10 min, tables in out/stability-quick/) or "
                         "full (tables in docs/stability/)")
    ap.add_argument("--quick", action="store_true", help="the same as --level quick")
    ap.add_argument("--out", help="folder of the tables (default: by --level)")
    ap.add_argument("--parts", default=",".join(PARTS),
                    help=f"comma-separated subset of {','.join(PARTS)}")
    batch.add_backend_args(ap, threads=False, no_wait=False)
    args = ap.parse_args(argv)
    if args.quick:
        args.level = "quick"
    for name in args.parts.split(","):
        if name not in PARTS:
            ap.error(f"unknown part {name!r}; choose from {', '.join(PARTS)}")
    return args


def main(argv: list[str] | None = None) -> int:
    global OUT, BACKEND
    args = parse_args(argv)
    BACKEND = batch.backend_of(args)
    level = args.level
    OUT = Path(args.out) if args.out else folder_of(level)
    names = args.parts.split(",")
    lv = LEVELS[level]
    t0 = time.monotonic()
    for name in names:
        say(f"== part {name} ({level})")
        PARTS[name](lv)
    say(f"study ({level}) took {time.monotonic() - t0:.0f} s; tables in {OUT}; figures: "
        f"python3 -m plots.plot_stability --dir {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
