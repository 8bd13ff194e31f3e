#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The Python side is one package tree with one namelist reader (docs/architecture.md):

- nothing in plots/, tools/ or tests/ changes the module search path (no `sys.path` edit, no
  `site.addsitedir`), in Python files or in the Python inside shell scripts;
- every folder of them that holds Python is a package (an ``__init__.py``), and every module
  imports from the repository root with no PYTHONPATH, as ``python3 -m plots.plot_case`` has it;
- no README, doc, Makefile or help text tells to run a script by its path
  (``python3 plots/plot_case.py``, which cannot import the packages), and each module a
  ``python3 -m`` command names exists;
- only ``plots/mpmplot/namelist.py`` reads namelist text: no other Python file matches a group
  start (``&name``) or a ``name =`` assignment with a regular expression, or looks for a line
  starting with ``&``. tools/fuzz_namelists.py is let through: it mutates namelist text on
  purpose, to feed the Fortran reader broken input.

Each checker is first run on made-up text that it must catch. Prints
`test_python_layout: N passed, M failed` last. Standard library only.
"""
from __future__ import annotations

import io
import os
import re
import subprocess
import sys
import tokenize
from pathlib import Path

from tests.pycheck import Checks

ROOT = Path(__file__).resolve().parent.parent
T = Checks("test_python_layout")
check = T.check

FOLDERS = ("plots", "tools", "tests")
#: folders of Python that are not packages, and why
NOT_PACKAGES = {"tests/paraview": "run by ParaView's pvbatch, not imported"}
#: the one namelist reader, and the files let through the parser check (with the reason)
READER = "plots/mpmplot/namelist.py"
PARSER_EXEMPT = {"tools/fuzz_namelists.py": "mutates namelist text to feed the Fortran reader"}
#: single regular expressions let through: (file, the literal) -> why
REGEX_EXEMPT = {("tests/test_docs_input.py", r'r"^##\s+&(\w+)\s*$"'):
                "the '## &group' headings of docs/input.md, markdown, not namelist text",
                ("tests/test_docs_input.py",
                 'r"' + r"character\(len=\w+\)\s*::\s*(\w+)\s*=\s*'(\w*)'" + '"'):
                "the defaults of the Fortran types, Fortran source, not namelist text"}

# the patterns are joined from pieces so that this file does not match itself
PATH_EDIT = re.compile(r"\bsys\.path\s*(\.\s*(insert|append|extend)\s*\(|\+?=[^=])"
                       r"|\bsite\." + r"addsitedir\b")
GROUP_REGEX = re.compile("&" + r"(\$\])?(\(|\\w|\[|\{)")
ASSIGN_REGEX = re.compile(r"(\\w\+?\)?|\}|\))\\s\*" + "=")
STARTS_AMP = re.compile(r"startswith\(\s*['\"]" + "&")


def python_files() -> list[Path]:
    return sorted(p for d in FOLDERS for p in (ROOT / d).rglob("*.py"))


def code_lines(name: str, text: str) -> list[tuple[int, str]]:
    """(line, code) of a source without its comments, and for Python without its strings
    (the Python of a shell script is in its here-documents and -c strings, so kept there)."""
    if not name.endswith(".py"):
        return [(n, ln.split("#", 1)[0] if ln.lstrip().startswith("#") else ln)
                for n, ln in enumerate(text.splitlines(), start=1)]
    lines: dict[int, str] = {}
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type not in (tokenize.STRING, tokenize.COMMENT):
            lines[tok.start[0]] = lines.get(tok.start[0], "") + tok.string
    return sorted(lines.items())


def path_edits(name: str, text: str) -> list[str]:
    """`file:line` of each change of the module search path in code."""
    return [f"{name}:{n}" for n, code in code_lines(name, text) if PATH_EDIT.search(code)]


def strings(text: str) -> list[tuple[int, str]]:
    """(line, text) of every string literal of a Python source."""
    out = []
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type == tokenize.STRING:
            out.append((tok.start[0], tok.string))
    return out


def parser_signs(name: str, text: str) -> list[str]:
    """`file:line: what` of each sign of a namelist parser in a Python source: a regular
    expression (a raw string) for a group start or an assignment, or startswith('&')."""
    hits = []
    for n, s in strings(text):
        prefix = s[:s.index(s[-1])].lower()
        if "r" not in prefix or (name, s) in REGEX_EXEMPT:
            continue                                   # a regex is written as a raw string
        if GROUP_REGEX.search(s):
            hits.append(f"{name}:{n}: a regex for a group start: {s[:60]}")
        elif ASSIGN_REGEX.search(s):
            hits.append(f"{name}:{n}: a regex for an assignment: {s[:60]}")
    for n, line in enumerate(text.splitlines(), start=1):
        if STARTS_AMP.search(line):
            hits.append(f"{name}:{n}: a line starting with '&': {line.strip()[:60]}")
    return hits


def check_checkers() -> None:
    """The checkers catch what they are for, and let ordinary code through."""
    fake_insert = "import sys\nsys.path" + ".insert(0, 'plots')\n"
    check(path_edits("fake.py", fake_insert) == ["fake.py:2"], "a sys.path insert is caught")
    check(path_edits("fake.sh", "python3 -c 'import sys; sys.path" + " += [\"x\"]'\n")
          == ["fake.sh:1"], "a sys.path edit inside a shell script is caught")
    check(path_edits("fake.py", "print(sys.path)\n# sys.path" + ".insert(0, x)\n") == [],
          "reading sys.path, or a comment, is not an edit")
    fakes = {
        "group start": 'START = re.compile(r"^\\s*' + '&([a-z_]\\w*)", re.I)\n',
        "group of a name": 'm = re.search(rf"(?im)^(\\s*' + '&{group}\\b)", text)\n',
        "assignment": 'm = re.search(rf"(?im)^\\s*{name}\\s*' + '=\\s*([^!\\n]*)", text)\n',
        "line start": "if ln.startswith('" + "&'):\n    pass\n",
    }
    for what, src in fakes.items():
        check(len(parser_signs("fake.py", src)) == 1, f"a parser's {what} is caught: {src!r}")
    ordinary = ('TEXT = "' + '&summary\\n status = \'ok\'\\n/\\n"\n'
                'KEY = re.compile(r"^(\\w+)=(.*)$")\nx = a & b\n')
    check(parser_signs("fake.py", ordinary) == [], "namelist text as data, '&' as an operator "
          "and a KEY=VALUE split are not parsers")
    check(parser_signs(READER, (ROOT / READER).read_text()) != [],
          f"{READER}, the reader, shows the signs the check looks for")


def check_no_path_edits() -> None:
    files = python_files() + sorted(p for d in FOLDERS for p in (ROOT / d).rglob("*.sh"))
    hits = [h for p in files
            for h in path_edits(str(p.relative_to(ROOT)), p.read_text(errors="replace"))]
    check(len(files) > 50 and not hits,
          f"no change of the module search path in {len(files)} files: {hits[:5]}")


def check_packages() -> list[str]:
    """Every folder of Python is a package; returns the module names."""
    folders = sorted({p.parent for p in python_files()})
    missing = [str(f.relative_to(ROOT)) for f in folders
               if not (f / "__init__.py").is_file()
               and str(f.relative_to(ROOT)) not in NOT_PACKAGES]
    check(not missing, f"every folder of Python is a package (__init__.py): missing {missing}")
    mods = []
    for p in python_files():
        rel = p.relative_to(ROOT)
        if str(rel.parent) in NOT_PACKAGES or p.name == "__init__.py":
            continue
        mods.append(".".join(rel.with_suffix("").parts))
    return mods


def check_imports(mods: list[str]) -> None:
    """Each module imports in a fresh interpreter started in the repository root, without
    PYTHONPATH (matplotlib and h5py as installed; a module that cannot import says why)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["MPLBACKEND"] = "Agg"
    code = ("import importlib, sys\nbad = []\nfor m in sys.argv[1:]:\n"
            "    try:\n        importlib.import_module(m)\n"
            "    except BaseException as e:\n        bad.append(f'{m}: {type(e).__name__}: {e}')\n"
            "print('\\n'.join(bad))\n")
    p = subprocess.run([sys.executable, "-c", code, *mods], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=300)
    bad = [ln for ln in p.stdout.splitlines() if ln.strip()]
    check(p.returncode == 0 and not bad and len(mods) > 50,
          f"{len(mods)} modules import from the root with no PYTHONPATH: "
          f"{bad[:5]} {p.stderr.strip()[-300:]}")


def tracked_text() -> dict[str, str]:
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True,
                           text=True).stdout.split()
    out = {}
    for f in files:
        if f.startswith("src/") or not (ROOT / f).is_file():
            continue
        try:
            out[f] = (ROOT / f).read_text()
        except (UnicodeDecodeError, OSError):
            continue
    return out


def check_commands(texts: dict[str, str]) -> None:
    """No doc tells to run a script by its path; each module of a `-m` command exists."""
    by_path = re.compile(r"(python3?|\$\(PYTHON\)|\$py|\$\{PYTHON[^}]*\})\s+\"?"
                         r"((plots|tools|tests)/[\w/]+\.py)")
    module = re.compile(r"-m\s+((plots|tools|tests)(\.\w+)+)")
    old, gone = [], []
    for f, text in texts.items():
        for m in by_path.finditer(text):
            if f != "tests/test_python_layout.py":
                old.append(f"{f}: {m.group(0)}")
        for m in module.finditer(text):
            path = ROOT / (m.group(1).replace(".", "/") + ".py")
            if not path.is_file():
                gone.append(f"{f}: {m.group(0)}")
    check(not old, f"no command runs a script by its path (python3 -m instead): {old[:5]}")
    check(not gone, f"every module a 'python3 -m' command names exists: {gone[:5]}")
    check(sum("python3 -m plots.plot_case" in t for t in texts.values()) >= 2,
          "the docs show python3 -m plots.plot_case")


def check_one_reader() -> None:
    hits = []
    for p in python_files():
        rel = str(p.relative_to(ROOT))
        if rel in (READER, "tests/test_python_layout.py") or rel in PARSER_EXEMPT:
            continue
        hits += parser_signs(rel, p.read_text())
    check(not hits, f"only {READER} parses namelist text: {hits[:5]}")


def main() -> int:
    check_checkers()
    check_no_path_edits()
    check_imports(check_packages())
    check_commands(tracked_text())
    check_one_reader()
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
