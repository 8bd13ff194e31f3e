#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The checks of `make test-slurm`, run by tests/slurm/run.sh once its one-node cluster is up
(SLURM_CONF set): the Slurm backend of tools/batch.py against the local one, through
tools/sweep.py.

1. A small sweep (impact scene, D/t 10 and 25 x speed 10 and 30 m/s, a few seconds a run) runs
   locally and as one Slurm job array; every run's history.csv and summary.nml numbers must be
   equal to round-off (rtol 1e-12: both run one thread, so they are in fact bit-identical),
   and so must the two sweep.csv tables but for the times.
2. A second sweep of three short runs and a long one is submitted without waiting; submitting
   it again while it runs must submit nothing. The long run's array task is cancelled
   (scancel) while it runs: it must leave no result.json while the short ones finish. Running
   the sweep again must submit an array of that one run only, leave the other runs' results
   untouched, and complete it.

The last line is `check_slurm: N passed, M failed` (exit 1 if M > 0).

    tests/slurm/run.sh          (make test-slurm; starts the cluster, then this)
"""
from __future__ import annotations

import argparse
import csv
import json
import subprocess
import sys
import time
from pathlib import Path

from tests.pycheck import Checks, close
from plots.mpmplot import readers

ROOT = Path(__file__).resolve().parent.parent.parent

T = Checks("check_slurm")
check = T.check
BASE = ROOT / "namelists" / "impact.nml"
#: the small sweep: history every 2 us, one snapshot, n_thick 4, 0.15 ms (contact starts after
#: 17 us at 30 m/s)
COMMON = ["--set", "run.t_end=1.5e-4", "--set", "run.history_every=2.0e-6",
          "--set", "run.snapshot_every=1.5e-4", "--set", "body.n_thick=4"]
SWEEP = COMMON + ["--vary", "ring.D_over_t=10,25", "--vary", "ring.speed=10,30"]
RTOL = 1.0e-12


def sweep(args: list[str], out: Path, binary: Path) -> subprocess.CompletedProcess:
    cmd = [sys.executable, "-m", "tools.sweep", str(BASE), "--out", str(out),
           "--binary", str(binary)] + args
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
    print(f"$ tools/sweep.py ... {' '.join(args[-6:])}   ({time.monotonic() - t0:.1f} s)")
    print("  " + (p.stdout + p.stderr).strip().replace("\n", "\n  "))
    return p


def numbers_equal(a: dict, b: dict, what: str) -> bool:
    """Every numeric entry of a equal to b's to RTOL (and the same keys)."""
    if set(a) != set(b):
        return check(False, f"{what}: different entries {sorted(set(a) ^ set(b))}")
    bad = []
    for k in a:
        x, y = a[k], b[k]
        if hasattr(x, "shape"):
            same = x.shape == y.shape and all(close(float(u), float(v), RTOL, 1e-300)
                                               for u, v in zip(x, y))
        elif isinstance(x, float) and isinstance(y, float):
            same = close(x, y, RTOL, 1e-300)
        else:
            same = x == y
        if not same:
            bad.append(k)
    return check(not bad, f"{what}: equal to rtol {RTOL:g}" + (f"; differ: {bad}" if bad else ""))


def squeue() -> dict[str, str]:
    p = subprocess.run(["squeue", "--noheader", "--array", "--format=%i %T"],
                       capture_output=True, text=True)
    return dict(ln.split() for ln in p.stdout.splitlines() if len(ln.split()) == 2)


def part_compare(scratch: Path, binary: Path) -> None:
    local, slurm = scratch / "local", scratch / "slurm"
    p1 = sweep(SWEEP + ["--jobs", "2"], local, binary)
    p2 = sweep(SWEEP + ["--backend", "slurm", "--poll", "1", "--time", "10",
                        "--partition", "test"], slurm, binary)
    if not check(p1.returncode == 0 and p2.returncode == 0, "both sweeps exit 0"):
        return
    check("submitted job array" in p2.stdout, "the Slurm sweep submitted a job array")
    runs = sorted(d.name for d in local.iterdir() if (d / "case.nml").is_file())
    check(len(runs) == 4, f"4 runs: {runs}")
    for name in runs:
        a, b = local / name, slurm / name
        ra, rb = json.loads((a / "result.json").read_text()), \
            json.loads((b / "result.json").read_text())
        check(ra["exit_code"] == 0 and rb["exit_code"] == 0, f"{name}: both exit 0")
        check(ra["input_hash"] == rb["input_hash"], f"{name}: same input")
        check(rb.get("backend") == "slurm" and rb.get("slurm_task", "").count("_") == 1,
              f"{name}: result.json names its array task ({rb.get('slurm_task')})")
        check("backend" not in ra, f"{name}: the local result.json as before")
        numbers_equal(readers.read_history(a / "history.csv"),
                      readers.read_history(b / "history.csv"), f"{name}: history.csv")
        sa, sb = readers.read_summary(a / "summary.nml"), readers.read_summary(b / "summary.nml")
        for s in (sa, sb):                          # times differ from run to run
            for k in ("wall_seconds", "runtime_ratio", "updates_per_second"):
                s.pop(k, None)
        numbers_equal(sa, sb, f"{name}: summary.nml")
        check(sa.get("status") == "completed", f"{name}: completed")
        task = rb.get("slurm_task", "x_x")
        out = slurm / "slurm" / f"{task}.out"
        check(out.is_file() and f"{name}: exit 0" in out.read_text(),
              f"{name}: Slurm's output of task {task} names the run")
    ta = list(csv.DictReader(open(local / "sweep.csv")))
    tb = list(csv.DictReader(open(slurm / "sweep.csv")))
    same = len(ta) == len(tb) == 4 and all(
        ra.keys() == rb.keys() and all(
            ra[k] == rb[k] or (k in ("cpu_s", "wall_s")) or
            close(float(ra[k]), float(rb[k]), 1e-9, 1e-300) for k in ra)
        for ra, rb in zip(ta, tb))
    check(same, "sweep.csv of both backends equal but for the times")
    plastic = {r["name"]: float(r["plastic_end"]) for r in tb}
    check(all(v > 0 for v in plastic.values()) and
          plastic["D_over_t10_speed30"] > plastic["D_over_t10_speed10"],
          f"plastic_end positive, larger at 30 m/s: {plastic}")


def part_cancel(scratch: Path, binary: Path) -> None:
    out = scratch / "cancel"
    table = scratch / "cancel.csv"
    # three short runs and a long one (about 10 s on one core)
    table.write_text("name,ring.speed,run.t_end\nshort1,10,4e-5\nshort2,20,4e-5\n"
                     "short3,30,4e-5\nlong,30,3e-4\n")
    args = ["--set", "body.n_thick=4", "--set", "run.history_every=2.0e-6",
            "--table", str(table), "--backend", "slurm", "--poll", "1"]
    p = sweep(args + ["--no-wait"], out, binary)
    check(p.returncode == 0 and "submitted job array" in p.stdout, "submitted without waiting")
    p = sweep(args + ["--no-wait"], out, binary)
    tasks = sorted((out / "slurm").glob("*.tasks"))
    check(p.returncode == 0 and "submitted" not in p.stdout and "queued or running" in p.stdout
          and len(tasks) == 1,
          f"submitted again while queued: nothing new ({len(tasks)} task lists)")
    long_task = json.loads((out / "long" / "slurm.json").read_text())["task_id"]
    deadline = time.monotonic() + 180
    while time.monotonic() < deadline:              # the long run under way, the others done
        if squeue().get(long_task) == "RUNNING" and (out / "long" / "run.log").is_file() and \
                all((out / f"short{i}" / "result.json").is_file() for i in (1, 2, 3)):
            break
        time.sleep(0.3)
    time.sleep(1.0)
    if not check(squeue().get(long_task) == "RUNNING", f"task {long_task} is running"):
        return
    subprocess.run(["scancel", long_task], check=False)
    print(f"$ scancel {long_task}")
    while long_task in squeue() and time.monotonic() < deadline:
        time.sleep(0.3)
    check(long_task not in squeue(), f"task {long_task} cancelled")
    check(not (out / "long" / "result.json").exists(), "the cancelled run has no result.json")
    slurm_out = out / "slurm" / f"{long_task}.out"
    text = slurm_out.read_text() if slurm_out.is_file() else ""
    check("CANCELLED" in text and "stopped by a signal" in text,
          f"Slurm's output of the cancelled task says so: {text.strip()!r}")
    before = {i: (out / f"short{i}" / "result.json").read_text() for i in (1, 2, 3)}
    p = sweep(args, out, binary)
    tasks = sorted((out / "slurm").glob("*.tasks"), key=lambda f: f.stat().st_mtime)
    check(p.returncode == 0 and "submitted job array" in p.stdout and ": 1 run (" in p.stdout,
          "submitted again: one run")
    newest = tasks[-1].read_text().split() if tasks else []
    check(len(tasks) == 2 and newest == [str((out / "long").resolve())],
          f"the new job array holds only the cancelled run: {newest}")
    check(all((out / f"short{i}" / "result.json").read_text() == before[i] for i in (1, 2, 3)),
          "the finished runs were not run again (result.json unchanged)")
    res = json.loads((out / "long" / "result.json").read_text()) \
        if (out / "long" / "result.json").is_file() else {}
    check(res.get("exit_code") == 0 and res.get("slurm_task", "").split("_")[0]
          != long_task.split("_")[0], f"the long run completed in the new array: {res}")
    rows = list(csv.DictReader(open(out / "sweep.csv")))
    check(len(rows) == 4 and all(r["status"] == "completed" for r in rows),
          "sweep.csv: four completed runs")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--binary", type=Path, default=ROOT / "bin" / "tubempm")
    ap.add_argument("--scratch", type=Path, required=True)
    args = ap.parse_args()
    t0 = time.monotonic()
    for part in (part_compare, part_cancel):
        try:
            part(args.scratch, args.binary.resolve())
        except Exception as e:                      # a crash is a failure
            import traceback
            traceback.print_exc()
            check(False, f"{part.__name__} raised {e!r}")
    print(f"checks took {time.monotonic() - t0:.0f} s")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
