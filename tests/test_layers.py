#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The layers of docs/architecture.md hold: read its layer table and the `use` lines of
src/*.f90; no module uses a module of a lower layer (a later row of the table), and every
module and program of src/ is in the table. The checker is first run on a made-up table and
sources with one upward and one downward use, so that it is seen to catch the wrong one.
Prints `test_layers: N passed, M failed` last. Standard library only.
"""
import fnmatch
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from pycheck import Checks  # noqa: E402

T = Checks("test_layers")
check = T.check

ROW = re.compile(r"^\|\s*([^|]+?)\s*\|\s*([^|]+?)\s*\|")
UNIT = re.compile(r"^\s*(module|program)\s+(\w+)\s*(!.*)?$", re.IGNORECASE)
USE = re.compile(r"^\s*use\s*(?:,\s*\w+\s*::)?\s*(\w+)", re.IGNORECASE)


def layers(markdown: str) -> list[tuple[str, list[str]]]:
    """The rows of the table under '## Layers' (Python's excepted): layer name, name patterns
    (`mpm_config*`; a program by its file name, `tubempm.f90`)."""
    out = []
    part = markdown.split("## Layers", 1)[1].split("\n## ", 1)[0]
    for line in part.splitlines():
        m = ROW.match(line)
        if not m or m.group(1) in ("layer", "Python") or set(m.group(1)) <= set("-"):
            continue
        out.append((m.group(1), [p.removesuffix(".f90") for p in re.findall(r"`([^`]+)`",
                                                                            m.group(2))]))
    return out


def units(sources: dict[str, str]) -> dict[str, list[str]]:
    """Module or program name -> the modules it uses, from the text of each file."""
    out: dict[str, list[str]] = {}
    for text in sources.values():
        name = None
        for line in text.splitlines():
            m = UNIT.match(line)
            if m and m.group(2).lower() != "procedure":
                name = m.group(2).lower()
                out.setdefault(name, [])
            u = USE.match(line)
            if u and name:
                out[name].append(u.group(1).lower())
    return out


def violations(table: list[tuple[str, list[str]]], used: dict[str, list[str]]
               ) -> tuple[list[str], list[str]]:
    """The uses of a lower layer's module, and the units that are in no layer."""
    def layer_of(name: str) -> int | None:
        for k, (_, pats) in enumerate(table):
            if any(fnmatch.fnmatchcase(name, p.lower()) for p in pats):
                return k
        return None
    down, missing = [], []
    for name, uses in sorted(used.items()):
        k = layer_of(name)
        if k is None:
            missing.append(name)
            continue
        for u in uses:
            j = layer_of(u) if u in used else None     # intrinsic and library modules: no layer
            if j is not None and j > k:
                down.append(f"{name} ({table[k][0]}) uses {u} ({table[j][0]})")
    return down, missing


def main() -> int:
    # the checker on a made-up case: b (kernels) may use a (base); a using b is the wrong way
    toy = "## Layers\n\n| layer | modules | what |\n|---|---|---|\n" \
          "| base | `m_a` | x |\n| kernels | `m_b*` | y |\n\n## Next\n"
    down, missing = violations(layers(toy), units({
        "a.f90": "module m_a\n  use m_b2, only: f\nend module m_a\n",
        "b.f90": "module m_b2\n  use m_a\n  use iso_c_binding\nend module m_b2\n",
        "c.f90": "module m_c\nend module m_c\n"}))
    check(down == ["m_a (base) uses m_b2 (kernels)"], f"the made-up downward use: {down}")
    check(missing == ["m_c"], f"the made-up module in no layer: {missing}")

    table = layers((ROOT / "docs" / "architecture.md").read_text())
    check(len(table) >= 6, f"docs/architecture.md: layer table of {len(table)} rows")
    sources = {p.name: p.read_text() for p in sorted((ROOT / "src").glob("*.f90"))}
    used = units(sources)
    check(len(used) >= 40, f"src/: {len(used)} modules and programs found")
    down, missing = violations(table, used)
    for v in down:
        check(False, f"a use of a lower layer: {v} (docs/architecture.md, Layers)")
    for name in missing:
        check(False, f"src/: {name} is in no layer of docs/architecture.md")
    check(not down and not missing, f"{len(used)} units in {len(table)} layers, every use "
          "of its own layer or one above")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
