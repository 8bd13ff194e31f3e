#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The layers of src/ hold, read from its folders: every module's `use` lines reach only
modules of its own layer or of a lower one (LAYERS, lowest first; docs/architecture.md's layer
table names the same folders in the same order). Every source of src/ lies in a folder of a
layer, and no two sources share a file name (the build puts every object in one folder).
mpm_advice is used only by the report of the set-up and the driver. The checker is first run on a made-up
tree with one use of a lower layer and one of a higher one, so that it is seen to catch the
wrong one. Prints `test_layers: N passed, M failed` last. Standard library only.
"""
import re
import sys
from pathlib import Path

from tests.pycheck import Checks

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

T = Checks("test_layers")
check = T.check

# (layer, its folders under src/), lowest first; "" is the top of src/. A layer may use itself
# and the layers before it. method and contact are one layer in two folders: the state holds
# the contact's work arrays, and the contact's phases take the state. The advice reads the case
# and sits above the input, which uses none of it.
LAYERS = [
    ("base", ["base"]),
    ("method", ["method", "contact"]),
    ("bodies", ["bodies"]),
    ("input", ["input"]),
    ("advice", ["advice"]),
    ("io", ["io"]),
    ("driver", ["driver"]),
]
#: The only units that use mpm_advice: the report of the set-up (--check, a run's banner),
#: the driver (the end-of-run warning) and the study's advice (mpm_study_advice, --check's, in
#: the advice layer). Nothing on the way from the input to the results does (issue 32: a basis
#: that no study has run compiles and runs).
ADVICE_USERS = {"mpm_report", "tubempm", "mpm_study_advice"}

UNIT = re.compile(r"^\s*(module|program)\s+(\w+)\s*(!.*)?$", re.IGNORECASE)
USE = re.compile(r"^\s*use\s*(?:,\s*\w+\s*::)?\s*(\w+)", re.IGNORECASE)
ROW = re.compile(r"^\|\s*([^|]+?)\s*\|\s*([^|]+?)\s*\|")


def folder_of(rel: str) -> str:
    """The layer folder of a path relative to src/: its first folder, "" at the top."""
    parts = rel.split("/")
    return parts[0] if len(parts) > 1 else ""


def units(sources: dict[str, str]) -> dict[str, tuple[str, list[str]]]:
    """Module or program name -> (its file, the modules it uses), from each file's text."""
    out: dict[str, tuple[str, list[str]]] = {}
    for rel, text in sources.items():
        name = None
        for line in text.splitlines():
            m = UNIT.match(line)
            if m and m.group(2).lower() != "procedure":
                name = m.group(2).lower()
                out.setdefault(name, (rel, []))
            u = USE.match(line)
            if u and name:
                out[name][1].append(u.group(1).lower())
    return out


def violations(layers, sources: dict[str, str]) -> tuple[list[str], list[str]]:
    """The uses of a higher layer's module, and the files in no layer's folder."""
    rank = {f: k for k, (_, folders) in enumerate(layers) for f in folders}
    up, stray = [], []
    used = units(sources)
    for rel in sorted(sources):
        if folder_of(rel) not in rank:
            stray.append(rel)
    for name, (rel, uses) in sorted(used.items()):
        k = rank.get(folder_of(rel))
        if k is None:
            continue
        for u in uses:
            if u not in used:           # intrinsic and library modules (hdf5): no layer
                continue
            j = rank.get(folder_of(used[u][0]))
            if j is not None and j > k:
                up.append(f"{name} (src/{rel}, {layers[k][0]}) uses {u} "
                          f"(src/{used[u][0]}, {layers[j][0]})")
    return up, stray


def main() -> int:
    # the checker on a made-up tree: b (kernels) may use a (base); a using b is the wrong way
    toy = [("base", ["base"]), ("kernels", ["kern", ""])]
    up, stray = violations(toy, {
        "base/a.f90": "module m_a\n  use m_b2, only: f\nend module m_a\n",
        "kern/b.f90": "module m_b2\n  use m_a\n  use iso_c_binding\nend module m_b2\n",
        "top.f90": "module m_t\n  use m_a\n  use m_b2\nend module m_t\n",
        "other/c.f90": "module m_c\nend module m_c\n"})
    check(up == ["m_a (src/base/a.f90, base) uses m_b2 (src/kern/b.f90, kernels)"],
          f"the made-up use of a higher layer: {up}")
    check(stray == ["other/c.f90"], f"the made-up file in no layer's folder: {stray}")

    src = ROOT / "src"
    paths = sorted(p for p in src.rglob("*") if p.suffix in (".f90", ".c", ".inc"))
    rel = {p.relative_to(src).as_posix(): p for p in paths}
    sources = {r: p.read_text() for r, p in rel.items() if p.suffix == ".f90"}
    used = units(sources)
    check(len(used) >= 40, f"src/: {len(used)} modules and programs found")
    up, stray = violations(LAYERS, {r: (p.read_text() if p.suffix == ".f90" else "")
                                    for r, p in rel.items()})
    for v in up:
        check(False, f"a use of a higher layer: {v} (tests/test_layers.py, LAYERS)")
    for r in stray:
        check(False, f"src/{r} is in no layer's folder (tests/test_layers.py, LAYERS)")
    check(not up and not stray, f"{len(used)} units in {len(LAYERS)} layers, every use of "
          "its own layer or a lower one")
    advised = {name for name, (_, uses) in used.items() if "mpm_advice" in uses} - {"mpm_advice"}
    check(advised == ADVICE_USERS, f"mpm_advice is used only by {sorted(ADVICE_USERS)}: "
          f"{sorted(advised)}")

    names: dict[str, list[str]] = {}
    for r, p in rel.items():
        if p.suffix != ".inc":
            names.setdefault(p.stem, []).append(r)
    twins = {n: rs for n, rs in names.items() if len(rs) > 1}
    check(not twins, f"sources of one file name in two folders (one build folder): {twins}")
    for r, text in sources.items():
        for inc in re.findall(r"^\s*include\s+['\"]([^'\"]+)['\"]", text, re.M | re.I):
            check((rel[r].parent / inc).is_file(), f"src/{r} includes {inc}: not beside it")

    # docs/architecture.md's layer table: the same folders in the same order
    part = (ROOT / "docs" / "architecture.md").read_text().split("## Layers", 1)[1]
    part = part.split("\n## ", 1)[0]
    listed = []
    for line in part.splitlines():
        m = ROW.match(line)
        if m:
            listed += [f.strip("/").removeprefix("src").strip("/")
                       for f in re.findall(r"`(src/[\w/]*)`", m.group(2))]
    want = [f for _, folders in LAYERS for f in folders]
    check(listed == want, f"docs/architecture.md, Layers: folders {listed}, expected {want}")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
