# SPDX-License-Identifier: MIT
"""Readers of the tubempm outputs and the closed-form results the plots compare with.

This is the only module that reads tubempm files (shared/INTERFACE.md, docs/output.md):

* ``history.csv``  -> :func:`read_history`
* ``summary.nml``  -> :func:`read_summary`
* ``input.nml`` and any case file -> :func:`read_namelist` (a small tolerant namelist reader)
* ``particles.h5`` / ``crash_<step>.h5`` -> :func:`read_frames`, :func:`read_frame`

and it holds the closed forms of docs/theory.md (shared/METHOD.md section 7): the
DeRuntz-Hodge crushing load, the elastic diametral stiffness of a ring, wave speeds, plus the
post-processing of history columns (contact phases, rebound velocity, arrival times).

It needs numpy; h5py only for the particle files (imported when first needed). It never
imports matplotlib, so tests can use it without a display or a plotting stack.
Units are SI throughout (m, kg, s, N, Pa, J).
"""
from __future__ import annotations

import math
import os
import re
from pathlib import Path
from typing import Any, Sequence

import numpy as np

__all__ = [
    "REQUIRED_DATASETS", "NamelistError", "read_history", "read_summary", "read_namelist",
    "read_frames", "read_frame", "case_output_dir", "resolve_case", "scene_kind", "wall_table",
    "crush_displacement",
    "ring_body", "body_material", "ring_properties", "sector_factor", "history_probes",
    "plane_of", "depth_of", "deruntz_hodge",
    "deruntz_hodge_energy", "plastic_collapse_load", "ring_elastic_stiffness", "bar_speed",
    "plate_speed", "dilatational_speed", "shear_speed", "wave_speeds", "contact_phases",
    "impact_velocity", "rebound_velocity", "arrival_times", "moving_average", "history_walls",
    "probe_disturbance",
    "read_experiment",
]

#: Datasets every snapshot group of particles.h5 must hold, with their number of columns
#: (None: one-dimensional).
REQUIRED_DATASETS: dict[str, int | None] = {
    "x": 2, "v": 2, "mass": None, "volume": None, "stress": 4, "F": 4, "eqps": None,
    "corners": 2, "quads": 4,
}


# ----------------------------------------------------------------------------------------------
# history.csv
# ----------------------------------------------------------------------------------------------

def read_history(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """Read history.csv into ``{column name: 1-D float array}`` (columns in file order).

    A last line with the wrong number of fields (a run still writing) is dropped; a wrong line
    elsewhere raises ``ValueError`` naming the line.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: history file not found (has the case been run?)")
    with path.open() as f:
        lines = [ln.strip() for ln in f]
    lines = [ln for ln in lines if ln]
    if not lines:
        raise ValueError(f"{path}: empty file, expected a header line of column names")
    names = [n.strip() for n in lines[0].split(",")]
    if len(set(names)) != len(names):
        raise ValueError(f"{path}: repeated column names in the header")
    rows: list[list[float]] = []
    for i, line in enumerate(lines[1:], start=2):
        fields = line.split(",")
        try:
            if len(fields) != len(names):
                raise ValueError(f"{len(fields)} fields, header has {len(names)}")
            rows.append([_fortran_float(s) for s in fields])
        except ValueError as exc:
            if i == len(lines):        # the run may still be writing this line
                break
            raise ValueError(f"{path}:{i}: {exc}") from None
    data = np.array(rows, dtype=float).reshape(len(rows), len(names))
    return {name: data[:, j].copy() for j, name in enumerate(names)}


def _fortran_float(text: str) -> float:
    """A number as Fortran writes it (``1.0D+00``, ``1.0+100``, ``Infinity``, ``NaN``)."""
    s = text.strip().lower().replace("d", "e")
    try:
        return float(s)
    except ValueError:
        # Fortran drops the 'e' of three-digit exponents with some edit descriptors: 1.0-100
        m = re.fullmatch(r"([+-]?[0-9.]+)([+-][0-9]+)", s)
        if m:
            return float(m.group(1) + "e" + m.group(2))
        raise ValueError(f"not a number: {text.strip()!r}") from None


def history_walls(history: dict[str, np.ndarray]) -> int:
    """Number of walls (``wall<k>_force`` columns) in a history."""
    k = 0
    while f"wall{k + 1}_force" in history:
        k += 1
    return k


def history_probes(history: dict[str, np.ndarray]) -> int:
    """Number of probes (``probe<k>_vx`` columns) in a history."""
    k = 0
    while f"probe{k + 1}_vx" in history:
        k += 1
    return k


# ----------------------------------------------------------------------------------------------
# Namelists (input.nml, summary.nml, case files)
# ----------------------------------------------------------------------------------------------

class NamelistError(ValueError):
    """A namelist file that cannot be read."""


_TOKEN = re.compile(
    r"""\s*(?:
        (?P<str1>'(?:[^']|'')*')
      | (?P<str2>"(?:[^"]|"")*")
      | (?P<group>[&$][A-Za-z_]\w*)
      | (?P<eq>=)
      | (?P<comma>,)
      | (?P<slash>/)
      | (?P<word>[^\s,=/'"]+)
    )""",
    re.VERBOSE,
)


def _strip_comment(line: str) -> str:
    """The line without its ``!`` comment (a ``!`` inside quotes is kept)."""
    quote = ""
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = ""
        elif ch in "'\"":
            quote = ch
        elif ch == "!":
            return line[:i]
    return line


def _tokens(text: str, where: str) -> list[tuple[str, str, int]]:
    """(kind, text, line number) tokens of a namelist file, comments removed."""
    out: list[tuple[str, str, int]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = _strip_comment(raw)
        pos = 0
        while pos < len(line):
            if line[pos:].strip() == "":
                break
            m = _TOKEN.match(line, pos)
            if not m or m.end() == pos:
                raise NamelistError(f"{where}:{lineno}: cannot read {line[pos:].strip()!r}")
            kind = m.lastgroup or "word"
            out.append((kind, m.group(kind), lineno))
            pos = m.end()
    return out


def _convert(kind: str, text: str) -> Any:
    """One namelist value: str, bool, int or float (other bare words stay strings)."""
    if kind == "str1":
        return text[1:-1].replace("''", "'")
    if kind == "str2":
        return text[1:-1].replace('""', '"')
    low = text.lower()
    if re.fullmatch(r"\.?t(rue)?\.?", low):
        return True
    if re.fullmatch(r"\.?f(alse)?\.?", low):
        return False
    if re.fullmatch(r"[+-]?\d+", text):
        return int(text)
    try:
        return _fortran_float(text)
    except ValueError:
        return text


def read_namelist(path: str | os.PathLike) -> dict[str, list[dict[str, Any]]]:
    """Read every namelist group of a file: ``{group: [ {name: value}, ... ]}``.

    Group and variable names are lower case; a group that occurs several times (``&material``,
    ``&body``, ``&wall``, ``&probe``) gives several dicts, in file order. Values are ``str``
    (quotes removed), ``bool`` (``.true.``, ``T``), ``int``, ``float`` (``1.0d-3`` too), or a
    list of those for arrays (``a, b`` or ``3*0.0``; values may continue on the next lines).
    ``name(i) = v`` sets element i. ``!`` starts a comment outside quotes; text outside
    groups is ignored.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: namelist file not found")
    return parse_namelist(path.read_text(errors="replace"), str(path))


def parse_namelist(text: str, where: str = "<text>") -> dict[str, list[dict[str, Any]]]:
    """:func:`read_namelist` on a string (``where`` names it in error messages)."""
    toks = _tokens(text, where)
    groups: dict[str, list[dict[str, Any]]] = {}
    i = 0
    n = len(toks)
    while i < n:
        kind, tok, _ = toks[i]
        i += 1
        if kind != "group" or tok[1:].lower() == "end":
            continue                           # text outside a group
        gname = tok[1:].lower()
        entries: dict[str, Any] = {}
        closed = False
        while i < n:
            kind, tok, line = toks[i]
            if kind == "slash" or (kind == "group" and tok[1:].lower() == "end"):
                i += 1
                closed = True
                break
            if kind == "group":
                raise NamelistError(f"{where}:{line}: &{gname} is not closed with '/' before "
                                    f"{tok}")
            if kind != "word" or i + 1 >= n or toks[i + 1][0] != "eq":
                raise NamelistError(f"{where}:{line}: &{gname}: expected 'name = value', "
                                    f"found {tok!r}")
            name = tok.lower()
            i += 2
            values: list[Any] = []
            pending = True                     # a value may follow (start, or after a comma)
            while i < n:
                kind, tok, line = toks[i]
                if kind in ("slash", "group"):
                    break
                if kind == "word" and i + 1 < n and toks[i + 1][0] == "eq":
                    break                      # the next 'name ='
                if kind == "comma":
                    if pending:
                        values.append(None)    # null value
                    pending = True
                    i += 1
                    continue
                if kind == "eq":
                    raise NamelistError(f"{where}:{line}: &{gname}: unexpected '='")
                rep = re.fullmatch(r"(\d+)\*(.*)", tok) if kind == "word" else None
                if rep:
                    count = int(rep.group(1))
                    if rep.group(2):
                        val = _convert("word", rep.group(2))
                    elif i + 1 < n and toks[i + 1][0] in ("str1", "str2"):
                        i += 1
                        val = _convert(toks[i][0], toks[i][1])
                    else:
                        val = None
                    values.extend([val] * count)
                else:
                    values.append(_convert(kind, tok))
                pending = False
                i += 1
            _assign(entries, name, values)
        if not closed:
            raise NamelistError(f"{where}: &{gname} is not closed with '/'")
        groups.setdefault(gname, []).append(entries)
    return groups


def _assign(entries: dict[str, Any], name: str, values: list[Any]) -> None:
    """Store values under name; ``name(i)`` or ``name(i:j)`` sets elements (1-based)."""
    m = re.fullmatch(r"(\w+)\((\d+)(?::(\d+))?\)", name)
    if not m:
        entries[name] = values[0] if len(values) == 1 else values
        return
    base, first = m.group(1), int(m.group(2))
    current = entries.get(base, [])
    if not isinstance(current, list):
        current = [current]
    need = first - 1 + len(values)
    current = current + [None] * max(0, need - len(current))
    current[first - 1:first - 1 + len(values)] = values
    entries[base] = current


def read_summary(path: str | os.PathLike) -> dict[str, Any]:
    """Read summary.nml: the ``&summary`` group as a flat dict."""
    groups = read_namelist(path)
    if "summary" not in groups:
        raise NamelistError(f"{path}: no &summary group")
    return groups["summary"][0]


# ----------------------------------------------------------------------------------------------
# Cases and inputs
# ----------------------------------------------------------------------------------------------

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


def _is_mirror(wall: dict[str, Any]) -> bool:
    """A mirror plane given in the input ('slip' contact)."""
    return str(wall.get("contact", "frictionless")).strip().lower() == "slip"


def wall_table(inputs: dict[str, list[dict[str, Any]]], nwall: int | None = None
               ) -> list[dict[str, Any]]:
    """The walls as numbered in history.csv: the input's ``&wall`` groups, then the mirror
    planes a half/quarter ``sector`` adds (normal (1, 0), then (0, 1), through the centre of
    the first sector ring).

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
               if str(b.get("shape", "ring")).lower() == "ring"]
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


def crush_displacement(history: dict[str, np.ndarray], inputs: dict[str, list[dict[str, Any]]]
                       ) -> tuple[np.ndarray, np.ndarray, int]:
    """Crush displacement delta [m], platen force [N] and the platen's wall index.

    ``wall<k>_disp`` is the travel along minus the normal: negative for a platen moving into
    the tube. delta is the relative approach of the platens: the advance of every moving
    platen, plus that of its mirror image where a mirror plane of a half/quarter model is
    parallel to it (the quarter model's bottom platen is the top one's image). The force is
    that of the first moving platen. ValueError if no wall moves.
    """
    table = wall_table(inputs, history_walls(history))
    moving = [w for w in table if w["moving"] and not w["mirror"]]
    if not moving:
        raise ValueError("crush: no moving wall (platen) in the case")
    k = moving[0]["index"]
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
    return disp, history[f"wall{k}_force"], k


def scene_kind(inputs: dict[str, list[dict[str, Any]]]) -> str:
    """Which scenario a case is: 'crush', 'wave', 'impact' or 'generic' (tested in this order).

    crush: a non-mirror wall with a nonzero velocity and no motion table;
    wave: probes present, or a wall with a motion table;
    impact: a body with a nonzero velocity and a static wall.
    """
    walls = [w for w in wall_table(inputs) if not w["mirror"]]
    if any(w["moving"] and not w["table"] for w in walls):
        return "crush"
    if inputs.get("probe") or any(w["table"] for w in walls):
        return "wave"
    if any(_nonzero(b.get("velocity")) for b in inputs.get("body", [])) and \
            any(not w["moving"] for w in walls):
        return "impact"
    return "generic"


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
        if str(b.get("shape", "ring")).lower() != "ring":
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


# ----------------------------------------------------------------------------------------------
# particles.h5
# ----------------------------------------------------------------------------------------------

def _h5py():
    """The h5py module, with a clear message when it is missing."""
    try:
        import h5py  # noqa: PLC0415 (only the particle readers need it)
    except ImportError as exc:  # pragma: no cover
        raise ImportError("reading particles.h5 needs h5py: pip install h5py "
                          "(see plots/requirements.txt)") from exc
    return h5py


def _open_h5(path: Path):
    """Open an HDF5 file read-only without taking the file lock, so that the particle file of
    a run still in progress can be read (tubempm flushes it after every snapshot)."""
    h5py = _h5py()
    try:
        return h5py.File(path, "r", locking=False)
    except (TypeError, ValueError):            # old h5py or HDF5: no locking argument
        return h5py.File(path, "r")


def _snap_key(name: str) -> int:
    return int(name.split("_")[-1])


def read_frames(h5path: str | os.PathLike) -> list[str]:
    """Names of the snapshot groups of a particle file (``snap_000000``, ...), in order."""
    h5py = _h5py()
    path = Path(h5path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: particle file not found (has the case been run?)")
    with _open_h5(path) as f:
        names = [k for k in f.keys() if re.fullmatch(r"snap_\d+", k)
                 and isinstance(f[k], h5py.Group)]
    return sorted(names, key=_snap_key)


def _attr_value(value: Any) -> Any:
    """An HDF5 attribute as a Python scalar or string."""
    if isinstance(value, bytes):
        return value.decode(errors="replace").rstrip("\x00 ")
    if isinstance(value, np.ndarray):
        if value.dtype.kind == "S":
            return _attr_value(value.ravel()[0]) if value.size == 1 else \
                [_attr_value(v) for v in value.ravel()]
        if value.size == 1:
            return value.ravel()[0].item()
        return value
    if isinstance(value, np.generic):
        return value.item()
    return value


def read_frame(h5path: str | os.PathLike, name_or_index: str | int = -1) -> dict[str, Any]:
    """One snapshot as a dict of numpy arrays.

    Keys: the datasets (``x`` (np,2), ``v`` (np,2), ``mass``, ``volume``, ``stress`` (np,4:
    xx, yy, xy, zz), ``F`` (np,4), ``eqps``, ``corners`` (ncorner,2), ``quads`` (np,4),
    0-based) plus any others, the group attributes (``time``, ``step``, ``dt``, ``np``,
    ``ncorner``, ...), ``name`` and ``units`` (dataset -> units string). ``name_or_index`` is a
    group name or a position in :func:`read_frames` (negative counts from the end).
    Raises ``KeyError`` naming what is missing when a required dataset is absent, and
    ``ValueError`` when a shape is wrong.
    """
    h5py = _h5py()
    path = Path(h5path)
    names = read_frames(path)
    if not names:
        raise KeyError(f"{path}: no snapshot groups (snap_NNNNNN) in the file")
    if isinstance(name_or_index, (int, np.integer)):
        try:
            name = names[int(name_or_index)]
        except IndexError:
            raise IndexError(f"{path}: snapshot index {name_or_index} out of range; the file "
                             f"holds {len(names)} snapshots") from None
    else:
        name = str(name_or_index)
        if name not in names:
            raise KeyError(f"{path}: no snapshot {name!r}; it holds {names[0]} .. {names[-1]}")
    out: dict[str, Any] = {"name": name, "units": {}}
    with _open_h5(path) as f:
        g = f[name]
        missing = [d for d in REQUIRED_DATASETS if d not in g]
        if missing:
            raise KeyError(f"{path}:/{name}: required dataset(s) missing: {', '.join(missing)} "
                           f"(expected {', '.join(REQUIRED_DATASETS)}); the file is not a "
                           f"complete tubempm snapshot")
        for key, val in g.attrs.items():
            out[key] = _attr_value(val)
        for key, item in g.items():
            if isinstance(item, h5py.Dataset):
                out[key] = item[()]
                out["units"][key] = _attr_value(item.attrs.get("units", ""))
    npart = out["x"].shape[0]
    for key, ncol in REQUIRED_DATASETS.items():
        arr = np.asarray(out[key])
        want_rows = out["corners"].shape[0] if key == "corners" else npart
        want = (want_rows,) if ncol is None else (want_rows, ncol)
        if ncol is None and arr.ndim == 2 and 1 in arr.shape:
            arr = arr.reshape(-1)
            out[key] = arr
        if arr.shape != want:
            raise ValueError(f"{path}:/{name}/{key}: shape {arr.shape}, expected {want}")
    for key in ("np", "ncorner", "step", "ndim"):
        if key in out and isinstance(out[key], float) and out[key].is_integer():
            out[key] = int(out[key])
    return out


# ----------------------------------------------------------------------------------------------
# Closed forms (docs/theory.md; shared/METHOD.md section 7). Per `depth` metres of tube.
# ----------------------------------------------------------------------------------------------

def _plastic_moment(t: float, sigma0: float, plane: str) -> float:
    """Fully plastic moment per unit length M0 [N m/m]: sigma0 t^2/4 (plane stress) or
    sigma0 t^2/(2 sqrt 3) (plane strain, von Mises)."""
    if plane.lower() == "stress":
        return sigma0 * t * t / 4.0
    return sigma0 * t * t / (2.0 * math.sqrt(3.0))


def plastic_collapse_load(D: float, t: float, sigma0: float, plane: str = "strain",
                          depth: float = 1.0) -> float:
    """Four-hinge collapse load P0 = 4 M0 / R of a ring between flat plates [N for depth].

    D: mean diameter [m]; t: wall thickness [m]; sigma0: yield stress [Pa];
    plane: 'strain' or 'stress'; depth: tube length [m].
    """
    R = 0.5 * D
    return 4.0 * _plastic_moment(t, sigma0, plane) / R * depth


def deruntz_hodge(delta: np.ndarray | float, D: float, t: float, sigma0: float,
                  plane: str = "strain", depth: float = 1.0) -> np.ndarray:
    """DeRuntz & Hodge (1963) crushing load P = P0 / sqrt(1 - (delta/D)^2) [N for depth].

    Rigid-perfectly plastic ring with geometry change. delta: platen displacement [m];
    D = 2 R mean diameter [m]; t: wall [m]; sigma0: yield stress [Pa]. NaN for delta >= D.
    """
    d = np.asarray(delta, dtype=float) / D
    p0 = plastic_collapse_load(D, t, sigma0, plane, depth)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = p0 / np.sqrt(1.0 - d * d)
    return np.where(np.abs(d) < 1.0, p, np.nan)


def deruntz_hodge_energy(delta: np.ndarray | float, D: float, t: float, sigma0: float,
                         plane: str = "strain", depth: float = 1.0) -> np.ndarray:
    """Energy absorbed in the DeRuntz-Hodge model, W = P0 D arcsin(delta / D) [J for depth]."""
    d = np.clip(np.asarray(delta, dtype=float) / D, -1.0, 1.0)
    return plastic_collapse_load(D, t, sigma0, plane, depth) * D * np.arcsin(d)


def ring_elastic_stiffness(R: float, t: float, E: float, nu: float = 0.0,
                           plane: str = "strain", depth: float = 1.0) -> float:
    """Diametral stiffness P / delta of a thin ring between flat plates [N/m for depth].

    P/delta = E I / ((pi/4 - 2/pi) R^3), I = t^3/12 * depth; plane strain uses E/(1 - nu^2).
    R: mean radius [m]; t: wall [m]; E: Young's modulus [Pa]; nu: Poisson's ratio.
    """
    e_eff = E / (1.0 - nu * nu) if plane.lower() == "strain" else E
    inertia = t ** 3 / 12.0 * depth
    return e_eff * inertia / ((math.pi / 4.0 - 2.0 / math.pi) * R ** 3)


def bar_speed(E: float, rho: float) -> float:
    """Bar wave speed sqrt(E / rho) [m/s]."""
    return math.sqrt(E / rho)


def plate_speed(E: float, nu: float, rho: float) -> float:
    """Plane-strain plate (membrane) wave speed sqrt(E / (rho (1 - nu^2))) [m/s]."""
    return math.sqrt(E / (rho * (1.0 - nu * nu)))


def dilatational_speed(E: float, nu: float, rho: float) -> float:
    """Dilatational wave speed sqrt((lambda + 2 mu) / rho) [m/s]."""
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = E / (2.0 * (1.0 + nu))
    return math.sqrt((lam + 2.0 * mu) / rho)


def shear_speed(E: float, nu: float, rho: float) -> float:
    """Shear wave speed sqrt(mu / rho) [m/s]."""
    return math.sqrt(E / (2.0 * (1.0 + nu)) / rho)


def wave_speeds(E: float, nu: float, rho: float) -> dict[str, float]:
    """All four wave speeds [m/s]: keys 'bar', 'plate', 'dilatational', 'shear'."""
    return {"bar": bar_speed(E, rho), "plate": plate_speed(E, nu, rho),
            "dilatational": dilatational_speed(E, nu, rho), "shear": shear_speed(E, nu, rho)}


# ----------------------------------------------------------------------------------------------
# Post-processing of history columns
# ----------------------------------------------------------------------------------------------

def contact_phases(time: np.ndarray, force: np.ndarray, fraction: float = 0.01,
                   hold: int = 3, away: np.ndarray | None = None) -> dict[str, float]:
    """First contact of a wall force record.

    Contact starts at the first row where the force exceeds ``fraction`` of its peak, and the
    first contact ends at the first later row from which the force stays at or below that
    level for ``hold`` rows (so that a single quiet row inside the contact does not end it).
    ``away`` (optional, one bool per row: the body moves away from the wall, e.g. the centre
    of mass velocity along the wall normal > 0) additionally requires the body to be leaving
    at that row, so that chatter while the body still approaches does not end the contact.
    Returns ``start``, ``end``, ``duration`` [s] (NaN if no contact, ``end`` and ``duration``
    NaN when the record stops during the contact), ``peak`` [N], ``peak_time`` [s],
    ``impulse`` (integral of the force over the contact, N s), ``threshold`` [N] and
    ``ended`` (1.0 or 0.0).
    """
    t = np.asarray(time, dtype=float)
    f = np.asarray(force, dtype=float)
    nan = float("nan")
    res = {"start": nan, "end": nan, "duration": nan, "peak": nan, "peak_time": nan,
           "impulse": nan, "threshold": nan, "ended": 0.0}
    if f.size == 0 or not np.any(np.isfinite(f)):
        return res
    peak = float(np.nanmax(f))
    if peak <= 0.0:
        return res
    thr = fraction * peak
    on = f > thr
    i0 = int(np.argmax(on))
    quiet = ~on
    i1 = None
    for i in range(i0 + 1, len(f)):
        if np.all(quiet[i:i + max(hold, 1)]) and (away is None or bool(away[i])):
            i1 = i
            break
    seg = slice(i0, (i1 + 1) if i1 is not None else len(f))
    fs, ts = f[seg], t[seg]
    k = int(np.nanargmax(fs))
    res.update(start=float(t[i0]), peak=float(fs[k]), peak_time=float(ts[k]), threshold=thr)
    lo = max(i0 - 1, 0)                        # include the ramp from the row before contact
    hi = (i1 + 1) if i1 is not None else len(f)
    res["impulse"] = _trapezoid(f[lo:hi], t[lo:hi])
    if i1 is not None:
        res.update(end=float(t[i1]), duration=float(t[i1] - t[i0]), ended=1.0)
    return res


def _trapezoid(y: np.ndarray, x: np.ndarray) -> float:
    """Trapezoidal integral of y over x (0 for fewer than two points)."""
    if len(y) < 2:
        return 0.0
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def _com_velocity(history: dict[str, np.ndarray]) -> np.ndarray:
    return np.column_stack([history["com_vx"], history["com_vy"]])


def _wall_normal(history: dict[str, np.ndarray], wall: int,
                 normal: Sequence[float] | None) -> np.ndarray:
    """The target normal: given, or from the direction of the largest wall force (the material
    pushes the wall along minus its normal)."""
    if normal is not None:
        n = np.asarray(normal, dtype=float)
        return n / np.linalg.norm(n)
    fx, fy = history[f"wall{wall}_fx"], history[f"wall{wall}_fy"]
    k = int(np.nanargmax(np.hypot(fx, fy)))
    f = np.array([fx[k], fy[k]])
    if not np.any(f):
        raise ValueError(f"wall {wall} never carries a force: give the normal")
    return -f / np.linalg.norm(f)


def impact_velocity(history: dict[str, np.ndarray], wall: int = 1,
                    normal: Sequence[float] | None = None,
                    phases: dict[str, float] | None = None) -> float:
    """Approach speed of the centre of mass towards the wall just before the first contact,
    -v_com . n [m/s] (positive when approaching)."""
    t = history["time"]
    n = _wall_normal(history, wall, normal)
    if phases is None:
        phases = contact_phases(t, history[f"wall{wall}_force"])
    v = _com_velocity(history) @ n
    if not np.isfinite(phases["start"]):
        return float(-v[-1])
    i0 = int(np.searchsorted(t, phases["start"]))
    return float(-v[max(i0 - 1, 0)])


def rebound_velocity(history: dict[str, np.ndarray], wall: int = 1,
                     normal: Sequence[float] | None = None,
                     phases: dict[str, float] | None = None) -> float:
    """Centre-of-mass velocity along the target normal after the first contact, v_com . n
    [m/s] (positive when moving away). The mean over the rows from the end of the first contact
    to the next contact (or the end of the record); NaN when the contact has not ended.
    ``normal`` defaults to the direction of the wall force.
    """
    t = history["time"]
    f = history[f"wall{wall}_force"]
    n = _wall_normal(history, wall, normal)
    if phases is None:
        phases = contact_phases(t, f)
    if not phases["ended"]:
        return float("nan")
    i1 = int(np.searchsorted(t, phases["end"]))
    after = f[i1:] > phases["threshold"]
    i2 = i1 + (int(np.argmax(after)) if np.any(after) else len(after))
    v = _com_velocity(history)[i1:max(i2, i1 + 1)] @ n
    return float(np.mean(v))


def moving_average(y: np.ndarray, n: int) -> np.ndarray:
    """Centred moving average of y over n samples; near the ends the window shrinks to the
    samples there are (so a record that starts and ends at zero stays zero there)."""
    n = max(1, int(n))
    k = np.ones(n)
    return np.convolve(y, k, mode="same") / np.convolve(np.ones_like(y), k, mode="same")


def probe_disturbance(history: dict[str, np.ndarray]) -> np.ndarray:
    """|v - v(0)| of every probe, shape (rows, probes) [m/s]: the disturbance to time the
    arrival of a wave by (:func:`arrival_times`), also for a body moving at t = 0."""
    cols = [np.hypot(history[f"probe{j}_vx"] - history[f"probe{j}_vx"][0],
                     history[f"probe{j}_vy"] - history[f"probe{j}_vy"][0])
            for j in range(1, history_probes(history) + 1)]
    return np.column_stack(cols) if cols else np.zeros((len(history["time"]), 0))


def arrival_times(time: np.ndarray, v: np.ndarray, threshold: float = 0.1) -> np.ndarray | float:
    """First time at which |v| exceeds ``threshold`` times its peak [s].

    v: shape (n,) (one signal) or (n, m) (m signals in columns); the result is a float or an
    array of m floats, NaN for a signal that stays zero. The crossing time is interpolated
    linearly between rows. Pass a disturbance (e.g. |v - v(0)|) for a body that moves at t = 0.
    """
    t = np.asarray(time, dtype=float)
    a = np.abs(np.asarray(v, dtype=float))
    single = a.ndim == 1
    if single:
        a = a[:, None]
    out = np.full(a.shape[1], np.nan)
    for j in range(a.shape[1]):
        s = a[:, j]
        peak = np.nanmax(s) if s.size else 0.0
        if not np.isfinite(peak) or peak <= 0.0:
            continue
        level = threshold * peak
        above = np.nonzero(s > level)[0]
        if above.size == 0:
            continue
        i = int(above[0])
        if i == 0:
            out[j] = t[0]
        else:
            s0, s1 = s[i - 1], s[i]
            w = (level - s0) / (s1 - s0) if s1 != s0 else 1.0
            out[j] = t[i - 1] + w * (t[i] - t[i - 1])
    return float(out[0]) if single else out


# ----------------------------------------------------------------------------------------------
# Measured curves
# ----------------------------------------------------------------------------------------------

def read_experiment(path: str | os.PathLike, columns: Sequence[str]) -> tuple[np.ndarray, ...]:
    """Columns of a measured-curve CSV file.

    The first non-comment line is a header of column names (``#`` starts a comment line). The
    named ``columns`` are returned as float arrays; when the header does not name them, the
    first len(columns) columns are used in order.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: experiment file not found")
    lines = [ln.strip() for ln in path.read_text().splitlines()]
    lines = [ln for ln in lines if ln and not ln.startswith("#")]
    if not lines:
        raise ValueError(f"{path}: no data")
    header = [h.strip().lower() for h in lines[0].split(",")]
    try:
        [float(h) for h in header]
        body = lines                           # no header line
        idx = list(range(len(columns)))
    except ValueError:
        body = lines[1:]
        if all(c.lower() in header for c in columns):
            idx = [header.index(c.lower()) for c in columns]
        else:
            idx = list(range(len(columns)))
    rows = []
    for i, ln in enumerate(body):
        fields = ln.split(",")
        try:
            rows.append([float(fields[j]) for j in idx])
        except (ValueError, IndexError):
            raise ValueError(f"{path}: cannot read data line {i + 1}: {ln!r} (expected "
                             f"columns {', '.join(columns)})") from None
    data = np.array(rows, dtype=float).reshape(len(rows), len(columns))
    return tuple(data[:, j] for j in range(len(columns)))
