#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A foam-filled ring crushed between platens (issue 35; namelists/foam/filled_ring.nml,
coarse): the ring and its foam core meet by frictionless contact and stay two bodies. Run with
the binary under test; the oracles are the energy balance and the particle domains of
particles.h5, not the contact code.

The scene is filled_ring.nml's steel ring (r 23.95-25.43 mm) around a touching disc of its
Alporas-like foam, a quarter model, coarse and quick: h = t/2 = 0.74 mm, 4 particles through
the wall (about square), the disc 24 O-grid divisions (its surface particles h deep and 2.1 h
along, as filled_ring.nml's at its h), mass_scale 4, the platens approaching at 20 m/s to
delta = 24 mm (delta/D = 0.47). Checks:

* the run completes, and its energy balance is within 5 % (0.05 %; two velocity fields meet,
  and the loss of their contact is in `contact_loss`, docs/output.md; tests/test_sections_crush.py's
  tolerance);
* the plastic work is shared: ring and core each absorb more than a tenth of it;
* no crossing: in no snapshot does a domain corner of one body lie more than h/10 inside a
  particle of the other (tests/test_sections_crush.py's `crossing`, run on the corners of
  both bodies against the particles of one; the ring's own particles are non-neighbours of
  each other too, so the measure also covers the ring folding onto itself);
* no welding: the bodies touch all round at t = 0 (the gap at the equator, between the ring's
  innermost corner and the core's outermost corner near y = centre, below h/10), and at the
  end the ring's side has moved out from the core by more than 2 h: a weld would carry the
  core's edge with the ring (with the foam's plastic Poisson's ratio of 0 the core does not
  widen as it is crushed);
* the measures can fail: the same run with the ring's particles of aspect 2 along the wall
  (n_circ = 212) crosses by 0.27 h (at the bend of the crown, each body's corners sink into
  the other's particles; at aspect 1, 0.005 h); and on the first snapshot the crossing
  measure finds the core's boundary corners moved 0.2 h out into the ring, and the gap
  measure the ring moved 3 h out.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_filled_ring SCRATCH
"""
from __future__ import annotations

import sys
from pathlib import Path

import h5py
import numpy as np

from plots.mpmplot import readers
from tests.pycheck import Checks
from tests.pyscene import run_scene
from tests.test_sections_crush import crossing

T = Checks("test_filled_ring")
check = T.check
H = 0.74e-3                     # t/2
CY = 25.43e-3                   # the ring's centre (its outer radius above the bottom platen)
R_IN, R_OUT = 23.95e-3, 25.43e-3

#: the tube's steel and foam_block.nml's Alporas-like foam (test_filled_square uses them too)
MATERIALS = """&material name = 'steel', model = 'j2', E = 210.0e9, nu = 0.3, rho = 7800.0,
  sigma_y = 310.0e6, hardening = 10.0e6 /
&material name = 'alporas', model = 'foam', E = 1.0e9, nu = 0.3, rho = 230.0, sigma_p = 1.6e6,
  nu_plastic = 0.0, foam_gamma = 2.0e6, foam_alpha2 = 4.0e6, foam_beta = 4.0, eps_d = 2.46 /
"""

SCENE = f"""&run title = 'filled', cfl = 0.875, history_every = 1.0e-5, snapshot_every = 2.0e-4,
  output_dir = 'OUT' /
&solver basis = 'cpdi2', scheme = 'musl', plane = 'strain', mass_scale = 4.0 /
&grid h = {H} /
{MATERIALS}&body shape = 'ring', material = 'steel', center = 0.0, {CY}, r_inner = {R_IN},
  r_outer = {R_OUT}, n_thick = 4, sector = 'quarter' /
&body shape = 'disc', material = 'alporas', center = 0.0, {CY}, r_outer = {R_IN},
  n_thick = 24, sector = 'quarter' /
&contact bodies = 1, 2, law = 'frictionless' /
&wall point = 0.0, {2.0 * CY}, normal = 0.0, -1.0, velocity = 0.0, -10.0, ramp = 1.0e-4,
  stroke = 12.0e-3 /
"""


def snapshot(f: h5py.File, key: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Corners, quads and the body of each particle of one snapshot (the computed quarter)."""
    g = f[key]
    return g["corners"][...], g["quads"][...].astype(int), g["body"][...].astype(int)


def between(corners: np.ndarray, quads: np.ndarray, body: np.ndarray) -> float:
    """The deepest a corner of one body lies inside a particle of the other [m]: `crossing`
    on every corner against the ring's particles, then against the core's (a body's own
    corners are its particles' or their neighbours' and so count only where the body folds
    onto itself)."""
    return max(crossing(corners, quads[body == 1]), crossing(corners, quads[body == 2]))


def equator_gap(corners: np.ndarray, quads: np.ndarray, body: np.ndarray) -> float:
    """The ring's innermost corner less the core's outermost, along x, among the corners
    within h/4 of the plane y = centre [m] (the quarter's side, where the ring moves out)."""
    def side(k: int, pick) -> float:
        ids = np.unique(quads[body == k])
        c = corners[ids]
        return float(pick(c[np.abs(c[:, 1] - CY) < 0.25 * H, 0]))
    return side(1, np.min) - side(2, np.max)


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_filled_ring")
    _, s = run_scene(T, scratch, "filled", SCENE)
    if not s:
        return 0
    err = float(s["energy_error"])
    check(err <= 0.05, f"energy error {err:.4f} <= 0.05 (two bodies)")
    r = readers.read_results(scratch / "filled" / "out" / "summary.nml")
    ring, core = float(r["body1_energy"]), float(r["body2_energy"])
    check(min(ring, core) > 0.1 * (ring + core), f"plastic work shared: ring {ring:.1f} J, "
                                                 f"core {core:.1f} J")
    check(float(r["stroke"]) > 0.99 * 24.0e-3, f"approach {float(r['stroke']):.4g} m reached")

    with h5py.File(scratch / "filled" / "out" / "particles.h5", "r") as f:
        keys = sorted(k for k in f if k.startswith("snap_"))
        c0, q0, b0 = snapshot(f, keys[0])
        deepest = max(between(*snapshot(f, k)) for k in keys)
        gap0 = equator_gap(c0, q0, b0)
        gap_end = equator_gap(*snapshot(f, keys[-1]))
    check(deepest <= 0.1 * H, f"ring and core cross by at most h/10 = {0.1 * H:.1e} m "
                              f"(deepest {deepest:.2e} m over {len(keys)} snapshots)")
    check(abs(gap0) <= 0.1 * H, f"touching at t = 0: equator gap {gap0:.2e} m")
    check(gap_end > 2.0 * H, f"no weld: the ring's side has left the core by {gap_end:.2e} m "
                             f"> 2 h at the end")

    # the measures can fail: the core's boundary corners moved out by 0.2 h (into the ring);
    # the ring moved out by 3 h (a gap)
    core_ids = np.unique(q0[b0 == 2])
    radial = c0 - [0.0, CY]
    radius = np.linalg.norm(radial, axis=1)
    edge = core_ids[radius[core_ids] > R_IN - 0.5 * H]
    moved = c0.copy()
    moved[edge] += 0.2 * H * radial[edge] / radius[edge, None]
    found = between(moved, q0, b0)
    check(0.15 * H < found <= 0.25 * H, f"the crossing measure finds the core pushed "
                                              f"0.2 h into the ring ({found / H:.3f} h)")
    ring_ids = np.unique(q0[b0 == 1])
    moved = c0.copy()
    moved[ring_ids] += 3.0 * H * radial[ring_ids] / radius[ring_ids, None]
    found = equator_gap(moved, q0, b0)
    check(abs(found - 3.0 * H) < 0.1 * H, f"the gap measure finds the ring moved out by 3 h "
                                          f"({found / H:.3f} h)")
    return 0


if __name__ == "__main__":
    rc = main()
    sys.exit(max(T.summary(), rc))
