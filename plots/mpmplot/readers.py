# SPDX-License-Identifier: MIT
"""Readers of the tubempm output files (docs/output.md):

* ``history.csv``  -> :func:`read_history` (and :func:`history_walls`, :func:`history_probes`)
* ``summary.nml``  -> :func:`read_summary`
* ``particles.h5`` / ``crash_<step>.h5`` -> :func:`read_frames`, :func:`read_frame`
* a measured-curve CSV file -> :func:`read_experiment`

numpy only; h5py is imported when a particle file is first read.
"""
from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .namelist import NamelistError, fortran_float, read_namelist

__all__ = ["REQUIRED_DATASETS", "read_history", "history_walls", "history_probes",
           "read_summary", "run_failure", "read_frames", "read_frame", "read_experiment"]

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
            rows.append([fortran_float(s) for s in fields])
        except ValueError as exc:
            if i == len(lines):        # the run may still be writing this line
                break
            raise ValueError(f"{path}:{i}: {exc}") from None
    data = np.array(rows, dtype=float).reshape(len(rows), len(names))
    return {name: data[:, j].copy() for j, name in enumerate(names)}


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

def read_summary(path: str | os.PathLike) -> dict[str, Any]:
    """Read summary.nml: the ``&summary`` group as a flat dict."""
    groups = read_namelist(path)
    if "summary" not in groups:
        raise NamelistError(f"{path}: no &summary group")
    return groups["summary"][0]


def read_results(path: str | os.PathLike) -> dict[str, Any]:
    """Read summary.nml's ``&results`` group (the absorber results, docs/output.md) as a flat
    dict; {} for a run without a loading wall."""
    groups = read_namelist(path)
    return groups["results"][0] if "results" in groups else {}


def run_failure(outdir: str | os.PathLike) -> str:
    """'' for a run whose summary.nml says 'completed', else one line saying how it ended
    (the status and message of summary.nml, or that there is no summary.nml yet)."""
    path = Path(outdir) / "summary.nml"
    if not path.is_file():
        return f"RUN NOT FINISHED: no {path} (still running, or killed)"
    try:
        summary = read_summary(path)
    except (OSError, ValueError) as exc:
        return f"RUN STATUS UNKNOWN: {exc}"
    status = str(summary.get("status", "")).strip()
    if status == "completed":
        return ""
    message = str(summary.get("message", "")).strip()
    return f"RUN FAILED (status '{status}'): {message}" if message else \
        f"RUN FAILED (status '{status}')"


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


def read_frame(h5path: str | os.PathLike, name_or_index: str | int = -1,
               mirrored: bool = False) -> dict[str, Any]:
    """One snapshot as a dict of numpy arrays.

    Keys: the datasets (``x`` (np,2), ``v`` (np,2), ``mass``, ``volume``, ``stress`` (np,4:
    xx, yy, xy, zz), ``F`` (np,4), ``eqps``, ``corners`` (ncorner,2), ``quads`` (np,4),
    0-based) plus any others, the group attributes (``time``, ``step``, ``dt``, ``np``,
    ``ncorner``, ...), ``name`` and ``units`` (dataset -> units string). ``name_or_index`` is a
    group name or a position in :func:`read_frames` (negative counts from the end).
    Raises ``KeyError`` naming what is missing when a required dataset is absent, and
    ``ValueError`` when a shape is wrong. With ``mirrored``, the datasets and ``np``,
    ``ncorner`` come from the snapshot's subgroup ``mirrored`` where there is one (a half or
    quarter model: the whole tube, the computed sector first; docs/output.md), with ``image``
    (the copy of each particle) and ``images``; ``mirrored`` in the result says which was read.
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
        for key, val in g.attrs.items():
            out[key] = _attr_value(val)
        out["mirrored"] = bool(mirrored and "mirrored" in g)
        if out["mirrored"]:
            g = g["mirrored"]
        missing = [d for d in REQUIRED_DATASETS if d not in g]
        if missing:
            raise KeyError(f"{path}:/{name}: required dataset(s) missing: {', '.join(missing)} "
                           f"(expected {', '.join(REQUIRED_DATASETS)}); the file is not a "
                           f"complete tubempm snapshot")
        if out["mirrored"]:                  # np, ncorner, images, mirror_x/_y of the tube
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
