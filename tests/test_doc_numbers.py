#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The manual quotes the same timings in several places; they must agree.

- The refinement study's full level (runs, CPU hours, minutes on two free cores) as README.md,
  the `make help` text (the `## ` comment lines of the Makefile) and docs/validation.md quote
  it; the runs and the CPU hours must also be those of the committed table
  (docs/study/study_full.csv: its rows, the sum of its cpu_s rounded to 0.1 h).
- The other targets' durations quoted in more than one of README.md, `make help` and the docs
  (the study's quick level, make bench, make fe-reference, make design-example, make
  test-slurm): every quote of one target the same.
- The run time of each shipped scene: docs/scenes.md's table has a row for every file of
  namelists/*.nml, and where README.md quotes a scene's time (the shipped-cases table, and
  `make run`'s default.nml) it is the one of docs/scenes.md.
- No date of the form 20YY-MM-DD in README.md or docs/**/*.md (a docs/CHANGELOG.md may have
  them): the manual describes the code as it is.

Each quote is looked for with a pattern; a required quote that is not found is a failure too,
so rewording a sentence cannot make the test pass by silence.

    python3 -m tests.test_doc_numbers [SCRATCH]      (SCRATCH is not used)
"""
from __future__ import annotations

import csv
import re
import sys
from pathlib import Path

from tests.pycheck import Checks

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_doc_numbers")
DATE = re.compile(r"\b20\d\d-[01]\d-[0-3]\d\b")


def flat(text: str) -> str:
    """Whitespace collapsed to single spaces (quotes wrap across lines)."""
    return re.sub(r"\s+", " ", text)


def make_help() -> str:
    """The `make help` text: the Makefile's `## ` comment lines, joined."""
    lines = [ln[3:] for ln in (ROOT / "Makefile").read_text().splitlines()
             if ln.startswith("## ")]
    return flat(" ".join(lines))


def sources() -> dict[str, str]:
    texts = {"README.md": flat((ROOT / "README.md").read_text()), "make help": make_help()}
    for p in sorted((ROOT / "docs").rglob("*.md")):
        texts[str(p.relative_to(ROOT))] = flat(p.read_text())
    return texts


# quantity: ({source: pattern}, required sources). Each pattern's groups are the quoted value.
QUOTES = {
    "study LEVEL=full (runs, CPU hours, minutes)": (
        r"LEVEL=full\W{0,30}(\d+) runs, ([\d.]+) CPU h(?:ours)?\W{1,3}about (\d+) min",
        ["README.md", "make help", "docs/validation.md"]),
    "study LEVEL=quick (minutes)": (
        r"LEVEL=quick\W{0,6}under (\d+) min", ["README.md", "make help"]),
    "make bench (minutes)": (
        r"bench\b.{0,150}?\b(\d+-\d+) min", ["README.md", "make help", "docs/performance.md"]),
    "make fe-reference (CPU minutes)": (
        r"fe-reference\b.{0,150}?about (\d+) CPU min",
        ["README.md", "make help", "docs/validation.md"]),
    "make design-example (minutes on two cores)": (
        r"design-example\b.{0,250}?about ([\d.]+) min",
        ["README.md", "make help", "docs/design.md"]),
    "make test-slurm (seconds)": (
        r"(\d+) s with the (?:install of the packages|packages' install)",
        ["make help", "docs/batch.md"]),
}


def check_quotes(texts: dict[str, str]) -> dict[str, tuple]:
    agreed = {}
    for name, (pattern, required) in QUOTES.items():
        found = {}
        for src, text in texts.items():
            m = re.search(pattern, text)
            if m:
                found[src] = m.groups()
        for src in required:
            T.check(src in found, f"{name}: no quote found in {src} (pattern {pattern!r})")
        values = set(found.values())
        T.check(len(values) <= 1, f"{name}: the quotes differ: "
                                  + "; ".join(f"{s}: {v}" for s, v in sorted(found.items())))
        if len(values) == 1:
            agreed[name] = values.pop()
    return agreed


def check_study_table(agreed: dict[str, tuple]) -> None:
    """The full study's runs and CPU hours are those of the committed table."""
    key = "study LEVEL=full (runs, CPU hours, minutes)"
    with open(ROOT / "docs" / "study" / "study_full.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    runs, hours = len(rows), sum(float(r["cpu_s"]) for r in rows) / 3600.0
    if key not in agreed:
        return
    q_runs, q_hours, q_minutes = agreed[key]
    T.check(int(q_runs) == runs, f"{key}: quoted {q_runs} runs, the table has {runs}")
    T.check(abs(float(q_hours) - hours) <= 0.05 + 1e-9,
            f"{key}: quoted {q_hours} CPU hours, the table sums to {hours:.2f}")
    # two runs at once on two free cores: the wall time is about half the CPU time
    T.check(abs(float(q_minutes) - hours * 30.0) <= 0.15 * hours * 30.0,
            f"{key}: quoted about {q_minutes} minutes on two cores, half of {hours:.2f} CPU "
            f"hours is {hours * 30:.0f} minutes")


def check_scene_times(texts: dict[str, str]) -> None:
    scenes_md = (ROOT / "docs" / "scenes.md").read_text()
    table = {}
    for line in scenes_md.splitlines():
        m = re.match(r"\|\s*`([\w/]+\.nml)`\s*\|.*\|\s*(about [\d.]+ (?:s|min))\s*\|\s*$", line)
        if m:
            table[m.group(1)] = m.group(2)
    for nml in sorted((ROOT / "namelists").glob("*.nml")):
        T.check(nml.name in table, f"docs/scenes.md: no run time for namelists/{nml.name} in "
                                   "its table of shipped scenes")
    readme = (ROOT / "README.md").read_text()
    quoted = 0
    for line in readme.splitlines():
        m = re.match(r"\|\s*`([\w/]+\.nml)`\s*\|.*\|\s*(about [\d.]+ (?:s|min))\s*\|\s*$", line)
        if m:
            quoted += 1
            T.check(table.get(m.group(1)) == m.group(2),
                    f"README.md: {m.group(1)} runs in {m.group(2)}, docs/scenes.md says "
                    f"{table.get(m.group(1))}")
    T.check(quoted > 0, "README.md: no run time in the table of shipped cases")
    m = re.search(r"`make run`.{0,300}?(about [\d.]+ s) on one core", texts["README.md"])
    if T.check(m is not None, "README.md: no run time quoted for `make run`"):
        T.check(table.get("default.nml") == m.group(1),
                f"README.md: `make run` takes {m.group(1)}, docs/scenes.md says default.nml "
                f"takes {table.get('default.nml')}")


def check_no_dates() -> None:
    files = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    for f in files:
        if f.name.upper() == "CHANGELOG.MD":
            continue
        for k, line in enumerate(f.read_text().splitlines(), 1):
            for m in DATE.finditer(line):
                T.check(False, f"{f.relative_to(ROOT)}:{k}: a date ({m.group(0)}): the manual "
                               "describes the code as it is (history goes to a CHANGELOG)")
    T.check(True, f"{len(files)} files searched for dates")


def main() -> int:
    texts = sources()
    agreed = check_quotes(texts)
    check_study_table(agreed)
    check_scene_times(texts)
    check_no_dates()
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
