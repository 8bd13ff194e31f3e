#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""One scene classifier: tubempm's (``scene_of``, src/input/mpm_config_types.f90), which it
writes into summary.nml (``scene``) and prints with ``--scene`` without running; the plots only read it.

Every namelist of namelists/, namelists/contact/, namelists/foam/ and tests/scenes/ is classified both ways and
compared with the scene the file is known to be (the table below, written by hand from what each
file models, not by running the classifier): ``tubempm --scene`` on the case file, and a run of a
few steps (t_end cut to 1e-7 s) whose summary.nml must name it. mpmplot.scene.scene_kind must give
the same answer from the output folder (summary.nml) and from the case file alone (asking
``tubempm --scene``), trust summary.nml over the inputs (shown by a summary whose entry was
changed) and ask tubempm about input.nml when the entry is missing. No Python copy of the rule
is left (``classify_inputs`` is gone), and ``--scene`` on a bad input prints no kind and exits 2.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_scene_kind SCRATCH
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

from tests.pycheck import Checks
from plots.mpmplot import namelist, scene

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_scene_kind")
check = T.check

#: What each shipped file models (by reading it, not by running the classifier).
EXPECTED = {
    "namelists/crush.nml": "crush",            # platen at constant speed
    "namelists/crush_fixed.nml": "crush",      # the same, the bottom platen fixed
    "namelists/default.nml": "impact",         # ring at 30 m/s onto a static target
    "namelists/impact.nml": "impact",
    "namelists/drop_weight.nml": "impact",      # a wall with mass: a drop test
    "namelists/wave.nml": "wave",              # platen pulse (motion table back to 0), probes
    "namelists/contact/densify.nml": "crush",  # the crush scene's tube, platens to 0.95 D
    "namelists/contact/nested.nml": "crush",   # two nested tubes between platens
    "namelists/contact/nested_eccentric.nml": "crush",
    "namelists/contact/plates.nml": "crush",   # a platen drives the plates onto the tube
    "namelists/contact/row3.nml": "crush",     # one platen over three tubes
    "namelists/contact/row3_single.nml": "crush",
    "namelists/contact/stack.nml": "crush",
    "namelists/contact/two_rings.nml": "impact",  # two rings flying at each other, no wall moves
    "namelists/foam/foam_block.nml": "generic",   # a foam block between platens: no ring
    "namelists/foam/empty_ring.nml": "crush",     # the crush scene's tube, platen to 33 mm
    "namelists/foam/empty_ring_equal_mass.nml": "crush",
    "namelists/foam/filled_ring.nml": "crush",    # a ring and its foam core between platens
    "namelists/foam/filled_drop.nml": "impact",   # a wall with mass: a drop test
    "namelists/foam/foam_disc.nml": "generic",    # a foam disc between platens: no ring
    "namelists/foam/filled_square.nml": "generic",  # a square tube (no ring) and its core
    "namelists/foam/filled_square_bonded.nml": "generic",
    "namelists/foam/foam_square.nml": "generic",  # a foam block between platens: no ring
    "tests/scenes/crush_quarter.nml": "crush",
    "tests/scenes/damped_quarter.nml": "wave",    # a platen pulse (triangle back to 0)
    "tests/scenes/elastic_quarter.nml": "wave",   # a platen pulse, as the wave scene's
    "tests/scenes/impact_half.nml": "impact",
    "tests/scenes/stability_impact.nml": "impact",
    "tests/scenes/stick_crush.nml": "crush",      # two 'stick' platens close on a full ring
    "tests/scenes/sym_full.nml": "crush",
    "tests/scenes/sym_half.nml": "crush",
    "tests/scenes/sym_quarter.nml": "crush",
}


def prepare(case: Path, folder: Path) -> Path:
    """A copy of the case writing into folder/out, cut to a few steps."""
    # (a case whose walls all have a stroke may omit t_end: it gets one too)
    text = namelist.set_values(case.read_text(), {"run.output_dir": str(folder / "out"),
                                                  "run.t_end": 1.0e-7}, str(case))
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / case.name
    path.write_text(text)
    return path


def ask(binary: str, case: Path) -> subprocess.CompletedProcess:
    """tubempm --scene CASE."""
    return subprocess.run([binary, "--scene", str(case)], capture_output=True, text=True,
                          timeout=120)


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_scene_kind").resolve()
    binary = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
    os.environ["TUBEMPM"] = binary            # the plots ask the same binary
    files = sorted(str(p.relative_to(ROOT)) for d in ("namelists", "namelists/contact",
                                                      "namelists/foam", "tests/scenes")
                   for p in (ROOT / d).glob("*.nml"))
    check(sorted(EXPECTED) == files, f"the table names every scene file ({files})")
    check(not hasattr(scene, "classify_inputs"), "no Python copy of the scene rule")
    last = None
    for rel in files:
        case = ROOT / rel
        want = EXPECTED.get(rel, "?")
        proc = ask(binary, case)
        check(proc.returncode == 0 and proc.stdout == want + "\n",
              f"{rel}: tubempm --scene prints {proc.stdout!r} (exit {proc.returncode}), "
              f"expected {want!r}")
        check(scene.scene_kind(case=case) == want, f"{rel}: scene_kind(case file) asks tubempm")
        folder = scratch / case.stem
        path = prepare(case, folder)
        proc = subprocess.run([binary, "--quiet", str(path)], capture_output=True, text=True,
                              timeout=300, env=dict(os.environ, OMP_NUM_THREADS="1"))
        if not check(proc.returncode == 0, f"{rel}: runs (exit {proc.returncode}: "
                     f"{proc.stderr.strip()[-300:]})"):
            continue
        out = folder / "out"
        summary = namelist.read_namelist(out / "summary.nml")["summary"][0]
        check(summary.get("scene") == want,
              f"{rel}: summary.nml scene = {summary.get('scene')!r}, expected {want!r}")
        check(scene.scene_kind(out) == want, f"{rel}: scene_kind reads summary.nml")
        last = out
    if last is not None:
        # scene_kind trusts summary.nml over the inputs, and asks tubempm about input.nml when
        # the entry is missing
        text = (last / "summary.nml").read_text()
        rule = ask(binary, last / "input.nml").stdout.strip()
        check(rule in scene.SCENES, f"tubempm --scene input.nml answers a kind ({rule!r})")
        other = "generic" if rule != "generic" else "crush"
        (last / "summary.nml").write_text(re.sub(r"scene = '\w+'", f"scene = '{other}'", text))
        check(scene.scene_kind(last) == other, "scene_kind answers what summary.nml says")
        (last / "summary.nml").write_text(re.sub(r"(?m)^\s*scene = '\w+'\n", "", text))
        check("scene" not in namelist.read_namelist(last / "summary.nml")["summary"][0],
              "the edited summary.nml has no scene entry")
        check(scene.scene_kind(last) == rule, "scene_kind asks tubempm about input.nml for a "
              "summary.nml written before the entry")
    bad = ROOT / "tests" / "bad_inputs" / "05_unknown_variable.nml"
    proc = ask(binary, bad)
    check(proc.returncode == 2 and proc.stdout == "" and "ERROR [input]" in proc.stderr,
          f"tubempm --scene {bad.name}: exit 2, no kind, the input errors (exit "
          f"{proc.returncode}, stdout {proc.stdout!r})")
    try:
        scene.scene_kind(case=bad)
        check(False, "scene_kind refuses a bad input")
    except ValueError as exc:
        check("ERROR [input]" in str(exc), f"scene_kind passes tubempm's message on ({exc})")
    return 0


if __name__ == "__main__":
    rc = main()
    sys.exit(max(T.summary(), rc))
