#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Dynamic finite element references of the impact and wave scenes (tracker issue 31).

Builds the project's explicit FE code (tools/fe_reference/xfe.f90, gfortran -O2), writes its
&fe input for namelists/impact.nml and namelists/wave.nml (ring, material, wall, probes read
from the namelists) on a sequence of meshes (n_t elements through the wall, about square
elements around the half ring), runs them on one thread, measures every run with tools/study.py's
own metric functions (impact_metrics, wave_metrics: the FE writes history.csv in tubempm's
columns) and writes into docs/fe_reference/:

- impact_fe_nt<n>.csv, wave_fe_nt<n>.csv: the time histories of each mesh;
- impact_fe.csv, wave_fe.csv: the finest mesh's (the references);
- dynamic_convergence.json: per mesh the metrics, and per quantity the estimated error of the
  finest mesh (Richardson from the three finest when they converge monotonically, else the
  difference finest - next).

    python3 -m tools.fe_reference.fe_dynamic                  # impact 2-16, wave 2-32
    python3 -m tools.fe_reference.fe_dynamic --meshes 2 4     # a quick look
    python3 -m tools.fe_reference.fe_dynamic --scenes wave    # one scene

Runs go to out/fe_dynamic/<scene>_nt<n>/ and are reused while the input and the binary are
unchanged.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from plots.mpmplot import namelist, readers, scene
from tools import study

ROOT = Path(__file__).resolve().parent.parent.parent

SOURCE = ROOT / "tools" / "fe_reference" / "xfe.f90"
BINARY = ROOT / "build" / "xfe" / "xfe"
DOCS = ROOT / "docs" / "fe_reference"
WORK = ROOT / "out" / "fe_dynamic"
#: the meshes per scene (n_t; the wave's finest costs 15 CPU min, an impact on it would take 5 h)
MESHES = {"impact": (2, 4, 8, 16), "wave": (2, 4, 8, 16, 32)}
#: explicit time step: cfl times the smallest element's area over its longest diagonal over
#: the dilatational wave speed
CFL = 0.5
#: each scene's record: the study's end time for the impact (contact and rebound), 1e-4 s for
#: the wave (the study's window is 3e-5 s: its arrivals are measured on that part)
T_END = {"impact": study.SCENES["impact"]["set"]["run.t_end"], "wave": 1.0e-4}
EVERY = {"impact": study.SCENES["impact"]["set"]["run.history_every"],
         "wave": study.SCENES["wave"]["set"]["run.history_every"]}
WAVE_WINDOW = study.SCENES["wave"]["set"]["run.t_end"]
#: the observed orders of convergence for which the Richardson estimate is trusted
ORDER_RANGE = (0.5, 4.0)
FFLAGS = ["-std=f2008", "-fimplicit-none", "-Wall", "-O2"]


def build(binary: Path = BINARY, flags: list[str] | None = None) -> Path:
    """Compile xfe.f90 (release flags unless given) when the source is newer."""
    binary.parent.mkdir(parents=True, exist_ok=True)
    if binary.is_file() and binary.stat().st_mtime > SOURCE.stat().st_mtime and flags is None:
        return binary
    mod = binary.parent / ("mod_" + binary.name)
    mod.mkdir(exist_ok=True)
    cmd = ["gfortran", *(flags or FFLAGS), f"-J{mod}", "-o", str(binary), str(SOURCE)]
    subprocess.run(cmd, check=True)
    return binary


def fortran(v) -> str:
    if isinstance(v, bool):
        return ".true." if v else ".false."
    if isinstance(v, str):
        return f"'{v}'"
    if isinstance(v, (list, tuple, np.ndarray)):
        return ", ".join(fortran(x) for x in v)
    if isinstance(v, int):
        return str(v)
    return f"{float(v):.17g}"


def fe_namelist(values: dict) -> str:
    return "&fe\n" + "".join(f"  {k} = {fortran(v)}\n" for k, v in values.items()) + "/\n"


def scene_input(name: str, n_t: int, output: Path) -> dict:
    """The &fe values of a tubempm scene namelist (a ring, one wall y = const below it)."""
    inputs = namelist.read_namelist(study.SCENES[name]["base"])
    r = scene.ring_properties(inputs)
    body = scene.ring_body(inputs)
    if r["plane"] != "strain" or r["model"] != "j2":
        raise SystemExit(f"{name}: the FE reference models plane strain j2")
    walls = inputs.get("wall", [])
    if len(walls) != 1 or list(map(float, walls[0].get("normal", [0, 0]))) != [0.0, 1.0]:
        raise SystemExit(f"{name}: the FE reference needs one wall with normal (0, 1)")
    w = walls[0]
    mat = scene.body_material(inputs, body)
    vals = {"shape": "ring", "sector": str(body.get("sector", "half")),
            "r_inner": float(body["r_inner"]), "r_outer": float(body["r_outer"]),
            "center": [float(c) for c in body["center"]], "n_t": n_t,
            "velocity": [float(c) for c in body.get("velocity", [0.0, 0.0])],
            "E": float(mat["e"] if "e" in mat else mat["E"]), "nu": float(mat["nu"]),
            "rho": float(mat["rho"]), "sigma_y": float(mat["sigma_y"]),
            "hardening": float(mat.get("hardening", 0.0)),
            "wall_y": float(w.get("point", [0.0, 0.0])[1]),
            "wall_speed": float(np.atleast_1d(w.get("velocity", [0.0, 0.0]))[-1]),
            "t_end": T_END[name], "cfl": CFL, "history_every": EVERY[name],
            "depth": float(inputs.get("run", [{}])[0].get("depth", 1.0))
            if isinstance(inputs.get("run"), list) else float(inputs["run"].get("depth", 1.0)),
            "output": str(output)}
    if vals["sector"] != "half":
        raise SystemExit(f"{name}: the FE reference models the half ring")
    if "motion_t" in w:
        vals["motion_t"] = [float(x) for x in w["motion_t"]]
        vals["motion_f"] = [float(x) for x in w["motion_f"]]
    probes = inputs.get("probe", [])
    if probes:
        vals["probe_x"] = [float(p["point"][0]) for p in probes]
        vals["probe_y"] = [float(p["point"][1]) for p in probes]
    return vals


def run_case(binary: Path, folder: Path, values: dict, force: bool = False) -> float:
    """Run one &fe case in folder (history.csv there); reuse a finished run of the same input
    and binary. Returns the CPU seconds of the run (or of the reused one)."""
    folder.mkdir(parents=True, exist_ok=True)
    text = fe_namelist(values)
    key = hashlib.sha256(text.encode() + binary.read_bytes()).hexdigest()
    stamp = folder / "done.json"
    if not force and stamp.is_file():
        done = json.loads(stamp.read_text())
        if done.get("key") == key and (folder / "history.csv").is_file():
            return float(done["cpu_s"])
    (folder / "case.nml").write_text(text)
    t0 = time.process_time()
    r0 = os.times()
    env = dict(os.environ, OMP_NUM_THREADS="1")
    subprocess.run([str(binary), str(folder / "case.nml")], check=True, env=env,
                   stdout=open(folder / "log.txt", "w"), stderr=subprocess.STDOUT)
    r1 = os.times()
    cpu = (r1.children_user - r0.children_user) + (r1.children_system - r0.children_system)
    del t0
    stamp.write_text(json.dumps({"key": key, "cpu_s": cpu}))
    return cpu


def truncated(folder: Path, t_max: float) -> Path:
    """A copy of folder's history.csv cut at t_max (for metrics over the study's window)."""
    out = folder / f"window_{t_max:.3g}"
    out.mkdir(exist_ok=True)
    lines = (folder / "history.csv").read_text().splitlines()
    keep = [lines[0]] + [ln for ln in lines[1:] if float(ln.split(",")[0]) <= t_max * (1 + 1e-9)]
    (out / "history.csv").write_text("\n".join(keep) + "\n")
    return out


def impact_numbers(folder: Path, inputs: dict) -> dict:
    m = study.impact_metrics(folder, inputs)
    h = readers.read_history(folder / "history.csv")
    return {"duration": m["duration"], "cor": m["cor"], "v_rebound": m["cor"] * m["v_impact"],
            "peak_10us": m["peak_10us"], "plastic_end": float(h["plastic"][-1]),
            "impulse": m["impulse"], "v_impact": m["v_impact"],
            "energy_error": float(h["energy_error"][-1])}


def wave_numbers(folder: Path, inputs: dict) -> dict:
    """Arrivals at 10 % of each mesh's own peaks (the finest mesh's set the levels at which
    tools/study.py times every run: study.wave_levels)."""
    w = study.wave_metrics(truncated(folder, WAVE_WINDOW), inputs, own_peak=True)
    full = study.wave_metrics(folder, inputs, own_peak=True)
    return {"arrivals": [float(a) for a in w["arrivals"]], "wave_speed": w["wave_speed"],
            "arrivals_1e-4": [float(a) for a in full["arrivals"]],
            "angles": [float(a) for a in w["curve_x"]]}


def estimate(values: list[float]) -> dict:
    """Error estimate of the last (finest) value of a sequence at halved element sizes:
    Richardson from the last three when the differences shrink monotonically with an observed
    order p in ORDER_RANGE (p, the extrapolated value, |finest - extrapolated|), else
    |finest - next|."""
    v = [float(x) for x in values]
    out = {"finest": v[-1], "diff_next": abs(v[-1] - v[-2]) if len(v) > 1 else math.nan}
    out["error"] = out["diff_next"]
    out["method"] = "finest-next"
    if len(v) >= 3:
        d1, d2 = v[-2] - v[-3], v[-1] - v[-2]
        if d1 != 0.0 and d2 != 0.0 and d1 * d2 > 0.0 and abs(d2) < abs(d1):
            p = math.log2(abs(d1 / d2))
            if ORDER_RANGE[0] <= p <= ORDER_RANGE[1]:
                ext = v[-1] + d2 / (2.0 ** p - 1.0)
                out.update(order=p, extrapolated=ext, error=abs(v[-1] - ext),
                           method="richardson")
    return out


def write_history_csv(src: Path, dst: Path, columns: list[str]) -> None:
    h = readers.read_history(src / "history.csv")
    data = np.column_stack([h[c] for c in columns])
    np.savetxt(dst, data, delimiter=",", header=",".join(columns), comments="", fmt="%.9g")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--meshes", type=int, nargs="+", default=None,
                    help="n_t of the meshes (default: MESHES of each scene)")
    ap.add_argument("--scenes", nargs="+", default=["impact", "wave"])
    ap.add_argument("--docs", type=Path, default=DOCS)
    ap.add_argument("--work", type=Path, default=WORK)
    args = ap.parse_args(argv)
    binary = build()
    args.docs.mkdir(parents=True, exist_ok=True)
    conv_path = args.docs / "dynamic_convergence.json"
    conv = json.loads(conv_path.read_text()) if conv_path.is_file() else {}
    for name in args.scenes:
        inputs = namelist.read_namelist(study.SCENES[name]["base"])
        rows = []
        for n_t in sorted(args.meshes or MESHES[name]):
            folder = args.work / f"{name}_nt{n_t}"
            vals = scene_input(name, n_t, folder / "history.csv")
            cpu = run_case(binary, folder, vals)
            log = (folder / "log.txt").read_text()
            n_el = int(log.split("xfe: ")[1].split(" elements")[0]) if "elements" in log else 0
            row = {"n_t": n_t, "elements": n_el, "cpu_s": round(cpu, 1)}
            row.update(impact_numbers(folder, inputs) if name == "impact"
                       else wave_numbers(folder, inputs))
            rows.append(row)
            print(f"{name} n_t={n_t}: {json.dumps({k: v for k, v in row.items()})}")
            if name == "impact":
                cols = ["time", "wall1_force", "com_vx", "com_vy", "kinetic", "strain", "plastic",
                        "energy_error"]
            else:
                cols = ["time", "wall1_disp", "wall1_force", "com_vx", "com_vy", "kinetic", "strain",
                        "plastic"] + [f"probe{k}_{c}" for k in range(1, 8)
                                      for c in ("x", "y", "vx", "vy")]
            write_history_csv(folder, args.docs / f"{name}_fe_nt{n_t}.csv", cols)
        finest = rows[-1]["n_t"]
        write_history_csv(args.work / f"{name}_nt{finest}", args.docs / f"{name}_fe.csv",
                          cols)
        if name == "impact":
            keys = ["duration", "cor", "v_rebound", "peak_10us", "plastic_end"]
            est = {k: estimate([r[k] for r in rows]) for k in keys}
        else:
            est = {}
            for j in range(len(rows[-1]["arrivals"])):
                est[f"arrival_{j + 1}"] = estimate([r["arrivals"][j] for r in rows])
            est["wave_speed"] = estimate([r["wave_speed"] for r in rows])
        conv[name] = {"meshes": rows, "estimate": est, "cfl": CFL, "t_end": T_END[name],
                      "history_every": EVERY[name]}
        if name == "wave":
            conv[name]["arrival_window"] = WAVE_WINDOW
    conv_path.write_text(json.dumps(conv, indent=1) + "\n")
    print(f"wrote {conv_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
