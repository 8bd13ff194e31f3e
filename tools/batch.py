# SPDX-License-Identifier: MIT
"""Batch runs of tubempm: independent cases from a base namelist with overrides, several at
once, resumable.

Every case gets its own folder ``<root>/<name>/`` holding ``case.nml`` (the base namelist with
the overrides applied, ``output_dir`` pointing at the folder itself), the run's outputs,
``run.log`` (its standard output and error) and, once the process has ended, ``result.json``
(exit code, wall and CPU seconds, the hash of the input without the folder, the binary
and its hash). A case whose ``result.json`` exists
for the same input is skipped; any other folder (an interrupted run, or a changed input) is
cleared and run again. A run stopped from outside (Ctrl-C, kill, scancel, a time limit: exit
130 or 143) writes no result.json, so it is run again too. Runs use one OpenMP thread each
(``threads``), ``jobs`` at a time.

Two backends run them: local processes (the default), or Slurm (``Slurm``): one job array per
batch, one array task per run that is not finished, each task running this file with
``--task`` on the cluster's nodes (the run folders and the binary must be on a file system
they share). The folders, result.json and so everything that collects results are the same
for both; a Slurm run's folder also holds ``slurm.json`` (its job array task), and
``<root>/slurm/`` the submitted scripts, their task lists and Slurm's own output per task.
docs/batch.md shows both at work.

Used by tools/study.py (``make study``), tools/stability.py (``make stability``) and
tools/sweep.py.
"""
from __future__ import annotations

import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from plots.mpmplot import namelist  # the standard library only, as the array tasks need

ROOT = Path(__file__).resolve().parent.parent
BINARY = ROOT / "bin" / "tubempm"
#: tubempm's exit codes when SIGINT or SIGTERM stopped it (Ctrl-C, kill, scancel, a Slurm time
#: limit): the run did not end on its own, so it leaves no result.json and is run again
INTERRUPTED = (130, 143)


@dataclass
class Case:
    """One run: a base namelist and the variables to set in it.

    ``overrides`` maps ``"group.var"`` (first instance of the group) or ``"group[k].var"``
    (k-th instance, 1-based) to a Python value: str, bool, int, float or a sequence of those
    (written into the base by ``mpmplot.namelist.set_values``).
    ``labels`` are free fields (scene, factor, level, ...) carried into result tables.
    """
    name: str
    base: Path
    overrides: dict[str, Any] = field(default_factory=dict)
    labels: dict[str, Any] = field(default_factory=dict)


def case_text(case: Case, folder: Path) -> str:
    """case.nml for ``case`` run in ``folder``."""
    overrides = {"run.title": case.name, "run.output_dir": str(folder)}
    overrides.update(case.overrides)
    return namelist.set_values(case.base.read_text(), overrides, str(case.base))


def input_hash(case: Case) -> str:
    """Hash of a case's input without its folder (title and output_dir): a study folder can
    be moved without re-running, and a changed input is noticed."""
    text = namelist.set_values(case.base.read_text(), case.overrides, str(case.base))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _file_hash(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()[:16]


def result_of(folder: Path) -> dict[str, Any] | None:
    """The recorded result of a finished case, or None."""
    path = folder / "result.json"
    if not path.is_file():
        return None
    try:
        return json.loads(path.read_text())
    except (OSError, json.JSONDecodeError):
        return None


def _prepare(case: Case, folder: Path) -> None:
    """A cleared ``folder`` holding the case's case.nml."""
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    (folder / "case.nml").write_text(case_text(case, folder))


def _execute(folder: Path, name: str, digest: str, labels: dict[str, Any], threads: int,
             timeout: float | None, binary: Path, stop: threading.Event,
             extra: dict[str, Any] | None = None) -> dict[str, Any] | None:
    """Run the binary on ``folder``/case.nml and write result.json (with ``extra``); the
    result, or None when ``stop`` was set while it ran or a signal stopped it (exit 130, 143):
    such a run leaves no result.json."""
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t0 = time.monotonic()
    with open(folder / "run.log", "w") as logf:
        proc = subprocess.Popen([str(binary), "--quiet", str(folder / "case.nml")],
                                stdout=logf, stderr=subprocess.STDOUT, env=env,
                                start_new_session=True)
        deadline = None if timeout is None else t0 + timeout
        status = None
        rusage = None
        timed_out = False
        while True:
            pid, status, rusage = os.wait4(proc.pid, os.WNOHANG)
            if pid != 0:
                break
            if stop.is_set():
                os.killpg(proc.pid, signal.SIGTERM)
                os.wait4(proc.pid, 0)
                return None
            if deadline is not None and time.monotonic() > deadline:
                os.killpg(proc.pid, signal.SIGKILL)
                pid, status, rusage = os.wait4(proc.pid, 0)
                timed_out = True
                break
            time.sleep(0.05)
        proc.returncode = os.waitstatus_to_exitcode(status)
    if stop.is_set() or proc.returncode in INTERRUPTED:
        return None                                # stopped from outside: no result
    wall = time.monotonic() - t0
    result = {"name": name, "exit_code": proc.returncode, "wall_s": wall,
              "cpu_s": rusage.ru_utime + rusage.ru_stime, "threads": threads,
              "timed_out": timed_out, "input_hash": digest, "labels": labels,
              "binary": str(binary), "binary_hash": _file_hash(binary),
              "finished": time.strftime("%Y-%m-%d %H:%M:%S"), **(extra or {})}
    tmp = folder / "result.json.tmp"               # complete or absent, never half written
    tmp.write_text(json.dumps(result, indent=1) + "\n")
    os.replace(tmp, folder / "result.json")
    return result


def _finished(case: Case, folder: Path) -> dict[str, Any] | None:
    """The recorded result of ``case`` in ``folder`` if it ran with the same input."""
    old = result_of(folder)
    if old is not None and old.get("input_hash") == input_hash(case):
        old["skipped"] = True
        return old
    return None


def _run_one(case: Case, root: Path, threads: int, timeout: float | None,
             binary: Path, log: Callable[[str], None], stop: threading.Event) -> dict[str, Any]:
    folder = root / case.name
    old = _finished(case, folder)
    if old is not None:
        return old
    if stop.is_set():
        return {"name": case.name, "exit_code": None, "skipped": True}
    _prepare(case, folder)
    result = _execute(folder, case.name, input_hash(case), case.labels, threads, timeout,
                      binary, stop)
    if result is None:
        return {"name": case.name, "exit_code": None, "interrupted": True}
    log(f"{case.name}: exit {result['exit_code']}, {result['wall_s']:.1f} s")
    return result


# ----------------------------------------------------------------------------------------------
# The Slurm backend: one job array per batch, one array task per run
# ----------------------------------------------------------------------------------------------

#: states in which squeue lists a task that has not ended yet
_ALIVE = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED",
          "REQUEUE_HOLD", "REQUEUE_FED", "RESIZING", "SIGNALING", "STAGE_OUT", "STOPPED"}


@dataclass
class Slurm:
    """Where and how a batch runs on Slurm (``run_batch(..., backend=Slurm(...))``).

    One ``sbatch`` job array per call of run_batch, one array task per run that is not finished
    (nor still queued from an earlier submission), each with ``threads`` CPUs. ``partition``,
    ``time`` (a task's time limit, Slurm's format: ``MM``, ``HH:MM:SS``, ``D-HH``),
    ``account`` and ``max_running`` (array throttle ``%N``) are left to the cluster's defaults
    when None; ``options`` are added as ``#SBATCH`` lines verbatim (``--mem=2G``,
    ``--qos=short``). ``dry_run`` prints the script and submits nothing; ``wait=False``
    returns once submitted (run the same batch again to collect: queued tasks are waited for,
    not submitted twice). ``python`` is the interpreter the tasks start (on the compute nodes).
    """
    partition: str | None = None
    time: str | None = None
    account: str | None = None
    max_running: int | None = None
    options: list[str] = field(default_factory=list)
    dry_run: bool = False
    wait: bool = True
    poll: float = 10.0
    python: str = "python3"
    #: most tasks in one array (Slurm's MaxArraySize is 1001 by default): more runs are
    #: submitted as several arrays
    array_max: int = 1000


def _slurm_cmd(args: list[str]) -> subprocess.CompletedProcess:
    try:
        return subprocess.run(args, capture_output=True, text=True, timeout=120)
    except FileNotFoundError:
        raise RuntimeError(f"{args[0]} not found: is this a Slurm cluster (or load its module)?"
                           ) from None


def slurm_alive() -> set[str] | None:
    """Array tasks (``JOBID_TASK``) and jobs of this user that Slurm has not finished, or None
    when squeue does not answer."""
    p = _slurm_cmd(["squeue", "--noheader", "--array", "--me", "--format=%i %T"])
    if p.returncode != 0:
        return None
    return {w[0] for w in (ln.split() for ln in p.stdout.splitlines())
            if len(w) == 2 and w[1] in _ALIVE}


def sbatch_script(tasks_file: Path, ntasks: int, threads: int, slurm: Slurm,
                  job_name: str) -> str:
    """The ``sbatch`` script of one job array: task i runs the i-th folder of ``tasks_file``."""
    logs = tasks_file.parent
    lines = ["#!/bin/bash",
             f"#SBATCH --job-name={job_name}",
             f"#SBATCH --array=0-{ntasks - 1}"
             + (f"%{slurm.max_running}" if slurm.max_running else ""),
             "#SBATCH --ntasks=1",
             f"#SBATCH --cpus-per-task={threads}",
             f"#SBATCH --output={logs}/%A_%a.out"]
    if slurm.partition:
        lines.append(f"#SBATCH --partition={slurm.partition}")
    if slurm.time:
        lines.append(f"#SBATCH --time={slurm.time}")
    if slurm.account:
        lines.append(f"#SBATCH --account={slurm.account}")
    lines += [f"#SBATCH {o}" for o in slurm.options]
    lines += ["# one tubempm run per array task, in its own folder (tools/batch.py --task)",
              f"export OMP_NUM_THREADS={threads}",
              f"cd {ROOT}",
              f"exec {slurm.python} -m tools.batch --task {tasks_file}", ""]
    return "\n".join(lines)


def _slurm_batch(cases: list[Case], root: Path, threads: int, timeout: float | None,
                 binary: Path, say: Callable[[str], None], slurm: Slurm
                 ) -> list[dict[str, Any]]:
    results: dict[str, dict[str, Any]] = {}
    todo: list[Case] = []
    waiting: dict[str, str] = {}                   # case name -> its queued array task
    alive = None
    for case in cases:
        folder = root / case.name
        old = _finished(case, folder)
        if old is not None:
            results[case.name] = old
            continue
        sub = _read_json(folder / "slurm.json")
        if sub and sub.get("input_hash") == input_hash(case) and sub.get("task_id"):
            if alive is None:
                alive = slurm_alive()
                if alive is None:
                    raise RuntimeError("squeue failed: cannot tell which runs are still queued")
            if sub["task_id"] in alive:
                waiting[case.name] = sub["task_id"]
                continue
        todo.append(case)
    stamp = time.strftime("%Y%m%d-%H%M%S")
    chunks = [todo[k:k + slurm.array_max] for k in range(0, len(todo), slurm.array_max)]
    files = [(root / "slurm" / f"{stamp}-{os.getpid()}{f'-{n}' if n else ''}.tasks").resolve()
             for n in range(len(chunks))]
    scripts = [sbatch_script(f, len(c), threads, slurm, f"tubempm-{root.name}")
               for f, c in zip(files, chunks)]
    if slurm.dry_run:
        print(f"# {len(cases)} runs: {len(results)} finished, {len(waiting)} still queued, "
              f"{len(todo)} to submit")
        for tasks_file, chunk, script in zip(files, chunks, scripts):
            print(f"# {tasks_file} (one run folder per line):")
            for c in chunk:
                print(f"#   {(root / c.name).resolve()}")
            print(script, end="")
        return [results.get(c.name, {"name": c.name, "exit_code": None, "dry_run": True})
                for c in cases]
    for tasks_file, chunk, script in zip(files, chunks, scripts):
        tasks_file.parent.mkdir(parents=True, exist_ok=True)
        for i, case in enumerate(chunk):
            folder = root / case.name
            _prepare(case, folder)
            (folder / "slurm.json").write_text(json.dumps(
                {"name": case.name, "input_hash": input_hash(case), "labels": case.labels,
                 "threads": threads, "timeout": timeout, "binary": str(binary.resolve()),
                 "index": i}, indent=1) + "\n")
        tasks_file.write_text("".join(f"{(root / c.name).resolve()}\n" for c in chunk))
        script_file = tasks_file.with_suffix(".sbatch")
        script_file.write_text(script)
        p = _slurm_cmd(["sbatch", "--parsable", str(script_file)])
        if p.returncode != 0:
            raise RuntimeError(f"sbatch {script_file} failed: {p.stderr.strip()}")
        job = p.stdout.strip().split(";")[0]
        for i, case in enumerate(chunk):
            path = root / case.name / "slurm.json"
            sub = json.loads(path.read_text())
            sub.update(job_id=job, task_id=f"{job}_{i}")
            path.write_text(json.dumps(sub, indent=1) + "\n")
            waiting[case.name] = f"{job}_{i}"
        say(f"submitted job array {job}: {len(chunk)} run{'s' if len(chunk) > 1 else ''} "
            f"({script_file})")
    if waiting and not slurm.wait:
        shown = ", ".join(sorted(set(waiting.values()))[:4]) + (" ..." if len(waiting) > 4
                                                                  else "")
        say(f"{len(waiting)} run{'s' if len(waiting) > 1 else ''} queued or running (Slurm "
            f"tasks {shown}); run the same command again to wait for them and collect")
    if waiting and slurm.wait:
        if not todo:
            say(f"waiting for {len(waiting)} runs queued earlier")
        pending = set(waiting.values())
        try:
            while pending:
                time.sleep(slurm.poll)
                now = slurm_alive()
                if now is not None:                # (None: squeue busy, ask again)
                    pending &= now
        except KeyboardInterrupt:
            say(f"stopped waiting; the {len(pending)} queued or running tasks go on "
                "(scancel them to stop them); run the batch again to wait for them and collect")
            raise
    if slurm.wait and any(_finished(c, root / c.name) is None for c in cases
                          if c.name in waiting):
        time.sleep(min(slurm.poll, 5.0))           # a shared file system may show it late
    for case in cases:
        if case.name in results:
            continue
        res = _finished(case, root / case.name)
        if res is not None:
            res.pop("skipped", None)
            results[case.name] = res
            say(f"{case.name}: exit {res['exit_code']}, {res['wall_s']:.1f} s")
        elif slurm.wait:                           # cancelled, out of time, node failure
            results[case.name] = {"name": case.name, "exit_code": None, "interrupted": True}
        else:
            results[case.name] = {"name": case.name, "exit_code": None,
                                  "queued": waiting.get(case.name)}
    return [results[c.name] for c in cases]


def _read_json(path: Path) -> dict[str, Any] | None:
    try:
        return json.loads(path.read_text())
    except (OSError, json.JSONDecodeError):
        return None


def run_task(tasks_file: Path, index: int) -> int:
    """One Slurm array task: run the ``index``-th folder of ``tasks_file`` (prepared by the
    submitting run_batch) and write its result.json as the local backend does. SIGTERM (scancel,
    the time limit) stops the run and leaves no result.json, so the run is submitted again."""
    folders = tasks_file.read_text().splitlines()
    folder = Path(folders[index])
    sub = json.loads((folder / "slurm.json").read_text())
    # (from Slurm: the submitter may not have written the job id into slurm.json yet)
    slurm_task = f"{os.environ.get('SLURM_ARRAY_JOB_ID', '?')}_{index}"
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    result = _execute(folder, sub["name"], sub["input_hash"], sub["labels"], sub["threads"],
                      sub["timeout"], Path(sub["binary"]), stop,
                      extra={"backend": "slurm", "slurm_task": slurm_task})
    if result is None:
        print(f"{sub['name']}: stopped by a signal; no result.json (it is run again)")
        return 143
    print(f"{sub['name']}: exit {result['exit_code']}, {result['wall_s']:.1f} s")
    return 0


def run_batch(cases: list[Case], root: Path, jobs: int = 2, threads: int = 1,
              timeout: float | None = None, binary: Path = BINARY,
              log: Callable[[str], None] | None = None,
              backend: Slurm | None = None) -> list[dict[str, Any]]:
    """Run ``cases`` (skipping finished ones), ``jobs`` at a time; their results in order.

    Cases are started in the order given; order them cheapest first so that an interrupted
    batch has finished as much as possible. Ctrl-C stops the running cases (they are re-run
    next time) and raises KeyboardInterrupt.

    With ``backend=Slurm(...)`` the runs that are not finished go to Slurm as one job array
    (``jobs`` does not apply; see Slurm) and the call waits for them; a result's ``exit_code``
    is None for a run that did not end on its own (cancelled, out of time: it is submitted
    again next time) or, with ``wait=False``, is still queued.
    """
    names = [c.name for c in cases]
    if len(set(names)) != len(names):
        raise ValueError("case names must be unique")
    if not binary.is_file() and not (backend is not None and backend.dry_run):
        raise FileNotFoundError(f"{binary} not found: build it with 'make'")
    lock = threading.Lock()

    def say(msg: str) -> None:
        with lock:
            (log or (lambda m: print(m, flush=True)))(msg)

    if backend is not None:
        if not backend.dry_run:
            root.mkdir(parents=True, exist_ok=True)
        return _slurm_batch(cases, root, threads, timeout, binary, say, backend)
    root.mkdir(parents=True, exist_ok=True)

    stop = threading.Event()
    with ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = [pool.submit(_run_one, c, root, threads, timeout, binary, say, stop)
                   for c in cases]
        try:
            results = [f.result() for f in futures]
        except KeyboardInterrupt:
            stop.set()
            pool.shutdown(wait=True, cancel_futures=True)
            raise
    return results


def private_binary(folder: Path, binary: Path = BINARY) -> Path:
    """A copy of ``binary`` in ``folder`` for a long batch (rebuilding bin/ meanwhile does not
    change the runs still to come), replaced only when it differs, and then as a new file so
    that runs of the old one (queued or running) go on."""
    folder.mkdir(parents=True, exist_ok=True)
    copy = folder / binary.name
    if not copy.is_file() or _file_hash(copy) != _file_hash(binary):
        tmp = copy.with_name(copy.name + ".tmp")
        shutil.copy2(binary, tmp)
        os.replace(tmp, copy)
    return copy


def read_summary(folder: Path) -> dict[str, Any]:
    """summary.nml of a finished case as a dict ({} if missing)."""
    from plots.mpmplot import readers  # noqa: PLC0415 (numpy: only here)
    path = folder / "summary.nml"
    return readers.read_summary(path) if path.is_file() else {}


def add_backend_args(ap: Any, threads: bool = True, no_wait: bool = True) -> None:
    """The command-line options that choose where a batch runs (tools/study.py,
    tools/stability.py, tools/sweep.py); ``backend_of`` turns them into run_batch's backend.
    ``threads``, ``no_wait``: offer --threads, --no-wait."""
    g = ap.add_argument_group("where the runs go (docs/batch.md)")
    g.add_argument("--backend", choices=("local", "slurm"), default="local",
                   help="local processes (default) or one Slurm job array per batch")
    if threads:
        g.add_argument("--threads", type=int, default=1,
                       help="OpenMP threads per run (Slurm: CPUs per task; default 1)")
    g.add_argument("--partition", help="Slurm partition (default: the cluster's)")
    g.add_argument("--time", metavar="LIMIT",
                   help="Slurm time limit of one run, e.g. 30, 2:00:00, 1-00 (default: the "
                        "partition's); a run stopped by it is submitted again next time")
    g.add_argument("--account", help="Slurm account to charge (default: yours)")
    g.add_argument("--max-running", type=int, metavar="N",
                   help="Slurm: at most N tasks of an array at once (default: no limit)")
    g.add_argument("--sbatch-option", action="append", default=[], metavar="OPT",
                   help="Slurm: an extra #SBATCH line, e.g. --sbatch-option=--mem=2G "
                        "(repeatable)")
    g.add_argument("--poll", type=float, default=10.0, metavar="SECONDS",
                   help="Slurm: how often to ask squeue whether the runs have ended "
                        "(default 10)")
    g.add_argument("--dry-run", action="store_true",
                   help="Slurm: print the sbatch script of each batch, submit nothing")
    if no_wait:
        g.add_argument("--no-wait", action="store_true",
                       help="Slurm: return once submitted; run the same command again later "
                            "to wait for the queued runs and collect (nothing is submitted "
                            "twice)")


def backend_of(args: Any) -> Slurm | None:
    """run_batch's backend from the options of add_backend_args (None: local)."""
    slurm_only = [o for o, v in (("--partition", args.partition), ("--time", args.time),
                                 ("--account", args.account),
                                 ("--max-running", args.max_running),
                                 ("--sbatch-option", args.sbatch_option),
                                 ("--dry-run", args.dry_run),
                                 ("--no-wait", getattr(args, "no_wait", False))) if v]
    def refuse(msg: str) -> None:
        print(f"ERROR [batch]: {msg}", file=sys.stderr)
        raise SystemExit(2)

    if args.backend == "local":
        if slurm_only:
            refuse(f"{', '.join(slurm_only)}: only with --backend slurm")
        return None
    if getattr(args, "threads", 1) < 1:
        refuse(f"--threads {args.threads}: must be at least 1")
    if args.max_running is not None and args.max_running < 1:
        refuse(f"--max-running {args.max_running}: must be at least 1")
    return Slurm(partition=args.partition, time=args.time, account=args.account,
                 max_running=args.max_running, options=list(args.sbatch_option),
                 dry_run=args.dry_run, wait=not getattr(args, "no_wait", False),
                 poll=max(0.2, args.poll))


def main(argv: list[str] | None = None) -> int:
    """Command line: a library first; on its own it lists the cases of a batch folder, and
    runs one Slurm array task."""
    import argparse  # noqa: PLC0415 (only the command line needs it)
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__.split("\n\n", 1)[1] + "\nOn its own, it lists a batch folder (and writes "
        "nothing):\n    python3 -m tools.batch --status build/stability\nor runs one task of a "
        "Slurm job array (--task, what its sbatch script runs).")
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--status", metavar="ROOT",
                      help="list the case folders under ROOT with their exit code, CPU seconds "
                           "and summary status")
    mode.add_argument("--task", metavar="FILE",
                      help="(what a Slurm array task runs) run the folder on line "
                           "$SLURM_ARRAY_TASK_ID (from 0) of FILE, as the sbatch script says")
    args = ap.parse_args(argv)
    if args.task:
        index = os.environ.get("SLURM_ARRAY_TASK_ID", "")
        if not index.isdigit():
            print("ERROR [batch]: --task needs SLURM_ARRAY_TASK_ID (it runs inside a Slurm "
                  "job array)", file=sys.stderr)
            return 2
        return run_task(Path(args.task), int(index))
    root = Path(args.status)
    if not root.is_dir():
        print(f"ERROR [batch]: {root} is not a folder", file=sys.stderr)
        return 2
    for folder in sorted(p for p in root.iterdir() if (p / "case.nml").is_file()):
        res = result_of(folder)
        status = read_summary(folder).get("status", "-")
        sub = _read_json(folder / "slurm.json")
        if res is None and sub and sub.get("task_id"):
            print(f"{folder.name:50s} not finished (Slurm task {sub['task_id']})")
        elif res is None:
            print(f"{folder.name:50s} not finished")
        else:
            print(f"{folder.name:50s} exit {res.get('exit_code')!s:>4}  "
                  f"{float(res.get('cpu_s', float('nan'))):8.1f} CPU s  {status}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
