# SPDX-License-Identifier: MIT
"""The namelist reader and editor: ``input.nml``, ``summary.nml`` and any case file
(docs/input.md). The project's only Python reader of namelist text: plots/, tools/ and tests/
all read and edit namelists through it.

A small tolerant reader of Fortran namelist text, independent of the Fortran code's own reader;
``fortran_float`` reads a number as Fortran writes it (also used for history.csv).
``set_values`` writes values into namelist text, keeping everything else as it is, and
``format_value`` writes one Python value as namelist text.
"""
from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

__all__ = ["NamelistError", "read_namelist", "parse_namelist", "parse_values", "fortran_float",
           "format_value", "set_values", "split_key"]


def fortran_float(text: str) -> float:
    """A number as Fortran writes it (``1.0D+00``, ``1.0+100``, ``Infinity``, ``NaN``)."""
    s = text.strip().lower().replace("d", "e")
    try:
        return float(s)
    except ValueError:
        # Fortran drops the 'e' of three-digit exponents with some edit descriptors: 1.0-100
        m = re.fullmatch(r"([+-]?[0-9.]+)([+-][0-9]+)", s)
        if m:
            return float(m.group(1) + "e" + m.group(2))
        raise ValueError(f"not a number: {text.strip()!r}") from None


class NamelistError(ValueError):
    """A namelist file that cannot be read."""


_TOKEN = re.compile(
    r"""\s*(?:
        (?P<str1>'(?:[^']|'')*')
      | (?P<str2>"(?:[^"]|"")*")
      | (?P<group>[&$][A-Za-z_]\w*)
      | (?P<eq>=)
      | (?P<comma>,)
      | (?P<slash>/)
      | (?P<word>[^\s,=/'"]+)
    )""",
    re.VERBOSE,
)


class _Tok(NamedTuple):
    kind: str
    text: str
    line: int        #: 1-based line number
    start: int       #: offset of the token's first character in the whole text
    end: int         #: offset just past its last character


@dataclass
class _Assignment:
    name: str                 #: lower case, with its subscript: ``point(2)``
    values: list[Any]
    first: _Tok               #: the name
    last: _Tok                #: its last value (the '=' when there is none)


@dataclass
class _Group:
    name: str                 #: lower case, without '&'
    opening: _Tok
    closing: _Tok | None = None
    assignments: list[_Assignment] = field(default_factory=list)


def _strip_comment(line: str) -> str:
    """The line without its ``!`` comment (a ``!`` inside quotes is kept)."""
    quote = ""
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = ""
        elif ch in "'\"":
            quote = ch
        elif ch == "!":
            return line[:i]
    return line


def _tokens(text: str, where: str) -> list[_Tok]:
    """The tokens of a namelist text, comments removed."""
    out: list[_Tok] = []
    offset = 0
    for lineno, raw in enumerate(text.splitlines(keepends=True), start=1):
        line = _strip_comment(raw)
        pos = 0
        while pos < len(line):
            if line[pos:].strip() == "":
                break
            m = _TOKEN.match(line, pos)
            if not m or m.end() == pos:
                raise NamelistError(f"{where}:{lineno}: cannot read {line[pos:].strip()!r}")
            kind = m.lastgroup or "word"
            out.append(_Tok(kind, m.group(kind), lineno, offset + m.start(kind),
                            offset + m.end(kind)))
            pos = m.end()
        offset += len(raw)
    return out


def _convert(kind: str, text: str) -> Any:
    """One namelist value: str, bool, int or float (other bare words stay strings)."""
    if kind == "str1":
        return text[1:-1].replace("''", "'")
    if kind == "str2":
        return text[1:-1].replace('""', '"')
    low = text.lower()
    if re.fullmatch(r"\.?t(rue)?\.?", low):
        return True
    if re.fullmatch(r"\.?f(alse)?\.?", low):
        return False
    if re.fullmatch(r"[+-]?\d+", text):
        return int(text)
    try:
        return fortran_float(text)
    except ValueError:
        return text


def _closes(tok: _Tok) -> bool:
    return tok.kind == "slash" or (tok.kind == "group" and tok.text[1:].lower() == "end")


def _values(toks: list[_Tok], i: int, gname: str, where: str) -> tuple[list[Any], int]:
    """The values from toks[i] up to the next 'name =', '/' or group; and the index after."""
    n = len(toks)
    values: list[Any] = []
    pending = True                     # a value may follow (start, or after a comma)
    while i < n:
        tok = toks[i]
        if tok.kind in ("slash", "group"):
            break
        if tok.kind == "word" and i + 1 < n and toks[i + 1].kind == "eq":
            break                      # the next 'name ='
        if tok.kind == "comma":
            if pending:
                values.append(None)    # null value
            pending = True
            i += 1
            continue
        if tok.kind == "eq":
            raise NamelistError(f"{where}:{tok.line}: &{gname}: unexpected '='")
        rep = re.fullmatch(r"(\d+)\*(.*)", tok.text) if tok.kind == "word" else None
        if rep:
            count = int(rep.group(1))
            if rep.group(2):
                val = _convert("word", rep.group(2))
            elif i + 1 < n and toks[i + 1].kind in ("str1", "str2"):
                i += 1
                val = _convert(toks[i].kind, toks[i].text)
            else:
                val = None
            values.extend([val] * count)
        else:
            values.append(_convert(tok.kind, tok.text))
        pending = False
        i += 1
    return values, i


def _scan(text: str, where: str) -> list[_Group]:
    """Every group of a namelist text, in file order, with its assignments and where they
    stand; text outside groups is skipped."""
    toks = _tokens(text, where)
    groups: list[_Group] = []
    i = 0
    n = len(toks)
    while i < n:
        tok = toks[i]
        i += 1
        if tok.kind != "group" or tok.text[1:].lower() == "end":
            continue                           # text outside a group
        group = _Group(tok.text[1:].lower(), tok)
        while i < n:
            tok = toks[i]
            if _closes(tok):
                group.closing = tok
                i += 1
                break
            if tok.kind == "group":
                raise NamelistError(f"{where}:{tok.line}: &{group.name} is not closed with '/' "
                                    f"before {tok.text}")
            if tok.kind != "word" or i + 1 >= n or toks[i + 1].kind != "eq":
                raise NamelistError(f"{where}:{tok.line}: &{group.name}: expected "
                                    f"'name = value', found {tok.text!r}")
            values, j = _values(toks, i + 2, group.name, where)
            last = j - 1
            while last > i + 1 and toks[last].kind == "comma":
                last -= 1                      # the commas after the values are not theirs
            group.assignments.append(_Assignment(tok.text.lower(), values, tok, toks[last]))
            i = j
        if group.closing is None:
            raise NamelistError(f"{where}: &{group.name} is not closed with '/'")
        groups.append(group)
    return groups


def read_namelist(path: str | os.PathLike) -> dict[str, list[dict[str, Any]]]:
    """Read every namelist group of a file: ``{group: [ {name: value}, ... ]}``.

    Group and variable names are lower case; a group that occurs several times (``&material``,
    ``&body``, ``&wall``, ``&probe``) gives several dicts, in file order. Values are ``str``
    (quotes removed), ``bool`` (``.true.``, ``T``), ``int``, ``float`` (``1.0d-3`` too), or a
    list of those for arrays (``a, b`` or ``3*0.0``; values may continue on the next lines).
    ``name(i) = v`` sets element i. ``!`` starts a comment outside quotes; text outside
    groups is ignored.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: namelist file not found")
    return parse_namelist(path.read_text(errors="replace"), str(path))


def parse_namelist(text: str, where: str = "<text>") -> dict[str, list[dict[str, Any]]]:
    """:func:`read_namelist` on a string (``where`` names it in error messages)."""
    groups: dict[str, list[dict[str, Any]]] = {}
    for group in _scan(text, where):
        entries: dict[str, Any] = {}
        for a in group.assignments:
            _assign(entries, a.name, a.values)
        groups.setdefault(group.name, []).append(entries)
    return groups


def parse_values(text: str, where: str = "<value>") -> Any:
    """A value as written after ``name =`` in a namelist (``0.0, -5.0``, ``'usl'``, ``2*1.0``,
    ``.true.``): one value, or a list when there are several."""
    toks = _tokens(text, where)
    bad = [t for t in toks if t.kind in ("eq", "slash", "group")]
    if bad:
        raise NamelistError(f"{where}: {text.strip()!r}: {bad[0].text!r} in a value")
    values, _ = _values(toks, 0, "value", where)
    return values[0] if len(values) == 1 else values


def _assign(entries: dict[str, Any], name: str, values: list[Any]) -> None:
    """Store values under name; ``name(i)`` or ``name(i:j)`` sets elements (1-based)."""
    m = re.fullmatch(r"(\w+)\((\d+)(?::(\d+))?\)", name)
    if not m:
        entries[name] = values[0] if len(values) == 1 else values
        return
    base, first = m.group(1), int(m.group(2))
    current = entries.get(base, [])
    if not isinstance(current, list):
        current = [current]
    need = first - 1 + len(values)
    current = current + [None] * max(0, need - len(current))
    current[first - 1:first - 1 + len(values)] = values
    entries[base] = current


# ----------------------------------------------------------------------------------------------
# Writing: values into namelist text
# ----------------------------------------------------------------------------------------------

def format_value(value: Any) -> str:
    """A Python value as namelist text (``'it''s'``, ``.true.``, ``1.5``, ``0.0, -5.0``)."""
    if isinstance(value, bool):
        return ".true." if value else ".false."
    if isinstance(value, str):
        return "'" + value.replace("'", "''") + "'"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value).replace("inf", "Inf")
    if isinstance(value, (list, tuple)):
        return ", ".join(format_value(v) for v in value)
    raise TypeError(f"no namelist form for {value!r}")


_KEY = re.compile(r"^([a-z_]\w*)(?:\[(\d+)\])?\.([a-z_]\w*)$", re.IGNORECASE)


def split_key(key: str) -> tuple[str, int, str]:
    """``"group.var"`` -> (group, 1, var); ``"group[k].var"`` -> (group, k, var): the k-th
    instance of the group (1-based). Lower case; ValueError for any other form."""
    m = _KEY.match(key)
    if not m:
        raise ValueError(f"key {key!r}: expected 'group.var' or 'group[k].var'")
    return m.group(1).lower(), int(m.group(2) or 1), m.group(3).lower()


def _line_start(text: str, pos: int) -> int:
    return text.rfind("\n", 0, pos) + 1


def _line_end(text: str, pos: int) -> int:
    end = text.find("\n", pos)
    return len(text) if end < 0 else end


def set_values(text: str, values: dict[str, Any], where: str = "<text>") -> str:
    """The namelist ``text`` with ``values`` set: ``{"group.var" or "group[k].var": value}``
    (see :func:`split_key`; a value is a Python value, written by :func:`format_value`).

    An assignment of the variable already in that group instance is replaced: the whole line
    (its comment, which described the old value, goes too) when the line holds nothing else,
    else the assignment alone. Otherwise the assignment is added on a line of its own before
    the group's closing ``/``. The value None removes the variable's assignments (the same
    way: their lines, or the assignments alone). Everything else stays as it is. A group instance that is not in
    the text is a ValueError, and so is a key of another form.
    """
    wanted: dict[tuple[str, int], dict[str, str]] = {}
    for key, value in values.items():
        group, k, var = split_key(key)
        wanted.setdefault((group, k), {})[var] = None if value is None else format_value(value)
    count: dict[str, int] = {}
    edits: list[tuple[int, int, str]] = []         # (start, end, new text), in text order
    for group in _scan(text, where):
        count[group.name] = count.get(group.name, 0) + 1
        todo = wanted.get((group.name, count[group.name]), {})
        done = set()
        for a in group.assignments:
            if a.name not in todo:
                continue
            done.add(a.name)
            value = todo[a.name]
            head = _line_start(text, a.first.start)
            tail = _line_end(text, a.last.end)
            rest = _strip_comment(text[a.last.end:tail]).strip()
            if text[head:a.first.start].strip() == "" and rest in ("", ","):
                if value is None:                  # the line and its line end
                    edits.append((head, min(tail + 1, len(text)), ""))
                else:
                    edits.append((head, tail, text[head:a.first.start] + f"{a.name} = {value}"))
            elif value is None:                    # the assignment, its comma and blanks
                after = text[a.last.end:tail]
                gap = len(after) - len(after.lstrip(" \t"))
                if after[gap:gap + 1] == ",":
                    gap += 1 + len(after[gap + 1:]) - len(after[gap + 1:].lstrip(" \t"))
                edits.append((a.first.start, a.last.end + gap, ""))
            else:
                edits.append((a.first.start, a.last.end, f"{a.name} = {value}"))
        added = [f"  {var} = {val}" for var, val in todo.items()
                 if var not in done and val is not None]
        if added:
            close = group.closing
            head = _line_start(text, close.start)
            if text[head:close.start].strip() == "":
                edits.append((head, head, "\n".join(added) + "\n"))
            else:
                cut = len(text[:close.start].rstrip(" \t"))
                edits.append((cut, close.start, "\n" + "\n".join(added) + "\n"))
    missing = [f"&{g}[{k}]" for (g, k) in wanted if count.get(g, 0) < k]
    if missing:
        raise ValueError(f"{where}: no group instance " + ", ".join(missing)
                         + " to set a value in")
    for start, end, new in reversed(edits):
        text = text[:start] + new + text[end:]
    return text if text.endswith("\n") else text + "\n"
