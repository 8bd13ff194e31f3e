#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Scene fuzzer: valid but extreme scenes, run to their end (the namelist fuzzer,
tools/fuzz_namelists.py, only checks inputs).

A run passes when it exits 0, or exits 2 (refused input) or 4 (numerical failure) with at
least one line starting `ERROR [` on standard error, within the time limit, and prints no
runtime report: no `Fortran runtime error`, no `AddressSanitizer`/`runtime error:` of the
sanitizer build (make test BUILD=asan), no backtrace. Anything else (exit 1 or 3, a signal,
a hang, a report) fails, and the scene is kept in the output folder for reproduction.

    python3 -m tools.fuzz_scenes --bin build/debug/tubempm --count 12 --seed 1 --out DIR

Kinds of scene, in turn:
  edge    a ring or rectangle in a fixed grid with 0 to 2 cells of room, moving towards its edge
  fly     a fast body (300 to 3000 m/s) leaving its fitted grid
  sweep   a platen driven 0.2 to 1.2 diameters through a ring at 500 to 5000 m/s
  tiny    one or two particles through the wall, rectangles of 1 x 1 to 2 x 3 particles
  huge    up to 2e5 particles for two steps, under a memory limit (TUBEMPM_MEMORY_LIMIT) that
          some of them exceed (refused, exit 2)
  mixed   a random basis, scheme, flip, plane, sector, gravity, damping, mass_scale, fixed dt,
          several bodies, friction and motion tables
  units   lengths in millimetres typed as metres, a cell of a micrometre: within every range
          check, far beyond the machine (to be refused, exit 2)
Every scene is short: t_end is a few to a few tens of time steps at the scene's speed. Runs of
a build without the sanitizer get a 4 GiB address-space limit (ulimit -v), far above what any
scene here may use, so that a case that allocates without bound fails at once (exit 1)
instead of filling the machine.
"""
from __future__ import annotations

import argparse
import math
import os
import random
import re
import resource
import subprocess
import sys
import time

KINDS = ("edge", "fly", "sweep", "tiny", "huge", "mixed", "units")
BASES = ("linear", "ugimp", "cpdi1", "cpdi2")
REPORTS = re.compile(r"Fortran runtime error|AddressSanitizer|LeakSanitizer|runtime error:|"
                     r"Backtrace|ERROR STOP|Segmentation fault|Program received signal")
C_ALU = 6200.0          # dilatational wave speed of the aluminium below [m/s]


def f(x: float) -> str:
    return repr(float(x))


def material(rng: random.Random, name: str = "alu") -> str:
    model = rng.choice(("elastic", "neohookean", "j2", "j2"))
    text = (f"&material name = '{name}', model = '{model}', E = 70.0e9, "
            f"nu = {rng.choice((0.0, 0.33, 0.45))}, rho = 2700.0")
    if model == "j2":
        text += f", sigma_y = {f(rng.choice((50e6, 150e6, 400e6)))}"
        text += f", hardening = {f(rng.choice((0.0, 200e6)))}"
        if rng.random() < 0.3:
            text += ", rate_law = 'cowper_symonds'"
    return text + " /\n"


def t_end_for(h: float, speed: float, steps: int, cfl: float = 0.2) -> float:
    """Simulated time of about `steps` steps of the automatic time step."""
    return steps * cfl * h / (C_ALU + speed)


def ring(center, ri, ro, nt, vel, sector="full", extra="") -> str:
    return (f"&body center = {f(center[0])}, {f(center[1])}, r_inner = {f(ri)}, "
            f"r_outer = {f(ro)}, n_thick = {nt}, sector = '{sector}', "
            f"velocity = {f(vel[0])}, {f(vel[1])}{extra} /\n")


def rect(center, size, nx, ny, vel) -> str:
    return (f"&body shape = 'rect', center = {f(center[0])}, {f(center[1])}, "
            f"size = {f(size[0])}, {f(size[1])}, n_x = {nx}, n_y = {ny}, "
            f"velocity = {f(vel[0])}, {f(vel[1])} /\n")


def scene(kind: str, rng: random.Random, out: str) -> tuple[str, dict]:
    """The text of a scene of this kind, and extra environment variables for its run."""
    env: dict = {}
    h = rng.choice((0.5e-3, 1.0e-3))
    basis = rng.choice(BASES)
    run = f"output_dir = '{out}'"
    solver = f"&solver basis = '{basis}' /\n"
    bodies = walls = ""
    grid = f"&grid h = {f(h)} /\n"
    steps = rng.randint(3, 30)
    speed = 30.0
    if kind == "edge":
        room = rng.choice((0.0, 0.25, 0.5, 1.0, 2.0)) * h
        speed = rng.choice((0.0, 30.0, 300.0))
        ang = rng.uniform(0.0, 2.0 * math.pi)
        vel = (speed * math.cos(ang), speed * math.sin(ang))
        if rng.random() < 0.5:
            bodies = ring((0.0, 0.0), 0.024, 0.026, rng.choice((2, 4)), vel)
            lo, hi = (-0.026, -0.026), (0.026, 0.026)
        else:
            bodies = rect((0.0, 0.0), (0.02, 0.01), 20, 10, vel)
            lo, hi = (-0.01, -0.005), (0.01, 0.005)
        grid = (f"&grid h = {f(h)}, lower = {f(lo[0] - room)}, {f(lo[1] - room)}, "
                f"upper = {f(hi[0] + room)}, {f(hi[1] + room)} /\n")
    elif kind == "fly":
        speed = rng.uniform(300.0, 3000.0)
        ang = rng.uniform(0.0, 2.0 * math.pi)
        vel = (speed * math.cos(ang), speed * math.sin(ang))
        bodies = (ring((0.0, 0.0), 0.024, 0.026, 2, vel) if rng.random() < 0.5
                  else rect((0.0, 0.0), (0.004, 0.004), 4, 4, vel))
        steps = rng.randint(20, 120)
        solver = f"&solver basis = '{basis}', scheme = 'musl' /\n"
    elif kind == "sweep":
        speed = rng.choice((500.0, 2000.0, 5000.0))
        bodies = ring((0.0, 0.0265), 0.024, 0.026, rng.choice((2, 4)), (0.0, 0.0),
                      sector=rng.choice(("full", "half", "quarter")))
        walls = (f"&wall point = 0.0, 0.0531, normal = 0.0, -1.0, "
                 f"velocity = 0.0, {f(-speed)}, contact = "
                 f"'{rng.choice(('frictionless', 'stick', 'coulomb', 'bonded'))}'"
                 + (", friction = 0.2" if rng.random() < 0.5 else "") + " /\n")
        walls = walls.replace("'stick', friction = 0.2", "'stick'").replace(
            "'frictionless', friction = 0.2", "'frictionless'")
        walls += "&wall point = 0.0, 0.0, normal = 0.0, 1.0 /\n"
        travel = rng.uniform(0.2, 1.2) * 0.053            # through the ring and beyond
        steps = int(travel / (0.2 * h / (C_ALU + speed) * speed)) + 1
    elif kind == "tiny":
        nt = rng.choice((1, 2))
        bodies = ring((0.0, 0.0265), 0.024, 0.026, nt, (0.0, -30.0),
                      sector=rng.choice(("full", "half")),
                      extra=f", n_circ = {rng.choice((0, 4, 8))}")
        if rng.random() < 0.5:
            bodies += rect((0.03, -0.004), (0.004, 0.006), rng.randint(1, 2), rng.randint(1, 3),
                           (0.0, 0.0))
        walls = "&wall point = 0.0, -0.01, normal = 0.0, 1.0 /\n"
    elif kind == "huge":
        n = rng.choice((100, 200, 300, 450))
        h = 0.05 / n
        bodies = rect((0.0, 0.0), (0.05, 0.05), n, n, (0.0, -10.0))
        grid = f"&grid h = {f(h)} /\n"
        steps = 2
        env["TUBEMPM_MEMORY_LIMIT"] = str(rng.choice((60, 150, 400)))
    elif kind == "units":
        pick = rng.randrange(3)
        if pick == 0:                                     # radii in mm
            bodies = ring((0.0, 26.5), 24.0, 26.0, 4, (0.0, -30.0))
        elif pick == 1:                                   # a micrometre cell
            h = 1.0e-6
            grid = f"&grid h = {f(h)} /\n"
            bodies = ring((0.0, 0.0265), 0.024, 0.026, 4, (0.0, -30.0))
        else:                                             # a plate in mm
            bodies = rect((0.0, 0.0), (20.0, 10.0), 20, 10, (0.0, 0.0))
    else:                                                 # mixed
        sector = rng.choice(("full", "half", "quarter"))
        vel = (0.0, -rng.choice((0.0, 10.0, 100.0))) if sector != "quarter" else (0.0, 0.0)
        bodies = ring((0.0, 0.0265), 0.024, 0.026, rng.choice((2, 3, 4)), vel, sector=sector)
        if sector == "full" and rng.random() < 0.5:
            bodies += ring((0.0, 0.08), 0.02, 0.022, 2, (0.0, -50.0))
        gravity = (0.0, -9.81 * rng.choice((0.0, 1.0, 1e5))) if sector != "quarter" else (0, 0)
        run += f", gravity = {f(gravity[0])}, {f(gravity[1])}"
        if rng.random() < 0.3:
            run += f", dt = {f(rng.uniform(0.05, 1.0) * h / 10500.0)}"   # c_d <= 10 km/s
        solver = (f"&solver basis = '{basis}', scheme = '{rng.choice(('usl', 'usf', 'musl'))}'"
                  f", flip = {rng.choice((0.0, 0.5, 1.0))}, plane = "
                  f"'{rng.choice(('strain', 'stress'))}', mass_scale = "
                  f"{rng.choice((1.0, 100.0))}, damping = {rng.choice((0.0, 1e4))}, "
                  f"deterministic = {rng.choice(('T', 'F'))} /\n")
        walls = "&wall point = 0.0, 0.0, normal = 0.0, 1.0 /\n"
        if rng.random() < 0.5:
            walls += ("&wall point = 0.0, 0.0531, normal = 0.0, -1.0, velocity = 0.0, -20.0, "
                      "motion_t = 0.0, 1.0e-6, 2.0e-6, motion_f = 0.0, 1.0, -1.0 /\n")
        speed = 100.0
    run += f", t_end = {f(t_end_for(h, speed, steps))}"
    text = f"&run {run} /\n{solver}{grid}{material(rng)}{bodies}{walls}"
    return text, env


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.environ.get("TUBEMPM", "bin/tubempm"),
                    help="the tubempm binary (default $TUBEMPM or bin/tubempm)")
    ap.add_argument("--count", type=int, default=60, help="scenes (default 60)")
    ap.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    ap.add_argument("--timeout", type=float, default=120.0, help="seconds per run (default 120)")
    ap.add_argument("--out", default="out/fuzz_scenes",
                    help="folder for the scenes and their runs (default out/fuzz_scenes)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rng = random.Random(args.seed)
    with open(args.bin, "rb") as fh:
        sanitized = b"__asan_init" in fh.read()        # the shadow memory needs terabytes

    def limit_memory() -> None:
        if not sanitized:
            resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))

    outcome: dict = {}
    failures = 0
    t0 = time.time()
    for k in range(args.count):
        kind = KINDS[k % len(KINDS)]
        name = f"scene_{k:04d}_{kind}"
        folder = os.path.join(args.out, name)
        text, env = scene(kind, rng, folder)
        path = os.path.join(args.out, name + ".nml")
        with open(path, "w") as fh:
            fh.write(text)
        try:
            r = subprocess.run([args.bin, "--quiet", path], capture_output=True,
                               timeout=args.timeout, preexec_fn=limit_memory,
                               env=dict(os.environ, OMP_NUM_THREADS=str(1 + k % 2), **env))
            err = r.stderr.decode("latin-1") + r.stdout.decode("latin-1")
            has_error = any(ln.startswith("ERROR [") for ln in err.splitlines())
            report = REPORTS.search(err)
            if r.returncode == 0 and not report:
                why = "ok"
            elif r.returncode in (2, 4) and has_error and not report:
                why = f"exit {r.returncode} with a message"
            else:
                why = (f"exit {r.returncode}" + ("" if has_error else " without an ERROR line")
                       + (f" ({report.group(0)})" if report else ""))
        except subprocess.TimeoutExpired:
            why = f"hung past {args.timeout} s"
        outcome[f"{kind}: {why}"] = outcome.get(f"{kind}: {why}", 0) + 1
        if why == "ok" or why.endswith("with a message"):
            os.remove(path)
            subprocess.run(["rm", "-rf", folder])
            continue
        failures += 1
        print(f"FAIL [fuzz_scenes]: {path}: {why}")
    print(f"fuzz_scenes: {args.count} scenes in {time.time() - t0:.1f} s: " +
          ", ".join(f"{v} {k}" for k, v in sorted(outcome.items())))
    print(f"fuzz_scenes: {args.count - failures} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
