# SPDX-License-Identifier: MIT
"""Batch runs of tubempm: independent cases from a base namelist with overrides, several at
once, resumable.

Every case gets its own folder ``<root>/<name>/`` holding ``case.nml`` (the base namelist with
the overrides applied, ``output_dir`` pointing at the folder itself), the run's outputs,
``run.log`` (its standard output and error) and, once the process has ended, ``result.json``
(exit code, wall and CPU seconds, the hash of the input without the folder, the binary
and its hash). A case whose ``result.json`` exists
for the same input is skipped; any other folder (an interrupted run, or a changed input) is
cleared and run again. Runs use one OpenMP thread each (``threads``), ``jobs`` at a time.

Used by tools/study.py (``make study``) and tools/stability.py (``make stability``).
"""
from __future__ import annotations

import hashlib
import json
import os
import re
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

ROOT = Path(__file__).resolve().parent.parent
BINARY = ROOT / "bin" / "tubempm"


@dataclass
class Case:
    """One run: a base namelist and the variables to set in it.

    ``overrides`` maps ``"group.var"`` (first instance of the group) or ``"group[k].var"``
    (k-th instance, 1-based) to a Python value: str, bool, int, float or a sequence of those.
    ``labels`` are free fields (scene, factor, level, ...) carried into result tables.
    """
    name: str
    base: Path
    overrides: dict[str, Any] = field(default_factory=dict)
    labels: dict[str, Any] = field(default_factory=dict)


def fortran_value(value: Any) -> str:
    """A Python value as namelist text."""
    if isinstance(value, bool):
        return ".true." if value else ".false."
    if isinstance(value, str):
        return "'" + value.replace("'", "''") + "'"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value).replace("inf", "Inf")
    if isinstance(value, (list, tuple)):
        return ", ".join(fortran_value(v) for v in value)
    raise TypeError(f"no namelist form for {value!r}")


_KEY = re.compile(r"^([a-z_]\w*)(?:\[(\d+)\])?\.([a-z_]\w*)$", re.IGNORECASE)
_GROUP_START = re.compile(r"^\s*&([a-z_]\w*)", re.IGNORECASE)
_GROUP_END = re.compile(r"^\s*/\s*(!.*)?$")


def render(text: str, overrides: dict[str, Any]) -> str:
    """The namelist ``text`` with ``overrides`` applied (see Case).

    An assignment already present in the group instance is replaced (the whole line, which
    must hold that one assignment); otherwise the assignment is added before the group's
    closing ``/``. A group instance that does not exist is an error.
    """
    wanted: dict[tuple[str, int], dict[str, str]] = {}
    for key, value in overrides.items():
        m = _KEY.match(key)
        if not m:
            raise ValueError(f"override key {key!r}: expected 'group.var' or 'group[k].var'")
        group, k, var = m.group(1).lower(), int(m.group(2) or 1), m.group(3).lower()
        wanted.setdefault((group, k), {})[var] = fortran_value(value)
    lines = text.splitlines()
    out: list[str] = []
    count: dict[str, int] = {}
    current: tuple[str, int] | None = None
    done: set[tuple[tuple[str, int], str]] = set()
    for line in lines:
        if current is None:
            m = _GROUP_START.match(line)
            if m:
                g = m.group(1).lower()
                count[g] = count.get(g, 0) + 1
                current = (g, count[g])
            out.append(line)
            continue
        if _GROUP_END.match(line):
            for var, val in wanted.get(current, {}).items():
                if (current, var) not in done:
                    out.append(f"  {var} = {val}")
                    done.add((current, var))
            current = None
            out.append(line)
            continue
        m = re.match(r"^(\s*)([a-z_]\w*)\s*=", line, re.IGNORECASE)
        if m and m.group(2).lower() in wanted.get(current, {}):
            var = m.group(2).lower()
            out.append(f"{m.group(1)}{var} = {wanted[current][var]}")
            done.add((current, var))
            continue
        out.append(line)
    missing = [f"&{g}[{k}]" for (g, k) in wanted if count.get(g, 0) < k]
    if missing:
        raise ValueError("override of a group instance not in the base namelist: "
                         + ", ".join(missing))
    return "\n".join(out) + "\n"


def case_text(case: Case, folder: Path) -> str:
    """case.nml for ``case`` run in ``folder``."""
    overrides = {"run.title": case.name, "run.output_dir": str(folder)}
    overrides.update(case.overrides)
    return render(case.base.read_text(), overrides)


def input_hash(case: Case) -> str:
    """Hash of a case's input without its folder (title and output_dir): a study folder can
    be moved without re-running, and a changed input is noticed."""
    return hashlib.sha256(render(case.base.read_text(), case.overrides).encode()).hexdigest()[:16]


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


def _run_one(case: Case, root: Path, threads: int, timeout: float | None,
             binary: Path, log: Callable[[str], None], stop: threading.Event) -> dict[str, Any]:
    folder = root / case.name
    text = case_text(case, folder)
    digest = input_hash(case)
    old = result_of(folder)
    if old is not None and old.get("input_hash") == digest:
        old["skipped"] = True
        return old
    if stop.is_set():
        return {"name": case.name, "exit_code": None, "skipped": True}
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    (folder / "case.nml").write_text(text)
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
                return {"name": case.name, "exit_code": None, "interrupted": True}
            if deadline is not None and time.monotonic() > deadline:
                os.killpg(proc.pid, signal.SIGKILL)
                pid, status, rusage = os.wait4(proc.pid, 0)
                timed_out = True
                break
            time.sleep(0.05)
        proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.monotonic() - t0
    result = {"name": case.name, "exit_code": proc.returncode, "wall_s": wall,
              "cpu_s": rusage.ru_utime + rusage.ru_stime, "threads": threads,
              "timed_out": timed_out, "input_hash": digest, "labels": case.labels,
              "binary": str(binary), "binary_hash": _file_hash(binary),
              "finished": time.strftime("%Y-%m-%d %H:%M:%S")}
    (folder / "result.json").write_text(json.dumps(result, indent=1) + "\n")
    log(f"{case.name}: exit {proc.returncode}, {wall:.1f} s")
    return result


def run_batch(cases: list[Case], root: Path, jobs: int = 2, threads: int = 1,
              timeout: float | None = None, binary: Path = BINARY,
              log: Callable[[str], None] | None = None) -> list[dict[str, Any]]:
    """Run ``cases`` (skipping finished ones), ``jobs`` at a time; their results in order.

    Cases are started in the order given; order them cheapest first so that an interrupted
    batch has finished as much as possible. Ctrl-C stops the running cases (they are re-run
    next time) and raises KeyboardInterrupt.
    """
    names = [c.name for c in cases]
    if len(set(names)) != len(names):
        raise ValueError("case names must be unique")
    if not binary.is_file():
        raise FileNotFoundError(f"{binary} not found: build it with 'make'")
    root.mkdir(parents=True, exist_ok=True)
    lock = threading.Lock()

    def say(msg: str) -> None:
        with lock:
            (log or (lambda m: print(m, flush=True)))(msg)

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


def read_summary(folder: Path) -> dict[str, Any]:
    """summary.nml of a finished case as a dict ({} if missing)."""
    if str(ROOT / "plots") not in sys.path:
        sys.path.insert(0, str(ROOT / "plots"))
    from mpmplot import readers  # noqa: E402  (plots/ is not on the path by default)
    path = folder / "summary.nml"
    return readers.read_summary(path) if path.is_file() else {}


def main(argv: list[str] | None = None) -> int:
    """Command line: a library first; on its own it lists the cases of a batch folder."""
    import argparse  # noqa: PLC0415 (only the command line needs it)
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__.split("\n\n", 1)[1] + "\nOn its own, it reads a batch folder and writes "
        "nothing:\n    python3 tools/batch.py --status build/stability")
    ap.add_argument("--status", metavar="ROOT", required=True,
                    help="list the case folders under ROOT with their exit code, CPU seconds "
                         "and summary status")
    args = ap.parse_args(argv)
    root = Path(args.status)
    if not root.is_dir():
        print(f"ERROR [batch]: {root} is not a folder", file=sys.stderr)
        return 2
    for folder in sorted(p for p in root.iterdir() if p.is_dir()):
        res = result_of(folder)
        status = read_summary(folder).get("status", "-")
        if res is None:
            print(f"{folder.name:50s} not finished")
        else:
            print(f"{folder.name:50s} exit {res.get('exit_code')!s:>4}  "
                  f"{float(res.get('cpu_s', float('nan'))):8.1f} CPU s  {status}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
