# SPDX-License-Identifier: MIT
"""Closed forms of docs/method.md, per ``depth`` metres of tube, SI units: the DeRuntz-Hodge
crushing load and energy, the four-hinge collapse load, the elastic diametral stiffness of a
ring between two line loads, and the wave speeds.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["plastic_collapse_load", "deruntz_hodge", "deruntz_hodge_energy",
           "ring_elastic_stiffness", "bar_speed", "plate_speed", "dilatational_speed",
           "shear_speed", "wave_speeds"]


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
