#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""What the plotting scripts draw, not only that they write a PNG.

Output folders are made up here with known contents (history.csv, input.nml, summary.nml and a
particles.h5 of two particles), and plots/plot_case.py and plots/plot_shapes.py are run through
their command line in this process; the figure they save is caught and its artists inspected:

* crush: the force curves are the history's wall forces against the platen approach (the full
  ring's both platens: the sum of their travels), the DeRuntz-Hodge curve is P0 / sqrt(1 -
  (delta/D)^2) with P0 = 4 M0 / R, M0 = sigma0 t^2 / (2 sqrt 3) computed here, axis labels
  name the quantities and units, and no MPM-fit stiffness is printed;
* a crush of two tubes (two &body groups): no DeRuntz-Hodge or elastic-ring curve (a single
  tube's closed forms) against the force on both, and one printed line says they are left out;
* impact: the force and velocity curves are the history's columns, and the printed coefficient
  of restitution is the one built into the history (0.75);
* an impact without a wall to hit (two half rings thrown at each other, as
  namelists/contact/two_rings.nml): the generic plot instead, exit 0, with a one-line note that
  names plots/plot_bodies.py; asked for with --kind impact it is still an error (exit 2);
* shapes: the drawn polygons are the snapshot's corners (in mm) and their colours its eqps, or
  with --colour body one discrete colour per body id; the whole tube of a half or quarter
  model has its walls' mirror images drawn too (the lower platen of a quarter crush);
* a run whose summary.nml says 'unstable', or that has no summary.nml, is marked in red above
  the plots (and the mark is absent for a completed run); without summary.nml the kind of scene
  is asked of the binary named by TUBEMPM (`tubempm --scene input.nml`), so the made-up
  input.nml files are valid cases.

    TUBEMPM=build/debug/tubempm python3 -m tests.test_plots SCRATCH
"""
from __future__ import annotations

import contextlib
import io
import math
import shutil
import sys
from pathlib import Path

import numpy as np

from tests.pycheck import Checks
from plots import plot_case  # (selects the Agg backend through style)
from plots import plot_shapes
from plots.mpmplot import namelist, scene
from matplotlib.figure import Figure
from matplotlib.collections import PolyCollection

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_plots")
check = T.check

# the ring of tests/scenes/sym_full.nml: R = 25 mm, t = 2.5 mm, steel
R_IN, R_OUT, SIGMA_Y = 0.02375, 0.02625, 310.0e6
SAVED: list[Figure] = []
_savefig = Figure.savefig


def _catch(self: Figure, *args, **kwargs):
    SAVED.append(self)
    return _savefig(self, *args, **kwargs)


Figure.savefig = _catch   # every figure a script saves is kept for inspection


def write_history(path: Path, cols: dict[str, np.ndarray]) -> None:
    names = list(cols)
    rows = np.column_stack([cols[n] for n in names])
    with path.open("w") as f:
        f.write(",".join(names) + "\n")
        for r in rows:
            f.write(",".join(f"{v:.17g}" for v in r) + "\n")


def write_summary(folder: Path, status: str = "completed", scene: str = "crush",
                  message: str = "") -> None:
    (folder / "summary.nml").write_text(
        f"&summary\n  status = '{status}'\n  scene = '{scene}'\n  steps = 100\n"
        f"  message = '{message}'\n/\n")


def run_main(module, argv: list[str]) -> tuple[int, str, Figure | None]:
    """Run a script's main, return (exit code, standard output, the figure it saved)."""
    SAVED.clear()
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
        rc = module.main(argv)
    return rc, buf.getvalue(), (SAVED[-1] if SAVED else None)


def line(ax, label_start: str):
    """The first line of ax whose label starts with label_start, or None."""
    for ln in ax.get_lines():
        if str(ln.get_label()).startswith(label_start):
            return ln
    return None


def suptitle(fig: Figure) -> tuple[str, object]:
    st = fig._suptitle
    return ("", None) if st is None else (st.get_text(), st.get_color())


def check_failure_marks(folder: Path, module, argv: list[str], what: str) -> None:
    """A completed run has no mark; an unstable run and one without summary are marked."""
    summary = (folder / "summary.nml").read_text()
    rc, out, fig = run_main(module, argv)
    text, _ = suptitle(fig) if fig else ("", None)
    check(rc == 0 and "RUN" not in text, f"{what}: a completed run is not marked ({text!r})")
    (folder / "summary.nml").write_text(summary.replace("'completed'", "'unstable'").replace(
        "message = ''", "message = 'energy growth at step 57; lower cfl'"))
    rc, out, fig = run_main(module, argv)
    text, color = suptitle(fig) if fig else ("", None)
    check(rc == 0 and "RUN FAILED" in text and "unstable" in text and "energy growth" in text,
          f"{what}: an unstable run is marked on the figure (got {text!r})")
    check(color == "red", f"{what}: the mark is red (got {color!r})")
    check("RUN FAILED" in out, f"{what}: the failure is printed too")
    (folder / "summary.nml").unlink()
    rc, out, fig = run_main(module, argv)
    text, _ = suptitle(fig) if fig else ("", None)
    check(rc == 0 and "RUN NOT FINISHED" in text, f"{what}: a run without summary.nml is "
          f"marked as not finished (got {text!r})")
    (folder / "summary.nml").write_text(summary)


def test_crush(scratch: Path) -> None:
    folder = scratch / "crush"
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "input.nml").write_text(f"""&run title = 'synthetic crush', depth = 1.0, t_end = 1.0e-3 /
&grid h = 0.5e-3 /
&solver plane = 'strain' /
&material name = 'steel', model = 'j2', E = 210.0e9, nu = 0.3, rho = 7800.0,
  sigma_y = {SIGMA_Y!r} /
&body shape = 'ring', center = 0.0, 0.02625, r_inner = {R_IN!r}, r_outer = {R_OUT!r},
  sector = 'full' /
&wall point = 0.0, 0.0525, normal = 0.0, -1.0, velocity = 0.0, -5.0 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0, velocity = 0.0, 5.0 /
""")
    t = np.linspace(0.0, 2.0e-3, 401)
    f1 = 6.0e4 * (1.0 - np.exp(-t / 1.0e-4)) + 500.0 * np.sin(t * 3.0e4)
    f2 = 0.97 * f1
    zero = np.zeros_like(t)
    write_history(folder / "history.csv", {
        "time": t, "wall1_force": f1, "wall1_fx": zero, "wall1_fy": f1, "wall1_disp": -5.0 * t,
        "wall2_force": f2, "wall2_fx": zero, "wall2_fy": -f2, "wall2_disp": -5.0 * t,
        "com_vx": zero, "com_vy": zero, "kinetic": 1.0 + t, "strain": 2.0 * t,
        "plastic": 1.0e3 * t, "external": 1.0e3 * t})
    write_summary(folder, scene="crush")
    argv = ["--dir", str(folder), "--out", str(scratch / "crush.png")]
    rc, out, fig = run_main(plot_case, argv)
    if not check(rc == 0 and fig is not None, f"crush plot exits 0 and saves (rc {rc}: {out})"):
        return
    ax, ax2 = fig.axes[0], fig.axes[1]
    delta = 10.0 * t                            # both platens advance 5 t
    mpm = line(ax, "MPM, wall 1")
    check(mpm is not None and np.allclose(mpm.get_xdata(), delta * 1e3, rtol=1e-12, atol=0)
          and np.allclose(mpm.get_ydata(), f1 * 1e-3, rtol=1e-12, atol=0),
          "crush: the moving platen's curve is history's wall1_force [kN] against the approach "
          "of both platens [mm]")
    fixed = line(ax, "MPM, wall 2")
    check(fixed is not None and np.allclose(fixed.get_ydata(), f2 * 1e-3, rtol=1e-12, atol=0),
          "crush: the other platen's curve is wall2_force [kN]")
    R, th = 0.5 * (R_IN + R_OUT), R_OUT - R_IN
    p0 = 4.0 * (SIGMA_Y * th * th / (2.0 * math.sqrt(3.0))) / R
    dh = line(ax, "DeRuntz")
    if check(dh is not None, "crush: a DeRuntz-Hodge curve is drawn"):
        d = np.asarray(dh.get_xdata()) * 1e-3
        want = p0 / np.sqrt(1.0 - (d / (2.0 * R)) ** 2) * 1e-3
        check(np.allclose(dh.get_ydata(), want, rtol=1e-9, atol=0),
              f"crush: DeRuntz-Hodge curve = P0 / sqrt(1 - (delta/D)^2), P0 = {p0:.6g} N")
    check("platen approach" in ax.get_xlabel() and "[mm]" in ax.get_xlabel(),
          f"crush: x label names the approach in mm ({ax.get_xlabel()!r})")
    check("force [kN]" in ax.get_ylabel(), f"crush: y label is force in kN ({ax.get_ylabel()!r})")
    check("energy [J]" in ax2.get_ylabel(), f"crush: energies in J ({ax2.get_ylabel()!r})")
    pl = line(ax2, "plastic")
    check(pl is not None and np.allclose(pl.get_ydata(), 1.0e3 * t, rtol=1e-12, atol=0),
          "crush: the plastic energy curve is history's plastic column")
    check("elastic stiffness" not in out, "crush: no MPM-fit stiffness compared with the thin "
          "ring (a dynamic crush does not measure it)")
    check_failure_marks(folder, plot_case, argv, "crush plot")


def test_fixed_platen(scratch: Path) -> None:
    """scene.crush_displacement's platen="fixed": a half model with the bottom platen fixed
    (the study's crush_fixed scene) reads the fixed platen's force, and the approach is the
    moving platen's travel alone (the half model's mirror plane is vertical: no image)."""
    inputs = namelist.parse_namelist(f"""&run t_end = 1.0e-3 /
&body shape = 'ring', center = 0.0, 0.02625, r_inner = {R_IN!r}, r_outer = {R_OUT!r},
  sector = 'half' /
&wall point = 0.0, 0.0525, normal = 0.0, -1.0, velocity = 0.0, -10.0 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
""")
    t = np.linspace(0.0, 1.0e-3, 11)
    f1, f2 = 5.0e4 + 3.0e3 * np.sin(t * 4.0e4), np.full_like(t, 5.0e4)
    h = {"time": t, "wall1_force": f1, "wall1_disp": -10.0 * t, "wall2_force": f2,
         "wall2_disp": 0.0 * t, "wall3_force": 0.0 * t, "wall3_disp": 0.0 * t}
    d, f, k = scene.crush_displacement(h, inputs)
    check(k == 1 and np.array_equal(f, f1) and np.allclose(d, 10.0 * t, rtol=1e-12, atol=0),
          f"fixed platen: by default the moving platen's force (wall {k}) against its travel")
    d, f, k = scene.crush_displacement(h, inputs, platen="fixed")
    check(k == 2 and np.array_equal(f, f2) and np.allclose(d, 10.0 * t, rtol=1e-12, atol=0),
          f"fixed platen: platen='fixed' gives wall 2's force (wall {k}) against the same "
          "approach")
    both = namelist.parse_namelist(f"""&run t_end = 1.0e-3 /
&body shape = 'ring', center = 0.0, 0.02625, r_inner = {R_IN!r}, r_outer = {R_OUT!r},
  sector = 'quarter' /
&wall point = 0.0, 0.0525, normal = 0.0, -1.0, velocity = 0.0, -5.0 /
""")
    try:
        scene.crush_displacement({**h, "wall2_force": 0.0 * t}, both, platen="fixed")
        check(False, "fixed platen: a quarter model (no fixed platen) is refused")
    except ValueError as exc:
        check("no fixed platen" in str(exc), f"fixed platen: a quarter model is refused ({exc})")


def test_crush_bodies(scratch: Path) -> None:
    """A crush of two tubes (two &body groups, as namelists/contact/nested.nml): the closed
    forms are one tube's, so no DeRuntz-Hodge or elastic-ring curve is drawn against the force
    on both, and one printed line (and the legend) says why."""
    folder = scratch / "crush_bodies"
    folder.mkdir(parents=True, exist_ok=True)
    rings = "".join(f"""&body shape = 'ring', center = 0.0, 0.02625, r_inner = {ri!r},
  r_outer = {ro!r}, sector = 'full' /
""" for ri, ro in ((R_IN, R_OUT), (R_IN - 0.004, R_OUT - 0.004)))
    (folder / "input.nml").write_text(f"""&run title = 'two tubes', depth = 1.0, t_end = 1.0e-3 /
&grid h = 0.5e-3 /
&solver plane = 'strain' /
&material name = 'steel', model = 'j2', E = 210.0e9, nu = 0.3, rho = 7800.0,
  sigma_y = {SIGMA_Y!r} /
""" + rings + """&wall point = 0.0, 0.0525, normal = 0.0, -1.0, velocity = 0.0, -5.0 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
""")
    t = np.linspace(0.0, 2.0e-3, 401)
    f1 = 9.0e4 * (1.0 - np.exp(-t / 1.0e-4))
    zero = np.zeros_like(t)
    cols = {"time": t, "wall1_force": f1, "wall1_fx": zero, "wall1_fy": f1,
            "wall1_disp": -5.0 * t, "wall2_force": f1, "wall2_fx": zero, "wall2_fy": -f1,
            "wall2_disp": zero, "com_vx": zero, "com_vy": zero, "kinetic": 1.0 + t,
            "strain": 2.0 * t, "plastic": 1.0e3 * t, "external": 1.0e3 * t}
    for b in (1, 2):
        cols.update({f"body{b}_x": zero, f"body{b}_y": zero, f"body{b}_plastic": 500.0 * t})
    cols.update({"contact1_2_force": 0.5 * f1, "contact1_2_fx": zero, "contact1_2_fy": zero})
    write_history(folder / "history.csv", cols)
    write_summary(folder, scene="crush")
    argv = ["--dir", str(folder), "--out", str(scratch / "crush_bodies.png")]
    rc, out, fig = run_main(plot_case, argv)
    if not check(rc == 0 and fig is not None, f"two-tube crush plot exits 0 and saves (rc {rc}: "
                 f"{out.strip()[:300]})"):
        return
    ax, ax2 = fig.axes[0], fig.axes[1]
    mpm = line(ax, "MPM, wall 1")
    check(mpm is not None and np.allclose(mpm.get_ydata(), f1 * 1e-3, rtol=1e-12, atol=0),
          "two-tube crush: the platen's force is drawn")
    drawn = [str(ln.get_label()) for a in (ax, ax2) for ln in a.get_lines()]
    check(not any("DeRuntz" in d or "elastic ring" in d for d in drawn),
          f"two-tube crush: no single-tube closed form (DeRuntz-Hodge, elastic ring) is drawn "
          f"against the force on both tubes (curves {drawn})")
    check("DeRuntz-Hodge     " not in out and "plateau force" not in out,
          f"two-tube crush: no single-tube DeRuntz-Hodge or plateau number is printed ({out!r})")
    said = [ln for ln in out.splitlines() if "single tube" in ln and "left out" in ln]
    check(len(said) == 1 and "2 bodies" in said[0],
          f"two-tube crush: one printed line says the closed forms are a single tube's and are "
          f"left out (got {said})")
    leg = ax.get_legend()
    title = leg.get_title().get_text() if leg is not None else ""
    check("single tube" in title, f"two-tube crush: the legend says why there is no closed form "
          f"({title!r})")


def test_impact(scratch: Path) -> None:
    folder = scratch / "impact"
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "input.nml").write_text(f"""&run title = 'synthetic impact', depth = 1.0, t_end = 1.0e-3 /
&grid h = 0.5e-3 /
&material name = 'al', model = 'elastic', E = 70.0e9, nu = 0.3, rho = 2700.0 /
&body shape = 'ring', center = 0.0, 0.0265, r_inner = {R_IN!r}, r_outer = {R_OUT!r},
  velocity = 0.0, -30.0 /
&wall point = 0.0, 0.0, normal = 0.0, 1.0 /
""")
    t = np.linspace(0.0, 1.0e-3, 1001)
    t0, t1 = 0.2e-3, 0.5e-3                     # contact: a half-sine pulse
    on = (t > t0) & (t < t1)
    f = np.where(on, 4.0e4 * np.sin(np.pi * (t - t0) / (t1 - t0)), 0.0)
    v0, vr = -30.0, 22.5                        # COR 0.75
    frac = np.clip((t - t0) / (t1 - t0), 0.0, 1.0)
    vy = v0 + (vr - v0) * (1.0 - np.cos(np.pi * frac)) / 2.0
    zero = np.zeros_like(t)
    write_history(folder / "history.csv", {
        "time": t, "wall1_force": f, "wall1_fx": zero, "wall1_fy": -f, "wall1_disp": zero,
        "com_vx": zero, "com_vy": vy, "kinetic": zero, "strain": zero, "plastic": zero,
        "external": zero})
    write_summary(folder, scene="impact")
    argv = ["--dir", str(folder), "--out", str(scratch / "impact.png")]
    rc, out, fig = run_main(plot_case, argv)
    if not check(rc == 0 and fig is not None, f"impact plot exits 0 and saves (rc {rc}: {out})"):
        return
    ax, ax2 = fig.axes[0], fig.axes[1]
    ln = line(ax, "MPM, wall 1")
    check(ln is not None and np.allclose(ln.get_xdata(), t * 1e3, rtol=1e-12, atol=0)
          and np.allclose(ln.get_ydata(), f * 1e-3, rtol=1e-12, atol=0),
          "impact: the target force curve is history's wall1_force [kN] against time [ms]")
    vy_line = line(ax2, "$v_y$")
    check(vy_line is not None and np.allclose(vy_line.get_ydata(), vy, rtol=1e-12, atol=0),
          "impact: the v_y curve is history's com_vy")
    check(ax.get_xlabel() == "time [ms]" and "force on the target [kN]" in ax.get_ylabel(),
          f"impact: axis labels ({ax.get_xlabel()!r}, {ax.get_ylabel()!r})")
    cor = [ln for ln in out.splitlines() if ln.strip().startswith("COR")]
    value = float(cor[0].split()[-1]) if cor else float("nan")
    check(abs(value - 0.75) < 1e-3, f"impact: printed COR {value} = 0.75 built into the history")


def test_impact_no_wall(scratch: Path) -> None:
    folder = scratch / "impact_no_wall"
    folder.mkdir(parents=True, exist_ok=True)
    rings = "".join(f"""&body shape = 'ring', center = 0.0, {y!r}, r_inner = {R_IN!r},
  r_outer = {R_OUT!r}, sector = 'half', velocity = 0.0, {v!r} /
""" for y, v in ((0.0265, -30.0), (-0.0265, 30.0)))
    (folder / "input.nml").write_text("""&run title = 'two rings', depth = 1.0, t_end = 2.0e-4 /
&grid h = 0.5e-3 /
&material name = 'al', model = 'elastic', E = 70.0e9, nu = 0.3, rho = 2700.0 /
""" + rings)
    t = np.linspace(0.0, 2.0e-4, 101)
    zero = np.zeros_like(t)
    kinetic = np.where(t < 5e-5, 760.0, 760.0 - 2.0e6 * (t - 5e-5))
    cols = {"time": t, "wall1_disp": zero, "wall1_force": zero, "wall1_fx": zero,
            "wall1_fy": zero, "kinetic": kinetic, "strain": zero, "plastic": 760.0 - kinetic,
            "external": zero}
    for b in (1, 2):
        cols.update({f"body{b}_x": zero, f"body{b}_y": zero, f"body{b}_kinetic": kinetic / 2})
    cols["contact1_2_force"] = zero
    write_history(folder / "history.csv", cols)   # wall 1: the mirror plane x = 0
    write_summary(folder, scene="impact")
    argv = ["--dir", str(folder), "--out", str(scratch / "impact_no_wall.png")]
    rc, out, fig = run_main(plot_case, argv)
    notes = [ln for ln in out.splitlines() if ln.startswith("note:")]
    check(rc == 0 and fig is not None, f"impact without a wall: exit 0 and a figure (rc {rc}: "
          f"{out.strip()[:300]})")
    check(len(notes) == 1 and "no target wall" in notes[0] and "generic" in notes[0]
          and "plot_bodies.py" in notes[0], f"impact without a wall: one note line naming the "
          f"generic plot and plot_bodies.py (got {notes})")
    if fig is not None:
        ax = fig.axes[0]
        ln = line(ax, "kinetic")
        check(ln is not None and np.allclose(ln.get_ydata(), kinetic, rtol=1e-12, atol=0)
              and ax.get_xlabel().startswith("time"),
              "impact without a wall: the generic plot (history's kinetic energy against time)")
    rc, out, fig = run_main(plot_case, argv + ["--kind", "impact"])
    check(rc == 2 and "no target wall" in out, f"impact without a wall, --kind impact: exit 2 "
          f"naming the missing wall (rc {rc})")


def check_body_colours(scratch: Path, folder: Path) -> None:
    """--colour body: one colour per body id (tab10's first two for bodies 1 and 2), and a
    colour bar with exactly the ids as ticks (a discrete scale, not a continuous one)."""
    import matplotlib
    argv = ["--dir", str(folder), "--out", str(scratch / "bodies.png"), "--colour", "body"]
    rc, out, fig = run_main(plot_shapes, argv)
    if not check(rc == 0 and fig is not None, f"shapes --colour body exits 0 (rc {rc}: {out})"):
        return
    polys = [c for ax in fig.axes for c in ax.collections if isinstance(c, PolyCollection)]
    faces = np.asarray(polys[0].get_facecolors()) if polys else np.zeros((0, 4))
    tab = matplotlib.colormaps["tab10"]
    check(len(faces) == 2 and np.allclose(faces[0][:3], tab(0)[:3], atol=1e-9)
          and np.allclose(faces[1][:3], tab(1)[:3], atol=1e-9),
          f"shapes --colour body: body 1 and 2 in tab10's first two colours ({faces.tolist()})")
    bars = [a for a in fig.axes if a.get_ylabel() == "body"]
    ticks = list(bars[0].get_yticks()) if bars else []
    check(ticks == [1.0, 2.0], f"shapes --colour body: the colour bar's ticks are the body ids "
          f"({ticks})")


def test_shapes(scratch: Path) -> None:
    import h5py
    folder = scratch / "crush"                  # reuse the crush folder's inputs and history
    corners = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, 1.0],
                        [2.0, 1.0]]) * 1e-3 + np.array([0.0, 0.024])
    quads = np.array([[0, 1, 4, 3], [1, 2, 5, 4]])
    eqps = np.array([0.0, 0.3])
    with h5py.File(folder / "particles.h5", "w") as h:
        g = h.create_group("snap_000000")
        g.attrs["time"] = 0.0
        g.attrs["step"] = 0
        g.attrs["np"] = 2
        data = {"x": corners[quads].mean(axis=1), "v": np.zeros((2, 2)), "mass": np.ones(2),
                "volume": np.ones(2), "stress": np.zeros((2, 4)), "F": np.tile([1.0, 0, 0, 1], (2, 1)),
                "eqps": eqps, "corners": corners, "quads": quads, "body": np.array([1, 2])}
        for k, v in data.items():
            g.create_dataset(k, data=v)
    argv = ["--dir", str(folder), "--out", str(scratch / "shapes.png")]
    rc, out, fig = run_main(plot_shapes, argv)
    if not check(rc == 0 and fig is not None, f"plot_shapes exits 0 and saves (rc {rc}: {out})"):
        return
    polys = [c for ax in fig.axes for c in ax.collections if isinstance(c, PolyCollection)]
    if check(len(polys) == 1, f"shapes: one collection of particle domains ({len(polys)})"):
        verts = [np.asarray(p.vertices[:4]) for p in polys[0].get_paths()]
        want = corners[quads] * 1e3
        check(len(verts) == 2 and all(np.allclose(v, w, rtol=0, atol=1e-12)
                                      for v, w in zip(verts, want)),
              "shapes: the polygons are the snapshot's corners in mm")
        check(np.array_equal(np.asarray(polys[0].get_array()), eqps),
              "shapes: the colours are the snapshot's eqps")
    ax = fig.axes[0]
    check(ax.get_xlabel() == "x [mm]" and ax.get_ylabel() == "y [mm]", "shapes: axis labels")
    check_body_colours(scratch, folder)
    check_failure_marks(folder, plot_shapes, argv, "shapes plot")
    # a half model's file: the subgroup 'mirrored' holds the whole tube (docs/output.md); made
    # up here as the two particles and their reflection in x = 0 (corner order reversed)
    whole_c = np.vstack([corners, corners * [-1.0, 1.0]])
    whole_q = np.vstack([quads, quads[:, [0, 3, 2, 1]] + len(corners)])
    whole_e = np.concatenate([eqps, eqps])
    with h5py.File(folder / "particles.h5", "a") as h:
        m = h["snap_000000"].create_group("mirrored")
        m.attrs["np"] = 4
        m.attrs["images"] = 2
        mdata = {"x": whole_c[whole_q].mean(axis=1), "v": np.zeros((4, 2)), "mass": np.ones(4),
                 "volume": np.ones(4), "stress": np.zeros((4, 4)),
                 "F": np.tile([1.0, 0, 0, 1], (4, 1)), "eqps": whole_e, "corners": whole_c,
                 "quads": whole_q, "image": np.repeat([0, 1], 2)}
        for k, v in mdata.items():
            m.create_dataset(k, data=v)
    for extra, want_c, want_q, want_e in (([], whole_c, whole_q, whole_e),
                                          (["--sector"], corners, quads, eqps)):
        rc, out, fig = run_main(plot_shapes, argv + extra)
        what = "shapes of a half model" + (" --sector" if extra else "")
        if not check(rc == 0 and fig is not None, f"{what}: exits 0 (rc {rc}: {out})"):
            continue
        polys = [c for ax in fig.axes for c in ax.collections if isinstance(c, PolyCollection)]
        verts = [np.asarray(p.vertices[:4]) for p in polys[0].get_paths()] if polys else []
        check(len(verts) == len(want_q) and all(
            np.allclose(v, w, rtol=0, atol=1e-12) for v, w in zip(verts, want_c[want_q] * 1e3)),
            f"{what}: the polygons are the {'sector' if extra else 'whole tube'} "
            f"({len(verts)} drawn, {len(want_q)} expected)")
        check(polys and np.array_equal(np.asarray(polys[0].get_array()), want_e),
              f"{what}: the colours are its eqps")
        check(("whole tube" in suptitle(fig)[0]) == (not extra),
              f"{what}: the title says whether it is the whole tube ({suptitle(fig)[0]!r})")


def test_mirrored_walls(scratch: Path) -> None:
    """The whole tube of a quarter model is drawn with its walls' mirror images: a platen at
    y = 50 mm (normal -y) with mirror planes x = 0 and y = 25 mm gives it and the lower platen
    at y = 0 (normal +y), each once; a side wall at x = 30 mm (normal -x) gives also x = -30 mm
    (normal +x); the sector alone draws the walls as given."""
    def wall(k, point, normal, mirror=False, given=True):
        return {"index": k, "point": np.array(point), "normal": np.array(normal),
                "mirror": mirror, "input": {"point": point} if given else {}}
    # a user's own 'slip' wall (wall 5, given in the input) is not a plane of the images
    walls = [wall(1, [0.0, 0.05], [0.0, -1.0]), wall(2, [0.03, 0.0], [-1.0, 0.0]),
             wall(5, [0.0, -0.01], [0.0, 1.0], True),
             wall(3, [0.0, 0.0], [1.0, 0.0], True, False),
             wall(4, [0.0, 0.025], [0.0, 1.0], True, False)]

    def planes(mirrored):
        return sorted((round(float(n[0]), 12), round(float(n[1]), 12),
                       round(float(np.dot(n, p)), 12))
                      for p, n, _ in plot_shapes.wall_positions(walls, None, 0.0, mirrored))
    want = sorted([(0.0, -1.0, -0.05), (0.0, 1.0, 0.0), (-1.0, 0.0, -0.03), (1.0, 0.0, -0.03)])
    got = planes(True)
    check(got == want, f"shapes: a quarter model's walls and their mirror images, each once "
          f"(normal, offset n.p: {got}, expected {want})")
    got = planes(False)
    check(got == sorted([(0.0, -1.0, -0.05), (-1.0, 0.0, -0.03)]),
          f"shapes: the sector alone draws its own walls ({got})")


def main() -> int:
    scratch = Path(sys.argv[1] if len(sys.argv) > 1 else "/tmp/test_plots").resolve() / "plots"
    if scratch.exists():
        shutil.rmtree(scratch)
    scratch.mkdir(parents=True)
    for test in (test_crush, test_fixed_platen, test_crush_bodies, test_impact, test_impact_no_wall, test_shapes,
                 test_mirrored_walls):
        try:
            test(scratch)
        except Exception as exc:  # noqa: BLE001 - a crash is a failed check, the others go on
            import traceback
            traceback.print_exc()
            check(False, f"{test.__name__} crashed: {exc}")
    return 0


if __name__ == "__main__":
    main()
    sys.exit(T.summary())
