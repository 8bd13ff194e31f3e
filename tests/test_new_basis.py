#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A basis that no study has run compiles and takes a time step (issue 32, item 4): the
automatic cfl's table (src/method/mpm_time_step_table.inc) is found by the names of the basis
and the scheme, not by their codes. In a scratch folder, mpm_constants gets a new basis put
first in `basis_names` (every code moves by one) and mpm_time_step is compiled against it with
its table as committed; a small program then checks that

- the new basis takes the fallback, cfl_margin times the smallest cfl the study tried
  (0.5 x 0.125 = 0.0625), and that cfl_study says the studies have not run it;
- 'cpdi2' with 'musl' keeps its own value at its new code: 0.5 x 1.75 = 0.875 for a crush at
  2 particles per cell, the accurate 0.875 for another scene, 0.96875 at 1 particle per cell
  (docs/stability.md, "The automatic cfl"), and a quarter of 0.875 with a wall penalty of 4;
- the time step is cfl h / (c_d + v_max).

A table read by the basis's position would give the new basis 'linear''s value and 'cpdi2'
'cpdi1''s, and fail. Prints `test_new_basis: N passed, M failed` last.

    usage: python3 -m tests.test_new_basis SCRATCH
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from tests.pycheck import Checks

ROOT = Path(__file__).resolve().parent.parent
T = Checks("test_new_basis")
check = T.check

PROGRAM = """program new_basis
  use mpm_kinds, only: wp
  use mpm_constants, only: basis_names, SCHEME_MUSL
  use mpm_time_step, only: cfl_auto, cfl_study, time_step_dt
  implicit none
  real(wp) :: stable, accurate
  logical :: known
  integer :: cpdi2
  cpdi2 = findloc(basis_names, 'cpdi2', 1)
  call cfl_study(1, SCHEME_MUSL, 2.0_wp, stable, accurate, known)
  write(*, '(a, l1, 2es25.17)') 'new known ', known, stable, accurate
  write(*, '(a, es25.17)') 'new auto ', cfl_auto(1, SCHEME_MUSL, 2.0_wp, .true., 1.0_wp)
  write(*, '(a, i0, 4es25.17)') 'cpdi2 ', cpdi2, &
    cfl_auto(cpdi2, SCHEME_MUSL, 2.0_wp, .true., 1.0_wp), &
    cfl_auto(cpdi2, SCHEME_MUSL, 2.0_wp, .false., 1.0_wp), &
    cfl_auto(cpdi2, SCHEME_MUSL, 1.0_wp, .false., 1.0_wp), &
    cfl_auto(cpdi2, SCHEME_MUSL, 2.0_wp, .true., 4.0_wp)
  write(*, '(a, es25.17)') 'dt ', time_step_dt(0.5_wp, 1.0e-3_wp, 5.0e3_wp, 0.0_wp)
end program new_basis
"""


def main() -> int:
    scratch = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    work = scratch / "new_basis"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    text = (ROOT / "src/base/mpm_constants.f90").read_text()
    m = re.search(r"basis_names\((\d+)\) = \[character\(len=(\d+)\) :: &\s*\n(\s*)'", text)
    if not check(m is not None, "mpm_constants: basis_names found"):
        return T.summary()
    n, width, indent = int(m[1]), int(m[2]), m[3]
    text = text.replace(m[0], f"basis_names({n + 1}) = [character(len={max(width, 8)}) :: &\n"
                              f"{indent}'newbasis', '")
    (work / "mpm_constants.f90").write_text(text)
    for f in ("src/base/mpm_kinds.f90", "src/method/mpm_time_step.f90",
              "src/method/mpm_time_step_table.inc"):
        shutil.copy(ROOT / f, work)
    (work / "new_basis.f90").write_text(PROGRAM)
    cmd = ["gfortran", "-std=f2008", "-fimplicit-none", "-o", "new_basis", "mpm_kinds.f90",
           "mpm_constants.f90", "mpm_time_step.f90", "new_basis.f90"]
    r = subprocess.run(cmd, cwd=work, capture_output=True, text=True)
    if not check(r.returncode == 0, f"mpm_time_step compiles with a new basis:\n{r.stderr}"):
        return T.summary()
    out = subprocess.run(["./new_basis"], cwd=work, capture_output=True, text=True).stdout
    got = {line.split()[0]: line.split()[1:] for line in out.splitlines() if line.strip()}
    known = out.split("new known ")[1].split()[0] if "new known " in out else "?"
    check(known == "F", f"cfl_study: known = {known} for the new basis (expected F)")
    auto = [float(x) for x in out.split("new auto ")[1].split()[:1]] if "new auto" in out else []
    check(auto == [0.0625], f"the new basis's automatic cfl: {auto}, expected [0.0625]")
    c = got.get("cpdi2", [])
    check(c[:1] == ["5"], f"cpdi2 moved to code 5: {c[:1]}")
    check([float(x) for x in c[1:]] == [0.875, 0.875, 0.96875, 0.875 / 4],
          f"cpdi2 + musl keeps its values by name (crush, impact, 1 per cell; crush with "
          f"&wall penalty 4: divided by 4): {c[1:]}")
    dt = [float(x) for x in got.get("dt", [])]
    check(dt == [0.5 * 1.0e-3 / 5.0e3], f"dt = cfl h / (c_d + v_max): {dt}")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
