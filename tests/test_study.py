#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The study machinery: tools/batch.py (namelist overrides, resumable batch runs) and the
metrics of tools/study.py and plots/plot_study.py (Richardson extrapolation, Pareto front,
the cheapest run per error target).

Checks against closed forms (a sequence f(h) = f0 + C h^p), against hand-made inputs, and runs
two tiny wave cases (0.4 us of a 2-particle-thick ring) with the binary named by TUBEMPM to
check that finished runs are skipped, interrupted and changed runs re-run. The last line is
`test_study: N passed, M failed` (exit 1 if M > 0).

    TUBEMPM=build/debug/tubempm python3 -m tests.test_study
"""
from __future__ import annotations

import json
import math
import os
import shutil
import sys
import tempfile
import traceback
from pathlib import Path

import numpy as np

from plots.mpmplot import namelist
from tests.pycheck import Checks, close

ROOT = Path(__file__).resolve().parent.parent
NAME = "test_study"
T = Checks(NAME)
check = T.check


def test_render() -> None:
    """namelist.set_values, what batch writes each run's case.nml with."""
    base = (ROOT / "namelists" / "wave.nml").read_text()
    text = namelist.set_values(base, {"grid.h": 0.25e-3, "body.n_thick": 16, "probe[7].point":
                                      (0.0, 0.05), "solver.deterministic": True,
                                      "run.title": "a'b"})
    nml = namelist.parse_namelist(text, "rendered")
    check(close(nml["grid"][0]["h"], 0.25e-3), "render: replaced h")
    check(nml["body"][0]["n_thick"] == 16, "render: replaced n_thick")
    check(nml["solver"][0]["deterministic"] is True, "render: added deterministic")
    check(nml["run"][0]["title"] == "a'b", "render: quote doubled in a string")
    pts = [p["point"] for p in nml["probe"]]
    check(len(pts) == 7 and close(pts[6][1], 0.05) and close(pts[5][1], 0.047650635),
          "render: only the 7th &probe changed")
    orig = namelist.parse_namelist(base, "base")
    same = all(nml[g] == orig[g] for g in ("material", "wall"))
    check(same, "render: groups without overrides unchanged")
    for bad in ({"probe[8].point": (0.0, 0.0)}, {"grid h": 1.0}):
        try:
            namelist.set_values(base, bad)
            refused = False
        except ValueError:
            refused = True
        check(refused, f"render: {bad} is refused with ValueError")
    # a whole line is replaced with its comment (which spoke of the old value); an
    # assignment that shares its line, or a group on one line, is edited in place
    line = namelist.set_values("&grid\n  h = 1.0e-3   ! t/4\n/\n", {"grid.h": 2.0e-3})
    check(line == "&grid\n  h = 0.002\n/\n", f"render: the line replaced: {line!r}")
    one = "&run title = 'a', cfl = 0.2 ! c\n/\n&grid h = 1.0 /\n&grid h = 2.0 /\n"
    text = namelist.set_values(one, {"run.cfl": 0.5, "run.t_end": 1e-3, "grid[2].h": 3.0,
                                     "grid[1].n": 4})
    check(text == "&run title = 'a', cfl = 0.5 ! c\n  t_end = 0.001\n/\n"
          "&grid h = 1.0\n  n = 4\n/\n&grid h = 3.0 /\n",
          f"render: one-line groups edited in place: {text!r}")
    gone = namelist.set_values("&m\n  a = 1   ! x\n  b = 2, c = 3\n/\n", {"m.a": None, "m.b": None})
    check(gone == "&m\n  c = 3\n/\n", f"render: None removes an assignment: {gone!r}")
    check(namelist.format_value([1.5, 2]) == "1.5, 2", "format_value of a list")
    check(namelist.format_value(False) == ".false.", "format_value of a bool")


def test_richardson() -> None:
    from tools import study
    for p in (1.0, 1.5, 2.0):
        f0, c = 3.0, 0.7
        vals = [f0 + c * h ** p for h in (0.4, 0.2, 0.1)]
        r = study.richardson(*vals)
        check(close(r["order"], p, 1e-9), f"richardson order {r['order']} vs {p}")
        check(close(r["extrapolated"], f0, 1e-9), f"richardson limit {r['extrapolated']}")
        check(close(r["fine_error"], abs(vals[2] - f0) / f0, 1e-9), "richardson fine error")
    r = study.richardson(1.0, 2.0, 0.5)           # oscillating: no order
    check(math.isnan(r["order"]), "richardson: oscillating sequence gives NaN")


def test_pareto_advice() -> None:
    from plots import plot_study
    pts = [(1.0, 0.5), (2.0, 0.6), (3.0, 0.1), (4.0, 0.1), (5.0, 0.01)]
    check(plot_study.pareto(pts) == [(1.0, 0.5), (3.0, 0.1), (5.0, 0.01)], "pareto front")
    rows = []
    for i, (cost, err) in enumerate(pts):
        # each run with its two alignment variants (h x 0.97, 1.03), of the same error
        for hs in (1.0, 0.97, 1.03):
            rows.append({"scene": "crush", "name": f"r{i}" + ("" if hs == 1.0 else f"_hs{hs:g}"),
                         "reference": "ref", "error": err, "cpu_s": cost, "speed": math.nan,
                         "basis": "cpdi2", "scheme": "musl", "h_over_t": 1.0, "n_t": 4.0,
                         "n_c": 8.0, "aspect": 1.0, "cfl": 0.2, "particles": 10.0,
                         "runtime_ratio": 1.0, "h_scale": hs})

    def advice() -> dict[float, str]:
        return {a["target"]: a.get("name") for a in plot_study.advice(rows)
                if a["scene"] == "crush"}

    def row(name: str) -> dict:
        return next(r for r in rows if r["name"] == name)

    check(advice() == {0.05: "r4", 0.02: "r4", 0.01: "r4"},
          f"advice picks the cheapest: {advice()}")
    for name in ("r2", "r2_hs0.97", "r2_hs1.03"):
        row(name)["error"] = 0.03
    check(advice()[0.05] == "r2", f"advice 5 %: {advice()}")
    # by the worst of its alignments: r2 at 3 % as run but 6 % at h x 0.97 is not within 5 %
    row("r2_hs0.97")["error"] = 0.06
    check(advice()[0.05] == "r4" and math.isclose(plot_study.robust_error(row("r2"), rows),
                                                   0.06),
          f"advice 5 % by the worst alignment: {advice()}")
    # and a run never measured at another alignment is not advised however good as run
    row("r2_hs0.97")["error"] = 0.03
    rows[:] = [r for r in rows if not r["name"].startswith("r2_hs")]
    check(advice()[0.05] == "r4", f"advice 5 %: a run without its variants is not picked "
          f"({advice()})")
    # where no run of the scene has variants (the quick level) every run counts, as run
    rows[:] = [r for r in rows if "_hs" not in r["name"]]
    check(advice()[0.05] == "r2", f"advice 5 %: no variants in the scene, picked as run "
          f"({advice()})")


def test_batch_runs() -> None:
    from tools import batch
    exe = Path(os.environ.get("TUBEMPM", ROOT / "build" / "debug" / "tubempm"))
    if not check(exe.is_file(), f"binary {exe} missing"):
        return
    tmp = Path(tempfile.mkdtemp(prefix="test_study_"))
    try:
        base = ROOT / "namelists" / "wave.nml"
        small = {"run.t_end": 4.0e-7, "grid.h": 2.0e-3, "body.n_thick": 2,
                 "run.snapshot_every": 4.0e-7, "run.history_every": 1.0e-7, "run.threads": 1}
        cases = [batch.Case(f"c{i}", base, {**small, "run.cfl": c}) for i, c in
                 enumerate((0.2, 0.4))]
        res = batch.run_batch(cases, tmp, jobs=2, binary=exe, log=lambda m: None)
        check(all(r["exit_code"] == 0 for r in res), f"batch: both runs complete {res}")
        check(all((tmp / c.name / "result.json").is_file() for c in cases), "result.json")
        s = batch.read_summary(tmp / "c0")
        check(s.get("status") == "completed", "batch: summary.nml in the case folder")
        res2 = batch.run_batch(cases, tmp, jobs=2, binary=exe, log=lambda m: None)
        check(all(r.get("skipped") for r in res2), "batch: finished runs skipped")
        # an interrupted run (no result.json) and a changed input are run again
        (tmp / "c0" / "result.json").unlink()
        (tmp / "c0" / "stale").write_text("x")
        cases[1] = batch.Case("c1", base, {**small, "run.cfl": 0.3})
        res3 = batch.run_batch(cases, tmp, jobs=1, binary=exe, log=lambda m: None)
        check(not res3[0].get("skipped") and not (tmp / "c0" / "stale").exists(),
              "batch: interrupted run re-run in a cleared folder")
        check(not res3[1].get("skipped") and res3[1]["exit_code"] == 0,
              "batch: changed input re-run")
        rec = json.loads((tmp / "c1" / "result.json").read_text())
        check(rec["cpu_s"] > 0 and rec["wall_s"] > 0, "batch: times recorded")
        # a folder moved elsewhere is still recognised as finished
        moved = tmp / "moved"
        moved.mkdir()
        shutil.move(str(tmp / "c1"), str(moved / "c1"))
        res4 = batch.run_batch(cases[1:], moved, jobs=1, binary=exe, log=lambda m: None)
        check(bool(res4[0].get("skipped")), "batch: moved folder still finished")
        # a failing run is recorded with its exit code, not raised
        bad = batch.Case("bad", base, {**small, "run.cfl": -1.0})
        res5 = batch.run_batch([bad], tmp, jobs=1, binary=exe, log=lambda m: None)
        check(res5[0]["exit_code"] == 2, f"batch: bad input exit 2 ({res5[0]['exit_code']})")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def test_crush_metrics() -> None:
    """Crush metrics of a made-up history: a constant force F0 while the quarter model's platen
    advances at a constant speed (delta = twice the advance). The absorbed energy at
    delta/D = 0.5 is then F0 D / 2 exactly, the window mean is F0, and a curve compared with
    itself has no error."""
    from tools import study
    from plots.mpmplot import scene
    inputs = namelist.read_namelist(ROOT / "namelists" / "crush.nml")
    D = scene.ring_properties(inputs)["D"]
    tmp = Path(tempfile.mkdtemp(prefix="test_study_crush_"))
    try:
        n, f0 = 397, 3.0e4                      # rows deliberately not aligned with 0.5 D
        t = np.linspace(0.0, 1.0e-3, n)
        adv = 0.6 * D / 2 * t / t[-1]           # delta from 0 to 0.6 D
        cols = {"time": t, "wall1_disp": -adv, "wall1_force": np.full(n, f0),
                "wall2_disp": np.zeros(n), "wall2_force": np.zeros(n),
                "wall3_disp": np.zeros(n), "wall3_force": np.zeros(n)}
        with open(tmp / "history.csv", "w") as fh:
            fh.write(",".join(cols) + "\n")
            for i in range(n):
                fh.write(",".join(f"{cols[k][i]:.17g}" for k in cols) + "\n")
        m = study.crush_metrics(tmp, inputs)
        check(close(m["energy_50"], f0 * 0.5 * D, 1e-9),
              f"energy at delta/D = 0.5: {m['energy_50']} vs F0 D/2 = {f0 * 0.5 * D}")
        check(close(m["force_mean"], f0, 1e-12), f"window mean {m['force_mean']} vs {f0}")
        e = study.errors("crush", m, m)
        check(e["err_F_L2"] == 0.0 and e["err_energy_50"] == 0.0, f"self-error {e}")
        check(abs(e["noise"]) < 1e-12, f"noise of a constant force {e['noise']}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def test_check_advice() -> None:
    """`tubempm --check` prints the study's advice from the compiled table: the nearest run to
    namelists/crush.nml (h = t/4, n_thick 8, CPDI2, cfl 0.2) is that very run of the study, with
    the error of docs/study/study_full.csv, and the cheapest runs are those of
    docs/study/advice_full.csv."""
    import csv
    import re
    import subprocess
    exe = Path(os.environ.get("TUBEMPM", ROOT / "build" / "debug" / "tubempm"))
    table = ROOT / "docs" / "study" / "study_full.csv"
    adv_file = ROOT / "docs" / "study" / "advice_full.csv"
    if not check(exe.is_file() and table.is_file() and adv_file.is_file(),
                 "binary, study table and advice table present"):
        return
    out = subprocess.run([str(exe), "--check", "--quiet", str(ROOT / "namelists" / "crush.nml")],
                         capture_output=True, text=True).stdout
    m = re.search(r"nearest study run: h/t ([\d.]+), n_thick (\d+), aspect ([\d.]+), (\w+), "
                  r"cfl ([\d.]+): error +([\d.]+) %", out)
    if not check(m is not None, f"--check prints the nearest study run:\n{out}"):
        return
    hot, nt, asp, basis, cfl, err = (float(m[1]), int(m[2]), float(m[3]), m[4], float(m[5]),
                                     float(m[6]))
    check(math.isclose(hot, 0.25) and nt == 8 and math.isclose(asp, 1.0) and basis == "cpdi2"
          and math.isclose(cfl, 0.2), f"nearest run is the input's own settings: {m[0]}")
    rows = [r for r in csv.DictReader(open(table)) if r["scene"] == "crush"
            and r["basis"] == "cpdi2" and math.isclose(float(r["h_over_t"]), 0.25)
            and int(r["n_t"]) == 8 and math.isclose(float(r["aspect"]), 1.0)
            and math.isclose(float(r["cfl"]), 0.2)
            and (r.get("volumetric") or "standard") == "standard"]
    if check(len(rows) == 1 and rows[0]["error"] != "", "the run is in the table"):
        check(abs(err - 100 * float(rows[0]["error"])) < 0.006,
              f"error {err} % vs table {100 * float(rows[0]['error'])} %")
    # an input at the reference's settings is not told "error 0 %": references are not in the
    # compiled table (their error was never measured)
    ref_text = namelist.set_values((ROOT / "namelists" / "crush.nml").read_text(),
                                   {"grid.h": 1.48e-3 / 8, "body.n_thick": 16})
    with tempfile.NamedTemporaryFile("w", suffix=".nml", delete=False) as fh:
        fh.write(ref_text)
    try:
        out_ref = subprocess.run([str(exe), "--check", "--quiet", fh.name],
                                 capture_output=True, text=True).stdout
    finally:
        os.unlink(fh.name)
    m2 = re.search(r"nearest study run: .*error +([\d.]+) %", out_ref)
    check(m2 is not None and float(m2[1]) > 0.0,
          f"reference settings: nearest run has a measured error: {m2[0] if m2 else out_ref}")
    for a in csv.DictReader(open(adv_file)):
        if a["scene"] != "crush":
            continue
        target = f"error <= {100 * float(a['target']):4.1f} %"
        line = next((ln for ln in out.splitlines() if target in ln), "")
        if a["name"].startswith("none"):
            check("none in the study" in line, f"advice line for {target}: {line!r}")
        else:
            cpu = re.search(r"([\d.]+) CPU s", line)
            # (a run at cfl = 0 is compiled in, and advised, at the cfl it used: cfl_used)
            cfl = float(a.get("cfl_used") or a["cfl"])
            check(f"n_thick {int(float(a['n_t']))}," in line
                  and f"cfl {cfl:.2f}" in line and a["basis"] in line
                  and cpu is not None and close(float(cpu[1]), float(a["cpu_s"]), 5e-3),
                  f"advice line for {target} names the run's settings: {line!r}")


def test_volumetric_factor() -> None:
    """The anti-locking factor: 'fbar' runs carry the override and a name of their own, the
    standard runs keep their names and inputs (the committed runs stay valid), and every fbar run
    of a level has its standard twin."""
    from tools import batch
    from tools import study
    p_std = study.Point("crush", h_over_t=0.25, n_t=4)
    p_fb = study.Point("crush", h_over_t=0.25, n_t=4, volumetric="fbar")
    check(p_std.name == "crush_cpdi2_musl_h1_4_nt4_a1_cfl0.2", "volumetric: standard name kept")
    check(p_fb.name == p_std.name + "_fbar", "volumetric: fbar name")
    check("solver.volumetric" not in p_std.case().overrides,
          "volumetric: no override for standard (input hashes of earlier runs unchanged)")
    text = namelist.set_values(p_fb.case().base.read_text(), p_fb.case().overrides)
    nml = namelist.parse_namelist(text, "fbar")
    check(nml["solver"][0].get("volumetric") == "fbar", "volumetric: fbar in the namelist")
    check(p_fb.labels()["volumetric"] == "fbar" and "volumetric" in study.COLUMNS,
          "volumetric: label and table column")
    for level in ("quick", "full"):
        pts = study.design(level)
        for scene, runs in pts.items():
            names = {p.name for p in runs}
            fb = [p for p in runs if p.volumetric == "fbar" and p.h_scale == 1.0]
            check(len(fb) >= (1 if scene == "crush_fixed" else 2),
                  f"volumetric: {level} {scene} has fbar runs")
            twins = all(p.name[:-len("_fbar")] in names for p in fb)
            check(twins, f"volumetric: {level} {scene}: every fbar run has its standard twin")
            ppc = sorted({p.n_t * p.h_over_t for p in fb})
            # (the fixed-platen crush is run at one particle per cell only; the full crush
            # at half a particle per cell too)
            want = {1.0} if scene == "crush_fixed" else {1.0, 2.0}
            check(want <= set(ppc) <= want | {0.5},
                  f"volumetric: {level} {scene}: particles per cell {ppc}")


def test_crush_against_fe() -> None:
    """Crush errors against the finite element curve: a run whose F(delta) is the FE curve times
    (1 + eps) has an L2 error, smoothed error and energy error of eps and a mean force of
    (1 + eps) times FE's (all linear in F), whatever the self-reference says; the self-referenced
    error is the second column. The FE curve's own mean force is the one docs/fe_reference's
    convergence table gives for the finest mesh."""
    from tools import study
    from plots.mpmplot import scene
    fe = study.fe_metrics()
    if not check(fe is not None and "F_window" in fe, "FE curve read and over the window"):
        return
    conv = json.loads((ROOT / "docs" / "fe_reference" / "convergence.json").read_text())
    finest = next((m for m in conv["meshes"] if m["mesh"] == conv["reference"]), {})
    check(close(fe["force_mean"], float(finest.get("force_mean_N", math.nan)), 1e-4),
          f"FE mean force {fe['force_mean']:.1f} N/m vs convergence.json's "
          f"{finest.get('force_mean_N')}")
    a = np.loadtxt(study.FE_CURVE, delimiter=",", skiprows=1, ndmin=2)
    r = scene.ring_properties(namelist.read_namelist(study.SCENES["crush"]["base"]))
    eps = 0.037
    m = study.crush_curve_metrics(a[:, 0], (1.0 + eps) * a[:, 2], r)
    ref = study.crush_curve_metrics(a[:, 0], (1.0 - eps) * a[:, 2], r)
    e = study.errors("crush", m, ref, fe)
    check(close(e["error"], eps, 1e-9) and close(e["err_F_L2"], eps, 1e-9),
          f"L2 error against FE {e['error']} vs eps = {eps}")
    check(close(e["err_F_smooth"], eps, 1e-9) and close(e["err_energy_50"], eps, 1e-9),
          f"smoothed and energy errors against FE {e['err_F_smooth']}, {e['err_energy_50']}")
    check(close(e["force_over_fe"], 1.0 + eps, 1e-12), f"mean over FE {e['force_over_fe']}")
    want_self = 2.0 * eps / (1.0 - eps)
    check(close(e["err_self"], want_self, 1e-9),
          f"err_self against the finest run {e['err_self']} vs {want_self}")
    e2 = study.errors("crush", m, None, fe)
    check(close(e2["error"], eps, 1e-9) and math.isnan(e2["err_self"]),
          "no finest run: FE error kept, err_self NaN")


def test_quasi_static_design() -> None:
    """The study's crush: its platens reach delta/D >= 0.5 (the window's end) by t_end even
    if the ramp gave no travel at all (a lower bound), it approaches more slowly than the
    shipped scene, every crush run is at the crush's centre cfl except the cfl sweep and issue
    17's points (h = t/4, n_t = 8, aspect 2 at cfl 1.2, 1.6 and automatic), and
    plots/plot_study.py knows the same centre cfl per scene."""
    from tools import batch
    from plots import plot_study
    from tools import study
    from plots.mpmplot import scene
    pts = study.design("full")["crush"]
    case = pts[0].case()
    nml = namelist.parse_namelist(namelist.set_values(case.base.read_text(), case.overrides),
                                  "crush")
    inputs = namelist.read_namelist(case.base)
    D = scene.ring_properties(inputs)["D"]
    w = nml["wall"][0]
    v = abs(float(w["velocity"][1]))
    travel_min = 2.0 * v * (float(nml["run"][0]["t_end"]) - float(w["ramp"]))
    check(travel_min / D >= study.CRUSH_WINDOW[1],
          f"crush reaches delta/D {travel_min / D:.3f} >= {study.CRUSH_WINDOW[1]}")
    v_scene = abs(float(inputs["wall"][0]["velocity"][1]))
    check(v < v_scene and close(2.0 * v, study.CRUSH_APPROACH, 1e-12),
          f"quasi-static approach {2 * v} m/s, below the scene's {2 * v_scene} m/s")
    off = [p.name for p in pts if not close(p.cfl, study.CENTRE_CFL["crush"], 1e-12)]
    check(sorted(off) == sorted(p.name for p in pts if p.h_over_t == 0.25 and p.n_t == 8
                                and ((p.aspect == 1.0 and p.cfl in (0.2, 0.4))
                                     or (p.aspect == 2.0 and p.cfl in (1.2, 1.6, 0.0)))),
          f"crush runs off the centre cfl are the cfl sweep and issue 17's: {off}")
    check(plot_study.CENTRE_CFL == study.CENTRE_CFL, "plot_study and study: same centre cfl")


def test_automatic_cfl() -> None:
    """The study's runs at the automatic cfl (cfl = 0): tools/study.py's cfl_used, which the
    table, the cost estimate and --check's compiled advice use, is the cfl that tubempm
    reports for the run's input (`--check`: "cfl: X, automatic"), an independent computation
    (src/method/mpm_time_step.f90 from src/method/mpm_time_step_table.inc); and at one particle
    per cell (the 1-per-cell limits) as well as at two."""
    import re
    import subprocess
    from tools import batch
    from tools import study
    exe = Path(os.environ.get("TUBEMPM", ROOT / "build" / "debug" / "tubempm"))
    if not check(exe.is_file(), f"binary {exe} present"):
        return
    pts = [p for pts in study.design("full").values() for p in pts
           if p.cfl == 0.0 and p.h_scale == 1.0]
    check(sorted(p.scene for p in pts) == ["crush", "impact"],
          f"full design: one crush and one impact run at cfl = 0 ({[p.name for p in pts]})")
    # and the same setting at one particle per cell through the wall (another stability table)
    pts.append(study.Point("impact", h_over_t=0.25, n_t=4, cfl=0.0))
    with tempfile.TemporaryDirectory(prefix="test_study_cfl") as tmp:
        for p in pts:
            case = p.case()
            path = Path(tmp) / f"{p.name}.nml"
            path.write_text(namelist.set_values(case.base.read_text(), case.overrides))
            out = subprocess.run([str(exe), "--check", "--quiet", str(path)],
                                 capture_output=True, text=True).stdout
            m = re.search(r"cfl: ([\d.]+), automatic \(cfl = 0\)", out)
            if check(m is not None, f"{p.name}: --check reports the automatic cfl:\n{out}"):
                check(close(float(m[1]), p.cfl_used, 1e-6),
                      f"{p.name}: cfl_used {p.cfl_used} vs tubempm's {m[1]}")
            check(p.cfl_used > 0.0 and close(p.steps() * p.cfl_used,
                                             study.Point(p.scene, h_over_t=p.h_over_t,
                                                         n_t=p.n_t, cfl=1.0).steps(), 1e-12),
                  f"{p.name}: its step estimate uses cfl_used")


def test_mass_scaling_is_time_scaling() -> None:
    """Why the study slows its crush instead of scaling the mass (docs/validation.md, "A
    quasi-static crush"): for a rate-independent material, mass_scale m with the platen at
    v / sqrt(m), the ramp, the record and the history interval times sqrt(m) is the same model in
    the time t sqrt(m). With m = 4 (sqrt(m) = 2: every scaling exact in binary) a short crush
    gives the same platen force at every history row, to round-off, at twice the time."""
    from tools import batch
    from plots.mpmplot import readers
    exe = Path(os.environ.get("TUBEMPM", ROOT / "build" / "debug" / "tubempm"))
    if not check(exe.is_file(), f"binary {exe} missing"):
        return
    tmp = Path(tempfile.mkdtemp(prefix="test_study_mass_"))
    try:
        base = ROOT / "namelists" / "crush.nml"
        common = {"grid.h": 0.74e-3, "body.n_thick": 4, "run.threads": 1, "run.cfl": 0.8}
        cases = []
        for name, k, ms in (("plain", 1.0, 1.0), ("scaled", 2.0, 4.0)):
            cases.append(batch.Case(name, base, {**common, "solver.mass_scale": ms,
                                                 "run.t_end": 4.0e-4 * k,
                                                 "run.history_every": 1.0e-5 * k,
                                                 "run.snapshot_every": 4.0e-4 * k,
                                                 "wall.velocity": (0.0, -5.0 / k),
                                                 "wall.ramp": 2.0e-4 * k}))
        res = batch.run_batch(cases, tmp, jobs=2, binary=exe, log=lambda m: None)
        if not check(all(r["exit_code"] == 0 for r in res), f"mass scaling: both run {res}"):
            return
        a = readers.read_history(tmp / "plain" / "history.csv")
        b = readers.read_history(tmp / "scaled" / "history.csv")
        n = min(len(a["time"]), len(b["time"]))
        check(n > 30 and len(a["time"]) == len(b["time"]), f"mass scaling: rows {n}")
        check(np.allclose(b["time"][:n], 2.0 * a["time"][:n], rtol=1e-12, atol=1e-15),
              "mass scaling: the scaled run's rows at twice the time")
        fa, fb = a["wall1_force"][:n], b["wall1_force"][:n]
        err = float(np.max(np.abs(fb - fa)) / np.max(np.abs(fa)))
        check(np.max(np.abs(fa)) > 1.0e3 and err < 1.0e-9,
              f"mass scaling: same platen force row by row (largest difference {err:.2e} of "
              f"the peak {np.max(np.abs(fa)):.3g} N)")
        da, db = a["wall1_disp"][:n], b["wall1_disp"][:n]
        check(np.allclose(db, da, rtol=1e-9, atol=1e-15), "mass scaling: same platen travel")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main() -> int:
    for t in (test_render, test_richardson, test_pareto_advice, test_batch_runs,
              test_crush_metrics, test_check_advice, test_volumetric_factor,
              test_crush_against_fe, test_quasi_static_design, test_automatic_cfl,
              test_mass_scaling_is_time_scaling):
        try:
            t()
        except Exception:                      # a crash is a failure, with its traceback
            traceback.print_exc()
            check(False, f"{t.__name__} raised")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
