# SPDX-License-Identifier: MIT
"""The refinement study (`make study`): accuracy against cost for the crush, impact and wave
scenes of Sinaie et al. (2018).

    python3 -m tools.study [--level quick|full|all] [--jobs N] [--tables-only] [--list]
                           [--backend slurm [--partition P] [--time T] [--account A] ...]

Each scene is swept one factor at a time around a centre point (CPDI2, MUSL, cfl 0.2 (the
quasi-static crush: 0.8), square particles): the grid spacing h/t, the particles through the wall n_t, the particle aspect ratio
(length around / length through the wall, which sets n_c), the basis, the cfl number, for
the impact the impact speed, and the volumetric treatment (``&solver volumetric``: the
anti-locking F-bar 'fbar' and the fit through a ring's wall 'fbarwall', against 'standard' at
one and two particles per cell through the wall).
The full level adds the settings of issue 17's targets: the crush at h = t/4, n_t = 8, aspect 2
at cfl 1.2 and 1.6, and the automatic time step (``cfl = 0``: the run's cfl is then the table's
``cfl_used``) for that crush and for the impact at h = t/4, n_t = 8. Runs go to
out/study/<case>/ through tools/batch.py (several at once, one thread each, finished runs
skipped, interrupted runs re-run), or with ``--backend slurm`` as one Slurm job array
(docs/batch.md).

The study's crush is quasi-static (the platens approach at CRUSH_APPROACH, not the shipped
scene's 5 m/s), and every crush error is measured against the static finite element curve
docs/fe_reference/crush_fe.csv (make fe-reference); every impact (at 30 m/s) and wave error
against the dynamic finite element references docs/fe_reference/dynamic_convergence.json (make
fe-dynamic). The second column err_self is the difference from the scene's finest CPDI2 run of
the level (h = t/8, n_t = 16 for full and all, h = t/4, n_t = 8 for quick), with Richardson
extrapolation over the h sweep: convergence, not accuracy. Without a reference file a scene is
scored against its finest run, which the table's `reference` column then names. The metrics are written to
docs/study/study_<level>.csv (one row per run), with compact curves in docs/study/curves/ that
plots/plot_study.py turns into the figures of docs/validation.md (the quick level writes to
out/study-quick/ instead: it checks the machinery, its coarse reference is no result).
`--tables-only` recomputes the table from existing run folders without running anything.

Levels: ``quick`` (under 10 minutes on 2 cores: coarse sweeps, its own coarse reference),
``full`` (211 runs, 2.8 CPU hours, about 85 minutes on 2 free cores; the committed table and
figures; with the crush at a fixed platen, 31 settings on two more grids and 4 on ten),
``all`` (full plus n_t = 32 at h = t/8 for every scene, the crush's bases at h = t/4 and its
aspect 1/2; several hours more).
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tools import batch
from plots.mpmplot import analysis, namelist, readers, scene, theory

ROOT = Path(__file__).resolve().parent.parent

RUNS = ROOT / "out" / "study"    # not under build/: `make clean` must not delete a study
OUT = ROOT / "docs" / "study"


def out_dir(level: str) -> Path:
    """Where a level's table and curves go: docs/study (committed) for full and all,
    out/study-quick for the quick level (a check of the machinery, not a result)."""
    return ROOT / "out" / "study-quick" if level == "quick" else OUT

#: The study's crush is quasi-static, so that it compares with the static finite element
#: reference (docs/fe_reference/): the platens approach each other at CRUSH_APPROACH (the shipped
#: crush.nml: 10 m/s, whose inertia makes the force oscillate by 5-10 % about the static curve)
#: after a smooth ramp of CRUSH_RAMP (about the period of the ring's ovalling mode), without
#: damping or mass scaling (docs/validation.md, "A quasi-static crush", says why).
CRUSH_APPROACH = 2.5      # relative approach speed of the platens [m/s]
CRUSH_RAMP = 5.0e-4       # ramp of the platen speed [s]
#: the crush stops at this delta/D (D the mean diameter), past the error window's 0.5
CRUSH_END = 0.53
_CRUSH_D = 23.95e-3 + 25.43e-3            # mean diameter of namelists/crush.nml's ring [m]
_CRUSH_T_END = float(f"{CRUSH_RAMP / 2 + CRUSH_END * _CRUSH_D / CRUSH_APPROACH:.3g}")

#: The scenes: base namelist, wall thickness t [m], and the overrides that make the study
#: version (crush: quasi-static, stops at delta/D about 0.53; impact after the rebound, wave
#: after the front has passed the top).
SCENES: dict[str, dict[str, Any]] = {
    "crush": {"base": ROOT / "namelists" / "crush.nml", "t": 1.48e-3,
              "set": {"run.t_end": _CRUSH_T_END,
                      "run.history_every": float(f"{1.0e-4 / CRUSH_APPROACH:.3g}"),
                      "run.snapshot_every": float(f"{_CRUSH_T_END / 10:.3g}"),
                      "wall.velocity": (0.0, -0.5 * CRUSH_APPROACH), "wall.ramp": CRUSH_RAMP,
                      "wall.stroke": 0.0}},
    "impact": {"base": ROOT / "namelists" / "impact.nml", "t": 2.0e-3,
               "set": {"run.t_end": 0.9e-3, "run.history_every": 1.0e-6,
                       "run.snapshot_every": 1.0e-4}},
    "wave": {"base": ROOT / "namelists" / "wave.nml", "t": 2.0e-3,
             "set": {"run.t_end": 3.0e-5, "run.history_every": 1.0e-7,
                     "run.snapshot_every": 1.0e-5}},
    # the crush as the test machine does it (half model, the bottom platen fixed, the top one
    # driven at the whole approach speed), its force read at the fixed platen: a few settings
    # of the full level, against the same finite element curve (docs/validation.md, "The force
    # at a fixed platen")
    "crush_fixed": {"base": ROOT / "namelists" / "crush_fixed.nml", "t": 1.48e-3,
                    "set": {"run.t_end": _CRUSH_T_END,
                            "run.history_every": float(f"{1.0e-4 / CRUSH_APPROACH:.3g}"),
                            "run.snapshot_every": float(f"{_CRUSH_T_END / 10:.3g}"),
                            "wall[1].velocity": (0.0, -CRUSH_APPROACH),
                            "wall[1].ramp": CRUSH_RAMP, "wall[1].stroke": 0.0}},
}
#: the crush scenes: errors against the finite element curve
CRUSH_SCENES = ("crush", "crush_fixed")
#: The centre point's cfl per scene: the quasi-static crush runs at cfl 0.8, where the old
#: study found the same crush error as at 0.2 and 0.4 (docs/validation.md)
CENTRE_CFL = {"crush": 0.8, "impact": 0.2, "wave": 0.2, "crush_fixed": 0.8}
#: The crush's static finite element reference (make fe-reference): every crush error is
#: measured against it; the difference from the finest MPM run (convergence) is err_self
FE_CURVE = ROOT / "docs" / "fe_reference" / "crush_fe.csv"
FE_REFERENCE = "fe_reference/crush_fe.csv"
#: The impact's and the wave's dynamic finite element references (make fe-reference: the
#: project's explicit FE code xfe on four meshes, docs/fe_reference/README.md): every impact
#: error (at the reference's 30 m/s) and every wave error is against their finest mesh.
FE_DYNAMIC = ROOT / "docs" / "fe_reference" / "dynamic_convergence.json"
FE_DYNAMIC_REFERENCE = "fe_reference/dynamic_convergence.json"

#: The automatic cfl (``&run cfl = 0``, docs/input.md) is CFL_MARGIN times the largest cfl at
#: which the stability study found the basis and scheme stable (docs/stability/
#: cfl_limits_ppc*.csv: at 1 particle per cell through the wall below PPC_LOW, else at 2), or
#: CFL_MARGIN times the smallest cfl it tried where it found none stable:
#: src/method/mpm_time_step.f90's cfl_auto, which tests/test_study.py holds this to.
CFL_MARGIN = 0.5
PPC_LOW = 1.5
STABILITY = ROOT / "docs" / "stability"


def automatic_cfl(basis: str, scheme: str, ppc: float) -> float:
    """The cfl that tubempm uses for ``cfl = 0`` with this basis and scheme at ppc particles per
    cell through the wall (n_t h / t)."""
    def rows(name: str) -> list[dict[str, str]]:
        with open(STABILITY / name, newline="") as fh:
            return list(csv.DictReader(fh))
    limits = rows(f"cfl_limits_ppc{1 if ppc < PPC_LOW else 2}.csv")
    limit = next(float(r["stable_cfl"]) for r in limits
                 if r["basis"] == basis and r["scheme"] == scheme)
    if limit <= 0.0:
        limit = min(float(r["cfl"]) for k in (1, 2) for r in rows(f"cfl_runs_ppc{k}.csv"))
    return CFL_MARGIN * limit

#: Crush error window (delta / D, D the mean diameter) and energy point.
CRUSH_WINDOW = (0.05, 0.5)
#: Crush: width of the moving average of F(delta) for the smoothed error [delta / D].
SMOOTH_WIDTH = 0.02
#: Impact peak force: moving average over this window [s].
PEAK_WINDOW = 10.0e-6
#: Wave arrival: first |v - v0| above this fraction of the probe's peak in the dynamic FE
#: reference's record (FE_WAVE, over the study's window), the same level for every run; a
#: fraction of each run's own peak would time the runs at different levels: the top probe's
#: peak comes from the flexural arrival at 25-30 us, which h = t/4 does not resolve (1.7 m/s
#: against the FE's 4.2 m/s), and a level of 10 % of that timed the first arrival 0.6 us early
#: (docs/fe_reference/README.md).
ARRIVAL_THRESHOLD = 0.1
#: The finest FE mesh's wave record (make fe-dynamic), whose peaks set the arrival levels.
FE_WAVE = ROOT / "docs" / "fe_reference" / "wave_fe.csv"


@dataclass(frozen=True)
class Point:
    """One run's settings."""
    scene: str
    basis: str = "cpdi2"
    scheme: str = "musl"
    h_over_t: float = 0.25
    n_t: int = 8
    aspect: float = 1.0
    cfl: float = 0.2
    speed: float = 30.0          # impact only [m/s]
    volumetric: str = "standard"  # &solver volumetric: 'standard', 'fbar', 'fbarwall'
    penalty: float = 1.0         # &wall penalty of the scene's (first) wall
    #: the grid spacing is h_over_t * t * h_scale: h_scale 0.97 and 1.03 move the grid's rows
    #: by about a cell where the platen and the hinges are (r_outer / h changes by 1-2), the
    #: alignment variants of a setting (ALIGNED); 1 for every other run
    h_scale: float = 1.0

    @property
    def cfl_used(self) -> float:
        """The cfl the run uses: its input's, or the automatic value for cfl = 0."""
        return self.cfl if self.cfl > 0.0 else automatic_cfl(
            self.basis, self.scheme, self.n_t * self.h_over_t) / max(1.0, self.penalty)

    @property
    def name(self) -> str:
        def frac(x: float) -> str:
            return f"{x:g}" if x >= 1 else f"1_{round(1 / x):d}"
        n = (f"{self.scene}_{self.basis}_{self.scheme}_h{frac(self.h_over_t)}_nt{self.n_t}"
             f"_a{frac(self.aspect)}_cfl{self.cfl:g}")
        if self.scene == "impact" and self.speed != 30.0:
            n += f"_v{self.speed:g}"
        if self.volumetric != "standard":
            n += f"_{self.volumetric}"
        if self.penalty != 1.0:
            n += f"_p{self.penalty:g}"
        if self.h_scale != 1.0:
            n += f"_hs{self.h_scale:g}"
        return n

    def n_circ(self) -> int:
        """Particles around the whole ring for the aspect ratio (a multiple of 4)."""
        r = ring_of(self.scene)
        length = r["t"] / self.n_t * self.aspect
        return max(4, 4 * round(2.0 * math.pi * r["R"] / length / 4.0))

    def particles(self) -> int:
        parts = {"quarter": 4, "half": 2}.get(ring_of(self.scene)["sector"], 1)
        return self.n_t * self.n_circ() // parts

    def steps(self) -> float:
        r = ring_of(self.scene)
        h = self.h_over_t * SCENES[self.scene]["t"] * self.h_scale
        v = self.speed if self.scene == "impact" else \
            CRUSH_APPROACH if self.scene == "crush_fixed" else 0.5 * CRUSH_APPROACH
        dt = self.cfl_used * h / (r["c"] + v)
        return self.t_end() / dt

    def t_end(self) -> float:
        t = SCENES[self.scene]["set"]["run.t_end"]
        if self.scene == "impact" and self.speed != 30.0:
            t = 1.5e-3
        return t

    def cost(self) -> float:
        """Estimated particle-steps."""
        return self.particles() * self.steps()

    def case(self) -> batch.Case:
        sc = SCENES[self.scene]
        o = dict(sc["set"])
        o.update({"solver.basis": self.basis, "solver.scheme": self.scheme,
                  "run.cfl": self.cfl, "run.t_end": self.t_end(),
                  "grid.h": self.h_over_t * sc["t"] * self.h_scale, "body.n_thick": self.n_t,
                  "body.n_circ": self.n_circ(), "run.threads": 1})
        if self.scene == "impact":
            o["body.velocity"] = (0.0, -float(self.speed))
        if self.volumetric != "standard":       # (standard runs keep their inputs and names)
            o["solver.volumetric"] = self.volumetric
        if self.penalty != 1.0 or self.scene == "wave":   # (the wave's base has penalty 4)
            o["wall.penalty"] = self.penalty
        return batch.Case(self.name, sc["base"], o, labels=self.labels())

    def labels(self) -> dict[str, Any]:
        return {"scene": self.scene, "basis": self.basis, "scheme": self.scheme,
                "h_over_t": self.h_over_t, "n_t": self.n_t, "n_c": self.n_circ(),
                "aspect": self.aspect, "cfl": self.cfl, "cfl_used": self.cfl_used,
                # impact speed; the crush's relative platen approach
                "speed": self.speed if self.scene == "impact" else
                CRUSH_APPROACH if self.scene in CRUSH_SCENES else "",
                "volumetric": self.volumetric, "penalty": self.penalty,
                "h_scale": self.h_scale}


_RINGS: dict[str, dict[str, Any]] = {}


def ring_of(name: str) -> dict[str, Any]:
    """Mean radius, wall, sector and dilatational speed of a scene's ring."""
    if name not in _RINGS:
        inputs = namelist.read_namelist(SCENES[name]["base"])
        r = scene.ring_properties(inputs)
        r["sector"] = str(scene.ring_body(inputs).get("sector", "full")).lower()
        r["c"] = theory.dilatational_speed(r["E"], r["nu"], r["rho"])
        _RINGS[name] = r
    return _RINGS[name]


# ----------------------------------------------------------------------------------------------
# The designs
# ----------------------------------------------------------------------------------------------

BASES = ("linear", "ugimp", "cpdi1", "cpdi2")
#: n_t of the F-bar runs at h = t/2 (one and two particles per cell through the wall; at
#: h = t/4 twice as many)
FBAR_NT = (2, 4)
#: the volumetric treatments of the full level (&solver volumetric): 'fbarwall', the fit
#: through a ring's wall, is measured where 'fbar' is (docs/method.md, Volumetric locking)
VOLUMETRICS = ("standard", "fbar", "fbarwall")


def design(level: str) -> dict[str, list[Point]]:
    """The runs of a level, per scene, and which one is the reference (first)."""
    out: dict[str, list[Point]] = {}

    def P(scene: str, **kw: Any) -> Point:          # a point, at the scene's centre cfl
        kw.setdefault("cfl", CENTRE_CFL[scene])
        return Point(scene, **kw)
    if level == "quick":
        for scene in ("crush", "impact", "wave"):
            ref = P(scene, h_over_t=0.25, n_t=8)
            pts = [ref]
            pts += [P(scene, h_over_t=h, n_t=8) for h in (2.0, 1.0, 0.5)]
            pts += [P(scene, h_over_t=0.5, n_t=n) for n in (2, 4)]
            pts += [P(scene, h_over_t=0.5, n_t=4, aspect=a) for a in (4.0, 2.0, 0.5)]
            pts += [P(scene, basis=b, h_over_t=0.5, n_t=4) for b in BASES[:3]]
            pts += [P(scene, h_over_t=0.5, n_t=n, volumetric="fbar") for n in FBAR_NT]
            if scene == "impact":
                pts += [P(scene, h_over_t=0.5, n_t=4, speed=v) for v in (5.0, 16.5, 60.0,
                                                                                125.0)]
            out[scene] = pts
        return out
    for scene in ("crush", "impact", "wave"):
        ref = P(scene, h_over_t=0.125, n_t=16)
        pts = [ref]
        pts += [P(scene, h_over_t=h, n_t=16) for h in (2.0, 1.0, 0.5, 0.25)]
        nts = (2, 4, 8, 32)
        pts += [P(scene, h_over_t=0.25, n_t=n) for n in nts]
        # (the crush, the most expensive scene, keeps to the cheaper ends of two sweeps:
        # aspect 1/2 and the bases at h = t/4 are in LEVEL=all only)
        aspects = (4.0, 2.0, 1.0) if (scene == "crush" and level != "all") else \
            (4.0, 2.0, 1.0, 0.5)
        pts += [P(scene, h_over_t=0.25, n_t=8, aspect=a) for a in aspects]
        if scene != "crush" or level == "all":
            pts += [P(scene, basis=b, h_over_t=0.25, n_t=8) for b in BASES[:3]]
        pts += [P(scene, basis=b, h_over_t=0.5, n_t=8) for b in BASES]
        # (the crush's centre is cfl 0.8: its sweep goes down, to 0.4 and 0.2)
        pts += [P(scene, h_over_t=0.25, n_t=8, cfl=c) for c in
                ((0.2, 0.4) if CENTRE_CFL[scene] == 0.8 else (0.4, 0.8))]
        # anti-locking: F-bar at one and two particles per cell through the wall, at h = t/4
        # and t/2 (docs/method.md, Volumetric locking)
        for h in (0.25, 0.5):
            for n in FBAR_NT:
                pts += [P(scene, h_over_t=h, n_t=round(n * 0.5 / h), volumetric=v)
                        for v in VOLUMETRICS]
        # (elongated particles suit the F-bar at one particle per cell: docs/validation.md)
        pts += [P(scene, h_over_t=0.25, n_t=4, aspect=2.0, volumetric=v)
                for v in VOLUMETRICS]
        # fewer than one particle per cell through the wall (each particle spans two cells):
        # what --check's warning for it quotes
        if scene == "crush":
            pts += [P(scene, h_over_t=0.125, n_t=4, volumetric=v) for v in VOLUMETRICS]
        if scene == "impact":
            pts += [P(scene, h_over_t=0.25, n_t=8, speed=v)
                    for v in (1.0, 2.0, 5.0, 16.5, 30.0, 60.0, 125.0)]
        # a stiffer wall penalty (&wall penalty): the struck wave's force without the default
        # penalty's lag of about 4 h / c_d (docs/method.md, Rigid walls and contact)
        if scene == "wave":
            pts += [P(scene, **kw) for kw in WAVE_PENALTY]
        # issue 17's targets: the crush at h = t/4, n_t = 8, aspect 2 at cfl 1.2 and 1.6 (below
        # the stability study's limit, 1.75) and at the automatic cfl, the impact at its advised
        # setting (h = t/4, n_t = 8) at the automatic cfl
        if scene == "crush":
            pts += [P(scene, h_over_t=0.25, n_t=8, aspect=2.0, cfl=c) for c in (1.2, 1.6, 0.0)]
        if scene == "impact":
            # (and the F-bar there at cfl 0.8: the rebound without the standard treatment's
            # dependence on the grid's exact spacing, as cheaply as the time step allows)
            pts += [P(scene, h_over_t=0.25, n_t=8, cfl=0.0)]
            if level != "quick":
                pts += [P(scene, h_over_t=0.25, n_t=8, cfl=0.8, volumetric="fbar")]
        if level == "all":
            pts += [P(scene, h_over_t=0.125, n_t=32)]
        seen: set[str] = set()
        out[scene] = [p for p in pts if not (p.name in seen or seen.add(p.name))]
    # the crush with a fixed platen: one particle per cell through the wall with each
    # volumetric treatment, the once-advised 5 % setting (h = t/2, n_t = 4, 'fbarwall') and two per
    # cell (h = t/4, n_t = 8); its err_self is against the crush's finest run (the same curve)
    out["crush_fixed"] = [P("crush_fixed", h_over_t=0.25, n_t=4, volumetric=v)
                          for v in ("fbarwall", "fbar", "standard")]
    out["crush_fixed"] += [P("crush_fixed", h_over_t=0.5, n_t=4, volumetric="fbarwall"),
                           P("crush_fixed", h_over_t=0.25, n_t=8)]
    # the same settings on other grids: those the advice rests on at h x 0.97 and 1.03 (the
    # rows fall elsewhere on the ring), four of them at eight h scales more (three grids are a
    # lower bound on the worst case: docs/validation.md, "The grid's alignment ..."); a
    # setting's error is the worst of them (plots/plot_study.py robust_error), and the advice
    # picks by that
    for settings, scales in ((ALIGNED, H_SCALES), (SCANNED, H_SCAN)):
        for scene, kws in settings.items():
            out[scene] += [P(scene, **{"cfl": CENTRE_CFL[scene], **kw}, h_scale=f)
                           for kw in kws for f in scales]
    return out


#: the wave's runs with a stiffer wall penalty (design, ALIGNED)
WAVE_PENALTY: list[dict[str, Any]] = [dict(h_over_t=0.25, n_t=8, penalty=p) for p in (2.0, 4.0)] \
    + [dict(h_over_t=0.25, n_t=8, cfl=0.8, penalty=4.0),
       dict(h_over_t=0.125, n_t=16, penalty=2.0)]
#: the alignment variants' h scales
H_SCALES = (0.97, 1.03)
#: the further h scales of the scanned settings (SCANNED), and those settings: the crush's
#: 2 % advice, the fixed platen's one particle per cell with 'fbar' (issue 17's target), the
#: impact at h = t/4, n_t = 8 with and without 'fbar' (the default scene's settings)
H_SCAN = (0.96, 0.98, 0.99, 0.995, 1.005, 1.01, 1.02, 1.04)
SCANNED: dict[str, list[dict[str, Any]]] = {
    "crush": [dict(h_over_t=0.25, n_t=8, aspect=2.0, cfl=1.6)],
    "crush_fixed": [dict(h_over_t=0.25, n_t=4, volumetric="fbar")],
    "impact": [dict(h_over_t=0.25, n_t=8, cfl=0.8),
               dict(h_over_t=0.25, n_t=8, cfl=0.8, volumetric="fbar")],
}
#: the settings measured at those (besides as run), the ones the advice may pick from
#: (plots/plot_study.py advice): per scene every setting within reach of 5 % in a minute or
#: two, and the finest run (its variants show how far alignment moves the converged value)
ALIGNED: dict[str, list[dict[str, Any]]] = {
    "crush": [dict(h_over_t=0.5, n_t=4, volumetric="fbarwall"),
              dict(h_over_t=0.25, n_t=8, aspect=2.0, cfl=1.6),
              dict(h_over_t=0.25, n_t=4, volumetric="fbarwall"),
              dict(h_over_t=0.25, n_t=4, volumetric="fbar"),
              dict(h_over_t=0.25, n_t=8),
              dict(h_over_t=0.125, n_t=16)],
    "crush_fixed": [dict(h_over_t=0.25, n_t=4, volumetric="fbarwall"),
                    dict(h_over_t=0.25, n_t=4, volumetric="fbar"),
                    dict(h_over_t=0.5, n_t=4, volumetric="fbarwall"),
                    dict(h_over_t=0.25, n_t=8)],
    "impact": [dict(h_over_t=0.25, n_t=8, cfl=c) for c in (0.0, 0.2, 0.4, 0.8)]
              + [dict(h_over_t=0.25, n_t=8, aspect=2.0),
                 dict(h_over_t=0.25, n_t=8, volumetric="fbar"),
                 dict(h_over_t=0.25, n_t=8, cfl=0.8, volumetric="fbar"),
                 dict(h_over_t=0.25, n_t=4, volumetric="fbarwall"),
                 dict(h_over_t=0.25, n_t=4, aspect=2.0, volumetric="fbarwall"),
                 dict(h_over_t=0.25, n_t=16),
                 dict(h_over_t=0.125, n_t=16)],
    "wave": [dict(h_over_t=0.25, n_t=8, cfl=c) for c in (0.2, 0.8)]
            + [dict(h_over_t=0.25, n_t=n) for n in (2, 4, 16)]
            + [dict(h_over_t=0.25, n_t=8, aspect=2.0),
               dict(h_over_t=0.5, n_t=2),
               dict(h_over_t=0.5, n_t=4),
               dict(h_over_t=0.5, n_t=4, volumetric="fbarwall"),
               dict(h_over_t=0.125, n_t=16)] + WAVE_PENALTY,
}


# ----------------------------------------------------------------------------------------------
# Metrics of one run
# ----------------------------------------------------------------------------------------------

def crush_curve_metrics(disp: np.ndarray, force: np.ndarray, r: dict[str, Any]
                        ) -> dict[str, Any]:
    """The crush metrics of a curve F(delta) (delta the platens' relative approach [m], D the
    ring's mean diameter in r): F on the window's 91 points, the same smoothed, the window's
    mean force and the absorbed energy at delta/D = 0.5 (nothing when the curve stops short of
    the window's end)."""
    D = r["D"]
    x = np.linspace(*CRUSH_WINDOW, 91) * D
    m: dict[str, Any] = {"curve_x": disp / D, "curve_y": force}
    if disp.max() < CRUSH_WINDOW[1] * D:
        return m
    order = np.argsort(disp, kind="stable")          # disp is monotone once the ramp is over
    f = np.interp(x, disp[order], force[order])
    dh = theory.deruntz_hodge(x, D, r["t"], r["sigma_y"], r["plane"], r["depth"])
    m["F_window"] = f
    # the same, smoothed over delta/D = SMOOTH_WIDTH: the mean response without the
    # high-frequency (cell-crossing, contact) content
    fine = np.arange(0.0, disp.max(), 0.001 * D)
    ff = np.interp(fine, disp[order], force[order])
    k = max(1, int(round(SMOOTH_WIDTH / 0.001)))
    sm = analysis.moving_average(ff, k)
    m["F_smooth"] = np.interp(x, fine, sm)
    m["force_mean"] = float(np.mean(f))
    m["force_over_dh"] = float(np.mean(f) / np.mean(dh))
    work = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(disp))])
    m["energy_50"] = float(np.interp(CRUSH_WINDOW[1] * D, disp[order], work[order]))
    m["energy_50_dh"] = float(theory.deruntz_hodge_energy(CRUSH_WINDOW[1] * D, D, r["t"],
                                                           r["sigma_y"], r["plane"], r["depth"]))
    return m


def crush_metrics(folder: Path, inputs: dict, platen: str = "moving") -> dict[str, Any]:
    """The crush metrics of a run (crush_curve_metrics of the platen's force, platen "moving"
    or "fixed": scene.crush_displacement) and how quasi-static it was."""
    h = readers.read_history(folder / "history.csv")
    disp, force, _ = scene.crush_displacement(h, inputs, platen)
    r = scene.ring_properties(inputs)
    m = crush_curve_metrics(disp, force, r)
    if "F_window" in m and "kinetic" in h and "plastic" in h:
        # how quasi-static: the largest kinetic energy over the plastic work in the window
        x = disp / r["D"]
        inw = (x >= CRUSH_WINDOW[0]) & (x <= CRUSH_WINDOW[1]) & (h["plastic"] > 0.0)
        if np.any(inw):
            m["kinetic_over_plastic"] = float(np.max(h["kinetic"][inw] / h["plastic"][inw]))
    return m


def fe_metrics(path: Path = FE_CURVE) -> dict[str, Any] | None:
    """The crush metrics of the finite element reference curve (None without the file)."""
    if not path.is_file():
        return None
    a = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)   # delta_m, delta_over_D, force_N
    r = scene.ring_properties(namelist.read_namelist(SCENES["crush"]["base"]))
    return crush_curve_metrics(a[:, 0], a[:, 2], r)


def fe_dynamic(scene: str, path: Path = FE_DYNAMIC) -> dict[str, Any] | None:
    """The impact's or the wave's metrics on the finest mesh of the dynamic FE reference
    (None without the file): impact duration, cor and peak_10us, measured as impact_metrics
    measures a run; wave arrivals at the probes (as wave_metrics) and wave_speed."""
    if scene not in ("impact", "wave") or not path.is_file():
        return None
    est = json.loads(path.read_text())[scene]["estimate"]
    if scene == "impact":
        return {k: float(est[k]["finest"]) for k in ("duration", "cor", "peak_10us")}
    n = len([k for k in est if k.startswith("arrival_")])
    arrivals = np.array([float(est[f"arrival_{j + 1}"]["finest"]) for j in range(n)])
    return {"arrivals": arrivals, "wave_speed": float(est["wave_speed"]["finest"])}


def impact_metrics(folder: Path, inputs: dict) -> dict[str, Any]:
    h = readers.read_history(folder / "history.csv")
    t = h["time"]
    f = h["wall1_force"]
    vn = h["com_vy"]                                   # target normal (0, 1)
    ph = analysis.contact_phases(t, f, away=vn > 0.0)
    v_imp = analysis.impact_velocity(h, 1, (0.0, 1.0), ph)
    # A ring that rings after the blow may touch the target again (at low speeds, several
    # times): the contact lasts from the first touch to the last separation, and the rebound
    # velocity is the centre of mass's at the end, once the last 5 % of the record is free
    # of contact (otherwise NaN: the record is too short).
    on = np.nonzero(f > ph["threshold"])[0] if np.isfinite(ph["threshold"]) else np.array([])
    duration = math.nan
    v_reb = math.nan
    if on.size and on[-1] < int(0.95 * len(t)):
        duration = float(t[on[-1] + 1] - t[on[0]])
        v_reb = float(np.mean(vn[int(0.95 * len(t)):]))
    n = max(1, int(round(PEAK_WINDOW / float(np.median(np.diff(t))))))
    smooth = analysis.moving_average(f, n)
    m = {"curve_x": t, "curve_y": f, "duration": duration, "peak_10us": float(smooth.max()),
         "cor": v_reb / v_imp if v_imp else float("nan"), "v_impact": v_imp,
         "impulse": float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t))),
         "momentum_change": 0.0}
    return m


def wave_levels(path: Path = FE_WAVE) -> np.ndarray | None:
    """The disturbance |v - v(0)| at which a wave arrives at each probe: ARRIVAL_THRESHOLD
    times its peak in the FE reference's record up to the study's end time (None without the
    file)."""
    if not path.is_file():
        return None
    h = readers.read_history(path)
    keep = h["time"] <= SCENES["wave"]["set"]["run.t_end"] * (1.0 + 1e-9)
    d = analysis.probe_disturbance({k: v[keep] for k, v in h.items()})
    return ARRIVAL_THRESHOLD * d.max(axis=0)


def wave_metrics(folder: Path, inputs: dict, own_peak: bool = False) -> dict[str, Any]:
    """Arrival times at the probes, at the FE reference's levels (wave_levels; own_peak, or no
    reference with as many probes: ARRIVAL_THRESHOLD times each probe's own peak), and the
    wave speed fitted to the probes beyond the struck point."""
    from plots.plot_case import probe_angles
    h = readers.read_history(folder / "history.csv")
    dist = analysis.probe_disturbance(h)
    levels = None if own_peak else wave_levels()
    if levels is not None and levels.size != dist.shape[1]:
        levels = None
    arrival = np.atleast_1d(analysis.arrival_times(h["time"], dist, ARRIVAL_THRESHOLD,
                                                  levels=levels))
    angles, _, _ = probe_angles(h, inputs)
    r = scene.ring_properties(inputs)
    far = angles > 1.0
    s = np.radians(angles[far]) * r["R"]
    ok = np.isfinite(arrival[far])
    speed = float(np.polyfit(arrival[far][ok], s[ok], 1)[0]) if np.count_nonzero(ok) >= 2 \
        else float("nan")
    return {"curve_x": angles, "curve_y": arrival, "arrivals": arrival, "wave_speed": speed,
            "speed_bar": theory.bar_speed(r["E"], r["rho"]),
            "speed_plate": theory.plate_speed(r["E"], r["nu"], r["rho"])}

METRICS = {"crush": crush_metrics, "impact": impact_metrics, "wave": wave_metrics,
           "crush_fixed": lambda folder, inputs: crush_metrics(folder, inputs, "fixed")}


# ----------------------------------------------------------------------------------------------
# Errors against the reference, Richardson extrapolation
# ----------------------------------------------------------------------------------------------

def rel(a: float, b: float) -> float:
    return abs(a - b) / abs(b) if (np.isfinite(a) and np.isfinite(b) and b != 0) else math.nan


def crush_errors(m: dict[str, Any], ref: dict[str, Any]) -> dict[str, float]:
    """The crush errors of run m against the curve ref: relative L2 norm of F(delta) over the
    window, the same of the smoothed curves, the absorbed energy at delta/D = 0.5, the mean force
    over ref's, and the run's own high-frequency content (RMS of F minus its smoothed curve,
    over the mean force)."""
    if "F_window" not in m or "F_window" not in ref:
        return {}
    fr, rs = ref["F_window"], ref["F_smooth"]
    return {"err_F_L2": float(np.sqrt(np.mean((m["F_window"] - fr) ** 2) / np.mean(fr ** 2))),
            "err_energy_50": rel(m["energy_50"], ref["energy_50"]),
            "err_F_smooth": float(np.sqrt(np.mean((m["F_smooth"] - rs) ** 2)
                                          / np.mean(rs ** 2))),
            "force_over_ref": float(np.mean(m["F_window"]) / np.mean(fr)),
            "noise": float(np.sqrt(np.mean((m["F_window"] - m["F_smooth"]) ** 2))
                           / np.mean(m["F_smooth"]))}


def errors(scene: str, m: dict[str, Any], ref: dict[str, Any] | None,
           fe: dict[str, Any] | None = None) -> dict[str, float]:
    """The scene's error metrics of run m against the reference run ref (None: not run), and
    the headline ``error``. Crush: against the finite element curve fe, the L2 norm of F(delta)
    (err_F_L2, err_F_smooth, err_energy_50, force_over_fe), with the L2 norm against the finest
    MPM run ref as the second column err_self (and err_F_smooth_self); without fe, against ref.
    Impact: against fe, the largest relative error of contact time, COR and 10 us peak force.
    Wave: the largest arrival-time error at the probes beyond the struck point, relative to the
    reference's arrival at the farthest probe. err_self is the headline difference from the
    finest run for every scene: a convergence measure, not an accuracy."""
    e: dict[str, float] = {}
    if ref is None and fe is None:
        return e
    if scene in CRUSH_SCENES:
        self_e = crush_errors(m, ref) if ref is not None else {}
        main = crush_errors(m, fe) if fe is not None else self_e
        e.update({k: v for k, v in main.items() if k != "force_over_ref"})
        if fe is not None and "force_over_ref" in main:
            e["force_over_fe"] = main["force_over_ref"]
        e["error"] = main.get("err_F_L2", math.nan)
        e["err_self"] = self_e.get("err_F_L2", math.nan)
        e["err_F_smooth_self"] = self_e.get("err_F_smooth", math.nan)
        return e
    elif scene == "impact":
        # against the FE reference when there is one: contact time, COR and the 10 us mean
        # peak force, all three in the headline; against the finest run: err_self (contact
        # time and COR, the peak not having converged there: Richardson order 0.4)
        def impact_errors(r: dict[str, Any]) -> dict[str, float]:
            return {"err_duration": rel(m["duration"], r["duration"]),
                    "err_cor": rel(m["cor"], r["cor"]),
                    "err_peak": rel(m["peak_10us"], r["peak_10us"])}
        if ref is not None:
            s = impact_errors(ref)
            vals = [s["err_duration"], s["err_cor"]]
            e["err_self"] = max(vals) if all(np.isfinite(vals)) else math.nan
        e.update(impact_errors(fe if fe is not None else ref))
        vals = [e["err_duration"], e["err_cor"]] + ([e["err_peak"]] if fe is not None else [])
        e["error"] = max(vals) if all(np.isfinite(vals)) else math.nan
        if fe is None:
            e["err_self"] = e["error"]
    else:
        # arrival-time errors beyond the struck point, relative to the reference's transit
        # time to the farthest probe (relative to each probe's own arrival, the nearest
        # probes' few-microsecond arrivals would weigh threshold jitter most)
        far = m["curve_x"] > 1.0

        def wave_errors(r: dict[str, Any]) -> dict[str, float]:
            if m["arrivals"].size != r["arrivals"].size or not np.any(far):
                return {"err_arrival": math.nan, "err_speed": math.nan}
            a, ar = m["arrivals"][far], r["arrivals"][far]
            return {"err_arrival": float(np.max(np.abs(a - ar)) / np.max(ar)),
                    "err_speed": rel(m["wave_speed"], r["wave_speed"])}
        if ref is not None:
            e["err_self"] = wave_errors(ref)["err_arrival"]
        e.update(wave_errors(fe if fe is not None else ref))
        e["error"] = e["err_arrival"]
        if fe is None:
            e["err_self"] = e["error"]
    return e


def richardson(f1: float, f2: float, f3: float, ratio: float = 2.0) -> dict[str, float]:
    """Observed order and extrapolated value from three levels (coarse f1, f2, fine f3) of
    constant refinement ratio; NaN when the differences do not shrink monotonically."""
    d1, d2 = f2 - f1, f3 - f2
    if not (np.isfinite(d1) and np.isfinite(d2)) or d1 == 0 or d2 / d1 <= 0 or abs(d2) >= abs(d1):
        return {"order": math.nan, "extrapolated": math.nan, "fine_error": math.nan}
    p = math.log(d1 / d2) / math.log(ratio)
    fx = f3 + d2 / (ratio ** p - 1.0)
    return {"order": p, "extrapolated": fx, "fine_error": abs(f3 - fx) / abs(fx)}


# ----------------------------------------------------------------------------------------------
# Table
# ----------------------------------------------------------------------------------------------

COLUMNS = ["scene", "name", "reference", "self_reference", "basis", "scheme", "h_over_t", "n_t",
           "n_c", "aspect", "cfl", "cfl_used", "speed", "volumetric", "penalty", "h_scale",
           "particles",
           "steps",
           "status", "exit_code", "wall_s", "cpu_s", "runtime_ratio", "mps", "energy_error",
           "error", "err_self", "err_F_L2", "err_F_smooth", "noise", "err_energy_50", "force_mean",
           "force_over_fe", "force_over_dh", "err_F_smooth_self", "kinetic_over_plastic",
           "energy_50", "energy_50_dh", "err_duration", "err_cor", "err_peak", "duration", "cor",
           "peak_10us", "v_impact", "impulse", "err_arrival", "err_speed", "wave_speed",
           "speed_bar", "speed_plate"]


def point_row(level: str, scene: str, p: Point) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """The table's row of run p from its folder (before the errors), with its metrics (None
    when it did not finish); its curve written to the level's curves/."""
    curves = out_dir(level) / "curves"
    folder = RUNS / p.name
    res = batch.result_of(folder)
    if res is not None and res.get("input_hash") != batch.input_hash(p.case()):
        res = {"exit_code": None, "stale": True}   # an older design's run: not scored
    summ = batch.read_summary(folder) if res is not None and not res.get("stale") else {}
    row: dict[str, Any] = {"scene": scene, "name": p.name, **p.labels()}
    row["particles"] = summ.get("particles", p.particles())
    row["steps"] = summ.get("steps", "")
    row["status"] = summ.get("status", "not run" if res is None else
                             "stale input" if res.get("stale") else "no summary")
    row["exit_code"] = "" if res is None else res.get("exit_code")
    if res is not None and summ and res.get("cpu_s") is not None:
        cpu = float(res["cpu_s"])
        row["wall_s"] = round(float(res["wall_s"]), 2)
        row["cpu_s"] = round(cpu, 2)
        row["runtime_ratio"] = float(summ["sim_time"]) / cpu if cpu > 0 else math.nan
        row["mps"] = float(summ["particles"]) * float(summ["steps"]) / cpu / 1e6
        row["energy_error"] = summ.get("energy_error", "")
    m = None
    if res is not None and res.get("exit_code") == 0:
        inputs = namelist.read_namelist(folder / "case.nml")
        m = METRICS[scene](folder, inputs)
        row.update({k: v for k, v in m.items() if np.isscalar(v)})
        np.savetxt(curves / f"{p.name}.csv", np.column_stack([m["curve_x"], m["curve_y"]]),
                   delimiter=",", header="x,y", comments="", fmt="%.7g")
    else:
        (curves / f"{p.name}.csv").unlink(missing_ok=True)   # an older run's curve
    return row, m


def collect(level: str, points: dict[str, list[Point]]) -> tuple[list[dict[str, Any]],
                                                                 dict[str, Any]]:
    """Rows of the table and the Richardson estimates, from the run folders."""
    rows: list[dict[str, Any]] = []
    extra: dict[str, Any] = {}
    curves = out_dir(level) / "curves"
    curves.mkdir(parents=True, exist_ok=True)
    # curves of runs no longer in the level's design (or not finished) are not kept
    wanted = {p.name for pts in points.values() for p in pts}
    for old in curves.glob("*.csv"):
        if old.stem not in wanted and old.stem.split("_")[0] in points:
            old.unlink()
    crush_ref: tuple[str, dict[str, Any] | None] = ("", None)
    for scene, pts in points.items():
        metrics: dict[str, dict[str, Any]] = {}
        base_rows: dict[str, dict[str, Any]] = {}
        for p in pts:
            row, m = point_row(level, scene, p)
            if m is not None:
                metrics[p.name] = m
            base_rows[p.name] = row
            rows.append(row)
        ref = pts[0]
        ref_name, ref_m = ref.name, metrics.get(ref.name)
        if scene == "crush":
            crush_ref = (ref_name, ref_m)
        elif scene == "crush_fixed":          # the same curve: the crush's finest run
            ref_name, ref_m = crush_ref
        fe = fe_metrics() if scene in CRUSH_SCENES else fe_dynamic(scene)
        if ref_m is not None or fe is not None:
            for name, row in base_rows.items():
                if scene == "impact" and row["speed"] != ref.speed:
                    continue                   # no reference at other impact speeds
                row["reference"] = ((FE_REFERENCE if scene in CRUSH_SCENES else
                                     FE_DYNAMIC_REFERENCE) if fe is not None else ref_name)
                row["self_reference"] = ref_name
                if name in metrics:
                    row.update(errors(scene, metrics[name], ref_m, fe))
        # Richardson over h at the reference's n_t (h/t = 4 h_ref, 2 h_ref, h_ref)
        hs = [ref.h_over_t * 4, ref.h_over_t * 2, ref.h_over_t]
        names = [Point(scene, h_over_t=h, n_t=ref.n_t, cfl=ref.cfl).name for h in hs]
        if all(n in metrics for n in names):
            keys = {"crush": ["force_mean", "energy_50"],
                    "impact": ["duration", "cor", "peak_10us"], "wave": ["wave_speed"]}[scene]
            extra[scene] = {k: {**richardson(*[metrics[n][k] for n in names]),
                                "values": [metrics[n][k] for n in names],
                                "h_over_t": hs} for k in keys}
    return rows, extra


def write_table(level: str, rows: list[dict[str, Any]], extra: dict[str, Any]) -> Path:
    out = out_dir(level)
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"study_{level}.csv"
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    def clean(x: Any) -> Any:                       # strict JSON: NaN as null
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items()}
        if isinstance(x, list):
            return [clean(v) for v in x]
        return None if isinstance(x, float) and not math.isfinite(x) else x
    (out / f"richardson_{level}.json").write_text(json.dumps(clean(extra), indent=1) + "\n")
    return path


def remeasure(level: str, rows: list[dict[str, str]], scenes: list[str]) -> int:
    """The rows of `scenes` whose run folders hold a finished run of the design's input:
    their metrics and energy error measured again (METRICS, e.g. the wave's arrivals at the FE
    reference's levels), their curves rewritten. The cost columns keep the table's (the same
    steps; timings on a busy machine would not compare with the other rows'). Returns how
    many."""
    points = {p.name: p for pts in design(level).values() for p in pts}
    curves = out_dir(level) / "curves"
    n = 0
    for r in rows:
        p = points.get(r["name"])
        if r["scene"] not in scenes or p is None or r.get("status") != "completed":
            continue
        folder = RUNS / p.name
        res = batch.result_of(folder)
        if res is None or res.get("exit_code") != 0 or \
                res.get("input_hash") != batch.input_hash(p.case()):
            continue
        m = METRICS[r["scene"]](folder, namelist.read_namelist(folder / "case.nml"))
        m["energy_error"] = float(batch.read_summary(folder).get("energy_error", math.nan))
        r.update({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in m.items()
                  if np.isscalar(v) and k in COLUMNS})
        np.savetxt(curves / f"{p.name}.csv", np.column_stack([m["curve_x"], m["curve_y"]]),
                   delimiter=",", header="x,y", comments="", fmt="%.7g")
        n += 1
    return n


def add_rows(level: str, rows: list[dict[str, str]], scenes: list[str]) -> int:
    """The design's runs of `scenes` that the table has no row for (a setting added to the
    design), from their finished runs in out/study (point_row), each after its scene's last
    row; their errors follow in rejudge. Returns how many."""
    have = {r["name"] for r in rows}
    n = 0
    for scene, pts in design(level).items():
        if scene not in scenes:
            continue
        for p in pts:
            if p.name in have:
                continue
            row, m = point_row(level, scene, p)
            if m is None:
                continue
            row["self_reference"] = pts[0].name
            last = max(i for i, r in enumerate(rows) if r["scene"] == scene)
            rows.insert(last + 1, {k: (f"{v:.6g}" if isinstance(v, float) else str(v))
                                   for k, v in row.items()})
            n += 1
    return n


def rejudge(level: str, scenes: list[str] | None = None) -> Path:
    """Score the impact and wave rows of the committed table again against the dynamic FE
    reference (fe_dynamic), from the table's metrics and the wave's arrival curves alone: no
    run folder is needed. The crush rows and every other column are kept as written. With
    `scenes`, the rows of those scenes whose runs are in out/study are measured again first
    (remeasure)."""
    path = out_dir(level) / f"study_{level}.csv"
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    if scenes:
        print(f"measured again from their runs: {remeasure(level, rows, scenes)} rows")
        print(f"added from their runs: {add_rows(level, rows, scenes)} rows")
    curves = out_dir(level) / "curves"
    byname = {r["name"]: r for r in rows}

    def metrics(r: dict[str, str]) -> dict[str, Any] | None:
        if r.get("status") != "completed":
            return None
        if r["scene"] == "impact":
            vals = {k: float(r[k]) if r.get(k) not in (None, "") else math.nan
                    for k in ("duration", "cor", "peak_10us")}
            return vals
        c = curves / f"{r['name']}.csv"
        if not c.is_file():
            return None
        a = np.loadtxt(c, delimiter=",", skiprows=1, ndmin=2)
        return {"curve_x": a[:, 0], "arrivals": a[:, 1],
                "wave_speed": float(r["wave_speed"]) if r.get("wave_speed") else math.nan}
    keys = ("err_duration", "err_cor", "err_peak", "err_arrival", "err_speed", "error",
            "err_self")
    ref_metrics: dict[str, dict[str, Any] | None] = {}
    for scene in ("impact", "wave"):
        fe = fe_dynamic(scene)
        if fe is None:
            continue
        for r in rows:
            if r["scene"] != scene or (scene == "impact" and float(r["speed"] or 0) != 30.0):
                continue
            m = metrics(r)
            if m is None:
                continue
            name = r.get("self_reference", "")
            if name not in ref_metrics:            # one reading of the finest run's curve
                ref_metrics[name] = metrics(byname[name]) if name in byname else None
            e = errors(scene, m, ref_metrics[name], fe)
            r["reference"] = FE_DYNAMIC_REFERENCE
            for k in keys:
                if k in e:
                    r[k] = f"{e[k]:.6g}" if np.isfinite(e[k]) else "nan"
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--level", choices=("quick", "full", "all"), default="quick")
    ap.add_argument("--quick", action="store_const", const="quick", dest="level",
                    help="same as --level quick")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="runs at once (default: the number of cores)")
    ap.add_argument("--tables-only", action="store_true",
                    help="recompute the table from the run folders, run nothing")
    ap.add_argument("--list", action="store_true", help="list the runs and their estimated cost")
    ap.add_argument("--rejudge", action="store_true",
                    help="score the committed table's impact and wave rows again against the "
                         "dynamic FE reference (docs/fe_reference/dynamic_convergence.json), "
                         "from the table and its curves alone; run nothing. With --scenes, "
                         "run those scenes' runs first (not with --tables-only) and measure "
                         "their rows again from the runs")
    ap.add_argument("--scenes", default="",
                    help="comma-separated scenes whose runs to run or list (default: all of the "
                         "level's: crush, impact, wave, and crush_fixed at full and all; the "
                         "table always covers every scene of the level)")
    batch.add_backend_args(ap, threads=False)
    args = ap.parse_args(argv)
    backend = batch.backend_of(args)
    points = design(args.level)
    chosen = [s.strip() for s in args.scenes.split(",") if s.strip()] or list(points)
    unknown = [s for s in chosen if s not in points]
    if unknown:
        ap.error(f"--scenes: unknown scene(s) {', '.join(unknown)}; allowed: "
                 f"{', '.join(points)}")
    allpts = [p for s, pts in points.items() if s in chosen for p in pts]
    if args.rejudge and args.scenes and not args.tables_only:
        binary = batch.private_binary(RUNS)
        batch.run_batch([p.case() for p in sorted(allpts, key=Point.cost)], RUNS,
                        jobs=args.jobs, threads=1, binary=binary)
    if args.rejudge:
        path = rejudge(args.level, chosen if args.scenes else None)
        print(f"rescored the impact and wave rows of {path.relative_to(ROOT)} against "
              f"{FE_DYNAMIC.relative_to(ROOT)}")
        return 0
    if args.list:
        for p in sorted(allpts, key=Point.cost):
            res = batch.result_of(RUNS / p.name)
            done = res is not None and res.get("input_hash") == batch.input_hash(p.case())
            print(f"{p.name:50s} {p.particles():7d} particles {p.steps():9.0f} steps "
                  f"{p.cost() / 2.2e6:8.0f} s{'  done' if done else ''}")
        print(f"{len(allpts)} runs, about {sum(p.cost() for p in allpts) / 2.2e6 / 60:.0f} "
              f"CPU minutes at 2.2 M particle-steps/s")
        return 0
    if not args.tables_only:
        # the longest run first, then the rest cheapest first: the long run overlaps the
        # others, and an interrupted study has finished as many runs as it could
        order = sorted(allpts, key=Point.cost)
        order = order[-1:] + order[:-1]
        cases = [p.case() for p in order]
        where = f"{args.jobs} at once" if backend is None else "on Slurm"
        print(f"study {args.level}: {len(cases)} runs in {RUNS} ({where})", flush=True)
        try:
            # a private copy of the binary: rebuilding bin/ during a long study does not
            # change the runs still to come
            binary = RUNS / "tubempm" if backend is not None and backend.dry_run else \
                batch.private_binary(RUNS)
            res = batch.run_batch(cases, RUNS, jobs=args.jobs, threads=1, binary=binary,
                                  backend=backend)
        except KeyboardInterrupt:
            print("interrupted: finished runs are kept; run again to continue", file=sys.stderr)
            return 130
        if backend is not None and (backend.dry_run or not backend.wait):
            return 0                       # nothing to tabulate yet
        unfinished = [r["name"] for r in res if r.get("exit_code") is None]
        if unfinished:
            print(f"{len(unfinished)} runs did not end on their own (cancelled, or out of "
                  f"time): {', '.join(unfinished[:5])}{' ...' if len(unfinished) > 5 else ''}; "
                  "run again to re-run them", file=sys.stderr)
    rows, extra = collect(args.level, points)
    path = write_table(args.level, rows, extra)
    failed = [r["name"] for r in rows if r.get("exit_code") != 0]
    print(f"wrote {path.relative_to(ROOT)} ({len(rows)} runs; {len(failed)} not run, stale or "
          f"failed)")
    for scene in points:
        # (the crushes' errors are against the FE curve, err_self against the crush's finest
        # run, which crush_fixed shares: its own first run is no reference)
        ref = points["crush" if scene in CRUSH_SCENES and "crush" in points else scene][0]
        against = (f"FE curve {FE_CURVE.relative_to(ROOT)}, err_self against {ref.name}"
                   if scene in CRUSH_SCENES else f"reference {ref.name}")
        rich = ", ".join(f"{k} order {v['order']:.2f} ref error {v['fine_error']:.2%}"
                         for k, v in extra.get(scene, {}).items())
        print(f"  {scene}: errors against the {against}" + (f"; Richardson: {rich}" if rich
                                                             else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
