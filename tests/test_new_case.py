#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""tools/new_case.py writes cases that tubempm accepts without a warning, with what was asked:

* crush (quarter model): the platen's stroke is half the asked approach (its mirror image
  brings the other half), --check reports delta = the asked stroke, the platen speed is at most
  0.01 D omega_2 (the ring's n = 2 ovalling frequency computed here from Love's formula, not the
  tool's) and 5 m/s, h = t/4 and n_thick = 8;
* drop (half model): the weight's mass and speed as asked, a rigid base, end_at_release;
* shear (full model): the top platen moves sideways at the asked ratio of its downward speed;
  with --fixed both platens are 'bonded' (the tube fixed to them) and --check reports the
  points tied to each;
* --section square (crush, quarter model; drop, half model): shape = 'tube' with the centreline
  square of side D - t resting on y = 0 (its lowest centreline at t/2), the corner radius asked,
  an approach of at most 2 m/s;
* a diameter in millimetres typed as metres is refused with exit 2 and what to type;
* the seven designs of tools/design_example.py (make design-example) pass --check too.
Each case passes `tubempm --check` with exit 0 and no WARNING line.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_new_case SCRATCH
"""
from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from pathlib import Path

from tests.pycheck import Checks, close
from plots.mpmplot import namelist

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_new_case")
check = T.check
EXE = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
TOOL = ["-m", "tools.new_case"]
D, TT = 50.86e-3, 1.48e-3
E, NU, RHO = 210.0e9, 0.3, 7800.0


def make(scratch: Path, name: str, *args: str) -> tuple[Path, dict]:
    out = scratch / f"{name}.nml"
    r = subprocess.run([sys.executable, *TOOL, *args, "--out", str(out)],
                       capture_output=True, text=True, cwd=ROOT)
    check(r.returncode == 0 and out.is_file(), f"{name}: written ({r.stderr.strip()[:200]})")
    return out, (namelist.read_namelist(out) if out.is_file() else {})


def checked(path: Path, name: str) -> str:
    r = subprocess.run([EXE, "--check", str(path)], capture_output=True, text=True)
    check(r.returncode == 0 and "WARNING" not in r.stderr,
          f"{name}: --check exit 0 and no warning (exit {r.returncode}: {r.stderr.strip()[:300]})")
    return r.stdout


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_new_case")
    scratch.mkdir(parents=True, exist_ok=True)
    path, nml = make(scratch, "crush", "crush", "--D", str(D), "--t", str(TT),
                     "--stroke", "30e-3")
    if nml:
        body, wall = nml["body"][0], nml["wall"][0]
        check(body["sector"] == "quarter" and body["n_thick"] == 8 and
              close(nml["grid"][0]["h"], TT / 4, 1e-5), "crush: quarter, n_thick 8, h = t/4")
        check(close(wall["stroke"], 15e-3, 1e-9), f"crush: platen stroke {wall['stroke']} = "
                                                  f"half of 30 mm")
        dm, i = D - TT, TT ** 3 / 12
        omega = math.sqrt(E / (1 - NU ** 2) * i / (RHO * TT * (dm / 2) ** 4) * 4 * 9 / 5)
        v = 2 * abs(wall["velocity"][1])
        check(v <= min(5.0, 0.01 * dm * omega) * (1 + 1e-6),
              f"crush: approach {v:.4g} m/s <= min(5, 0.01 D omega_2 = "
              f"{0.01 * dm * omega:.4g}) m/s")
        out = checked(path, "crush")
        m = re.search(r"delta = ([0-9.E+-]+) m", out)
        check(m is not None and close(float(m.group(1)), 30e-3, 1e-4),
              f"crush: --check reports delta = 30 mm ({m.group(0) if m else out[-300:]})")
    path, nml = make(scratch, "drop", "drop", "--D", "60e-3", "--t", "2e-3", "--material",
                     "aluminium", "--mass", "10", "--speed", "6")
    if nml:
        w = [x for x in nml["wall"] if float(x.get("mass", 0)) > 0]
        check(len(w) == 1 and close(w[0]["mass"], 10.0, 1e-12) and
              close(w[0]["velocity"][1], -6.0, 1e-12) and nml["run"][0]["end_at_release"],
              "drop: one weight of 10 kg at 6 m/s, end_at_release")
        check(nml["body"][0]["sector"] == "half" and len(nml["wall"]) == 2,
              "drop: half model on a rigid base")
        checked(path, "drop")
    path, nml = make(scratch, "shear", "shear", "--D", "50e-3", "--t", "2e-3", "--stroke",
                     "10e-3", "--shear-ratio", "0.5")
    if nml:
        top = nml["wall"][1]
        check(nml["body"][0]["sector"] == "full" and
              close(top["velocity"][0], -0.5 * top["velocity"][1], 1e-9) and
              top["contact"] == "coulomb", "shear: full model, sideways at half the downward "
                                           "speed, loose (coulomb)")
        checked(path, "shear")
    path, nml = make(scratch, "shear_fixed", "shear", "--D", "50e-3", "--t", "2e-3", "--stroke",
                     "10e-3", "--shear-ratio", "0.5", "--fixed")
    if nml:
        laws = [w["contact"] for w in nml["wall"]]
        check(laws == ["bonded", "bonded"] and
              all(float(w.get("friction", 0)) == 0.0 for w in nml["wall"]),
              f"shear --fixed: both platens 'bonded' (Xiang's fixed group): {laws}")
        out = checked(path, "shear --fixed")
        check(out.count("bonded: ") == 2 and "tied" in out,
              "shear --fixed: --check reports the points tied to each platen")
    a, ts, rc = 40e-3, 1.5e-3, 4e-3
    path, nml = make(scratch, "square", "crush", "--section", "square", "--D", str(a), "--t",
                     str(ts), "--corner-radius", str(rc), "--material", "aluminium",
                     "--stroke", "20e-3")
    if nml:
        body, wall = nml["body"][0], nml["wall"][0]
        xs, ys = body["vertices"][0::2], body["vertices"][1::2]
        check(body["shape"] == "tube" and body["sector"] == "quarter" and
              close(max(xs) - min(xs), a - ts, 1e-9) and close(max(ys) - min(ys), a - ts, 1e-9)
              and close(min(ys), ts / 2, 1e-9) and close(body["corner_radius"], rc, 1e-12) and
              close(body["thickness"], ts, 1e-12) and close(body["center"][1], a / 2, 1e-9),
              f"square: a tube of centreline side D - t on y = 0, corner radius {rc}: {body}")
        check(2 * abs(wall["velocity"][1]) <= 2.0 * (1 + 1e-9) and
              close(wall["stroke"], 10e-3, 1e-9), f"square: approach at most 2 m/s, platen "
                                                  f"stroke half of 20 mm ({wall})")
        out = checked(path, "square")
        m = re.search(r"delta = ([0-9.E+-]+) m", out)
        check(m is not None and close(float(m.group(1)), 20e-3, 1e-4),
              f"square: --check reports delta = 20 mm ({m.group(0) if m else out[-300:]})")
    path, nml = make(scratch, "square_drop", "drop", "--section", "square", "--D", str(a),
                     "--t", str(ts), "--material", "aluminium", "--mass", "10", "--speed", "6")
    if nml:
        check(nml["body"][0]["shape"] == "tube" and nml["body"][0]["sector"] == "half" and
              close(nml["body"][0]["corner_radius"], 1.5 * ts, 1e-12),
              "square drop: half model, the default corner radius 1.5 t")
        checked(path, "square drop")
    from tools import design_example  # noqa: PLC0415
    cases = design_example.designs(scratch / "design")
    check(len(cases) == 7, f"design example: 7 designs ({len(cases)})")
    for c in cases:
        checked(c.base, f"design example {c.name}")
    r = subprocess.run([sys.executable, *TOOL, "crush", "--D", "50.86", "--t", "1.48",
                        "--out", str(scratch / "mm.nml")], capture_output=True, text=True,
                       cwd=ROOT)
    check(r.returncode == 2 and "metres" in r.stderr and "Traceback" not in r.stderr,
          f"millimetres as metres refused, saying metres ({r.stderr.strip()[:200]!r})")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
