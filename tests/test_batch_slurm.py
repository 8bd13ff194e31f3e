#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The Slurm backend of tools/batch.py without a Slurm cluster (make test-slurm runs a real
one, tests/slurm/):

- the sbatch script (``--dry-run`` of tools/sweep.py, and ``batch.sbatch_script``): every
  option in its #SBATCH line, valid bash, nothing written or submitted;
- the submission path against stand-ins for ``sbatch`` and ``squeue`` (shell scripts on PATH:
  this sbatch runs the array's tasks one after the other, as Slurm would, then prints a job id):
  the runs' history.csv equal the local backend's, finished runs are not submitted again, a
  run still queued is waited for and not submitted twice, one no longer queued is;
- an array task (``batch.py --task``) stopped by SIGTERM, as scancel does: it stops the run
  and leaves no result.json, so the run is submitted again.

The last line is `test_batch_slurm: N passed, M failed` (exit 1 if M > 0).

    TUBEMPM=build/debug/tubempm python3 -m tests.test_batch_slurm
"""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path

from tests.pycheck import Checks, close
from tools import batch
from plots.mpmplot import readers

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_batch_slurm")
check = T.check
EXE = Path(os.environ.get("TUBEMPM", ROOT / "build" / "debug" / "tubempm")).resolve()
WAVE = ROOT / "namelists" / "wave.nml"
#: 0.4 us of a 2-particle-thick ring: a fraction of a second in the debug build
SMALL = {"run.t_end": 4.0e-7, "grid.h": 2.0e-3, "body.n_thick": 2,
         "run.snapshot_every": 4.0e-7, "run.history_every": 1.0e-7, "run.threads": 1}

#: stand-in sbatch: runs every task of the array (from its #SBATCH --array line) in turn with
#: SLURM_ARRAY_TASK_ID set, output where --output says, logs its call, prints a job id
FAKE_SBATCH = r"""#!/bin/bash
script=${@: -1}
echo "$*" >> "$FAKE_LOG"
job=$(( $(wc -l < "$FAKE_LOG") + 100 ))
range=$(sed -n 's/^#SBATCH --array=\([0-9-]*\).*/\1/p' "$script")
out=$(sed -n 's/^#SBATCH --output=//p' "$script")
for i in $(seq ${range%-*} ${range#*-}); do
  o=${out//%A/$job}; o=${o//%a/$i}
  SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_JOB_ID=$job bash "$script" > "$o" 2>&1
done
echo "$job"
"""
#: stand-in squeue: prints $FAKE_QUEUE (lines "JOBID_TASK STATE")
FAKE_SQUEUE = "#!/bin/bash\nprintf '%s' \"${FAKE_QUEUE:-}\"\n"


def sweep_cli(args: list[str], env: dict | None = None) -> subprocess.CompletedProcess:
    # the binary under test (make test builds only the debug one; bin/ may not exist)
    return subprocess.run([sys.executable, "-m", "tools.sweep"] + args
                          + ["--binary", str(EXE)], capture_output=True, text=True, env=env,
                          cwd=ROOT)


def test_dry_run(tmp: Path) -> None:
    out = tmp / "dry"
    env = dict(os.environ, PATH=str(tmp / "nothing"))   # no sbatch, no squeue to be found
    p = sweep_cli([str(WAVE), "--out", str(out), "--vary", "run.cfl=0.1,0.2,0.3",
                   "--set", "run.t_end=1e-6", "--backend", "slurm", "--dry-run",
                   "--partition", "short", "--time", "0:30:00", "--account", "proj42",
                   "--threads", "2", "--max-running", "3", "--sbatch-option=--mem=1G"], env)
    text = p.stdout
    check(p.returncode == 0, f"dry run exits 0 ({p.returncode}: {p.stderr.strip()})")
    lines = text.splitlines()
    for want in ("#SBATCH --array=0-2%3", "#SBATCH --cpus-per-task=2", "#SBATCH --ntasks=1",
                 "#SBATCH --partition=short", "#SBATCH --time=0:30:00",
                 "#SBATCH --account=proj42", "#SBATCH --mem=1G", "export OMP_NUM_THREADS=2"):
        check(want in lines, f"dry run: the script has the line {want!r}")
    check(any(ln.startswith(f"#SBATCH --output={out.resolve()}/slurm/%A_%a.out")
              for ln in lines), "dry run: Slurm's output per task in <out>/slurm/")
    exe = [ln for ln in lines if ln.startswith("exec ")]
    check(f"cd {ROOT}" in lines, "dry run: the task starts in the repository root")
    check(len(exe) == 1 and f" -m tools.batch --task {out.resolve()}/slurm/"
          in exe[0] and exe[0].endswith(".tasks"), f"dry run: the task line {exe}")
    listed = [ln.split()[-1] for ln in lines if ln.startswith("#   ")]
    check(listed == [str((out / f"cfl{c}").resolve()) for c in ("0p1", "0p2", "0p3")],
          f"dry run: the three run folders listed in order: {listed}")
    script = text[text.index("#!/bin/bash"):]
    q = subprocess.run(["bash", "-n"], input=script, capture_output=True, text=True)
    check(q.returncode == 0, f"dry run: the script is valid bash ({q.stderr.strip()})")
    check(not out.exists(), "dry run: writes nothing")
    # with the cluster's defaults: no partition, time or account lines, no throttle
    s = batch.sbatch_script(Path("/x/slurm/a.tasks"), 5, 1, batch.Slurm(), "tubempm-x")
    check("#SBATCH --array=0-4" in s.splitlines() and "--partition" not in s and
          "--time" not in s and "--account" not in s, "default script: no cluster options")
    # more runs than one array may hold: several arrays, each numbered from 0
    import contextlib
    import io
    buf = io.StringIO()
    cases = [batch.Case(f"r{i}", WAVE, {"run.cfl": 0.1 + 0.01 * i}) for i in range(5)]
    with contextlib.redirect_stdout(buf):
        batch.run_batch(cases, tmp / "chunks", binary=tmp / "none",
                        backend=batch.Slurm(dry_run=True, array_max=2))
    arrays = [ln for ln in buf.getvalue().splitlines() if ln.startswith("#SBATCH --array=")]
    check(arrays == ["#SBATCH --array=0-1", "#SBATCH --array=0-1", "#SBATCH --array=0-0"],
          f"5 runs, at most 2 per array: {arrays}")
    check(not (tmp / "chunks").exists(), "dry run: no folder made")
    # the Slurm options without --backend slurm are refused (exit 2, the option named)
    p = sweep_cli([str(WAVE), "--out", str(out), "--vary", "run.cfl=0.1", "--partition", "x"])
    check(p.returncode == 2 and "--partition" in p.stderr and "--backend slurm" in p.stderr,
          f"--partition without --backend slurm refused: {p.stderr.strip()!r}")
    p = subprocess.run([sys.executable, "-m", "tools.batch", "--task", "x"],
                       capture_output=True, text=True, cwd=ROOT,
                       env={k: v for k, v in os.environ.items() if k != "SLURM_ARRAY_TASK_ID"})
    check(p.returncode == 2 and "SLURM_ARRAY_TASK_ID" in p.stderr,
          "--task outside a job array refused")


def fake_slurm(tmp: Path) -> Path:
    bindir = tmp / "fakebin"
    bindir.mkdir()
    for name, text in (("sbatch", FAKE_SBATCH), ("squeue", FAKE_SQUEUE)):
        (bindir / name).write_text(text)
        (bindir / name).chmod(0o755)
    os.environ["PATH"] = f"{bindir}:{os.environ['PATH']}"
    os.environ["FAKE_LOG"] = str(tmp / "sbatch.log")
    os.environ["FAKE_QUEUE"] = ""
    return tmp / "sbatch.log"


def calls(log: Path) -> int:
    return len(log.read_text().splitlines()) if log.is_file() else 0


def test_submit(tmp: Path) -> None:
    if not check(EXE.is_file(), f"binary {EXE}"):
        return
    log = fake_slurm(tmp)
    cases = [batch.Case(f"c{i}", WAVE, {**SMALL, "run.cfl": c}, {"cfl": c})
             for i, c in enumerate((0.2, 0.4))]
    quiet = dict(log=lambda m: None)
    loc = batch.run_batch(cases, tmp / "local", jobs=2, binary=EXE, **quiet)
    slurm = batch.Slurm(poll=0.2)
    res = batch.run_batch(cases, tmp / "slurm", binary=EXE, backend=slurm, **quiet)
    check(calls(log) == 1, f"one sbatch call for the batch ({calls(log)})")
    check(all(r["exit_code"] == 0 for r in loc + res), "both backends: runs exit 0")
    for c, r in zip(cases, res):
        check(r.get("backend") == "slurm" and r.get("slurm_task", "").endswith(
            f"_{cases.index(c)}"), f"{c.name}: result names its array task {r.get('slurm_task')}")
        check(r["labels"] == c.labels and r["input_hash"] == batch.input_hash(c),
              f"{c.name}: labels and input hash recorded as locally")
        ha = readers.read_history(tmp / "local" / c.name / "history.csv")
        hb = readers.read_history(tmp / "slurm" / c.name / "history.csv")
        same = ha.keys() == hb.keys() and all(
            len(ha[k]) == len(hb[k]) and all(close(float(x), float(y), 1e-12, 1e-300)
                                             for x, y in zip(ha[k], hb[k])) for k in ha)
        check(same, f"{c.name}: history.csv equal to the local backend's (rtol 1e-12)")
    keys_local = set(json.loads((tmp / "local" / "c0" / "result.json").read_text()))
    keys_slurm = set(json.loads((tmp / "slurm" / "c0" / "result.json").read_text()))
    check(keys_slurm - keys_local == {"backend", "slurm_task"} and keys_local <= keys_slurm,
          f"result.json: the local keys plus backend, slurm_task ({keys_slurm ^ keys_local})")
    res2 = batch.run_batch(cases, tmp / "slurm", binary=EXE, backend=slurm, **quiet)
    check(calls(log) == 1 and all(r.get("skipped") for r in res2),
          "finished runs: skipped, nothing submitted")
    # c0 queued from an earlier submission (squeue lists its task), c1 changed: only c1 goes
    (tmp / "slurm" / "c0" / "result.json").unlink()
    task0 = json.loads((tmp / "slurm" / "c0" / "slurm.json").read_text())["task_id"]
    os.environ["FAKE_QUEUE"] = f"{task0} RUNNING\n"
    cases[1] = batch.Case("c1", WAVE, {**SMALL, "run.cfl": 0.3}, {"cfl": 0.3})
    res3 = batch.run_batch(cases, tmp / "slurm", binary=EXE,
                           backend=batch.Slurm(poll=0.2, wait=False), **quiet)
    tasks = sorted((tmp / "slurm" / "slurm").glob("*.tasks"), key=lambda f: f.stat().st_mtime)
    check(calls(log) == 2 and tasks[-1].read_text().split() ==
          [str((tmp / "slurm" / "c1").resolve())], "a changed run is submitted alone")
    check(res3[0].get("queued") == task0 and res3[0]["exit_code"] is None,
          f"a queued run is not submitted again: {res3[0]}")
    check(res3[1]["exit_code"] == 0 and close(float(json.loads(
        (tmp / "slurm" / "c1" / "result.json").read_text())["labels"]["cfl"]), 0.3),
        "the changed run ran with its new input")
    # once the queue has forgotten c0's task (cancelled, node lost), it is submitted again
    os.environ["FAKE_QUEUE"] = ""
    res4 = batch.run_batch(cases, tmp / "slurm", binary=EXE, backend=slurm, **quiet)
    check(calls(log) == 3 and res4[0]["exit_code"] == 0 and res4[1].get("skipped"),
          "a run no longer queued and without result is submitted again, alone")


def start_task(root: Path, name: str) -> tuple[subprocess.Popen, Path]:
    """An array task (batch.py --task) of one long run, started as Slurm would."""
    case = batch.Case(name, WAVE, {**SMALL, "run.t_end": 3.0e-4, "grid.h": 1.0e-3,
                                   "body.n_thick": 4})
    folder = root / name
    batch._prepare(case, folder)
    (folder / "slurm.json").write_text(json.dumps(
        {"name": name, "input_hash": batch.input_hash(case), "labels": {}, "threads": 1,
         "timeout": None, "binary": str(EXE), "index": 0, "task_id": "7_0"}))
    tasks = root / "slurm" / f"{name}.tasks"
    tasks.parent.mkdir(parents=True, exist_ok=True)
    tasks.write_text(f"{folder}\n")
    p = subprocess.Popen([sys.executable, "-m", "tools.batch", "--task",
                          str(tasks)], cwd=ROOT, env=dict(os.environ, SLURM_ARRAY_TASK_ID="0",
                                                SLURM_ARRAY_JOB_ID="7"),
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    t0 = time.monotonic()
    while not (folder / "history.csv").is_file() and time.monotonic() - t0 < 60:
        time.sleep(0.1)
    time.sleep(0.5)
    return p, folder


def test_sigterm(tmp: Path) -> None:
    """An array task stopped by SIGTERM leaves no result.json: sent to the task (which passes
    it on to the run), or to the run itself (Slurm signals every process of the task)."""
    if not check(EXE.is_file(), f"binary {EXE}"):
        return
    for who in ("task", "run"):
        p, folder = start_task(tmp / "term", who)
        running = p.poll() is None
        children = Path(f"/proc/{p.pid}/task/{p.pid}/children")
        kids = children.read_text().split() if children.is_file() else []
        if who == "task":
            p.send_signal(signal.SIGTERM)
        elif kids:
            os.kill(int(kids[0]), signal.SIGTERM)
        out, _ = p.communicate(timeout=60)
        check(running and (who == "task" or len(kids) == 1),
              f"SIGTERM to the {who}: the task was running ({kids})")
        if who == "task":
            check(p.returncode == 143 and "stopped by a signal" in out,
                  f"SIGTERM to the task: it exits 143 and says why ({p.returncode}: {out!r})")
        else:
            check("stopped by a signal" in out, f"SIGTERM to the run: the task says so ({out!r})")
        check(not (folder / "result.json").exists(), f"SIGTERM to the {who}: no result.json")
        log = (folder / "run.log").read_text()
        check("SIGTERM" in log, f"SIGTERM to the {who} reached the run (its run.log)")


def main() -> int:
    tmp = Path(tempfile.mkdtemp(prefix="test_batch_slurm_"))
    saved = dict(os.environ)
    try:
        for t in (test_dry_run, test_submit, test_sigterm):
            try:
                t(tmp)
            except Exception:                      # a crash is a failure, with its traceback
                traceback.print_exc()
                check(False, f"{t.__name__} raised")
    finally:
        os.environ.clear()
        os.environ.update(saved)
        shutil.rmtree(tmp, ignore_errors=True)
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
