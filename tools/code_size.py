#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Size of the Fortran sources: lines per module (file) and per routine against the limits of
docs/architecture.md, and, for information, the lines of each layer folder and of the input
reader (src/input/mpm_config*.f90; no ceiling: the limits are per file and per routine).

    python3 -m tools.code_size           # largest modules and routines, the reader's total
    python3 -m tools.code_size --check   # exit 1 when a limit is passed (tests/test_code_size.py)
    python3 -m tools.code_size --top 20  # more rows

A routine is a subroutine or function from its first line to its `end subroutine` or
`end function` line, both included (internal routines count in their host as well). Lines are
physical lines, comments and blank lines included.
"""
import argparse
import glob
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

MODULE_MAX = 900        # lines of one source file
ROUTINE_MAX = 120       # lines of one routine

_PREFIX = r"(?:(?:pure|elemental|impure|recursive|module)\s+)*"
_TYPE = r"(?:(?:integer|real|logical|complex|character|type|class)\s*(?:\([^()]*(?:\([^()]*\))?[^()]*\))?\s+)?"
START = re.compile(r"^\s*" + _PREFIX + _TYPE + _PREFIX + r"(subroutine|function)\s+(\w+)", re.I)
END = re.compile(r"^\s*end\s*(subroutine|function)\b", re.I)


def routines(text):
    """[(name, first line, lines)] of every subroutine and function of Fortran source text."""
    found, stack = [], []
    for number, line in enumerate(text.split("\n"), 1):
        code = line.split("!", 1)[0]
        if END.match(code):
            if stack:
                name, first = stack.pop()
                found.append((name, first, number - first + 1))
            continue
        m = START.match(code)
        if m and not re.match(r"^\s*end\b", code, re.I):
            stack.append((m.group(2), number))
    return found


def measure(root=ROOT):
    """{'modules': [(path, lines)], 'routines': [(path, name, lines)], 'reader': lines}."""
    modules, rows = [], []
    for path in sorted(glob.glob(os.path.join(root, "src", "**", "*.f90"), recursive=True)):
        with open(path) as f:
            text = f.read()
        rel = os.path.relpath(path, root)
        modules.append((rel, text.count("\n")))
        rows += [(rel, name, n) for name, _, n in routines(text)]
    reader = sum(n for p, n in modules if os.path.basename(p).startswith("mpm_config"))
    return {"modules": modules, "routines": rows, "reader": reader}


def problems(m):
    """Every limit passed, as text ([] when none)."""
    out = [f"{p}: {n} lines (limit {MODULE_MAX})" for p, n in m["modules"] if n > MODULE_MAX]
    out += [f"{p}: {name}: {n} lines (limit {ROUTINE_MAX})" for p, name, n in m["routines"]
            if n > ROUTINE_MAX]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--check", action="store_true", help="exit 1 when a limit is passed")
    ap.add_argument("--top", type=int, default=8, help="rows of each list (default 8)")
    args = ap.parse_args(argv)
    m = measure()
    print(f"modules (limit {MODULE_MAX} lines):")
    for p, n in sorted(m["modules"], key=lambda r: -r[1])[:args.top]:
        print(f"  {n:5d}  {p}")
    print(f"routines (limit {ROUTINE_MAX} lines):")
    for p, name, n in sorted(m["routines"], key=lambda r: -r[2])[:args.top]:
        print(f"  {n:5d}  {p}: {name}")
    folders = {}
    for p, n in m["modules"]:
        folders[os.path.dirname(p)] = folders.get(os.path.dirname(p), 0) + n
    print("layer folders: " + ", ".join(f"{os.path.basename(f)} {n}" for f, n in sorted(folders.items())))
    print(f"input reader src/input/mpm_config*.f90: {m['reader']} lines")
    bad = problems(m)
    for b in bad:
        print("OVER  " + b)
    return 1 if (args.check and bad) else 0


if __name__ == "__main__":
    sys.exit(main())
