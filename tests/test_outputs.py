#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The output files of a run follow docs/output.md (history.csv, summary.nml, input.nml,
particles.h5, particles.xdmf), and the plotting scripts work on them.

A tiny elastic aluminium ring (r 24–26 mm, 2 particles through the wall, h = 2 mm) flies at
30 m/s onto a frictionless wall at y = 0 for 0.1 ms, with two probes. The case is written into
SCRATCHDIR and run with the binary named by the environment variable TUBEMPM; the checks are
counted and the last line is `test_outputs: N passed, M failed` (exit 1 if M > 0; a crash of
this script is reported as a failure too).

    TUBEMPM=build/debug/tubempm python3 -m tests.test_outputs SCRATCHDIR

Standard library, numpy and h5py only (plus plots/mpmplot, the readers under test).
"""
from __future__ import annotations

import math
import os
import shutil
import subprocess
import sys
import traceback
import xml.etree.ElementTree as ET
from pathlib import Path

from tests.pycheck import Checks, close
from plots.mpmplot import namelist, readers, scene

ROOT = Path(__file__).resolve().parent.parent
NAME = "test_outputs"

T = Checks(NAME)
check = T.check


# ----------------------------------------------------------------------------------------------
# the case
# ----------------------------------------------------------------------------------------------

T_END = 1.0e-4
HISTORY_EVERY = 1.0e-6
SNAPSHOT_EVERY = 5.0e-5
CENTER = (0.0, 0.0265)
R_IN, R_OUT = 0.024, 0.026
RHO = 2700.0
V0 = -30.0
PROBES = [(0.0, CENTER[1] - 0.025), (0.025, CENTER[1])]   # struck point and 90 degrees
NWALL = 1

CASE_TEXT = """! test_outputs: elastic aluminium ring onto a rigid frictionless wall (format test)
&run
  title = 'outputs'
  output_dir = '{outdir}'
  t_end = {t_end!r}
  history_every = {history_every!r}
  snapshot_every = {snapshot_every!r}
/
&solver
  plane = 'strain'   ! comment with a 'quote'
/
&grid
  h = 2.0e-3
/
&material
  name = 'aluminium'
  model = 'elastic'
  E = 70.0e9
  nu = 0.33
  rho = {rho!r}
/
&body
  shape = 'ring'
  material = 'aluminium'
  center = {cx!r}, {cy!r}
  r_inner = {r_in!r}
  r_outer = {r_out!r}
  n_thick = 2
  velocity = 0.0, {v0!r}
/
&wall
  point = 0.0, 0.0
  normal = 0.0, 1.0
  contact = 'frictionless'
/
&probe
  point = {p1x!r}, {p1y!r}
/
&probe
  point = {p2x!r}, {p2y!r}
/
"""


def expected_header(nwall: int, nprobe: int) -> list[str]:
    """history.csv columns from the rules of docs/output.md (with the added columns after
    damped: contact_loss, step, dt, energy_error)."""
    cols = ["time"]
    for k in range(1, nwall + 1):
        cols += [f"wall{k}_disp", f"wall{k}_force", f"wall{k}_fx", f"wall{k}_fy"]
    cols += ["kinetic", "strain", "plastic", "external", "com_x", "com_y", "com_vx", "com_vy"]
    for k in range(1, nprobe + 1):
        cols += [f"probe{k}_{s}" for s in ("x", "y", "vx", "vy", "eqps")]
    cols += ["damped", "contact_loss", "step", "dt", "energy_error"]
    return cols

SUMMARY_FIELDS = ["status", "scene", "steps", "particles", "nodes", "sim_time", "wall_seconds",
                  "runtime_ratio", "updates_per_second", "threads", "energy_error", "dt_last",
                  "active_nodes", "grid_grown", "min_corner_jacobian", "max_area_deviation",
                  "message"]

#: dataset -> number of columns (None: 1-D), rows np except corners (ncorner)
DATASETS = {"x": 2, "v": 2, "mass": None, "volume": None, "stress": 4, "F": 4, "eqps": None,
            "corners": 2, "quads": 4}
SNAP_ATTRS = ["time", "step", "dt", "ndim", "np", "ncorner"]
GROUPS = ["run", "solver", "grid", "material", "body", "wall", "probe"]


def run(cmd: list[str], timeout: float, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    """Run a command, capturing its output; a timeout becomes exit code -9."""
    try:
        return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as exc:
        return subprocess.CompletedProcess(cmd, -9, exc.stdout or "", f"timeout after {timeout} s")


def show(proc: subprocess.CompletedProcess) -> None:
    """Print the tail of a failed command's output."""
    for name, text in (("stdout", proc.stdout), ("stderr", proc.stderr)):
        lines = (text or "").strip().splitlines()
        if lines:
            print(f"  {name} (last lines):")
            for ln in lines[-15:]:
                print(f"    {ln}")


# ----------------------------------------------------------------------------------------------
# checks of each file
# ----------------------------------------------------------------------------------------------

def check_history(outdir: Path) -> dict[str, list[float]] | None:
    """Header, row lengths, increasing times, first and last rows."""
    path = outdir / "history.csv"
    if not check(path.is_file(), f"{path} exists"):
        return None
    lines = [ln.rstrip("\n") for ln in path.read_text().splitlines() if ln.strip()]
    if not check(len(lines) >= 2, "history.csv has a header and at least one row"):
        return None
    header = [h.strip() for h in lines[0].split(",")]
    want = expected_header(NWALL, len(PROBES))
    if not check(header == want, "history.csv header equals the docs/output.md order for 1 wall "
                 "and 2 probes"):
        print(f"  got:      {header}")
        print(f"  expected: {want}")
    rows: list[list[float]] = []
    bad_len, bad_num = [], []
    for i, ln in enumerate(lines[1:], start=2):
        fields = ln.split(",")
        if len(fields) != len(want):
            bad_len.append(i)
            continue
        try:
            rows.append([float(f) for f in fields])
        except ValueError:
            bad_num.append(i)
    check(not bad_len, f"every history row has {len(want)} fields (bad lines: {bad_len[:5]})")
    check(not bad_num, f"every history field is a number (bad lines: {bad_num[:5]})")
    check(all(math.isfinite(v) for r in rows for v in r), "every history value is finite")
    if not rows:
        return None
    cols = {name: [r[j] for r in rows] for j, name in enumerate(header[:len(rows[0])])}
    t = cols.get("time", [])
    check(all(b > a for a, b in zip(t, t[1:])), "history times increase strictly")
    check(t[0] == 0.0, f"first history row at t = 0 (got {t[0]})")
    check(close(t[-1], T_END, rtol=1e-9) or t[-1] > T_END,
          f"last history row at t_end = {T_END} (got {t[-1]})")
    nrow = round(T_END / HISTORY_EVERY) + 1
    check(nrow - 2 <= len(t) <= nrow + 2,
          f"about one row per history_every: {len(t)} rows, expected {nrow} (+-2)")
    if "com_vy" in cols and "wall1_disp" in cols:
        check(close(cols["com_vy"][0], V0, rtol=1e-9), f"initial com_vy = {V0} m/s "
              f"(got {cols['com_vy'][0]})")
        check(all(d == 0.0 for d in cols["wall1_disp"]), "a static wall has wall1_disp = 0")
    if "probe1_x" in cols:
        for k, (px, py) in enumerate(PROBES, start=1):
            d = math.hypot(cols[f"probe{k}_x"][0] - px, cols[f"probe{k}_y"][0] - py)
            check(d < 1.5e-3, f"probe {k} starts at the particle nearest its point "
                  f"(distance {d:.3g} m)")
    return cols


def check_summary(outdir: Path) -> dict | None:
    """Every field of docs/output.md, status completed."""
    path = outdir / "summary.nml"
    if not check(path.is_file(), f"{path} exists"):
        return None
    try:
        groups = namelist.read_namelist(path)
    except Exception as exc:  # noqa: BLE001 - any reader failure is a failed check
        check(False, f"summary.nml reads as a namelist: {exc}")
        return None
    if not check("summary" in groups, "summary.nml has a &summary group"):
        return None
    s = groups["summary"][0]
    for field in SUMMARY_FIELDS:
        check(field in s, f"summary.nml has '{field}'")
    check(s.get("status") == "completed", f"status = 'completed' (got {s.get('status')!r})")
    check(s.get("scene") == "impact", f"scene = 'impact' for a ring flying onto a static wall "
          f"(got {s.get('scene')!r})")
    for field in ("steps", "particles", "nodes", "threads", "active_nodes"):
        check(isinstance(s.get(field), int) and s[field] > 0,
              f"summary {field} is a positive integer (got {s.get(field)!r})")
    if isinstance(s.get("sim_time"), float):
        check(close(s["sim_time"], T_END, rtol=1e-9) or s["sim_time"] > T_END,
              f"summary sim_time = t_end (got {s['sim_time']})")
    return s


def h5_text(value) -> str:
    """An HDF5 string attribute as str."""
    import numpy as np
    if isinstance(value, np.ndarray):
        value = value.ravel()[0] if value.size else b""
    if isinstance(value, bytes):
        value = value.decode(errors="replace")
    return str(value).rstrip("\x00 ")


def check_h5(outdir: Path, summary: dict | None) -> list[dict]:
    """Every dataset in every snapshot with its shape and attributes; mass conservation."""
    import h5py
    import numpy as np
    path = outdir / "particles.h5"
    if not check(path.is_file(), f"{path} exists"):
        return []
    snaps: list[dict] = []
    with h5py.File(path, "r") as f:
        check("meta" in f and "code_version" in f["meta"].attrs, "/meta has code_version")
        check("meta" in f and "input_nml" in f["meta"], "/meta has input_nml")
        if "meta" in f and "input_nml" in f["meta"]:
            text = h5_text(f["meta"]["input_nml"][()])
            check("&run" in text and "&probe" in text, "/meta/input_nml holds the input text")
        names = sorted(k for k in f.keys() if k.startswith("snap_"))
        check(names == [f"snap_{k:06d}" for k in range(len(names))],
              f"snapshots are snap_000000, snap_000001, ... (got {names})")
        nsnap = round(T_END / SNAPSHOT_EVERY) + 1
        check(len(names) == nsnap, f"{nsnap} snapshots (0, every {SNAPSHOT_EVERY} s, "
              f"end), got {len(names)}")
        for name in names:
            g = f[name]
            info = {"name": name}
            for a in SNAP_ATTRS:
                if check(a in g.attrs, f"{name} has attribute {a}"):
                    info[a] = float(np.ravel(g.attrs[a])[0])
            npart = int(info.get("np", -1))
            ncorner = int(info.get("ncorner", -1))
            check(info.get("ndim") == 2.0, f"{name} ndim = 2")
            if summary and isinstance(summary.get("particles"), int):
                check(npart == summary["particles"], f"{name} np = summary particles "
                      f"({npart} vs {summary['particles']})")
            for ds, ncol in DATASETS.items():
                if not check(ds in g and isinstance(g[ds], h5py.Dataset),
                             f"{name} has dataset {ds}"):
                    continue
                rows = ncorner if ds == "corners" else npart
                want = (rows,) if ncol is None else (rows, ncol)
                check(g[ds].shape == want, f"{name}/{ds} shape {g[ds].shape} == {want}")
                check(h5_text(g[ds].attrs.get("units", "")) != "",
                      f"{name}/{ds} has a units attribute")
                check(h5_text(g[ds].attrs.get("long_name", "")) != "",
                      f"{name}/{ds} has a long_name attribute")
                info[f"shape_{ds}"] = g[ds].shape
            if "mass" in g:
                info["mass"] = float(np.sum(g["mass"][()]))
            if "quads" in g and ncorner > 0:
                q = g["quads"][()]
                check(q.min() >= 0 and q.max() < ncorner,
                      f"{name}/quads are 0-based corner ids in [0, {ncorner})")
            if "x" in g:
                check(bool(np.all(np.isfinite(g["x"][()]))), f"{name}/x is finite")
            snaps.append(info)
    masses = [s["mass"] for s in snaps if "mass" in s]
    if masses:
        check(all(close(m, masses[0], rtol=1e-12) for m in masses),
              f"mass is the same in all snapshots to 1e-12 (sums {masses})")
        exact = RHO * math.pi * (R_OUT ** 2 - R_IN ** 2)
        check(close(masses[0], exact, rtol=1e-2),
              f"snapshot mass {masses[0]:.6g} kg/m = rho * ring area {exact:.6g} kg/m (1 %)")
    if snaps:
        check(close(snaps[0].get("time", -1.0), 0.0, atol=1e-300), "first snapshot at t = 0")
        check(close(snaps[-1].get("time", -1.0), T_END, rtol=1e-9) or
              snaps[-1].get("time", -1.0) > T_END, "last snapshot at t_end")
    return snaps

XDMF_ARRAYS = ["eqps", "mass", "volume", "vx", "vy", "sxx", "syy", "sxy", "szz", "body"]


def check_xdmf(outdir: Path, snaps: list[dict]) -> None:
    """The XDMF index parses, every HDF reference matches particles.h5, every grid has the ten
    cell arrays and no hyperslab."""
    import h5py
    path = outdir / "particles.xdmf"
    if not check(path.is_file(), f"{path} exists"):
        return
    try:
        root, err = ET.parse(path).getroot(), ""
    except ET.ParseError as exc:
        root, err = None, str(exc)
    if not check(root is not None, f"particles.xdmf parses as XML {err}"):
        return
    check(root.tag == "Xdmf" and root.get("Version", "").startswith("3"), "root is <Xdmf "
          "Version=\"3...\">")
    coll = root.find("./Domain/Grid")
    if not check(coll is not None and coll.get("GridType") == "Collection" and
                 coll.get("CollectionType") == "Temporal", "a temporal collection grid"):
        return
    grids = coll.findall("./Grid")
    check(len(grids) == len(snaps), f"{len(grids)} XDMF grids = {len(snaps)} snapshots")
    times = []
    for g in grids:
        tnode = g.find("./Time")
        times.append(float(tnode.get("Value")) if tnode is not None else float("nan"))
    check(len(times) == len(snaps) and
          all(close(a, s.get("time", float("nan")), rtol=1e-12, atol=1e-300)
              for a, s in zip(times, snaps)),
          f"XDMF Time values equal the snapshot time attributes ({times})")
    topo_ok = all(g.find("./Topology") is not None and
                  g.find("./Topology").get("TopologyType") == "Quadrilateral" and
                  g.find("./Geometry") is not None and
                  g.find("./Geometry").get("GeometryType") == "XY" for g in grids)
    check(topo_ok, "every grid has a Quadrilateral topology and an XY geometry")
    n_np = sum(1 for g, s in zip(grids, snaps)
               if g.find("./Topology") is not None and
               int(g.find("./Topology").get("NumberOfElements", "-1")) == int(s.get("np", -2)))
    check(n_np == len(grids), "Topology NumberOfElements = np of each snapshot")
    bad_ref, bad_shape, bad_slab, nref, nslab = [], [], [], 0, 0
    with h5py.File(outdir / "particles.h5", "r") as f:
        for g in grids:
            for item in g.iter("DataItem"):
                if item.get("Format") == "HDF":
                    nref += 1
                    text = (item.text or "").strip()
                    fname, _, dpath = text.partition(":")
                    dims = tuple(int(v) for v in item.get("Dimensions", "").split())
                    if fname != "particles.h5" or dpath not in f or \
                            not isinstance(f[dpath], h5py.Dataset):
                        bad_ref.append(text)
                        continue
                    if f[dpath].shape != dims:
                        bad_shape.append(f"{text}: {f[dpath].shape} vs {dims}")
            names = sorted(a.get("Name") for a in g.findall("./Attribute"))
            if names != sorted(XDMF_ARRAYS):
                bad_slab.append(f"{g.get('Name')}: attributes {names}")
            nslab += sum(1 for item in g.iter("DataItem") if item.get("ItemType") == "HyperSlab")
    check(nref > 0 and not bad_ref, f"every HDF DataItem ({nref}) names a dataset of "
          f"particles.h5 (bad: {bad_ref[:3]})")
    check(not bad_shape, f"every HDF DataItem's Dimensions equal the dataset shape "
          f"(bad: {bad_shape[:3]})")
    check(not bad_slab, f"every grid has the cell arrays {XDMF_ARRAYS} (bad: {bad_slab[:3]})")
    # ParaView's default reader (Xdmf3ReaderS) drops hyperslab items ("Skipping unrecognized
    # array type"); tests/test_paraview.sh checks with ParaView itself where it is installed
    check(nslab == 0, f"no HyperSlab items, which ParaView's default reader skips ({nslab})")


def check_input_echo(outdir: Path) -> None:
    """input.nml reads back and holds every group with the case's values."""
    path = outdir / "input.nml"
    if not check(path.is_file(), f"{path} exists"):
        return
    try:
        groups, err = namelist.read_namelist(path), ""
    except Exception as exc:  # noqa: BLE001
        groups, err = None, str(exc)
    if not check(groups is not None, f"input.nml reads back with read_namelist {err}"):
        return
    for g in GROUPS:
        check(g in groups, f"input.nml has &{g}")
    check(len(groups.get("probe", [])) == len(PROBES), "input.nml has both probes")
    check(len(groups.get("wall", [])) == NWALL, "input.nml has the one wall")
    run_g = (groups.get("run") or [{}])[0]
    body = (groups.get("body") or [{}])[0]
    check(isinstance(run_g.get("t_end"), float) and close(run_g["t_end"], T_END),
          f"input.nml t_end = {T_END} (got {run_g.get('t_end')!r})")
    check(body.get("r_inner") == R_IN and body.get("r_outer") == R_OUT,
          "input.nml keeps r_inner and r_outer exactly")
    check(body.get("velocity") == [0.0, V0], f"input.nml body velocity (got "
          f"{body.get('velocity')!r})")
    check(str(run_g.get("output_dir", "")) == str(outdir),
          "input.nml output_dir is the case's")


def check_readers(outdir: Path, scratch: Path, snaps: list[dict]) -> None:
    """plots/mpmplot reads the real files, and names what is missing in a broken one."""
    import h5py
    try:
        hist = readers.read_history(outdir / "history.csv")
        check(list(hist) == expected_header(NWALL, len(PROBES)),
              "readers.read_history gives the columns in file order")
        check(readers.read_summary(outdir / "summary.nml").get("status") == "completed",
              "readers.read_summary reads the status")
        names = readers.read_frames(outdir / "particles.h5")
        check(len(names) == len(snaps), "readers.read_frames lists every snapshot")
        frame = readers.read_frame(outdir / "particles.h5", -1)
        check(frame["x"].shape == (frame["np"], 2) and frame["name"] == names[-1],
              "readers.read_frame(-1) reads the last snapshot")
    except Exception as exc:  # noqa: BLE001
        check(False, f"mpmplot reads the outputs: {exc}")
        return
    broken = scratch / "broken.h5"
    shutil.copyfile(outdir / "particles.h5", broken)
    with h5py.File(broken, "r+") as f:
        del f["snap_000000"]["eqps"]
    try:
        readers.read_frame(broken, 0)
        check(False, "readers.read_frame raises on a snapshot without eqps")
    except KeyError as exc:
        check("eqps" in str(exc), f"readers.read_frame names the missing dataset ({exc})")


def check_png(path: Path, what: str) -> None:
    """A PNG file that exists and is larger than 10 kB."""
    ok = path.is_file()
    size = path.stat().st_size if ok else 0
    check(ok and size > 10_000, f"{what} wrote {path} > 10 kB (size {size} B)")
    if ok:
        check(path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is a PNG file")


# ----------------------------------------------------------------------------------------------

def main() -> int:
    """Write the case, run it, check the outputs and the plots."""
    if len(sys.argv) < 2:
        print(f"usage: TUBEMPM=path/to/tubempm {sys.argv[0]} SCRATCHDIR", file=sys.stderr)
        return 2
    scratch = Path(sys.argv[1]).resolve()
    scratch.mkdir(parents=True, exist_ok=True)
    binary = os.environ.get("TUBEMPM", "")
    if binary and not os.path.isabs(binary):
        binary = str((Path.cwd() / binary).resolve())
    if not check(bool(binary) and os.access(binary, os.X_OK),
                 f"TUBEMPM names an executable binary (got {binary!r})"):
        return 1

    outdir = scratch / "out_outputs"
    if outdir.is_dir():                        # outputs of an earlier run of this test
        shutil.rmtree(outdir)
    case = scratch / "outputs.nml"
    case.write_text(CASE_TEXT.format(
        outdir=outdir, t_end=T_END, history_every=HISTORY_EVERY,
        snapshot_every=SNAPSHOT_EVERY, rho=RHO, cx=CENTER[0], cy=CENTER[1], r_in=R_IN,
        r_out=R_OUT, v0=V0, p1x=PROBES[0][0], p1y=PROBES[0][1], p2x=PROBES[1][0],
        p2y=PROBES[1][1]))
    check(scene.case_output_dir(case) == str(outdir), "scene.case_output_dir finds the "
          "&run output_dir")

    # --check: validate only
    proc = run([binary, "--check", str(case)], timeout=120)
    if not check(proc.returncode == 0, f"--check exits 0 (got {proc.returncode})"):
        show(proc)
    check("input ok" in proc.stdout, "--check prints 'input ok'")
    check(not (outdir / "history.csv").exists(), "--check writes no history.csv")

    # the run
    proc = run([binary, "--quiet", str(case)], timeout=600)
    if not check(proc.returncode == 0, f"the run exits 0 (got {proc.returncode})"):
        show(proc)
        return 1
    cols = check_history(outdir)
    summary = check_summary(outdir)
    snaps = check_h5(outdir, summary)
    check_xdmf(outdir, snaps)
    check_input_echo(outdir)
    if cols is not None and snaps and "mass" in snaps[0]:
        ke0 = 0.5 * snaps[0]["mass"] * V0 ** 2       # depth 1 m
        check(close(cols["kinetic"][0], ke0, rtol=1e-9),
              f"initial kinetic energy {cols['kinetic'][0]:.6g} J = 1/2 m v^2 = {ke0:.6g} J")

    check_readers(outdir, scratch, snaps)

    # the plots
    kind = scene.scene_kind(outdir, case)
    proc = run([sys.executable, "-m", "plots.plot_case", "--case", str(case)], timeout=300)
    if not check(proc.returncode == 0, f"plot_case.py exits 0 (got {proc.returncode})"):
        show(proc)
    check_png(outdir / f"{kind}.png", "plot_case.py")
    proc = run([sys.executable, "-m", "plots.plot_case", "--dir", str(outdir),
                "--kind", "impact", "--out", str(scratch / "impact.png")], timeout=300)
    if not check(proc.returncode == 0, f"plot_case.py --kind impact exits 0 (got "
                 f"{proc.returncode})"):
        show(proc)
    check_png(scratch / "impact.png", "plot_case.py --kind impact")
    proc = run([sys.executable, "-m", "plots.plot_shapes", "--case", str(case)], timeout=300)
    if not check(proc.returncode == 0, f"plot_shapes.py exits 0 (got {proc.returncode})"):
        show(proc)
    check_png(outdir / "shapes.png", "plot_shapes.py")
    return 0


if __name__ == "__main__":
    try:
        rc = main()
    except Exception:  # noqa: BLE001 - a crash is a failure, with the summary line last
        traceback.print_exc()
        check(False, "the test script crashed (traceback above)")
        rc = 1
    sys.exit(max(T.summary(), 1 if rc != 0 else 0))
