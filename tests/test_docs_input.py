#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The tables of docs/input.md must list exactly the input variables of the table in
src/input/mpm_config_table.f90 (what each variable accepts and means; the variable itself is a
component of its group's type).

For every group, the names in the first column of the table under the heading `## &<group>`
are compared with the rows `var_spec_t('<group>', '<name>', ...)` of the source; a name in one
but not the other is a failure. The unit column must be the unit in brackets at the end of the
row's echo comment (`-` when it has none), and for a variable with a list of names (its comment
holds `%`) the default column must name the default of its component in the types
(`character(len=name_len) :: basis = 'cpdi2'`). The variables used in the full example of the
docs must be in the tables as well. The error lines quoted in "## Error messages" must be what the binary
named by TUBEMPM (default bin/tubempm) prints for the file they name, each one verbatim (so an
example cannot go stale when a group gains a variable). Prints `test_docs_input: N passed, M
failed` last; exit 1 on failure. Standard library only.
"""
import os
import re
import subprocess
import sys
from pathlib import Path

from plots.mpmplot import namelist
from tests.pycheck import Checks

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "input.md"
SRC = ROOT / "src" / "input" / "mpm_config_table.f90"
TYPES = [ROOT / "src" / "input" / "mpm_config_types.f90",
         ROOT / "src" / "method" / "mpm_material.f90", ROOT / "src" / "bodies" / "mpm_bodies.f90"]

T = Checks("test_docs_input")
check = T.check


def source_groups(text):
    """{group: [variables]} from the rows `var_spec_t('group', 'name', ...)` of the table."""
    groups = {}
    for m in re.finditer(r"var_spec_t\(\s*'(\w+)'\s*,\s*'(\w+)'", text):
        groups.setdefault(m.group(1).lower(), []).append(m.group(2).lower())
    return groups


#: a text component of a Fortran type with its default: `character(len=name_len) :: basis = 'cpdi2'`
TYPE_DEFAULT = re.compile(r"character\(len=\w+\)\s*::\s*(\w+)\s*=\s*'(\w*)'")


def type_defaults():
    """{component: default text} of the text components of the input's types."""
    found = {}
    for path in TYPES:
        for m in TYPE_DEFAULT.finditer(path.read_text()):
            found.setdefault(m.group(1).lower(), m.group(2))
    return found


def source_rows(text):
    """{(group, name): (unit, default name or None)} from the rows of the table."""
    rows = {}
    defaults = type_defaults()
    for m in re.finditer(r"var_spec_t\(\s*'(\w+)'\s*,\s*'(\w+)'(.*?)\)\s*(?:,\s*&|\])", text,
                         re.DOTALL):
        rest = re.sub(r"'\s*//\s*&\s*\n\s*'", "", m.group(3))   # join continued texts
        comment = re.search(r"comment='((?:[^']|'')*)'", rest)
        unit = re.search(r"\[([^\]]*)\]\s*$", comment.group(1)) if comment else None
        listed = comment is not None and "%" in comment.group(1)
        rows[(m.group(1).lower(), m.group(2).lower())] = (
            unit.group(1) if unit else "-",
            defaults.get(m.group(2).lower(), "") if listed else None)
    return rows


def doc_rows(text):
    """(group, name, cells) for every variable named in the first column of the tables after
    each `## &group` heading, in order; a heading gives (group, None, None) first."""
    current = None
    for line in text.splitlines():
        h = re.match(r"^##\s+&(\w+)\s*$", line)
        if h:
            current = h.group(1).lower()
            yield current, None, None
            continue
        if line.startswith("## "):
            current = None
            continue
        if current is None or not line.startswith("|"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        for name in re.findall(r"`([A-Za-z_]\w*)`", cells[0]):
            yield current, name.lower(), cells


def doc_cells(text):
    """{(group, name): [cells of its table row]}."""
    return {(g, name): cells for g, name, cells in doc_rows(text) if name}


def doc_groups(text):
    """{group: [variables]} from the first column of the table after each `## &group`."""
    groups = {}
    for g, name, _ in doc_rows(text):
        groups.setdefault(g, [])
        if name:
            groups[g].append(name)
    return groups


def example_names(text):
    """{group: set of variables assigned} in the fenced example block of the docs."""
    m = re.search(r"## Full example.*?```\w*\n(.*?)```", text, re.DOTALL)
    if not m:
        return None
    used = {}
    for group, entries in namelist.parse_namelist(m.group(1), "docs/input.md").items():
        used.setdefault(group, set()).update(k for e in entries for k in e)
    return used


def main():
    src_text = SRC.read_text()
    doc_text = DOC.read_text()
    src = source_groups(src_text)
    doc = doc_groups(doc_text)
    check(len(src) > 0, f"no var_spec_t rows found in {SRC}")
    check(len(doc) > 0, f"no '## &group' tables found in {DOC}")
    for group in sorted(set(src) | set(doc)):
        check(group in doc, f"&{group} is read by {SRC.name} but has no table in {DOC.name}")
        check(group in src, f"&{group} has a table in {DOC.name} but no rows in {SRC.name}")
        s = set(src.get(group, []))
        d = set(doc.get(group, []))
        for name in sorted(s | d):
            check(name in d, f"&{group}: {name} is in the namelist but not in the docs table")
            check(name in s, f"&{group}: {name} is in the docs table but not in the namelist")
        dup = sorted({n for n in doc.get(group, []) if doc[group].count(n) > 1})
        check(not dup, f"&{group}: listed more than once in the docs: {dup}")
    rows = source_rows(src_text)
    cells_of = doc_cells(doc_text)
    check(len(rows) == sum(len(v) for v in src.values()), "every row of the table parsed")
    for key in sorted(set(rows) & set(cells_of)):
        unit, default = rows[key]
        cells = cells_of[key]
        check(len(cells) >= 5 and cells[2] == unit,
              f"&{key[0]}: {key[1]}: unit {cells[2] if len(cells) > 2 else '?'!r} in the docs, "
              f"{unit!r} in the table's comment")
        check(default != "", f"&{key[0]}: {key[1]}: no default in the types ({TYPES[0].name} ...)")
        if default is not None:
            check(len(cells) >= 5 and f"'{default}'" in cells[4],
                  f"&{key[0]}: {key[1]}: default '{default}' of the table not in the docs")
    used = example_names(doc_text)
    check(used is not None, "docs/input.md has no '## Full example' with a fenced block")
    for group, names in (used or {}).items():
        for name in sorted(names):
            check(name in set(doc.get(group, [])),
                  f"the full example sets &{group}: {name}, which no table documents")
    check_quoted_errors(doc_text)
    return T.summary()


def check_quoted_errors(doc_text):
    """Each quoted `ERROR [input]: tests/bad_inputs/<file>:...` line is one the binary prints."""
    quoted = {}
    for m in re.finditer(r"(?m)^ {4}(ERROR \[input\]: (tests/bad_inputs/[\w.]+?\.nml)\b.*)$",
                         doc_text):
        quoted.setdefault(m.group(2), []).append(m.group(1))
    check(len(quoted) >= 2, f"docs/input.md quotes the errors of bad inputs ({sorted(quoted)})")
    binary = os.environ.get("TUBEMPM", str(ROOT / "bin" / "tubempm"))
    for rel, lines in sorted(quoted.items()):
        try:
            proc = subprocess.run([binary, rel], cwd=ROOT, capture_output=True, text=True,
                                  timeout=60)
        except OSError as exc:
            check(False, f"{binary} {rel}: cannot run ({exc})")
            continue
        printed = set(proc.stderr.splitlines())
        check(proc.returncode == 2, f"{rel}: exit 2 (got {proc.returncode})")
        for line in lines:
            check(line in printed, f"docs/input.md quotes a line {binary} does not print for "
                  f"{rel}: {line!r}")


if __name__ == "__main__":
    sys.exit(main())
