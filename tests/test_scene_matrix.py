#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The scene matrix: every documented option on every scene it is allowed on, each run short.

Three small scenes (a ring of R_m 9 mm, t 2 mm, h = t/2, 4 particles through the wall, aluminium
J2) take every value of every option below at least once, and every pair of values of two
options at least once where the pair is allowed (a pairwise covering array, built greedily and
deterministically here; `--list` prints it):

* scene: a crush between platens, an impact on a rigid target, and a collision of two rings, the
  lower one resting on a fixed wall;
* sector: full, half, quarter (the mirror planes, the 'slip' law);
* wall law: 'frictionless', 'coulomb' (friction 0.3), 'stick'; and 'bonded' (friction 0.3 for
  what is not tied; not on a drop weight, which the input refuses) on two rows of each scene
  that allow it, the first with basis 'cpdi2' and the first with another, run again with it
  (outside the pairwise array: with
  'bonded' as a fourth value the greedy array re-forms, and its row of 'stick' + drop weight +
  half + linear + usf + fbarwall + mass_scale 4 ends at 2.65 % energy error, bit for bit as
  before 'bonded' existed: a limit of that combination the array of three laws never ran);
* penalty: the first row of each scene, the first with a drop weight and the first with a
  'bonded' wall, again with every
  wall's `penalty = 4` (outside the pairwise array, as 'bonded'; so too the first section row,
  and a filler row with 'bonded' walls and a 'bonded' filler);
* law between the bodies (two rings only): 'frictionless', 'coulomb' (0.3), 'stick'; and
  'bonded' (basis 'cpdi2' only; friction 0.3 for what is not tied: the rings start h/2 apart,
  so nothing is tied and they meet by Coulomb's law) on the first row of the two rings with
  basis 'cpdi2', run again with it (outside the pairwise array, as the walls' 'bonded');
* loading of the crush: a platen at constant speed, a platen with a stroke, a drop weight;
* basis (linear, ugimp, cpdi1, cpdi2), scheme (usl, usf, musl), volumetric (standard, fbar,
  fbarwall), plane (strain, stress), damping (0 or 2000 1/s), mass_scale (1 or 4),
  self_contact (on or off), always at the automatic time step (cfl = 0).

The sections (docs/input.md, &body shape) take the options of the walls and the solver in a
second pairwise array (SECTION_FACTORS, `section_array`), walls 2 mm thick at 4 particles
through (2 per cell, the advised least): a half square tube with rounded corners and
self-contact, a 2 x 2 hexagonal honeycomb with self-contact, a 2 x 1 multi-cell tube read from
a walls file with self-contact, and a solid disc, each crushed between platens,
with every basis, scheme 'usf' and 'musl', every wall law, both planes and both volumetric
treatments a single velocity field allows (F-bar on the tube without self-contact; the
input refuses it for a disc).

A foam-filled half square tube (`shape = 'filler'`, FILLER_ROWS) takes every law between
tube and filler, each with another basis, scheme, wall law and plane: 'frictionless', 'coulomb'
(0.3), 'stick', 'bonded' (cpdi2: the filler touches the tube, so its surface is tied), and a
filler with `fill_gap` (0.5 mm, half a cell) that the crush closes, with 'coulomb'. With basis
'ugimp' a filler touching its tube went unstable at the automatic cfl (0.86; at 0.6 too, the
squares of the two bodies' particles overlap at t = 0): `--check` must warn of it, and the row
runs at the cfl the warning gives, 0.4.

Each run must complete (exit 0) with its energy balance (summary.nml `energy_error`: the largest
imbalance of kinetic + strain + plastic + damped + contact_loss against the external work over
the run) within the stated tolerance: ENERGY_TOL for a scene with walls only and for two bodies
meeting or a ring meeting itself, whose inelastic impulse between the fields is booked in
`contact_loss` (docs/output.md; the weld of a self-contact ring's halves is the one field they
would be, measured at most 1.2 % in the matrix); ENERGY_TOL_WARNED for the self-contact seams on
a sticking wall that `--check` warns of. Scheme 'usl' loses energy at every
cfl where material meets a wall or another body (docs/stability.md#schemes): its rows are held
to ENERGY_TOL_USL, and `--check` must warn of it. Basis 'linear' with 'usl' failed at every cfl
the stability study tried: it is not in the array; one run of it must stop cleanly instead
(exit 4, the last good state saved, the project's own error line), after a `--check` warning.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_scene_matrix SCRATCH [--list]
"""
from __future__ import annotations

import itertools
import os
import subprocess
import sys
from pathlib import Path

from plots.mpmplot import readers
from tests.pycheck import Checks
from tests.pyscene import run_scene

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

T = Checks("test_scene_matrix")
check = T.check

ENERGY_TOL = 0.02          # 2 % of max(E0, external work)
ENERGY_TOL_WARNED = 0.05   # seams on a sticking wall with a basis of squares (warned of)
ENERGY_TOL_USL = 0.20      # 'usl': 4-17 % lost in the matrix's contacts, warned of by --check

FACTORS = {
    "scene": ["crush", "impact", "two_rings"],
    "sector": ["full", "half", "quarter"],
    "wall_law": ["frictionless", "coulomb", "stick"],
    "body_law": ["none", "frictionless", "coulomb", "stick"],
    "loading": ["none", "speed", "stroke", "mass"],
    "basis": ["linear", "ugimp", "cpdi1", "cpdi2"],
    "scheme": ["usl", "usf", "musl"],
    "volumetric": ["standard", "fbar", "fbarwall"],
    "plane": ["strain", "stress"],
    "damping": [0.0, 2000.0],
    "mass_scale": [1.0, 4.0],
    "self_contact": [False, True],
}


def allowed(c: dict) -> bool:
    """Whether a (partial) combination is one the input allows (docs/input.md)."""
    g = c.get
    scene = g("scene")
    if scene == "two_rings":
        if g("sector") not in (None, "full") or g("loading") not in (None, "none"):
            return False
        if g("body_law") == "none" or g("volumetric") not in (None, "standard"):
            return False          # F-bar: one body only
    elif scene is not None:
        if g("body_law") not in (None, "none"):
            return False
    if scene == "crush" and g("loading") == "none":
        return False
    if scene == "impact" and g("loading") not in (None, "none"):
        return False
    if scene == "impact" and g("sector") == "quarter":
        return False              # the impact is symmetric about x only
    if g("body_law") == "bonded" and g("basis") not in (None, "cpdi2"):
        return False              # 'bonded' bodies tie CPDI2's corners (docs/input.md)
    if g("loading") == "mass" and g("wall_law") == "bonded":
        return False              # a wall with mass is not 'bonded' (docs/input.md)
    if g("loading") == "mass" and g("sector") not in (None, "full", "half"):
        return False              # keep the drop weight on a model with one platen moving
    if g("basis") == "linear" and g("scheme") == "usl":
        return False              # unstable at every cfl: run once below, for a clean stop
    if g("volumetric") in ("fbar", "fbarwall") and (g("plane") == "stress"
                                                     or g("self_contact") is True):
        return False
    if g("self_contact") is True and g("sector") == "quarter":
        return False              # self-contact splits the ring into upper and lower halves
    return True


def covering_array() -> list[dict]:
    """A pairwise covering array of FACTORS under `allowed`: every allowed pair of values of
    two factors in some row. Greedy: each row starts from the first uncovered pair and takes,
    factor by factor, the allowed value that covers most uncovered pairs (ties: the first)."""
    names = list(FACTORS)
    pairs = set()
    for (i, a), (j, b) in itertools.combinations(enumerate(names), 2):
        for va in FACTORS[a]:
            for vb in FACTORS[b]:
                if allowed({a: va, b: vb}) and completable({a: va, b: vb}):
                    pairs.add((i, repr(va), j, repr(vb)))
    rows = []
    while pairs:
        i, va, j, vb = min(pairs)
        row = {names[i]: eval(va), names[j]: eval(vb)}  # noqa: S307 (our own repr)
        for k, name in enumerate(names):
            if name in row:
                continue
            best, score = None, -1
            for v in FACTORS[name]:
                trial = dict(row, **{name: v})
                if not allowed(trial) or not completable(trial):
                    continue
                s = sum(1 for n2, v2 in trial.items() if n2 != name and
                        _key(names, name, v, n2, v2) in pairs)
                if s > score:
                    best, score = v, s
            row[name] = best
        for (a, va), (b, vb) in itertools.combinations(row.items(), 2):
            pairs.discard(_key(names, a, va, b, vb))
        rows.append({n: row[n] for n in names})
    return rows


def _key(names, a, va, b, vb):
    i, j = names.index(a), names.index(b)
    return (i, repr(va), j, repr(vb)) if i < j else (j, repr(vb), i, repr(va))


def bonded_rows(rows: list[dict]) -> list[dict]:
    """Two rows of each scene that allow 'bonded' walls, with them: the first with basis
    'cpdi2' (the surface curve) and the first with another basis."""
    out = []
    for scene in FACTORS["scene"]:
        ok = [dict(r, wall_law="bonded") for r in rows if r["scene"] == scene]
        ok = [r for r in ok if allowed(r)]
        out += [r for r in ok if r["basis"] == "cpdi2"][:1]
        out += [r for r in ok if r["basis"] != "cpdi2"][:1]
    return out


def penalty_rows(rows: list[dict]) -> list[dict]:
    """The first row of each scene with every wall's penalty 4 times the default (&wall
    penalty; at the automatic cfl, which it divides by 4), outside the pairwise array as
    'bonded'; and so the first row with a drop weight and the first with a 'bonded' wall."""
    out = [dict(r, penalty=4.0) for s in FACTORS["scene"]
           for r in [r for r in rows if r["scene"] == s][:1]]
    out += [dict(r, penalty=4.0) for r in [r for r in rows if r["loading"] == "mass"][:1]]
    return out + [dict(r, penalty=4.0) for r in bonded_rows(rows)[:1]]


def bonded_body_rows(rows: list[dict]) -> list[dict]:
    """The first row of the two rings with basis 'cpdi2', with 'bonded' between the bodies."""
    ok = [dict(r, body_law="bonded") for r in rows
          if r["scene"] == "two_rings" and r["basis"] == "cpdi2"]
    return ok[:1]


def completable(partial: dict) -> bool:
    """Whether some full row extends this allowed partial one."""
    rest = [n for n in FACTORS if n not in partial]

    def extend(c, k):
        if not allowed(c):
            return False
        if k == len(rest):
            return True
        return any(extend(dict(c, **{rest[k]: v}), k + 1) for v in FACTORS[rest[k]])
    return extend(dict(partial), 0)


def check_warnings(nml: Path) -> str:
    """tubempm --check's standard error for a case."""
    res = subprocess.run([os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm")), "--check",
                          str(nml)], capture_output=True, text=True)
    return res.stderr

MATERIAL = ("&material name = 'al', model = 'j2', E = 70.0e9, nu = 0.33, rho = 2700.0, "
            "sigma_y = 150.0e6, hardening = 200.0e6 /\n")
RI, RO, H = 8.0e-3, 10.0e-3, 1.0e-3


def case_text(c: dict, name: str) -> str:
    """The namelist of one row."""
    wall = f"contact = '{c['wall_law']}'" + (", friction = 0.3" if c["wall_law"] in
                                              ("coulomb", "bonded") else "")
    if c.get("penalty", 1.0) != 1.0:
        wall += f", penalty = {c['penalty']}"
    solver = (f"&solver basis = '{c['basis']}', scheme = '{c['scheme']}', plane = "
              f"'{c['plane']}', damping = {c['damping']}, mass_scale = {c['mass_scale']}")
    if c["volumetric"] != "standard":
        solver += f", volumetric = '{c['volumetric']}'"
    solver += " /\n"
    sc = ", self_contact = .true." if c["self_contact"] else ""
    ring = f"r_inner = {RI}, r_outer = {RO}, n_thick = 4, material = 'al'"
    if c["scene"] == "crush":
        t_end = "t_end = 1.0e-4, " if c["loading"] != "stroke" else ""
        top = f"&wall point = 0.0, {2 * RO}, normal = 0.0, -1.0, {wall}, "
        if c["loading"] == "speed":
            top += "velocity = 0.0, -10.0, ramp = 2.0e-5 /\n"
        elif c["loading"] == "stroke":
            top += "velocity = 0.0, -10.0, ramp = 2.0e-5, stroke = 0.8e-3 /\n"
        else:   # a drop weight of 0.5 kg (for depth 1 m) at 10 m/s
            mass = 0.5 if c["sector"] == "full" else 0.25
            top += f"velocity = 0.0, -10.0, mass = {mass} /\n"
        body = (f"&body shape = 'ring', center = 0.0, {RO}, {ring}, sector = '{c['sector']}'"
                f"{sc} /\n")
        walls = top + f"&wall point = 0.0, 0.0, normal = 0.0, 1.0, {wall} /\n"
        if c["sector"] == "quarter":   # the quarter's lower mirror is the ring's mid-plane
            walls = top
        return (f"&run title = '{name}', {t_end}cfl = 0.0, history_every = 2.0e-6, "
                f"output_dir = 'OUT', snapshot_every = 1.0 /\n{solver}&grid h = {H} /\n"
                f"{MATERIAL}{body}{walls}")
    if c["scene"] == "impact":
        v = "8.0, -30.0" if c["sector"] == "full" else "0.0, -30.0"   # oblique on a full ring
        body = (f"&body shape = 'ring', center = 0.0, {RO + 0.5 * H}, {ring}, "
                f"sector = '{c['sector']}', velocity = {v}{sc} /\n")
        return (f"&run title = '{name}', t_end = 6.0e-5, cfl = 0.0, history_every = 2.0e-6, "
                f"output_dir = 'OUT', snapshot_every = 1.0 /\n{solver}&grid h = {H} /\n"
                f"{MATERIAL}{body}&wall point = 0.0, 0.0, normal = 0.0, 1.0, {wall} /\n")
    law = f"law = '{c['body_law']}'" + (", friction = 0.3" if c["body_law"] in
                                         ("coulomb", "bonded") else "")
    lower = f"&body shape = 'ring', center = 0.0, {RO}, {ring}{sc} /\n"
    upper = (f"&body shape = 'ring', center = 4.0e-3, {3 * RO + 0.5 * H}, {ring}, "
             f"velocity = 0.0, -30.0{sc} /\n")
    return (f"&run title = '{name}', t_end = 6.0e-5, cfl = 0.0, history_every = 2.0e-6, "
            f"output_dir = 'OUT', snapshot_every = 1.0 /\n{solver}&grid h = {H} /\n"
            f"{MATERIAL}{lower}{upper}&wall point = 0.0, 0.0, normal = 0.0, 1.0, {wall} /\n"
            f"&contact bodies = 1, 2, {law} /\n")


SECTION_FACTORS = {
    "shape": ["tube", "honeycomb", "walls", "walls_half", "disc"],
    "basis": ["linear", "ugimp", "cpdi1", "cpdi2"],
    "scheme": ["usf", "musl"],
    "wall_law": ["frictionless", "coulomb", "stick", "bonded"],
    "plane": ["strain", "stress"],
    "volumetric": ["standard", "fbar"],
}


def section_allowed(c: dict) -> bool:
    """F-bar needs one velocity field (no self-contact) and plane strain, and is refused for a
    disc: the tube without self-contact takes it."""
    if c.get("volumetric") == "fbar":
        return c.get("shape") in (None, "tube") and c.get("plane") in (None, "strain")
    return True


def section_array() -> list[dict]:
    """A pairwise covering array of SECTION_FACTORS (greedy, as covering_array)."""
    names = list(SECTION_FACTORS)
    pairs = {(i, repr(va), j, repr(vb))
             for (i, a), (j, b) in itertools.combinations(enumerate(names), 2)
             for va in SECTION_FACTORS[a] for vb in SECTION_FACTORS[b]
             if section_allowed({a: va, b: vb})}
    rows = []
    while pairs:
        i, va, j, vb = min(pairs)
        row = {names[i]: eval(va), names[j]: eval(vb)}  # noqa: S307 (our own repr)
        for name in names:
            if name in row:
                continue
            best, score = None, -1
            for v in SECTION_FACTORS[name]:
                trial = dict(row, **{name: v})
                if not section_allowed(trial):
                    continue
                sc = sum(1 for n2, v2 in trial.items() if n2 != name and
                         _key(names, name, v, n2, v2) in pairs)
                if sc > score:
                    best, score = v, sc
            row[name] = best
        for (a, xa), (b, xb) in itertools.combinations(row.items(), 2):
            pairs.discard(_key(names, a, xa, b, xb))
        rows.append({n: row[n] for n in names})
    return rows


SECTION_BODY = {
    # a half square tube: centreline 20 mm, t 2 mm, corners r 2 mm; bottom at y = 0
    "tube": ("&body shape = 'tube', material = 'al', vertices = -10.0e-3, 1.0e-3, 10.0e-3, "
             "1.0e-3, 10.0e-3, 21.0e-3, -10.0e-3, 21.0e-3, center = 0.0, 11.0e-3, thickness = "
             "2.0e-3, corner_radius = 2.0e-3, n_thick = 4, sector = 'half', "
             "self_contact = .true. /\n", 22.0e-3),
    # 2 x 2 regular cells of 8 mm walls, t 2 mm: apexes at +-(14 + 1.155) mm
    "honeycomb": ("&body shape = 'honeycomb', material = 'al', n_cells = 2, 2, cell_l = 8.0e-3, "
                  "cell_h = 8.0e-3, thickness = 2.0e-3, n_thick = 4, center = 0.0, 15.155e-3, "
                  "self_contact = .true. /\n", 30.31e-3),
    # two square cells of 10 mm side from a walls file, t 2 mm, sharp corners
    "walls": ("&body shape = 'walls', material = 'al', walls_file = 'cells.csv', n_thick = 4, "
              "self_contact = .true. /\n", 12.0e-3),
    # three square cells in a row from a walls file, its half x >= 0 (the plane cuts the middle
    # cell's walls square)
    "walls_half": ("&body shape = 'walls', material = 'al', walls_file = 'cells3.csv', "
                   "n_thick = 4, sector = 'half', center = 0.0, 6.0e-3, self_contact = .true. /\n",
                   12.0e-3),
    "disc": ("&body shape = 'disc', material = 'al', center = 0.0, 6.0e-3, r_outer = 6.0e-3, "
             "n_thick = 4 /\n", 12.0e-3),
}
CELLS_CSV = ("x1,y1,x2,y2,thickness\n" + "".join(
    f"{a:.5e},{b:.5e},{c:.5e},{d:.5e},2.0e-3\n" for a, b, c, d in [
        (-10e-3, 1e-3, 0.0, 1e-3), (0.0, 1e-3, 10e-3, 1e-3),
        (-10e-3, 11e-3, 0.0, 11e-3), (0.0, 11e-3, 10e-3, 11e-3),
        (-10e-3, 1e-3, -10e-3, 11e-3), (0.0, 1e-3, 0.0, 11e-3),
        (10e-3, 1e-3, 10e-3, 11e-3)]))
CELLS3_CSV = ("x1,y1,x2,y2,thickness\n" + "".join(
    f"{a:.5e},{b:.5e},{a + 10e-3 if b == d else a:.5e},{d:.5e},2.0e-3\n" for a, b, d in
    [(x, y, y) for x in (-15e-3, -5e-3, 5e-3) for y in (1e-3, 11e-3)]
    + [(x, 1e-3, 11e-3) for x in (-15e-3, -5e-3, 5e-3, 15e-3)]))


def section_text(c: dict, name: str) -> str:
    """The namelist of one section row: crushed between platens at 10 m/s for 0.1 ms. The
    platens start h/10 clear of the body: the squares of 'ugimp' and 'linear' particles
    reach past a section's faces (a particle of aspect a has the side sqrt(a) times its
    thickness), and a platen touching the faces would start inside them."""
    body, top = SECTION_BODY[c["shape"]]
    top += 0.1 * H
    if c["volumetric"] == "fbar":         # one velocity field
        body = body.replace(", self_contact = .true.", "")
    wall = f"contact = '{c['wall_law']}'" + (", friction = 0.3" if c["wall_law"] in
                                              ("coulomb", "bonded") else "")
    if c.get("penalty", 1.0) != 1.0:
        wall += f", penalty = {c['penalty']}"
    solver = (f"&solver basis = '{c['basis']}', scheme = '{c['scheme']}', plane = "
              f"'{c['plane']}', volumetric = '{c['volumetric']}', mass_scale = 4.0 /\n")
    return (f"&run title = '{name}', t_end = 1.0e-4, cfl = 0.0, history_every = 2.0e-6, "
            f"output_dir = 'OUT', snapshot_every = 1.0 /\n{solver}&grid h = {H} /\n"
            f"{MATERIAL}{body}"
            f"&wall point = 0.0, {top}, normal = 0.0, -1.0, {wall}, velocity = 0.0, -10.0, "
            f"ramp = 2.0e-5 /\n&wall point = 0.0, {-0.1 * H}, normal = 0.0, 1.0, {wall} /\n")


FOAM = ("&material name = 'foam', model = 'foam', E = 1.0e9, nu = 0.3, rho = 230.0, "
        "sigma_p = 1.6e6, nu_plastic = 0.0, foam_gamma = 2.0e6, foam_alpha2 = 4.0e6, "
        "foam_beta = 4.0, eps_d = 2.46 /\n")
FILLER_ROWS = [
    dict(law="frictionless", basis="linear", scheme="usf", wall_law="coulomb", plane="stress",
         gap=0.0),
    dict(law="coulomb", basis="ugimp", scheme="musl", wall_law="stick", plane="strain", gap=0.0),
    dict(law="stick", basis="cpdi1", scheme="usf", wall_law="bonded", plane="strain", gap=0.0),
    dict(law="bonded", basis="cpdi2", scheme="musl", wall_law="frictionless", plane="stress",
         gap=0.0),
    dict(law="coulomb", basis="cpdi2", scheme="usf", wall_law="coulomb", plane="strain",
         gap=0.5e-3),
    dict(law="bonded", basis="cpdi2", scheme="musl", wall_law="bonded", plane="strain",
         gap=0.0, penalty=4.0),
]


def filler_text(c: dict, name: str) -> str:
    """A filler row: SECTION_BODY's half square tube (without self-contact) filled with foam
    (12 divisions), crushed between platens at 10 m/s for 0.1 ms."""
    tube = SECTION_BODY["tube"][0].replace(", self_contact = .true.", "")
    law = f"law = '{c['law']}'" + (", friction = 0.3" if c["law"] in ("coulomb", "bonded")
                                   else "")
    wall = f"contact = '{c['wall_law']}'" + (", friction = 0.3" if c["wall_law"] in
                                              ("coulomb", "bonded") else "")
    if c.get("penalty", 1.0) != 1.0:
        wall += f", penalty = {c['penalty']}"
    top = SECTION_BODY["tube"][1] + 0.1 * H
    return (f"&run title = '{name}', t_end = 1.0e-4, cfl = 0.0, history_every = 2.0e-6, "
            f"output_dir = 'OUT', snapshot_every = 1.0 /\n&solver basis = '{c['basis']}', "
            f"scheme = '{c['scheme']}', plane = '{c['plane']}', mass_scale = 4.0 /\n"
            f"&grid h = {H} /\n{MATERIAL}{FOAM}{tube}&body shape = 'filler', material = 'foam', "
            f"fills = 1, n_thick = 12, fill_gap = {c['gap']} /\n&contact bodies = 1, 2, {law} /\n"
            f"&wall point = 0.0, {top}, normal = 0.0, -1.0, {wall}, velocity = 0.0, -10.0, "
            f"ramp = 2.0e-5 /\n&wall point = 0.0, {-0.1 * H}, normal = 0.0, 1.0, {wall} /\n")


def run_fillers(scratch: Path) -> int:
    """The filler rows: each completes within ENERGY_TOL (two bodies without self-contact: the
    contact's loss is booked; the ties of 'bonded' are springs)."""
    for law in ("frictionless", "coulomb", "stick", "bonded"):
        check(any(r["law"] == law for r in FILLER_ROWS), f"the filler rows run law = {law!r}")
    for k, c in enumerate(FILLER_ROWS):
        name = f"f{k:02d}_filler"
        text = filler_text(c, name)
        if c["basis"] == "ugimp" and c["gap"] < 0.5 * H:
            folder = scratch / name
            folder.mkdir(parents=True, exist_ok=True)
            (folder / f"{name}.nml").write_text(text.replace("OUT", str(folder / "out")))
            warn = check_warnings(folder / f"{name}.nml")
            check("filler touching its tube with 'ugimp'" in warn and "cfl = 0.4" in warn,
                  f"{name}: --check warns of 'ugimp' with a touching filler ({warn[-300:]!r})")
            text = text.replace("cfl = 0.0", "cfl = 0.4")
        _, s = run_scene(T, scratch, name, text)
        if not s:
            print(f"   (filler row {k}: {c})")
            continue
        err = float(s["energy_error"])
        check(err <= ENERGY_TOL, f"{name}: energy error {err:.4f} <= {ENERGY_TOL} ({c})")
    return len(FILLER_ROWS)


def seams_on_stick(scratch: Path, name: str, c: dict) -> None:
    """Self-contact seams on a 'stick' or 'bonded' wall with a basis of squares: --check warns
    of it, and the run completes within its tolerance or stops cleanly (exit 4, the last good
    state saved, the project's own lines)."""
    folder = scratch / name
    nml = folder / f"{name}.nml"
    nml.write_text(section_text(c, name).replace("OUT", str(folder / "out")))
    warn = check_warnings(nml)
    check("joints on a stick/bonded wall may go unstable" in warn,
          f"{name}: --check warns of seams on a sticking wall ({warn[-300:]!r})")
    res = subprocess.run([os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm")), "--quiet",
                          str(nml)], capture_output=True, text=True,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    clean = all(ln.startswith(("ERROR [", "WARNING [", " ")) for ln in lines)
    if res.returncode == 0:
        err = float(readers.read_summary(folder / "out" / "summary.nml")["energy_error"])
        check(err <= ENERGY_TOL_WARNED and clean, f"{name}: energy error {err:.4f} <= "
              f"{ENERGY_TOL_WARNED} ({c})")
    else:
        check(res.returncode == 4 and clean and any(folder.glob("out/crash_*.h5")),
              f"{name}: stops cleanly with the last good state (exit {res.returncode}: "
              f"{res.stderr[-300:]!r})")


def run_sections(scratch: Path) -> int:
    """The section rows: each completes within ENERGY_TOL (seams on a sticking wall with a basis of
    squares: seams_on_stick)."""
    rows = section_array()
    rows += [dict([r for r in rows if r["shape"] == "tube"][0], penalty=4.0)]   # (penalty_rows)
    for name, values in SECTION_FACTORS.items():
        for v in values:
            check(any(r[name] == v for r in rows), f"the section rows run {name} = {v!r}")
    for k, c in enumerate(rows):
        name = f"s{k:02d}_{c['shape']}"
        (scratch / name).mkdir(parents=True, exist_ok=True)
        (scratch / name / "cells.csv").write_text(CELLS_CSV)
        (scratch / name / "cells3.csv").write_text(CELLS3_CSV)
        if (c["basis"] in ("linear", "ugimp") and c["wall_law"] in ("stick", "bonded")
                and c["shape"] != "disc" and c["volumetric"] == "standard"):
            seams_on_stick(scratch, name, c)   # warned of; completes or stops cleanly
            continue
        _, s = run_scene(T, scratch, name, section_text(c, name))
        if not s:
            print(f"   (section row {k}: {c})")
            continue
        err = float(s["energy_error"])
        tol = ENERGY_TOL
        check(err <= tol, f"{name}: energy error {err:.4f} <= {tol} ({c})")
    half_matches_full(scratch)
    return len(rows)


def half_matches_full(scratch: Path) -> None:
    """A half walls body (its mirror plane added by the sector) against the whole body, same
    options (an independent computation of the same structure): the top platen's force, the
    half's doubled, within 1e-4 of the whole's peak at every row (measured: round-off)."""
    c = dict(shape="walls_half", basis="cpdi2", scheme="musl", wall_law="frictionless",
             plane="strain", volumetric="standard")
    hist = {}
    for model in ("half", "full"):
        name = f"s_{model}_vs"
        (scratch / name).mkdir(parents=True, exist_ok=True)
        (scratch / name / "cells3.csv").write_text(CELLS3_CSV)
        text = section_text(c, name).replace("cfl = 0.0", "cfl = 0.5")
        if model == "full":
            text = text.replace(", sector = 'half', center = 0.0, 6.0e-3", "")
        hist[model], _ = run_scene(T, scratch, name, text)
    if hist["half"] and hist["full"]:
        f_half, f_full = hist["half"]["wall1_force"], hist["full"]["wall1_force"]
        n = min(len(f_half), len(f_full))
        peak = max(abs(f_full).max(), 1e-30)
        dev = abs(f_half[:n] - f_full[:n]).max() / peak
        check(n > 10 and abs(f_full).max() > 0 and dev <= 1.0e-4,
              f"half walls body: platen force (whole structure's) within {dev:.2e} of the whole "
              f"model's peak {peak:.4g} N/m over {n} rows (allowed 1e-4)")


def main() -> int:
    rows = covering_array()
    rows += penalty_rows(rows) + bonded_rows(rows)
    rows += bonded_body_rows(rows)
    if "--list" in sys.argv:
        for k, r in enumerate(rows):
            print(k, r)
        for k, r in enumerate(section_array()):
            print("s", k, r)
        return 0
    scratch = Path([a for a in sys.argv[1:] if not a.startswith("--")][0]
                   if len(sys.argv) > 1 else "/tmp/test_scene_matrix")
    # the matrix itself: every allowed value of every factor appears on every scene
    for name, values in FACTORS.items():
        if name == "scene":
            continue
        for scene in FACTORS["scene"]:
            for v in values:
                if allowed({"scene": scene, name: v}) and completable({"scene": scene, name: v}):
                    check(any(r["scene"] == scene and r[name] == v for r in rows),
                          f"the matrix runs {name} = {v!r} on the {scene}")
    for scene in FACTORS["scene"]:
        check(sum(r["scene"] == scene and r["wall_law"] == "bonded" and "penalty" not in r
                  for r in rows) == 2,
              f"the matrix runs wall_law = 'bonded' on the {scene} twice")
    slid = False
    for k, c in enumerate(rows):
        name = f"m{k:02d}_{c['scene']}"
        _, s = run_scene(T, scratch, name, case_text(c, name))
        if not s:
            print(f"   (row {k}: {c})")
            continue
        err = float(s["energy_error"])
        tol = ENERGY_TOL
        if c["scheme"] == "usl":
            tol = ENERGY_TOL_USL
            warn = check_warnings(scratch / name / f"{name}.nml")
            check("scheme 'usl'" in warn, f"{name}: --check warns of 'usl' ({warn[-300:]!r})")
        check(err <= tol, f"{name}: energy error {err:.4f} <= {tol} ({c})")
        if c["scene"] == "impact" and c["sector"] == "full" and c["wall_law"] == "coulomb":
            slid = True
    check(slid, "the matrix has an oblique impact with a 'coulomb' wall")
    # linear + usl: warned of, and a clean stop with the last good state
    c = dict(rows[0], scene="crush", sector="half", loading="speed", basis="linear",
             scheme="usl", volumetric="standard", damping=0.0, mass_scale=1.0)
    folder = scratch / "linear_usl"
    folder.mkdir(parents=True, exist_ok=True)
    nml = folder / "linear_usl.nml"
    nml.write_text(case_text(c, "linear_usl").replace("OUT", str(folder / "out")))
    warn = check_warnings(nml)
    check("failed at every cfl" in warn,
          f"linear + usl: --check warns that it failed at every cfl ({warn[-300:]!r})")
    res = subprocess.run([os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm")), "--quiet",
                          str(nml)], capture_output=True, text=True,
                         env=dict(os.environ, OMP_NUM_THREADS="1"))
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    check(res.returncode in (0, 4) and all(ln.startswith(("ERROR [", "WARNING [", " "))
                                           for ln in lines),
          f"linear + usl: completes or stops cleanly with the project's lines (exit "
          f"{res.returncode}: {res.stderr[-300:]!r})")
    if res.returncode == 4:
        check(any(folder.glob("out/crash_*.h5")) and (folder / "out" / "history.csv").is_file(),
              "linear + usl: the stop leaves the last good state and history.csv")
    n_sections = run_sections(scratch)
    n_fillers = run_fillers(scratch)
    print(f"test_scene_matrix: {len(rows)} runs, {n_sections} section runs, {n_fillers} filler "
          f"runs")
    return 0


if __name__ == "__main__":
    rc = main()
    sys.exit(max(T.summary(), rc))
