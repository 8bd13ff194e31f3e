# SPDX-License-Identifier: MIT
"""Closed forms of docs/method.md, per ``depth`` metres of tube, SI units: the DeRuntz-Hodge
crushing load and energy, the four-hinge collapse load, the elastic diametral stiffness of a
ring between two line loads, the wave speeds, and Gibson & Ashby's in-plane modulus, Poisson's
ratio and plastic collapse stress of a honeycomb loaded along x1.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["plastic_collapse_load", "deruntz_hodge", "deruntz_hodge_energy",
           "ring_elastic_stiffness", "bar_speed", "plate_speed", "dilatational_speed",
           "shear_speed", "wave_speeds", "honeycomb_e1", "honeycomb_nu12",
           "honeycomb_sigma_pl1"]


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


def _honeycomb_wall_terms(t_l: float, theta: float, nu: float, plane: str) -> tuple[float, float]:
    """Gibson & Ashby's corrections of the inclined wall's bending deflection for its axial and
    shear deformation (Cellular Solids, 2nd ed., ch. 4): the factor on
    the compliance along x1, 1 + (2.4 + 1.5 nu_s + cot^2 theta)(t/l)^2, and the one on the
    lateral displacement, 1 + (1.4 + 1.5 nu_s)(t/l)^2. In plane strain nu_s is the plane-strain
    Poisson's ratio nu / (1 - nu)."""
    nus = nu / (1.0 - nu) if plane.lower() == "strain" else nu
    tl2 = t_l * t_l
    along = 1.0 + (2.4 + 1.5 * nus + 1.0 / math.tan(theta) ** 2) * tl2
    across = 1.0 + (1.4 + 1.5 * nus) * tl2
    return along, across


def honeycomb_e1(t_l: float, h_l: float, theta_deg: float, E: float, nu: float = 0.0,
                 plane: str = "strain", corrected: bool = True) -> float:
    """In-plane Young's modulus E1* of a honeycomb along x1, perpendicular to the walls of
    length h [Pa]: E1*/E_s = (t/l)^3 cos(theta) / ((h/l + sin(theta)) sin^2(theta)) (Gibson &
    Ashby, Cellular Solids, 2nd ed., ch. 4), divided by the axial and shear correction when
    `corrected`. E_s = E / (1 - nu^2) in plane strain. theta < 0: re-entrant cells.
    """
    th = math.radians(theta_deg)
    es = E / (1.0 - nu * nu) if plane.lower() == "strain" else E
    e1 = es * t_l ** 3 * math.cos(th) / ((h_l + math.sin(th)) * math.sin(th) ** 2)
    if corrected:
        e1 /= _honeycomb_wall_terms(t_l, th, nu, plane)[0]
    return e1


def honeycomb_nu12(t_l: float, h_l: float, theta_deg: float, nu: float = 0.0,
                   plane: str = "strain", corrected: bool = True) -> float:
    """Poisson's ratio nu12* = -eps2/eps1 for loading along x1 [-]: cos^2(theta) /
    ((h/l + sin(theta)) sin(theta)) (Gibson & Ashby), negative for re-entrant cells,
    times the ratio of the corrections when `corrected`."""
    th = math.radians(theta_deg)
    nu12 = math.cos(th) ** 2 / ((h_l + math.sin(th)) * math.sin(th))
    if corrected:
        along, across = _honeycomb_wall_terms(t_l, th, nu, plane)
        nu12 *= across / along
    return nu12


def honeycomb_sigma_pl1(t_l: float, h_l: float, theta_deg: float, sigma_y: float,
                        plane: str = "strain") -> float:
    """Plastic collapse stress along x1 [Pa], its magnitude: sigma_ys (t/l)^2 /
    (2 (h/l + sin(theta)) |sin(theta)|) (Gibson & Ashby), the inclined walls hinged at
    both ends at M_p = sigma_ys t^2/4; in plane strain (von Mises) sigma_ys = 2 sigma_y/sqrt 3,
    the M_p of _plastic_moment."""
    th = math.radians(theta_deg)
    sys_ = 4.0 * _plastic_moment(1.0, sigma_y, plane)
    return sys_ * t_l ** 2 / (2.0 * (h_l + math.sin(th)) * abs(math.sin(th)))
