#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""tools/sweep.py and plots/plot_sweep.py without running tubempm: the expansion of --set,
--vary and --table into runs, the ring's design variables checked against their definitions
(D/t = (r_o + r_i) / (r_o - r_i) with r_o kept, h/t kept, |v| = speed along the base's
direction) on the namelist text the runs would get, the refusals, and sweep.csv and the chart
from run folders written by hand (end, minimum and maximum of a known history).

The last line is `test_sweep: N passed, M failed` (exit 1 if M > 0).

    python3 -m tests.test_sweep
"""
from __future__ import annotations

import csv
import json
import math
import shutil
import subprocess
import sys
import tempfile
import traceback
from pathlib import Path

from tests.pycheck import Checks, close
from tools import batch
from tools import sweep
from plots.mpmplot import namelist

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_sweep")
check = T.check
IMPACT = ROOT / "namelists" / "impact.nml"
CRUSH = ROOT / "namelists" / "crush.nml"


def rendered(case: batch.Case) -> dict:
    """The groups of the namelist the run gets."""
    return namelist.parse_namelist(batch.case_text(case, Path("/x") / case.name), case.name)


def test_values() -> None:
    pv = sweep.parse_value
    check(pv("0 -30") == [0, -30], "a vector of words")
    check(pv("1.5d-3") == 1.5e-3 and pv("2") == 2 and isinstance(pv("2"), int), "numbers")
    check(pv(".true.") is True and pv("false") is False, "logicals")
    check(pv("cpdi1") == "cpdi1" and pv("'usl'") == "usl", "text")


def test_product() -> None:
    base = namelist.read_namelist(IMPACT)
    b0 = base["body"][0]
    r_o, r_i, h0 = b0["r_outer"], b0["r_inner"], base["grid"][0]["h"]
    q_list, s_list = (10, 15.5, 25), (10, 30)
    cases = sweep.expand(IMPACT, ["run.t_end=2e-4"], [
        "ring.D_over_t=" + ",".join(str(q) for q in q_list),
        "ring.speed=" + ",".join(str(s) for s in s_list)])
    check(len(cases) == len(q_list) * len(s_list), f"product: {len(cases)} runs")
    check(len({c.name for c in cases}) == len(cases), "names unique")
    check(cases[0].name == "D_over_t10_speed10" and cases[3].name == "D_over_t15p5_speed30",
          f"names from the values: {[c.name for c in cases]}")
    for c in cases:
        g = rendered(c)
        b = g["body"][0]
        q, s = c.labels["ring.D_over_t"], c.labels["ring.speed"]
        check(close(b["r_outer"], r_o, 1e-15), f"{c.name}: outer radius kept")
        check(close((b["r_outer"] + b["r_inner"]) / (b["r_outer"] - b["r_inner"]), q, 1e-9),
              f"{c.name}: D/t of the radii = {q}")
        check(close(g["grid"][0]["h"] / (b["r_outer"] - b["r_inner"]), h0 / (r_o - r_i), 1e-9),
              f"{c.name}: h/t kept")
        v = b["velocity"]
        check(close(math.hypot(*v), s, 1e-12) and v[0] == 0.0 and v[1] < 0.0,
              f"{c.name}: velocity {v}: speed {s} towards the target")
        check(close(g["run"][0]["t_end"], 2e-4, 1e-15), f"{c.name}: --set t_end")
        check(g["run"][0]["title"] == c.name and g["run"][0]["output_dir"] == f"/x/{c.name}",
              f"{c.name}: title and folder")
        check(g["material"] == base["material"] and g["wall"] == base["wall"],
              f"{c.name}: other groups unchanged")
    # ring.t, and an explicit grid.h wins over the kept h/t
    c = sweep.expand(IMPACT, ["grid.h=0.4e-3"], ["ring.t=1e-3"])[0]
    b = rendered(c)["body"][0]
    check(close(b["r_outer"] - b["r_inner"], 1e-3, 1e-9) and
          close(rendered(c)["grid"][0]["h"], 0.4e-3, 1e-15), "ring.t with grid.h given")
    # the base's D/t gives the base's input back
    c = sweep.expand(IMPACT, [], ["ring.D_over_t=25"])[0]
    g = rendered(c)
    check(close(g["body"][0]["r_inner"], r_i, 1e-12) and close(g["grid"][0]["h"], h0, 1e-12),
          "the base's own D/t changes nothing")
    # plain keys with vectors, and a k-th group instance
    cases = sweep.expand(CRUSH, [], ["wall[1].velocity=0 -2,0 -8", "solver.basis=cpdi1,cpdi2"])
    g = rendered(cases[1])
    check(len(cases) == 4 and g["wall"][0]["velocity"] == [0, -2] and
          g["solver"][0]["basis"] == "cpdi2", f"vectors and text: {cases[1].name}")


def test_table(tmp: Path) -> None:
    table = tmp / "rows.csv"
    table.write_text("name,note,ring.speed,solver.basis\nslow,a,5,cpdi1\nfast,b,40,cpdi2\n")
    rows = sweep.read_table(table)
    # a name column and a --vary give duplicate names: refused
    try:
        sweep.expand(IMPACT, [], ["run.cfl=0.1,0.2"], rows)
        dup = False
    except sweep.SweepError as e:
        dup = "same name" in str(e)
    check(dup, "named rows times --vary: duplicate names refused")
    cases = sweep.expand(IMPACT, [], [], rows)
    check([c.name for c in cases] == ["slow", "fast"], "a name column names the runs")
    check(cases[0].labels == {"note": "a", "ring.speed": 5, "solver.basis": "cpdi1"},
          f"labels: the keys and the label column {cases[0].labels}")
    g = rendered(cases[1])
    check(g["body"][0]["velocity"] == [0.0, -40.0] and g["solver"][0]["basis"] == "cpdi2",
          "table row applied")
    unnamed = tmp / "unnamed.csv"
    unnamed.write_text("ring.speed\n5\n40\n")
    cases = sweep.expand(IMPACT, [], ["run.cfl=0.1,0.2"], sweep.read_table(unnamed))
    names = [c.name for c in cases]
    check(names == ["speed5_cfl0p1", "speed5_cfl0p2", "speed40_cfl0p1", "speed40_cfl0p2"],
          f"rows x --vary: {names}")


def refused(fn, *args, words: str = "") -> bool:
    try:
        fn(*args)
    except (sweep.SweepError, ValueError) as e:
        return words.lower() in str(e).lower()
    return False


def test_refusals(tmp: Path) -> None:
    ex = sweep.expand
    check(refused(ex, IMPACT, [], ["grid h=1"], None, words="expected group.var"), "bad key")
    check(refused(ex, IMPACT, [], ["ring.D_over_t=1"], None, words="larger than 1"), "D/t <= 1")
    check(refused(ex, IMPACT, ["ring.t=1e-3"], ["ring.D_over_t=10"], None, words="give one"),
          "ring.t and ring.D_over_t")
    check(refused(ex, IMPACT, ["ring.t=0.03"], [], None, words="between 0"), "t > r_outer")
    check(refused(ex, CRUSH, [], ["ring.speed=5"], None, words="velocity"),
          "ring.speed on a body at rest")
    check(refused(ex, IMPACT, [], ["body[2].n_thick=4"], None, words="&body[2]"),
          "a group instance not in the base")
    check(refused(ex, IMPACT, [], ["run.cfl="], None, words="no values"), "empty --vary")
    bad = tmp / "bad.csv"
    bad.write_text("ring.speed\n5\n5\n")
    check(refused(ex, IMPACT, [], [], sweep.read_table(bad), words="same name"),
          "a repeated row")
    bad.write_text("ring.speed,run.cfl\n5,\n")
    check(refused(ex, IMPACT, [], [], sweep.read_table(bad), words="empty"), "an empty cell")
    p = subprocess.run([sys.executable, "-m", "tools.sweep", str(IMPACT), "--out",
                        str(tmp / "x"), "--vary", "ring.D_over_t=0.5"], capture_output=True,
                       text=True, cwd=ROOT)
    check(p.returncode == 2 and p.stderr.startswith("ERROR [sweep]: ") and
          not (tmp / "x").exists(), f"the command line: exit 2, one ERROR line: {p.stderr!r}")
    p = subprocess.run([sys.executable, "-m", "tools.sweep", str(IMPACT), "--out",
                        str(tmp / "x"), "--vary", "ring.speed=1,2,3", "--list"],
                       capture_output=True, text=True, cwd=ROOT)
    check(p.returncode == 0 and p.stdout.strip().endswith("3 runs") and
          "body[1].velocity = 0.0, -2.0" in p.stdout, f"--list: {p.stdout!r}")


def test_collect_and_plot(tmp: Path) -> None:
    """sweep.csv from hand-written run folders: plastic = t^2 rises to its last value, so
    plastic_end = plastic_max = t_end^2, plastic_min = 0; a failed run has no numbers; the
    chart leaves it out."""
    root = tmp / "sw"
    cases = sweep.expand(IMPACT, [], ["ring.speed=10,20,30"])
    for k, c in enumerate(cases):
        folder = root / c.name
        folder.mkdir(parents=True)
        code = 0 if k < 2 else 4
        (folder / "result.json").write_text(json.dumps(
            {"name": c.name, "exit_code": code, "wall_s": 2.0, "cpu_s": 1.5,
             "input_hash": batch.input_hash(c), "labels": c.labels}))
        (folder / "summary.nml").write_text(
            "&summary\n status = '%s',\n steps = 10,\n particles = 7,\n energy_error = 0.01\n/\n"
            % ("completed" if code == 0 else "unstable"))
        t = [0.1 * i for i in range(11)]
        s = c.labels["ring.speed"]
        with open(folder / "history.csv", "w") as fh:
            fh.write("time,wall1_force,plastic,probe1_x\n")
            for x in t:
                fh.write(f"{x},{s * (x - 0.5)},{s * x * x},{x}\n")
    path = sweep.collect(cases, root)
    rows = list(csv.DictReader(open(path)))
    check(len(rows) == 3 and rows[0]["ring.speed"] == "10", "one row per run, keys as columns")
    r = rows[1]
    check(close(float(r["plastic_end"]), 20.0, 1e-9) and close(float(r["plastic_max"]), 20.0,
                                                                1e-9)
          and float(r["plastic_min"]) == 0.0, f"plastic end/max/min {r}")
    check(close(float(r["wall1_force_min"]), -10.0, 1e-9) and
          close(float(r["wall1_force_max"]), 10.0, 1e-9), "force min and max")
    check("probe1_x_end" not in r and r["status"] == "completed" and r["cpu_s"] == "1.5",
          "probes not summarised; status and CPU time")
    check(rows[2]["exit_code"] == "4" and rows[2]["status"] == "unstable", "a failed run's row")
    # a run whose input changed since is not counted
    (root / cases[0].name / "result.json").write_text(json.dumps(
        {"name": "x", "exit_code": 0, "wall_s": 1, "cpu_s": 1, "input_hash": "other"}))
    rows = list(csv.DictReader(open(sweep.collect(cases, root))))
    check(rows[0]["status"] == "not run" and rows[0].get("plastic_end", "") == "",
          "an older input's run is 'not run'")
    from plots import plot_sweep
    s = plot_sweep.series(rows, "ring.speed", "plastic_end", None)
    check(list(s) == [""] and s[""][0] == [20.0], f"the chart's points: completed only {s}")
    out = tmp / "chart.png"
    p = subprocess.run([sys.executable, "-m", "plots.plot_sweep", "--dir",
                        str(root), "--x", "ring.speed", "--y", "plastic_end", "--out",
                        str(out)], capture_output=True, text=True, cwd=ROOT)
    check(p.returncode == 0 and out.is_file() and out.stat().st_size > 1000 and
          "left out 2" in p.stdout, f"plot_sweep draws the chart: {p.stdout} {p.stderr}")
    p = subprocess.run([sys.executable, "-m", "plots.plot_sweep", "--dir",
                        str(root), "--x", "D_over_t"], capture_output=True, text=True,
                       cwd=ROOT)
    check(p.returncode == 2 and "no such column" in p.stderr, "an unknown column is refused")


def main() -> int:
    tmp = Path(tempfile.mkdtemp(prefix="test_sweep_"))
    try:
        for t in (test_values, test_product, test_table, test_refusals, test_collect_and_plot):
            try:
                t(tmp) if t.__code__.co_argcount else t()
            except Exception:                      # a crash is a failure, with its traceback
                traceback.print_exc()
                check(False, f"{t.__name__} raised")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
