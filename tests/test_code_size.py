#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The size limits of docs/architecture.md hold (tools/code_size.py): no file in src/ over 900
lines, no routine over 120 (there is no ceiling on a group of files). The counter itself is checked first on a source whose routines are known: every
`end subroutine` / `end function` of src/ must close a routine it found. Prints
`test_code_size: N passed, M failed` last. Standard library only.
"""
import re
import sys
from pathlib import Path

from tests.pycheck import Checks
from tools import code_size

HERE = Path(__file__).resolve().parent

T = Checks("test_code_size")
check = T.check

SAMPLE = """module m
  implicit none
  interface
    function c_f(x) bind(c)           ! 3 lines
      integer :: c_f, x
    end function c_f
  end interface
contains
  pure integer function f(a) result(b)   ! 4 lines
    integer, intent(in) :: a
    b = a
  end function f
  elemental logical function g(x)        ! 3 lines
    g = x > 0
  end function
  subroutine host(x)                     ! 7 lines, holds an internal routine of 3
    x = 1
  contains
    character(len=4) function inner(y)
      inner = 'abcd'
    end function inner
  end subroutine host
  type(t_t) function mk() result(r)      ! 2 lines
  endfunction mk
  ! subroutine commented_out(x)
  real(wp) function h(x)                 ! 2 lines
  end function
end module m
"""


def main():
    found = {name: n for name, _, n in code_size.routines(SAMPLE)}
    expect = {"c_f": 3, "f": 4, "g": 3, "host": 7, "inner": 3, "mk": 2, "h": 2}
    check(found == expect, f"routines of the sample: {found}, expected {expect}")

    m = code_size.measure()
    check(len(m["modules"]) > 20, f"{len(m['modules'])} files found in src/")
    n_end = 0
    for path, _ in m["modules"]:
        text = Path(code_size.ROOT, path).read_text()
        n_end += len([ln for ln in text.split("\n")
                      if re.match(r"^\s*end\s*(subroutine|function)\b", ln.split("!")[0], re.I)])
    check(n_end == len(m["routines"]),
          f"every end subroutine/function of src/ closes a routine found ({len(m['routines'])} "
          f"routines, {n_end} end lines)")

    for path, n in m["modules"]:
        check(n <= code_size.MODULE_MAX, f"{path}: {n} lines > {code_size.MODULE_MAX}")
    for path, name, n in m["routines"]:
        check(n <= code_size.ROUTINE_MAX, f"{path}: {name}: {n} lines > {code_size.ROUTINE_MAX}")
    check(m["reader"] > 0, f"the input reader src/input/mpm_config*.f90 found ({m['reader']} lines)")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
