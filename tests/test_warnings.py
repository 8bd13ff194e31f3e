#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Warnings a person reads at a glance (issue 32, item 6): cases made to draw every warning of
`tubempm --check` (the reader's and the advice's) print each one as one line of about 120
characters (130 at most, the input file's path not counted), which says what to set (`Set ...`
or `Delete ...`) and ends with the doc section that explains it, `(docs/<file>.md#<section>)`. Each case
must draw the warnings it was made for, so that a warning that disappears is seen too.
Binary: TUBEMPM. Prints `test_warnings: N passed, M failed` last.

    usage: TUBEMPM=build/debug/tubempm python3 -m tests.test_warnings SCRATCH
"""
from __future__ import annotations

import os
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from plots.mpmplot import namelist
from tests.pycheck import Checks
from tools.fe_reference import square_speed

ROOT = Path(__file__).resolve().parent.parent
BIN = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
T = Checks("test_warnings")
check = T.check

RING = """&run t_end = 2.0e-3{run} /
&solver deterministic = .false.{solver} /
&grid h = {h} /
&material name = 'alu', E = 70e9, nu = 0.33, rho = 2700, sigma_y = 150e6{mat} /
&body center = 0.0, 0.0265, r_inner = 24.0e-3, r_outer = 26.0e-3, n_thick = {nt}{body} /
&wall point = 0, 0, normal = 0, 1{wall} /
"""

#: a half square tube filled with foam that touches it, basis 'ugimp' at the automatic cfl
FILLER = """&run t_end = 1.0e-4 /
&solver basis = 'ugimp', mass_scale = 4.0 /
&grid h = 1.0e-3 /
&material name = 'al', E = 70.0e9, nu = 0.33, rho = 2700.0, sigma_y = 150.0e6 /
&material name = 'foam', model = 'foam', E = 1.0e9, nu = 0.3, rho = 230.0, sigma_p = 1.6e6,
  nu_plastic = 0.0, eps_d = 2.46 /
&body shape = 'tube', vertices = -10.0e-3, 1.0e-3, 10.0e-3, 1.0e-3, 10.0e-3, 21.0e-3,
  -10.0e-3, 21.0e-3, center = 0.0, 11.0e-3, thickness = 2.0e-3, corner_radius = 2.0e-3,
  n_thick = 4, sector = 'half' /
&body shape = 'filler', material = 'foam', fills = 1, n_thick = 12, sector = 'half' /
&contact bodies = 1, 2, law = 'coulomb', friction = 0.3 /
&wall point = 0.0, 22.1e-3, normal = 0.0, -1.0, velocity = 0.0, -10.0, ramp = 2.0e-5 /
&wall point = 0.0, -0.1e-3, normal = 0.0, 1.0 /
"""

#: (name, the case's substitutions, texts that its warnings must hold); substitutions with
#: `text` give the whole case

CASES = [
    ("coarse", dict(solver=", basis = 'linear', scheme = 'usl', flip = 0.95", h="2.0e-3", nt=2,
                    wall=", velocity = 0, 30, ramp = 1e-4, motion_t = 0, 1e-4, motion_f = 0, 1"),
     ["ramp = 1e-4", "h >= wall t", "n_thick = 2 locks", "failed at every cfl",
      "scheme 'usl'", "basis 'linear'", "flip = ", "delta/D reaches"]),
    ("crush", dict(run=", cfl = 1.99", h="0.74e-3", nt=4, solver="",
                   wall=", velocity = 0, 30"),
     ["h/t = 0.37", "not quasi-static", "cfl 1.99 > "]),
    ("fbar", dict(solver=", volumetric = 'fbar'", h="0.5e-3", nt=2, run=", dt = 5e-8"),
     ["particles per cell", "dt = "]),
    ("fbarwall", dict(solver=", volumetric = 'fbarwall'", h="0.5e-3", nt=2),
     ["changes nothing with n_thick = 2"]),
    ("fbarwall8", dict(solver=", volumetric = 'fbarwall'", h="0.25e-3", nt=8,
                       body=", n_circ = 100"),
     ["'fbarwall' with n_thick = 8", "aspect"]),
    ("reader", dict(mat=", model = 'elastic', rate_law = 'cowper_symonds', jc_b = 1e8",
                    body=", size = 1, 1, n_x = 2", h="0.5e-3", nt=8,
                    wall=", friction = 0, friction = 0"),
     ["sigma_y = 150e6", "rate_law = ", "jc_* need", "size, n_x are ignored",
      "given again"]),
    ("units", dict(run=", check_units = .false.", mat=", rho = 7.8", h="0.5e-3", nt=4),
     ["rho = 7.8"]),
    ("long", dict(run=", t_end = 10.0", h="0.5e-3", nt=8), ["will take about"]),
    ("penalty", dict(run=", cfl = 0.5", h="0.5e-3", nt=8, wall=", penalty = 4.0"),
     ["over &wall penalty"]),
    ("filler", dict(text=FILLER), ["filler touching its tube with 'ugimp'",
                                   "sector is ignored for shape = 'filler'"]),
]


def case_text(subs: dict) -> str:
    if "text" in subs:
        return subs["text"]
    d = dict(run="", solver="", h="0.5e-3", mat="", nt=4, body="", wall="")
    d.update(subs)
    text = RING.format(**d)
    text = text.replace("t_end = 2.0e-3, t_end = 10.0", "t_end = 10.0")
    text = text.replace("rho = 2700, sigma_y = 150e6, rho = 7.8", "rho = 7.8, sigma_y = 150e6")
    return text


def square_tube(scratch: Path) -> None:
    """The quasi-static warning of a 'tube' (docs/validation.md#quasi-static): the shipped
    square tube at 2 m/s relative approach has none; at 4 m/s it warns with the ratio to
    H omega_1, worked out from the namelist by tools/fe_reference/square_speed.py (h_omega, the
    calibration's): a 48 mm centreline square, t 1.5 mm, so H = 49.5 mm; its longest wall L = a
    side's straight 42 mm and half of each rounded corner (r 3 mm on the centreline), omega_1 =
    pi^2 sqrt(E' t^3 / 12 / (rho t L^4))."""
    text = (ROOT / "namelists" / "sections" / "square_tube.nml").read_text()
    # crushed flat: H = 49.5 mm less two walls of 1.5 mm is 46.5 mm; the quarter model's
    # platen stroke of 23.5 mm is an approach of 47 mm, 23 mm one of 46 mm
    for stroke, warned in ((23.0e-3, False), (23.5e-3, True)):
        path = scratch / f"warn_square_flat_{stroke * 1e3:g}.nml"
        path.write_text(text.replace("stroke = 12.375e-3", f"stroke = {stroke}"))
        p = subprocess.run([BIN, "--check", str(path)], capture_output=True, text=True,
                           timeout=120)
        lines = [ln for ln in p.stderr.splitlines() if "height - 2t" in ln]
        check(p.returncode == 0 and bool(lines) == warned and
              (not warned or ("height - 2t, 4.65E-02 m. Set" in lines[0] and len(lines[0]) <= 120)),
              f"square tube, approach {2 * stroke * 1e3:g} mm: warned of solid walls "
              f"{'(expected)' if warned else '(not expected)'}: {lines}")
    for v, warned in ((1.0, False), (2.0, True)):
        path = scratch / f"warn_square_{v:g}.nml"
        path.write_text(text.replace("velocity = 0.0, -1.0", f"velocity = 0.0, -{v}"))
        p = subprocess.run([BIN, "--check", str(path)], capture_output=True, text=True,
                           timeout=120)
        lines = [ln for ln in p.stderr.splitlines() if "not quasi-static" in ln]
        check(bool(lines) == warned, f"square tube at {2 * v:g} m/s: quasi-static warning "
              f"{'expected' if warned else 'not expected'}: {lines}")
        if not (warned and lines):
            continue
        want = 2 * v / square_speed.h_omega(namelist.read_namelist(path))
        m = re.search(r"\(([0-9.]+) H omega_1\)", lines[0])
        got = float(m.group(1)) if m else math.nan
        check(abs(got - want) <= 0.02 * want + 5e-5, f"square tube: ratio {got} against "
              f"{want:.5f} worked out from the section")


def main() -> int:
    scratch = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    scratch.mkdir(parents=True, exist_ok=True)
    doc = re.compile(r"\(docs/([\w/]+\.md)#([\w-]+)\)$")
    seen = 0
    for name, subs, wanted in CASES:
        path = scratch / f"warn_{name}.nml"
        path.write_text(case_text(subs))
        p = subprocess.run([BIN, "--check", str(path)], capture_output=True, text=True,
                           timeout=120)
        lines = [ln for ln in p.stderr.splitlines() if ln.startswith("WARNING")]
        check(p.returncode == 0, f"{name}: --check exits 0 ({p.returncode}): {p.stderr[:400]}")
        for want in wanted:
            check(any(want in ln for ln in lines), f"{name}: a warning holds {want!r}: {lines}")
        for ln in lines:
            seen += 1
            short = ln.replace(str(path), "")
            check(len(short) <= 130, f"{name}: {len(short)} characters: {ln}")
            check(" Set " in ln or ". Delete " in ln, f"{name}: says what to set: {ln}")
            m = doc.search(ln)
            check(m is not None and (ROOT / "docs" / m.group(1)).is_file(),
                  f"{name}: ends with its doc section: {ln}")
    check(seen >= 20, f"{seen} warnings seen (20 or more expected)")
    square_tube(scratch)
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
