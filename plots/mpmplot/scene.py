# SPDX-License-Identifier: MIT
"""What a case is: its output folder, its walls as history.csv numbers them, its ring and
material, and its kind of scene (crush, wave, impact, generic): tubempm's answer, read from
summary.nml or asked of ``tubempm --scene``.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .namelist import read_namelist
from .readers import history_walls, read_summary

__all__ = ["case_output_dir", "resolve_case", "wall_table", "crush_displacement", "scene_kind",
           "tubempm_binary", "SCENES",
           "ring_body", "body_material", "plane_of", "depth_of", "sector_factor",
           "ring_properties"]


def _first(groups: dict[str, list[dict[str, Any]]], name: str) -> dict[str, Any]:
    """The first instance of a group, or an empty dict."""
    lst = groups.get(name) or [{}]
    return lst[0]


def case_output_dir(nml_path: str | os.PathLike) -> str:
    """The output folder of a case file, as the Fortran code chooses it.

    The ``&run output_dir`` if given, else ``out/<title>``, with the title defaulting to the
    file name stem; a relative path is relative to the current directory.
    """
    run = _first(read_namelist(nml_path), "run")
    out = run.get("output_dir")
    if isinstance(out, str) and out.strip():
        return out.strip()
    title = run.get("title")
    if not (isinstance(title, str) and title.strip()):
        title = Path(nml_path).stem
    return os.path.join("out", title.strip())


def resolve_case(case: str | None = None, outdir: str | None = None
                 ) -> tuple[str, dict[str, list[dict[str, Any]]]]:
    """(output folder, input groups) from a case file or an output folder.

    The inputs are the resolved ``input.nml`` in the output folder when it exists (defaults
    filled in), else the case file itself.
    """
    if case is None and outdir is None:
        raise ValueError("give a case file (--case) or an output folder (--dir)")
    if outdir is None:
        outdir = case_output_dir(case)
    resolved = Path(outdir) / "input.nml"
    if resolved.is_file():
        inputs = read_namelist(resolved)
    elif case is not None:
        inputs = read_namelist(case)
    else:
        raise FileNotFoundError(f"{resolved}: not found; is {outdir} a tubempm output folder?")
    return str(outdir), inputs


def _vec(value: Any, default: Sequence[float] = (0.0, 0.0)) -> np.ndarray:
    """A 2-vector from a namelist value (missing components from default)."""
    out = np.array(default, dtype=float)
    if value is None:
        return out
    vals = value if isinstance(value, list) else [value]
    for k, v in enumerate(vals[:2]):
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out[k] = float(v)
    return out


def _nonzero(value: Any) -> bool:
    """A vector value with a nonzero component."""
    return bool(np.any(_vec(value) != 0.0))


def _has_table(wall: dict[str, Any]) -> bool:
    """The wall has a motion table."""
    t = wall.get("motion_t")
    return t is not None and (not isinstance(t, list) or len([v for v in t if v is not None]) > 0)


#: the shapes that may be a half or quarter model (`has_sector` in src/bodies/mpm_bodies.f90)
SECTOR_SHAPES = ("ring", "tube", "walls", "disc")


def _is_mirror(wall: dict[str, Any]) -> bool:
    """A mirror plane given in the input ('slip' contact)."""
    return str(wall.get("contact", "frictionless")).strip().lower() == "slip"


def wall_table(inputs: dict[str, list[dict[str, Any]]], nwall: int | None = None
               ) -> list[dict[str, Any]]:
    """The walls as numbered in history.csv: the input's ``&wall`` groups, then the mirror
    planes a half/quarter ``sector`` adds (normal (1, 0), then (0, 1), through the centre of
    the first sector ring, tube, walls or disc).

    Each entry: ``index`` (1-based), ``point``, ``normal`` (unit), ``velocity``, ``mirror``,
    ``moving`` (prescribed velocity nonzero), ``table`` (has a motion table), ``input``
    (the namelist dict, empty for added mirror planes). ``nwall`` (from the history) adds
    mirror planes up to that count if the sector rule does not explain them all.
    """
    out: list[dict[str, Any]] = []
    for k, w in enumerate(inputs.get("wall", []), start=1):
        n = _vec(w.get("normal"), (0.0, 1.0))
        norm = float(np.hypot(*n)) or 1.0
        out.append({"index": k, "point": _vec(w.get("point")), "normal": n / norm,
                    "velocity": _vec(w.get("velocity")), "mirror": _is_mirror(w),
                    "moving": _nonzero(w.get("velocity")), "table": _has_table(w), "input": w})
    sectors = [str(b.get("sector", "full")).lower() for b in inputs.get("body", [])
               if str(b.get("shape", "ring")).lower() in SECTOR_SHAPES]
    anchor = np.zeros(2)
    for b in inputs.get("body", []):
        if str(b.get("sector", "full")).lower() != "full":
            anchor = _vec(b.get("center"))
            break
    normals: list[tuple[float, float]] = []
    if "half" in sectors:
        normals = [(1.0, 0.0)]
    if "quarter" in sectors:
        normals = [(1.0, 0.0), (0.0, 1.0)]
    if nwall is not None:
        while len(out) + len(normals) < nwall:
            normals.append((float("nan"), float("nan")))
    for n in normals:
        out.append({"index": len(out) + 1, "point": anchor.copy(), "normal": np.array(n),
                    "velocity": np.zeros(2), "mirror": True, "moving": False, "table": False,
                    "input": {}})
    if nwall is not None:
        out = out[:nwall]
    return out


def crush_displacement(history: dict[str, np.ndarray], inputs: dict[str, list[dict[str, Any]]],
                       platen: str = "moving") -> tuple[np.ndarray, np.ndarray, int]:
    """Crush displacement delta [m], platen force [N] and the platen's wall index.

    ``wall<k>_disp`` is the travel along minus the normal: negative for a platen moving into
    the tube. delta is the relative approach of the platens: the advance of every moving
    platen, plus that of its mirror image where a mirror plane of a half/quarter model is
    parallel to it (the quarter model's bottom platen is the top one's image). The force is
    that of the first moving platen, or with ``platen="fixed"`` that of the first fixed one
    parallel to it (a test machine's load cell; quieter at one particle per cell, since the
    material it touches does not cross the grid's rows: docs/validation.md). ValueError if no
    wall moves, or with "fixed" if no fixed platen faces the moving one.
    """
    table = wall_table(inputs, history_walls(history))
    moving = [w for w in table if w["moving"] and not w["mirror"]]
    if not moving:
        raise ValueError("crush: no moving wall (platen) in the case")
    k = moving[0]["index"]
    if platen == "fixed":
        fixed = [w for w in table if not (w["moving"] or w["mirror"] or w["table"])
                 and float(np.dot(w["normal"], moving[0]["normal"])) < -0.999]
        if not fixed:
            raise ValueError("crush: no fixed platen facing the moving one")
        k_force = fixed[0]["index"]
    elif platen == "moving":
        k_force = k
    else:
        raise ValueError(f"crush: platen {platen!r}: allowed 'moving', 'fixed'")
    mirrors = [w for w in table if w["mirror"]]
    disp = np.zeros_like(history[f"wall{k}_disp"])
    for w in moving:
        advance = -history[f"wall{w['index']}_disp"]
        disp = disp + advance
        for m in mirrors:
            if abs(float(np.dot(m["normal"], w["normal"]))) > 0.999:
                disp = disp + advance
    if disp.size and disp[np.argmax(np.abs(disp))] < 0.0:
        disp = -disp
    return disp, history[f"wall{k_force}_force"], k_force


SCENES = ("crush", "wave", "impact", "generic")   #: the kinds of scene summary.nml names


def tubempm_binary() -> str:
    """The tubempm to ask: ``$TUBEMPM``, else the repository's ``bin/tubempm``, else
    ``tubempm`` on the PATH. FileNotFoundError when none exists."""
    env = os.environ.get("TUBEMPM", "").strip()
    if env:
        return env
    local = Path(__file__).resolve().parents[2] / "bin" / "tubempm"
    if local.is_file():
        return str(local)
    found = shutil.which("tubempm")
    if found:
        return found
    raise FileNotFoundError(f"tubempm not found ({local}: build it with `make`, or set "
                            "TUBEMPM to the binary)")


def scene_kind(outdir: str | os.PathLike | None = None,
               case: str | os.PathLike | None = None) -> str:
    """Which scenario a case is: 'crush', 'wave', 'impact' or 'generic'.

    The answer is always tubempm's own (one classifier, ``scene_of`` in src/advice/mpm_advice.f90):
    the ``scene`` entry of ``<outdir>/summary.nml``; for a case not run yet, or an output
    written before summary.nml had that entry, what ``tubempm --scene`` prints for
    ``<outdir>/input.nml`` (the resolved input) or else for the case file. FileNotFoundError
    without tubempm, ValueError when it refuses the input.
    """
    if outdir is not None:
        path = Path(outdir) / "summary.nml"
        if path.is_file():
            scene = str(read_summary(path).get("scene", "")).strip().lower()
            if scene in SCENES:
                return scene
        if (Path(outdir) / "input.nml").is_file():
            case = Path(outdir) / "input.nml"
    if case is None:
        raise ValueError(f"no summary.nml with a scene, no input.nml in {outdir} and no case "
                         "file: nothing to classify")
    proc = subprocess.run([tubempm_binary(), "--scene", str(case)], capture_output=True,
                          text=True, timeout=120)
    scene = proc.stdout.strip()
    if proc.returncode != 0 or scene not in SCENES:
        raise ValueError(f"tubempm --scene {case} (exit {proc.returncode}): "
                         f"{(proc.stderr or proc.stdout).strip()[-400:]}")
    return scene


def ring_body(inputs: dict[str, list[dict[str, Any]]]) -> dict[str, Any] | None:
    """The first ring body, or None."""
    for b in inputs.get("body", []):
        if str(b.get("shape", "ring")).lower() == "ring":
            return b
    return None


def body_material(inputs: dict[str, list[dict[str, Any]]], body: dict[str, Any]
                  ) -> dict[str, Any]:
    """The &material group a body uses (the first material by default)."""
    mats = inputs.get("material", [])
    if not mats:
        return {}
    name = str(body.get("material", "") or "").strip().lower()
    for m in mats:
        if str(m.get("name", "")).strip().lower() == name:
            return m
    return mats[0]


def plane_of(inputs: dict[str, list[dict[str, Any]]]) -> str:
    """'strain' or 'stress' (&solver plane, default 'strain')."""
    p = str(_first(inputs, "solver").get("plane", "strain")).strip().lower()
    return "stress" if p == "stress" else "strain"


def depth_of(inputs: dict[str, list[dict[str, Any]]]) -> float:
    """&run depth [m] (default 1)."""
    d = _first(inputs, "run").get("depth", 1.0)
    return float(d) if isinstance(d, (int, float)) and not isinstance(d, bool) else 1.0


def sector_factor(inputs: dict[str, list[dict[str, Any]]]) -> float:
    """Factor from the modelled sector to the full ring: 1 (full), 2 (half) or 4 (quarter)."""
    f = 1.0
    for b in inputs.get("body", []):
        if str(b.get("shape", "ring")).lower() not in SECTOR_SHAPES:
            continue
        sector = str(b.get("sector", "full")).lower()
        f = max(f, {"half": 2.0, "quarter": 4.0}.get(sector, 1.0))
    return f


def ring_properties(inputs: dict[str, list[dict[str, Any]]]) -> dict[str, Any]:
    """Geometry and material of the first ring body, for the closed forms.

    Keys: ``center`` (2,) [m], ``R`` mean radius, ``t`` wall, ``D`` = 2 R [m], ``velocity``
    (2,) [m/s], ``E`` [Pa], ``nu``, ``rho`` [kg/m^3], ``sigma_y`` [Pa] (NaN when not given),
    ``hardening`` [Pa], ``model``, ``plane``, ``depth`` [m]. Raises ``ValueError`` without a
    ring body.
    """
    body = ring_body(inputs)
    if body is None:
        raise ValueError("the case has no ring body")

    def num(d: dict[str, Any], key: str, default: float = float("nan")) -> float:
        v = d.get(key, default)
        return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else default

    r_in, r_out = num(body, "r_inner"), num(body, "r_outer")
    mat = body_material(inputs, body)
    return {"center": _vec(body.get("center")), "R": 0.5 * (r_in + r_out), "t": r_out - r_in,
            "D": r_in + r_out, "velocity": _vec(body.get("velocity")), "E": num(mat, "e"),
            "nu": num(mat, "nu", 0.0), "rho": num(mat, "rho"), "sigma_y": num(mat, "sigma_y"),
            "hardening": num(mat, "hardening", 0.0),
            "model": str(mat.get("model", "j2")).lower(), "plane": plane_of(inputs),
            "depth": depth_of(inputs)}
