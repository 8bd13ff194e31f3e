#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write a commented tubempm namelist for a tube absorber from what an engineer knows.

    python3 -m tools.new_case crush --D 50.86e-3 --t 1.48e-3 --material steel --stroke 15e-3
    python3 -m tools.new_case drop  --D 60e-3 --t 2e-3 --material aluminium --mass 10 --speed 6
    python3 -m tools.new_case shear --D 50e-3 --t 2e-3 --material steel --stroke 10e-3 \
        --shear-ratio 0.5 --fixed
    python3 -m tools.new_case crush --section square --D 40e-3 --t 1.5e-3 --corner-radius 4e-3 \
        --material aluminium --stroke 20e-3
    (add --out FILE, default out/<title>.nml; --title; --sigma-y, --hardening, --E, --nu, --rho
     to change the material; --symmetry full|half|quarter)

Load cases:
  crush  two frictionless platens close on the tube to a stroke (the run ends there): the
         quasi-static force-stroke curve, SEA and CFE (docs/output.md, "Results");
  drop   a weight of a given mass and speed falls on the tube lying on a rigid base;
  shear  the top platen moves down and sideways (compression and shear, as Xiang et al.'s
         tests), the tube loose between the platens ('coulomb') or fixed to them (--fixed:
         'bonded').

Sections: --section round (a ring of outer diameter --D) or square (shape = 'tube': a square of
outer side --D, its centreline corners rounded with --corner-radius, default 1.5 t). The case
lies on y = 0 (the vertices of a square are absolute coordinates; its centre is where the
mirror planes of a half or quarter model pass).

The case uses the resolution the refinement study advises (h = t/4, 8 particles through the
wall; docs/validation.md), a platen speed --check calls quasi-static (an approach of at most
0.01 D omega_2, omega_2 the ring's ovalling frequency, and at most 5 m/s; a square tube, whose
flat faces meet the platens all at once, at most 0.004 H omega_1, omega_1 its wall's first
bending mode, and 2 m/s) for crush and shear, and the symmetry
the load case allows (crush: quarter; drop: half; shear: none). Lengths are in metres, masses in
kg for the &run depth (1 m unless --depth): the model is a lateral crush in plane strain, a
section of a long tube. The file is the input; check it with `bin/tubempm --check FILE` and run
it with `bin/tubempm FILE`.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from tools.fe_reference.square_speed import square_h_omega

ROOT = Path(__file__).resolve().parent.parent

#: materials: E [Pa], nu, rho [kg/m^3], sigma_y [Pa], linear hardening [Pa]
MATERIALS = {
    "steel": (210.0e9, 0.3, 7800.0, 310.0e6, 10.0e6),
    "aluminium": (70.0e9, 0.33, 2700.0, 150.0e6, 200.0e6),
}
QUASI_STATIC = 0.01     #: approach / (D omega_2) written (--check warns above 0.012)
QUASI_STATIC_TUBE = 0.004  #: approach / (H omega_1) written for a square (--check: 0.005)
SPEED_MAX = {"round": 5.0, "square": 2.0}  #: the fastest quasi-static approach [m/s]
RAMP_PERIODS = 1.0      #: the platen's ramp in ovalling periods


def ovalling_omega(D: float, t: float, E: float, nu: float, rho: float) -> float:
    """The n = 2 in-plane mode of a thin ring in plane strain [rad/s] (Love; the rule of
    --check): omega^2 = E I n^2 (n^2 - 1)^2 / (rho A R^4 (n^2 + 1))."""
    ei = E * t ** 3 / 12.0 / (1.0 - nu * nu)
    r = 0.5 * D
    return math.sqrt(ei / (rho * t * r ** 4) * 36.0 / 5.0)


def collapse_load(D: float, t: float, sigma_y: float) -> float:
    """Four-hinge collapse load of the ring between plates, plane strain [N per m]."""
    m0 = 2.0 / math.sqrt(3.0) * sigma_y * t * t / 4.0
    return 8.0 * m0 / D


def parse(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=__doc__.split("\n\n", 1)[1])
    p.add_argument("load", choices=("crush", "drop", "shear"), help="the load case")
    p.add_argument("--section", choices=("round", "square"), default="round",
                   help="the tube's section (default round)")
    p.add_argument("--D", type=float, required=True, help="outer diameter, or outer side of a "
                   "square [m]")
    p.add_argument("--t", type=float, required=True, help="wall thickness [m]")
    p.add_argument("--corner-radius", type=float, help="square: corner radius on the wall's "
                   "centreline [m] (default 1.5 t; at least t/2)")
    p.add_argument("--material", choices=sorted(MATERIALS), default="steel")
    for name in ("E", "nu", "rho", "sigma-y", "hardening"):
        p.add_argument(f"--{name}", type=float, help="override the material's value (SI)")
    p.add_argument("--stroke", type=float, help="crush, shear: the platens' approach [m] "
                   "(default 0.6 D)")
    p.add_argument("--mass", type=float, help="drop: the weight [kg, for depth]")
    p.add_argument("--speed", type=float, help="drop: its speed [m/s]; crush, shear: the "
                   "approach speed (default: quasi-static)")
    p.add_argument("--shear-ratio", type=float, default=0.5,
                   help="shear: sideways over downward platen speed (default 0.5)")
    p.add_argument("--fixed", action="store_true", help="shear: the tube bonded to the platens")
    p.add_argument("--friction", type=float, default=0.2, help="shear, loose: Coulomb "
                   "coefficient (default 0.2)")
    p.add_argument("--symmetry", choices=("full", "half", "quarter"),
                   help="model part (default: the load case's)")
    p.add_argument("--depth", type=float, default=1.0, help="tube length [m] (default 1)")
    p.add_argument("--title", help="case title (default <load>_<material>)")
    p.add_argument("--out", help="namelist to write (default out/<title>.nml)")
    a = p.parse_args(argv)
    errors = []
    if not 0.0 < a.t < 0.5 * a.D:
        errors.append(f"--t {a.t}: the wall must be thinner than half the diameter --D {a.D}")
    if a.D > 1.0 or a.t > 0.1:
        errors.append(f"--D {a.D}, --t {a.t}: lengths are in metres (a 50 mm tube: --D 0.05)")
    if a.load == "drop" and not (a.mass and a.mass > 0 and a.speed and a.speed > 0):
        errors.append("drop: give --mass (kg) and --speed (m/s) of the weight")
    if a.load == "drop" and a.symmetry == "quarter":
        errors.append("drop: --symmetry quarter would mirror the weight onto the base; use half")
    if a.load == "shear" and a.symmetry not in (None, "full"):
        errors.append("shear: a sideways platen breaks the mirror symmetry; use full")
    if a.stroke is not None and not 0.0 < a.stroke < a.D - 2.0 * a.t:
        errors.append(f"--stroke {a.stroke}: between 0 and {a.D - 2.0 * a.t:.6g} m, the "
                      f"height --D {a.D} less the two walls that meet")
    if a.corner_radius is not None and a.section != "square":
        errors.append("--corner-radius is for --section square")
    if a.section == "square":
        side = a.D - a.t
        if a.corner_radius is None:
            a.corner_radius = 1.5 * a.t
        if not 0.5 * a.t <= a.corner_radius < 0.5 * side:
            errors.append(f"--corner-radius {a.corner_radius}: from t/2 = {0.5 * a.t:.6g} to "
                          f"below half the centreline side {0.5 * side:.6g} m")
    if errors:
        for e in errors:
            print(f"ERROR [new_case]: {e}", file=sys.stderr)
        sys.exit(2)
    return a


def material(a: argparse.Namespace) -> tuple[float, float, float, float, float]:
    E, nu, rho, sy, hard = MATERIALS[a.material]
    return (a.E or E, a.nu if a.nu is not None else nu, a.rho or rho,
            a.sigma_y or sy, a.hardening if a.hardening is not None else hard)


def render(a: argparse.Namespace) -> tuple[str, str]:
    E, nu, rho, sy, hard = material(a)
    ro, t = 0.5 * a.D, a.t
    dm = a.D - t                                   # mean diameter
    h = t / 4.0
    omega = ovalling_omega(dm, t, E, nu, rho)
    ramp = RAMP_PERIODS * 2.0 * math.pi / omega
    title = a.title or f"{a.load}_{a.material}"
    sym = a.symmetry or {"crush": "quarter", "drop": "half", "shear": "full"}[a.load]
    cy = ro
    shape = (f"outer diameter {a.D * 1e3:.4g} mm" if a.section == "round" else
             f"square, outer side {a.D * 1e3:.4g} mm, corners of {a.corner_radius * 1e3:.4g} mm "
             f"radius on the centreline ({(a.corner_radius + 0.5 * a.t) * 1e3:.4g} mm outside)")
    lines = [f"! {title}: written by tools/new_case.py {a.load} (docs/tutorial.md).",
             f"! Tube: {shape}, wall {t * 1e3:.4g} mm "
             f"(D/t = {a.D / t:.3g}), {a.material} (E {E / 1e9:.4g} GPa, sigma_y "
             f"{sy / 1e6:.4g} MPa, hardening {hard / 1e6:.4g} MPa), a lateral crush in plane "
             f"strain, {a.depth:g} m long.",
             "! Resolution as the refinement study advises: h = t/4, 8 particles through the",
             "! wall (docs/validation.md). Units are SI (m, kg, s, Pa); docs/input.md has every",
             "! variable."]
    run = [f"  title = '{title}'", f"  depth = {a.depth:g}                   ! tube length [m]"]
    walls: list[str] = []
    stroke = a.stroke if a.stroke is not None else 0.6 * a.D
    if a.load in ("crush", "shear"):
        v_qs = min(SPEED_MAX[a.section], QUASI_STATIC * dm * omega)
        if a.section == "square":                  # --check: 0.005 H omega_1 for a 'tube'
            v_qs = min(SPEED_MAX["square"],
                       QUASI_STATIC_TUBE * square_h_omega(dm, t, a.corner_radius, E, nu, rho))
        v = a.speed if a.speed else v_qs
        lines.append(f"! The platens approach at {v:.3g} m/s (quasi-static: at most "
                     f"{v_qs:.3g} m/s for this tube) to a stroke of {stroke * 1e3:.4g} mm "
                     f"(delta/D = {stroke / dm:.3g}); the run ends there.")
        per_wall = v / 2.0 if sym == "quarter" else v
        travel = stroke / 2.0 if sym == "quarter" else stroke
        hist = max(stroke / v / 400.0, 1.0e-7)
        run += [f"  history_every = {hist:.3g}        ! interval of history.csv rows [s]",
                f"  snapshot_every = {(travel / per_wall + ramp) / 10:.3g}       ! [s]"]
        if a.load == "crush":
            walls.append(wall_text("top platen", (0.0, 2 * ro), (0.0, -1.0), "frictionless",
                                   (0.0, -per_wall), ramp=ramp, stroke=travel))
            if sym == "full":
                cy = ro
            if sym in ("full", "half"):
                walls.insert(0, wall_text("bottom platen (fixed)", (0.0, 0.0), (0.0, 1.0),
                                          "frictionless", None))
        else:
            law = "bonded" if a.fixed else "coulomb"
            vx = a.shear_ratio * per_wall
            lines.append(f"! The top platen also moves sideways at {vx:.3g} m/s; the tube is "
                         + ("bonded to both platens (Xiang's fixed group)." if a.fixed else
                            f"loose between them (Coulomb friction {a.friction:g})."))
            fr = None if a.fixed else a.friction
            walls.append(wall_text("bottom platen (fixed)", (0.0, 0.0), (0.0, 1.0), law, None,
                                   friction=fr))
            walls.append(wall_text("top platen", (0.0, 2 * ro), (0.0, -1.0), law,
                                   (vx, -per_wall), ramp=ramp, stroke=travel, friction=fr))
    else:
        energy = 0.5 * a.mass * a.speed ** 2
        p0 = collapse_load(dm, t, sy) * a.depth
        est = energy / p0                          # rigid-plastic stroke estimate [m]
        t_end = 2.5 * min(est, 0.8 * dm) / a.speed + 4.0 * ramp
        lines.append(f"! A {a.mass:g} kg weight strikes the tube at {a.speed:g} m/s "
                     f"({energy:.4g} J); the tube lies on a rigid base. The run ends once the "
                     f"weight has left or at t_end.")
        if a.section == "round":
            lines.append(f"! A rigid-plastic estimate of the stroke is {est * 1e3:.3g} mm "
                         f"(energy / collapse load {p0 / 1e3:.3g} kN).")
        else:                                      # (t_end from the ring's rule: an upper bound)
            lines.append(f"! t_end allows for a stroke of {min(est, 0.8 * dm) * 1e3:.3g} mm; "
                         f"a square's flat faces carry more than a ring's collapse load.")
        if est > 0.8 * dm and a.section == "round":
            lines.append("! The estimate exceeds 0.8 D: the tube would be crushed flat; "
                         "--check warns of the full crush.")
        run += [f"  t_end = {t_end:.3g}                ! at most [s]",
                "  end_at_release = .true.       ! end once the weight has left",
                "  history_every = 1.0e-6        ! [s]: the peak force is read at these rows",
                "  cfl = 0.8                     ! the study's impact setting (docs/validation.md)",
                f"  snapshot_every = {t_end / 10:.3g}      ! [s]",
                "  gravity = 0.0, -9.81          ! [m/s^2]"]
        walls.append(wall_text("rigid base", (0.0, 0.0), (0.0, 1.0), "frictionless", None))
        walls.append(wall_text("drop weight", (0.0, 2 * ro), (0.0, -1.0), "frictionless",
                               (0.0, -a.speed), mass=a.mass))
    if sym == "quarter":
        lines.append("! A quarter of the tube is modelled (x >= 0, y >= centre): the bottom "
                     "platen is the top one's mirror image.")
    elif sym == "half":
        lines.append("! Half the tube is modelled (x >= 0); outputs are the whole tube's.")
    text = "\n".join(lines) + "\n\n&run\n" + "\n".join(run) + "\n/\n\n"
    fbar = ("  volumetric = 'fbar'           ! the study's 5 % setting of an impact\n"
            if a.load == "drop" else "")
    text += ("&solver\n  basis = 'cpdi2'\n  scheme = 'musl'\n  plane = 'strain'\n" + fbar +
             "/\n\n"
             f"&grid\n  h = {h:.6g}                 ! cell size [m] = t/4\n/\n\n"
             f"&material\n  name = '{a.material}'\n  model = 'j2'\n  E = {E:.6g}\n"
             f"  nu = {nu:g}\n  rho = {rho:g}\n  sigma_y = {sy:.6g}\n"
             f"  hardening = {hard:.6g}\n/\n\n"
             + body_text(a, cy, sym))
    text += "".join("\n" + w for w in walls)
    return title, text


def body_text(a: argparse.Namespace, cy: float, sym: str) -> str:
    """The &body group: a ring, or a square tube (its centreline polygon in absolute
    coordinates, counter-clockwise), resting on y = 0 with its centre at (0, cy)."""
    head = f"&body\n  shape = '{'ring' if a.section == 'round' else 'tube'}'\n" \
           f"  material = '{a.material}'\n  center = 0.0, {cy:.6g}       ! resting on y = 0 [m]\n"
    if a.section == "round":
        geometry = f"  r_inner = {0.5 * a.D - a.t:.6g}\n  r_outer = {0.5 * a.D:.6g}\n"
    else:
        c = 0.5 * (a.D - a.t)                     # half the centreline side
        pts = [(-c, cy - c), (c, cy - c), (c, cy + c), (-c, cy + c)]
        geometry = ("  vertices = " + ",  ".join(f"{x:.6g}, {y:.6g}" for x, y in pts) +
                    "   ! centreline corners [m]\n"
                    f"  thickness = {a.t:.6g}\n"
                    f"  corner_radius = {a.corner_radius:.6g}   ! on the centreline [m]\n")
    return head + geometry + f"  n_thick = 8\n  sector = '{sym}'\n/\n"


def wall_text(what: str, point: tuple[float, float], normal: tuple[float, float], law: str,
              velocity: tuple[float, float] | None, ramp: float = 0.0, stroke: float = 0.0,
              mass: float = 0.0, friction: float | None = None) -> str:
    out = [f"&wall                           ! {what}",
           f"  point = {point[0]:.6g}, {point[1]:.6g}",
           f"  normal = {normal[0]:g}, {normal[1]:g}", f"  contact = '{law}'"]
    if friction:
        out.append(f"  friction = {friction:g}")
    if velocity is not None:
        out.append(f"  velocity = {velocity[0]:.6g}, {velocity[1]:.6g}   ! [m/s]")
    if ramp > 0.0:
        out.append(f"  ramp = {ramp:.3g}                ! smooth start [s]")
    if stroke > 0.0:
        out.append(f"  stroke = {stroke:.6g}           ! travel, then at rest [m]")
    if mass > 0.0:
        out.append(f"  mass = {mass:g}                   ! a free rigid body [kg]")
    return "\n".join(out) + "\n/\n"


def main(argv: list[str] | None = None) -> int:
    a = parse(argv)
    title, text = render(a)
    out = Path(a.out) if a.out else ROOT / "out" / f"{title}.nml"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(f"wrote {out}\ncheck it with: bin/tubempm --check {out}\nrun it with:   "
          f"bin/tubempm {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
