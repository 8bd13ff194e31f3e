#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A parameter sweep of tubempm: a base namelist, a table of overrides, one run per row, and
one table of results (``sweep.csv``) for plots/plot_sweep.py.

    python3 -m tools.sweep BASE.nml --out DIR [--set KEY=VALUE ...] [--vary KEY=V1,V2,...]
                           [--table ROWS.csv] [--jobs N] [--threads N] [--list] [--collect]
                           [--backend slurm [--partition P] [--time T] [--account A] ...]

The runs are the rows of ``--table`` (a CSV file whose header names the keys) times every
combination of the ``--vary`` lists (a product), each with the ``--set`` values. A key is a
namelist variable, ``group.var`` (the first instance of the group) or ``group[k].var`` (the
k-th), or one of the ring's design variables, which act on the first ring ``&body``:

  ring.D_over_t  mean diameter / wall thickness; the outer radius is kept (so walls and gaps
                 stay where they are) and the inner radius follows; grid.h follows too, so
                 that h/t stays the base's, unless grid.h is set as well
  ring.t         wall thickness [m], the same way
  ring.speed     the body's speed [m/s] along the base's velocity (which must not be zero)

Values are numbers, .true./.false. or text; a vector is written with spaces (``0 -30``), so
``--vary "body.velocity=0 -10,0 -20"`` is two runs. In a table, a column named ``name`` names
the runs, and a column whose name has no dot is a label only (carried into sweep.csv).

Each run goes to DIR/<name>/ through tools/batch.py (finished runs are skipped, interrupted or
changed ones re-run), as local processes (``--jobs`` at a time) or as one Slurm job array
(``--backend slurm``, docs/batch.md). Then DIR/sweep.csv gets one row per run: the keys'
values and labels, exit code, status, CPU seconds, and per history column the value at the
end, the minimum and the maximum (``plastic_end``: the energy absorbed plastically [J]), and
the run's ``&results`` (``sea``, ``cfe``, ``mean_force``, ``absorbed_energy``, ...; docs/output.md).

A design chart, absorbed energy against D/t and impact speed:

    python3 -m tools.sweep namelists/impact.nml --out out/chart \\
        --vary ring.D_over_t=10,15,20,25 --vary ring.speed=10,20,30 --set run.t_end=1.0e-3
    python3 -m plots.plot_sweep --dir out/chart --x ring.D_over_t --y plastic_end \\
        --by ring.speed
"""
from __future__ import annotations

import argparse
import csv
import itertools
import math
import os
import re
import sys
from pathlib import Path
from typing import Any

from tools import batch
from plots.mpmplot import namelist

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

#: the design variables of the first ring body (see the module's help)
RING_KEYS = ("ring.d_over_t", "ring.t", "ring.speed")
#: history columns summarised in sweep.csv (end, min, max of each)
HISTORY = re.compile(r"^(kinetic|strain|plastic|external|damped|contact_loss|com_v[xy]"
                     r"|wall\d+_(force|disp)"
                     r"|contact\d+_\d+_force)$")
NAME_MAX = 60           #: longest run name (the title of a run holds 64 characters)


class SweepError(ValueError):
    """A sweep that cannot be set up; the message says what and how to fix it."""


def parse_value(text: str) -> Any:
    """A value as written on the command line or in a table cell, read as the value of a
    namelist assignment (``mpmplot.namelist.parse_values``): int, float, logical (``.true.``,
    ``false``, ``T``), text (quoted or not), or a list of those when it has several words;
    a cell that is no namelist value (``h/t``) stays text."""
    if not text.strip():
        return ""
    try:
        return namelist.parse_values(text)
    except namelist.NamelistError:
        return text.strip()


def _check_key(key: str, where: str) -> str:
    if key.lower() in RING_KEYS:
        return key
    try:
        namelist.split_key(key)
    except ValueError:
        raise SweepError(f"{where}: key {key!r}: expected group.var, group[k].var or one of "
                         f"ring.D_over_t, ring.t, ring.speed") from None
    return key


def parse_assignment(text: str, where: str) -> tuple[str, str]:
    """``KEY=VALUE`` split at the first ``=``."""
    if "=" not in text:
        raise SweepError(f"{where}: {text!r}: expected KEY=VALUE")
    key, value = text.split("=", 1)
    key = key.strip()
    return _check_key(key, where), value.strip()


def read_table(path: Path) -> list[dict[str, str]]:
    """The rows of a CSV table of overrides (header: keys, ``name``, labels)."""
    try:
        with open(path, newline="") as fh:
            rows = [{(k or "").strip(): (v or "").strip() for k, v in r.items()}
                    for r in csv.DictReader(fh)]
    except OSError as e:
        raise SweepError(f"{path}: cannot read the table: {e.strerror}") from None
    if not rows:
        raise SweepError(f"{path}: the table has no rows (the first line names the keys)")
    for col in rows[0]:
        if "." in col or "[" in col:
            _check_key(col, f"{path}: column")
    return rows


def _ring(base: dict[str, list[dict[str, Any]]], where: str) -> tuple[int, dict[str, Any]]:
    for k, body in enumerate(base.get("body", []), start=1):
        if str(body.get("shape", "ring")).lower() == "ring":
            return k, body
    raise SweepError(f"{where}: the ring design variables need a ring &body in the base")


def _round(x: float) -> float:
    """x to 12 digits: derived values without the round-off of their formula in the input."""
    return float(f"{x:.12g}")


def resolve(base: dict[str, list[dict[str, Any]]], overrides: dict[str, Any], where: str
            ) -> dict[str, Any]:
    """The namelist overrides of one run: the design variables (ring.*) turned into the
    variables they set; the others as they are."""
    plain = {k: v for k, v in overrides.items() if k.lower() not in RING_KEYS}
    ring = {k.lower(): v for k, v in overrides.items() if k.lower() in RING_KEYS}
    if not ring:
        return plain
    k, body = _ring(base, where)
    if "ring.d_over_t" in ring and "ring.t" in ring:
        raise SweepError(f"{where}: ring.D_over_t and ring.t both set: give one of them")
    if "ring.d_over_t" in ring or "ring.t" in ring:
        if any(key.lower() in (f"body[{k}].r_inner", f"body[{k}].r_outer") or
               (k == 1 and key.lower() in ("body.r_inner", "body.r_outer")) for key in plain):
            raise SweepError(f"{where}: ring.D_over_t / ring.t and the ring's radii both set")
        r_out = float(body["r_outer"])
        t0 = r_out - float(body["r_inner"])
        if "ring.t" in ring:
            t = float(ring["ring.t"])
        else:
            q = float(ring["ring.d_over_t"])
            if not q > 1.0:
                raise SweepError(f"{where}: ring.D_over_t = {q}: must be larger than 1")
            t = 2.0 * r_out / (q + 1.0)                 # D = 2 r_out - t = q t
        if not 0.0 < t < r_out:
            raise SweepError(f"{where}: wall thickness {t} m: must be between 0 and the outer "
                             f"radius {r_out} m")
        plain[f"body[{k}].r_inner"] = _round(r_out - t)
        if not any(key.lower() == "grid.h" for key in plain):
            plain["grid.h"] = _round(float(base["grid"][0]["h"]) * t / t0)
    if "ring.speed" in ring:
        v0 = body.get("velocity", [0.0, 0.0])
        v0 = [float(x) for x in (v0 if isinstance(v0, (list, tuple)) else [v0])] + [0.0]
        norm = math.hypot(v0[0], v0[1])
        if norm == 0.0:
            raise SweepError(f"{where}: ring.speed needs a &body velocity in the base (its "
                             "direction)")
        s = float(ring["ring.speed"])
        plain[f"body[{k}].velocity"] = [_round(s * v0[0] / norm), _round(s * v0[1] / norm)]
    return plain


def _short(key: str) -> str:
    return key.split(".")[-1]


def _fmt(value: Any) -> str:
    if isinstance(value, list):
        return "_".join(_fmt(v) for v in value)
    text = f"{value:g}" if isinstance(value, float) else str(value)
    return re.sub(r"[^A-Za-z0-9_]", "", text.replace(".", "p").replace("-", "m"))


def expand(base_path: Path, sets: list[str] | None = None, varies: list[str] | None = None,
           table: list[dict[str, str]] | None = None) -> list[batch.Case]:
    """The runs of a sweep (see the module's help): ``sets`` and ``varies`` as written on the
    command line (``KEY=VALUE``, ``KEY=V1,V2,...``), ``table`` as read_table gives it."""
    try:
        base = namelist.read_namelist(base_path)
    except (OSError, ValueError) as e:
        raise SweepError(f"{base_path}: cannot read the base namelist: {e}") from None
    fixed = dict(parse_assignment(s, "--set") for s in (sets or []))
    fixed = {k: parse_value(v) for k, v in fixed.items()}
    lists: list[tuple[str, list[Any]]] = []
    for text in varies or []:
        key, values = parse_assignment(text, "--vary")
        vals = [parse_value(v) for v in values.split(",") if v.strip()]
        if not vals:
            raise SweepError(f"--vary {text!r}: no values")
        lists.append((key, vals))
    rows = table or [{}]
    varied = [c for c in (rows[0] if table else {}) if c != "name" and ("." in c or "[" in c)] \
        + [k for k, _ in lists]
    shorts = [_short(k) for k in varied]
    use_short = len(set(shorts)) == len(shorts)
    n_combo = math.prod(len(v) for _, v in lists)
    cases: list[batch.Case] = []
    for i, (row, combo) in enumerate(itertools.product(rows, itertools.product(
            *[v for _, v in lists]))):
        where = f"run {i + 1}"
        over: dict[str, Any] = dict(fixed)
        labels: dict[str, Any] = {}
        for col, cell in row.items():
            if col == "name":
                continue
            if "." in col or "[" in col:
                if cell == "":
                    raise SweepError(f"table row {i // n_combo + 1}: column {col!r} is empty")
                over[col] = labels[col] = parse_value(cell)
            else:
                labels[col] = parse_value(cell) if cell else ""
        for (key, _), value in zip(lists, combo):
            over[key] = labels[key] = value
        name = row.get("name", "")
        if not name:
            parts = [f"{(_short(k) if use_short else k.replace('.', '_'))}{_fmt(over[k])}"
                     for k in varied]
            name = re.sub(r"[\[\]]", "", "_".join(parts)) or "run"
            if len(name) > NAME_MAX:
                name = f"run{i:04d}"
        if not re.fullmatch(r"[A-Za-z0-9_.+-]+", name) or len(name) > NAME_MAX:
            raise SweepError(f"{where}: run name {name!r}: letters, digits and _ . + - only, "
                             f"at most {NAME_MAX} characters")
        cases.append(batch.Case(name, base_path.resolve(), resolve(base, over, where), labels))
    names = [c.name for c in cases]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise SweepError(f"two runs have the same name {dup[0]!r}: the table repeats a row, "
                         "or name the runs with a 'name' column")
    for c in cases:                                # a bad key fails here, before any run
        namelist.set_values(c.base.read_text(), c.overrides, str(c.base))
    return cases


def collect(cases: list[batch.Case], root: Path) -> Path:
    """sweep.csv from the run folders: one row per run (runs not finished have no numbers)."""
    from plots.mpmplot import readers  # noqa: PLC0415 (numpy only here)
    rows: list[dict[str, Any]] = []
    columns: list[str] = ["name"]
    for c in cases:
        for k in c.labels:
            if k not in columns:
                columns.append(k)
    columns += ["exit_code", "status", "particles", "steps", "cpu_s", "wall_s", "energy_error"]
    hist_cols: list[str] = []
    res_cols: list[str] = []
    for c in cases:
        folder = root / c.name
        res = batch.result_of(folder)
        if res is not None and res.get("input_hash") != batch.input_hash(c):
            res = None                                       # an older input's run
        row: dict[str, Any] = {"name": c.name, **c.labels}
        row["exit_code"] = "" if res is None else res.get("exit_code")
        summ = batch.read_summary(folder) if res is not None else {}
        row["status"] = summ.get("status", "not run" if res is None else "no summary")
        for k in ("particles", "steps", "energy_error"):
            row[k] = summ.get(k, "")
        if res is not None:
            row["cpu_s"] = round(float(res["cpu_s"]), 3)
            row["wall_s"] = round(float(res["wall_s"]), 3)
        if res is not None and (folder / "summary.nml").is_file():   # &results: SEA, CFE, ...
            for k, v in readers.read_results(folder / "summary.nml").items():
                if isinstance(v, (int, float)) and not isinstance(v, bool):
                    row[k] = float(v)
                    if k not in res_cols:
                        res_cols.append(k)
        hfile = folder / "history.csv"
        if res is not None and hfile.is_file():
            h = readers.read_history(hfile)
            for col, val in h.items():
                if HISTORY.match(col) and len(val):
                    for suffix, x in (("end", val[-1]), ("min", val.min()), ("max", val.max())):
                        row[f"{col}_{suffix}"] = float(x)
                        if f"{col}_{suffix}" not in hist_cols:
                            hist_cols.append(f"{col}_{suffix}")
        rows.append(row)
    path = root / "sweep.csv"
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=columns + res_cols + hist_cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.10g}" if isinstance(v, float) else
                            " ".join(f"{x:g}" for x in v) if isinstance(v, list) else v)
                        for k, v in r.items()})
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("base", type=Path, help="the base namelist")
    ap.add_argument("--out", type=Path, required=True,
                    help="the sweep's folder: one folder per run, and sweep.csv")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a value for every run (repeatable)")
    ap.add_argument("--vary", action="append", default=[], metavar="KEY=V1,V2,...",
                    help="values to sweep; several --vary give every combination")
    ap.add_argument("--table", type=Path, metavar="ROWS.csv",
                    help="a CSV table of overrides, one run per row (with --vary: every row "
                         "times every combination)")
    ap.add_argument("--jobs", type=int, default=0,
                    help="local: runs at once (default: cores / threads)")
    ap.add_argument("--binary", type=Path, default=batch.BINARY,
                    help="the tubempm to run (default bin/tubempm; `make` builds it); the "
                         "sweep runs a copy of it kept in its folder")
    ap.add_argument("--list", action="store_true", help="list the runs and their overrides, "
                    "run nothing")
    ap.add_argument("--collect", action="store_true",
                    help="write sweep.csv from the run folders, run nothing")
    batch.add_backend_args(ap)
    args = ap.parse_args(argv)
    backend = batch.backend_of(args)
    try:
        table = read_table(args.table) if args.table else None
        cases = expand(args.base, args.set, args.vary, table)
    except (SweepError, ValueError) as e:
        print(f"ERROR [sweep]: {e}", file=sys.stderr)
        return 2
    if args.list:
        for c in cases:
            print(f"{c.name:40s} " + ", ".join(f"{k} = {namelist.format_value(v)}"
                                               for k, v in c.overrides.items()))
        print(f"{len(cases)} runs")
        return 0
    if not args.collect:
        if not args.binary.is_file():
            print(f"ERROR [sweep]: {args.binary} not found: build it with 'make'",
                  file=sys.stderr)
            return 2
        jobs = args.jobs or max(1, (os.cpu_count() or 1) // args.threads)
        binary = args.out / args.binary.name if backend is not None and backend.dry_run \
            else batch.private_binary(args.out, args.binary)
        try:
            res = batch.run_batch(cases, args.out, jobs=jobs, threads=args.threads,
                                  binary=binary, backend=backend)
        except KeyboardInterrupt:
            print("interrupted: finished runs are kept; run again to continue", file=sys.stderr)
            return 130
        except RuntimeError as e:
            print(f"ERROR [sweep]: {e}", file=sys.stderr)
            return 3
        if backend is not None and (backend.dry_run or not backend.wait):
            return 0
        bad = [r["name"] for r in res if r.get("exit_code") != 0]
        if bad:
            print(f"{len(bad)} of {len(res)} runs failed or did not end: "
                  f"{', '.join(bad[:5])}{' ...' if len(bad) > 5 else ''} (their run.log)",
                  file=sys.stderr)
    path = collect(cases, args.out)
    print(f"wrote {path} ({len(cases)} runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
