#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""How much the `make BUILD=native` profile (-march=native: AVX2, FMA contraction) changes
results against the portable release build (docs/performance.md, "Build profiles").

Builds both binaries (make BUILD=release and BUILD=native; incremental), runs three scenes that
are not chaotic over the time run (tests/scenes/elastic_quarter.nml and impact_half.nml,
namelists/wave.nml, each to a quarter of its t_end, one thread) with both, and compares
history.csv: the energies (kinetic, strain, plastic, external) relative to the largest energy of
the run, the wall forces relative to the largest wall force of the run. They must agree to
1e-8 (round-off, grown over thousands of steps, measured 1e-13 to 1e-12); the largest
difference is printed. The chaotic scenes (namelists/impact.nml and crush.nml: contact chatter
amplifies any round-off change) differ by more, as they do for any change of the rounding
(docs/performance.md).

    usage: python3 -m tests.check_native SCRATCH   (make bench runs it first; not in make test)
"""
from __future__ import annotations

import csv
import os
import subprocess
import sys
from pathlib import Path

from tools import check_identical as ci
from tests.pycheck import Checks

ROOT = Path(__file__).resolve().parent.parent

T = Checks("check_native")
check = T.check
TOL = 1.0e-8
CASES = ["tests/scenes/elastic_quarter.nml", "tests/scenes/impact_half.nml",
         "namelists/wave.nml"]
ENERGIES = ("kinetic", "strain", "plastic", "external")


def history(folder: Path) -> tuple[list[str], list[list[float]]]:
    with open(folder / "out" / "history.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], [[float(x) for x in r] for r in rows[1:]]


def largest_difference(a: Path, b: Path) -> tuple[float, str]:
    """Largest difference of the energies (over the largest energy) and of the wall forces
    (over the largest wall force), with the column it is in."""
    head, ra = history(a)
    head_b, rb = history(b)
    if head != head_b or len(ra) != len(rb):
        return float("inf"), "different columns or rows"
    groups = {"energy": [head.index(c) for c in ENERGIES],
              "force": [j for j, c in enumerate(head) if c.startswith("wall")
                        and c.endswith(("_force", "_fx", "_fy"))]}
    worst, where = 0.0, ""
    for cols in groups.values():
        scale = max((abs(r[j]) for r in ra for j in cols), default=0.0)
        if scale == 0.0:
            continue
        for j in cols:
            d = max(abs(x[j] - y[j]) for x, y in zip(ra, rb)) / scale
            if d > worst:
                worst, where = d, head[j]
    return worst, where


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/check_native").resolve()
    scratch.mkdir(parents=True, exist_ok=True)
    bins = {}
    for profile in ("release", "native"):
        rc = subprocess.call(["make", "--no-print-directory", "-C", str(ROOT), "-j2",
                              f"BUILD={profile}", f"build/{profile}/tubempm"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
        if not check(rc == 0, f"make BUILD={profile} failed"):
            return T.summary()
        bins[profile] = str(ROOT / "build" / profile / "tubempm")
    for case in CASES:
        folders = {}
        for profile, binary in bins.items():
            folder = scratch / profile / Path(case).stem
            nml = ci.prepare(str(ROOT / case), str(folder), 0.25)
            rc = ci.run(binary, nml, str(folder))
            check(rc == 0, f"{case}, {profile}: exit {rc}")
            folders[profile] = folder
        d, col = largest_difference(folders["release"], folders["native"])
        print(f"{case}: native - release, largest difference {d:.2e} ({col})")
        check(d <= TOL, f"{case}: native and release differ by {d:.2e} in {col} "
              f"(tolerance {TOL})")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
