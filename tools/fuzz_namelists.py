#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Namelist fuzzer: mutate the shipped namelists and run `tubempm --check` on each mutant.

A mutant passes when the program exits 0, or exits 2 with at least one line starting
`ERROR [` on standard error, within the time limit. Anything else (a crash, a signal, a runtime
error without an ERROR line, exit 1/3/4, a hang) is a failure, and the mutant is kept in the
output folder for reproduction.

    python3 -m tools.fuzz_namelists --bin bin/tubempm --count 200 --seed 1 --out DIR

Mutations: deleted, repeated and swapped lines; values replaced by wrong types, huge, tiny,
negative, zero, NaN and Inf numbers; unknown names; truncated files; binary noise; mangled
group names and delimiters; duplicated groups; empty and whitespace-only files.
"""
from __future__ import annotations

import argparse
import glob
import os
import random
import re
import subprocess
import sys
import time

NUMBERS = ["0", "-1", "1e308", "-1e308", "1e-308", "1e400", "-0.0", "nan", "NaN", "inf",
           "-Infinity", "3.5", "-2.5e-3", "2147483648", "-2147483649", "1.5d0", "0x10",
           "1e", "--1", "1..2", "'text'", ".true.", "*", "1,", ",", "1 2 3 4 5 6 7 8 9"]
WORDS = ["'cpdi3'", "'LINEAR'", "'ring'", "'rect'", "''", "'a''b'", "abc", "'unterminated",
         "'" + "x" * 300 + "'", ".false.", "T", "'strain'", "'stress'", "'half'", "'octant'"]
NAMES = ["poison", "E_mod", "h2", "basis_", "r_inner(3)", "center(0)", "motion_t(65)",
         "velocity(2,2)", "n_thick%x", "title", "dt"]
GROUPS = ["&run", "&solver", "&grid", "&material", "&body", "&wall", "&probe", "&bodyy",
          "&RUN", "& run", "&", "$run", "&end"]


def mutate(text: str, rng: random.Random) -> str:
    """Apply one to three random mutations to a namelist text."""
    lines = text.splitlines()
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(14)
        if not lines:
            lines = [""]
        i = rng.randrange(len(lines))
        if kind == 0:                                   # delete a line
            del lines[i]
        elif kind == 1:                                 # repeat a line
            lines.insert(i, lines[i])
        elif kind == 2:                                 # swap two lines
            j = rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        elif kind in (3, 4, 5):                         # replace a value by a bad number
            m = list(re.finditer(r"=\s*([^!,/\n]+)", lines[i]))
            if m:
                g = rng.choice(m)
                lines[i] = lines[i][:g.start(1)] + rng.choice(NUMBERS) + lines[i][g.end(1):]
        elif kind == 6:                                 # replace a value by a bad word
            m = list(re.finditer(r"=\s*([^!,/\n]+)", lines[i]))
            if m:
                g = rng.choice(m)
                lines[i] = lines[i][:g.start(1)] + rng.choice(WORDS) + lines[i][g.end(1):]
        elif kind == 7:                                 # rename a variable
            lines[i] = re.sub(r"^\s*\w+", "  " + rng.choice(NAMES), lines[i], count=1)
        elif kind == 8:                                 # truncate the file
            cut = rng.randrange(max(1, len("\n".join(lines))))
            return "\n".join(lines)[:cut]
        elif kind == 9:                                 # binary noise
            noise = "".join(chr(rng.randrange(1, 256)) for _ in range(rng.randint(1, 40)))
            lines.insert(i, noise)
        elif kind == 10:                                # mangle a group name or delimiter
            if "&" in lines[i]:
                lines[i] = re.sub(r"&\w+", rng.choice(GROUPS), lines[i], count=1)
            elif "/" in lines[i]:
                lines[i] = lines[i].replace("/", rng.choice(["", "//", "\\", "&end"]), 1)
        elif kind == 11:                                # duplicate a whole group
            starts = [k for k, l in enumerate(lines) if l.lstrip().startswith("&")]
            if starts:
                s = rng.choice(starts)
                e = next((k for k in range(s, len(lines)) if lines[k].rstrip().endswith("/")),
                         len(lines) - 1)
                lines.extend(lines[s:e + 1])
        elif kind == 12:                                # empty or whitespace-only file
            return rng.choice(["", "\n\n", "   \t  \n", "!\n"])
        else:                                           # a variable assigned twice
            lines.insert(i, lines[i].split("!")[0] + " , " + lines[i].split("!")[0].strip())
    return "\n".join(lines) + ("\n" if rng.random() < 0.8 else "")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.environ.get("TUBEMPM", "bin/tubempm"))
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=10.0, help="seconds per run")
    ap.add_argument("--out", default="out/fuzz", help="folder for mutants and failures "
                    "(default out/fuzz)")
    ap.add_argument("--inputs", default="namelists/*.nml")
    args = ap.parse_args()

    os.makedirs(args.out, exist_ok=True)
    seeds = [open(f, encoding="latin-1").read() for f in sorted(glob.glob(args.inputs))]
    if not seeds:
        print(f"no input namelists match {args.inputs}")
        return 2
    rng = random.Random(args.seed)
    outcome = {"ok (exit 0)": 0, "rejected (exit 2 + ERROR)": 0}
    failures = 0
    t0 = time.time()
    for k in range(args.count):
        text = mutate(rng.choice(seeds), rng)
        path = os.path.join(args.out, f"mutant_{k:05d}.nml")
        with open(path, "w", encoding="latin-1") as f:
            f.write(text)
        try:
            r = subprocess.run([args.bin, "--check", "--quiet", path], capture_output=True,
                               timeout=args.timeout, env=dict(os.environ, OMP_NUM_THREADS="1"))
            err = r.stderr.decode("latin-1")
            has_error = any(l.startswith("ERROR [") for l in err.splitlines())
            if r.returncode == 0:
                outcome["ok (exit 0)"] += 1
                os.remove(path)
                continue
            if r.returncode == 2 and has_error:
                outcome["rejected (exit 2 + ERROR)"] += 1
                os.remove(path)
                continue
            why = f"exit {r.returncode}" + ("" if has_error else " without an ERROR line")
        except subprocess.TimeoutExpired:
            why = f"hung past {args.timeout} s"
        failures += 1
        outcome[why] = outcome.get(why, 0) + 1
        print(f"FAIL [fuzz]: {path}: {why}")
    print(f"fuzz: {args.count} mutants in {time.time() - t0:.1f} s: " +
          ", ".join(f"{v} {k}" for k, v in outcome.items()))
    print(f"fuzz: {args.count - failures} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
