# SPDX-License-Identifier: MIT
"""Run one scene with the binary under test, for the Python tests that run scenes.

    from tests.pyscene import run_scene
    h, s = run_scene(T, scratch, "name", text)   # text: a case with OUT for its output folder

The case is written to SCRATCH/name/name.nml with OUT replaced by SCRATCH/name/out and run
with `$TUBEMPM --quiet` (default bin/tubempm) on one thread; a failed run is a failed check of
T (pycheck.Checks) and gives ({}, {}), else its history.csv and summary.nml as dicts.
Not a test itself (no test_ prefix).
"""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

from plots.mpmplot import readers

ROOT = Path(__file__).resolve().parent.parent


def run_scene(checks, scratch: Path, name: str, text: str) -> tuple[dict, dict]:
    """Run one scene; its history and summary ({} when it failed)."""
    folder = scratch / name
    folder.mkdir(parents=True, exist_ok=True)
    nml = folder / f"{name}.nml"
    nml.write_text(text.replace("OUT", str(folder / "out")))
    res = subprocess.run([os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm")), "--quiet",
                          str(nml)], capture_output=True, text=True,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    if not checks.check(res.returncode == 0, f"{name}: run completes (exit {res.returncode}: "
                                             f"{res.stderr.strip()[-300:]})"):
        return {}, {}
    return (readers.read_history(folder / "out" / "history.csv"),
            readers.read_summary(folder / "out" / "summary.nml"))
