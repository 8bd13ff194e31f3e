# SPDX-License-Identifier: MIT
"""Post-processing of history columns: contact phases, impact and rebound velocities, moving
averages, probe disturbances and wave arrival times.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from .readers import history_probes

__all__ = ["contact_phases", "impact_velocity", "rebound_velocity", "moving_average",
           "probe_disturbance", "arrival_times"]


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


def arrival_times(time: np.ndarray, v: np.ndarray, threshold: float = 0.1,
                  levels: np.ndarray | None = None) -> np.ndarray | float:
    """First time at which |v| exceeds ``threshold`` times its peak [s], or, with ``levels``
    (one per signal, in v's units), exceeds that level.

    v: shape (n,) (one signal) or (n, m) (m signals in columns); the result is a float or an
    array of m floats, NaN for a signal that stays zero or below its level. The crossing time
    is interpolated linearly between rows. Pass a disturbance (e.g. |v - v(0)|) for a body that
    moves at t = 0. Records compared by their arrivals are timed at the same levels (``levels``,
    e.g. the reference's): a share of each record's own peak moves with whatever sets that
    peak, which may come long after the first arrival.
    """
    t = np.asarray(time, dtype=float)
    a = np.abs(np.asarray(v, dtype=float))
    single = a.ndim == 1
    if single:
        a = a[:, None]
    out = np.full(a.shape[1], np.nan)
    given = None if levels is None else np.atleast_1d(np.asarray(levels, dtype=float))
    if given is not None and given.size != a.shape[1]:
        raise ValueError(f"arrival_times: {given.size} levels for {a.shape[1]} signals")
    for j in range(a.shape[1]):
        s = a[:, j]
        if given is not None:
            level = float(given[j])
            if not np.isfinite(level) or level <= 0.0:
                continue
        else:
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
