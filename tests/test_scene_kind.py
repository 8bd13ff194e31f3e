#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""One scene classifier: tubempm writes it into summary.nml (``scene``), the plots read it.

Every namelist of namelists/ and tests/scenes/ is run for a few steps (t_end cut to 1e-7 s) with
the binary named by TUBEMPM; its summary.nml must name the scene the file is known to be (the
table below, written by hand from what each file models), the Python rule
(mpmplot.scene.classify_inputs, the fallback for outputs written before the entry) must give the
same answer from input.nml and from the case file, and scene_kind must read summary.nml (shown by
a summary whose entry was changed) and fall back to the rule when the entry is missing.

    TUBEMPM=build/debug/tubempm python3 tests/test_scene_kind.py SCRATCH
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(ROOT / "plots"))
from pycheck import Checks  # noqa: E402
from mpmplot import namelist, scene  # noqa: E402

T = Checks("test_scene_kind")
check = T.check

#: What each shipped file models (by reading it, not by running the classifier).
EXPECTED = {
    "namelists/crush.nml": "crush",            # platen at constant speed
    "namelists/default.nml": "impact",         # ring at 30 m/s onto a static target
    "namelists/impact.nml": "impact",
    "namelists/wave.nml": "wave",              # platen pulse (motion table back to 0), probes
    "tests/scenes/crush_quarter.nml": "crush",
    "tests/scenes/elastic_quarter.nml": "wave",   # a platen pulse, as the wave scene's
    "tests/scenes/impact_half.nml": "impact",
    "tests/scenes/stability_impact.nml": "impact",
    "tests/scenes/sym_full.nml": "crush",
    "tests/scenes/sym_half.nml": "crush",
    "tests/scenes/sym_quarter.nml": "crush",
}


def prepare(case: Path, folder: Path) -> Path:
    """A copy of the case writing into folder/out, cut to a few steps."""
    text = case.read_text()
    text = re.sub(r"(?im)^\s*output_dir\s*=.*$", "", text)
    text = re.sub(r"(?i)\bt_end\s*=\s*[0-9.eEdD+-]+", "t_end = 1.0e-7", text, count=1)
    text = re.sub(r"(?i)(&run\b)", rf"\1 output_dir = '{folder / 'out'}',", text, count=1)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / case.name
    path.write_text(text)
    return path


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_scene_kind").resolve()
    binary = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
    files = sorted(str(p.relative_to(ROOT)) for d in ("namelists", "tests/scenes")
                   for p in (ROOT / d).glob("*.nml"))
    check(sorted(EXPECTED) == files, f"the table names every scene file ({files})")
    last = None
    for rel in files:
        case = ROOT / rel
        folder = scratch / case.stem
        path = prepare(case, folder)
        proc = subprocess.run([binary, "--quiet", str(path)], capture_output=True, text=True,
                              timeout=300, env=dict(os.environ, OMP_NUM_THREADS="1"))
        if not check(proc.returncode == 0, f"{rel}: runs (exit {proc.returncode}: "
                     f"{proc.stderr.strip()[-300:]})"):
            continue
        out = folder / "out"
        summary = namelist.read_namelist(out / "summary.nml")["summary"][0]
        want = EXPECTED.get(rel, "?")
        check(summary.get("scene") == want,
              f"{rel}: summary.nml scene = {summary.get('scene')!r}, expected {want!r}")
        resolved = scene.classify_inputs(namelist.read_namelist(out / "input.nml"))
        check(resolved == want, f"{rel}: classify_inputs(input.nml) = {resolved!r}, "
              f"expected {want!r}")
        given = scene.classify_inputs(namelist.read_namelist(case))
        check(given == want, f"{rel}: classify_inputs(case file) = {given!r}, expected {want!r}")
        check(scene.scene_kind({}, out) == want, f"{rel}: scene_kind reads summary.nml")
        last = out
    if last is not None:
        # scene_kind trusts summary.nml over the inputs, and falls back when it has no entry
        text = (last / "summary.nml").read_text()
        inputs = namelist.read_namelist(last / "input.nml")
        rule = scene.classify_inputs(inputs)
        other = "generic" if rule != "generic" else "crush"
        (last / "summary.nml").write_text(re.sub(r"scene = '\w+'", f"scene = '{other}'", text))
        check(scene.scene_kind(inputs, last) == other, "scene_kind answers what summary.nml says")
        (last / "summary.nml").write_text(re.sub(r"(?m)^\s*scene = '\w+'\n", "", text))
        check("scene" not in namelist.read_namelist(last / "summary.nml")["summary"][0],
              "the edited summary.nml has no scene entry")
        check(scene.scene_kind(inputs, last) == rule, "scene_kind falls back to the rule for a "
              "summary.nml written before the entry")
    return 0


if __name__ == "__main__":
    rc = main()
    sys.exit(max(T.summary(), rc))
