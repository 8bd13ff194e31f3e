# SPDX-License-Identifier: MIT
"""The namelist reader: ``input.nml``, ``summary.nml`` and any case file (docs/input.md).

A small tolerant reader of Fortran namelist text, independent of the Fortran code's own reader;
``fortran_float`` reads a number as Fortran writes it (also used for history.csv).
"""
from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

__all__ = ["NamelistError", "read_namelist", "parse_namelist", "fortran_float"]


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


def _tokens(text: str, where: str) -> list[tuple[str, str, int]]:
    """(kind, text, line number) tokens of a namelist file, comments removed."""
    out: list[tuple[str, str, int]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = _strip_comment(raw)
        pos = 0
        while pos < len(line):
            if line[pos:].strip() == "":
                break
            m = _TOKEN.match(line, pos)
            if not m or m.end() == pos:
                raise NamelistError(f"{where}:{lineno}: cannot read {line[pos:].strip()!r}")
            kind = m.lastgroup or "word"
            out.append((kind, m.group(kind), lineno))
            pos = m.end()
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
    toks = _tokens(text, where)
    groups: dict[str, list[dict[str, Any]]] = {}
    i = 0
    n = len(toks)
    while i < n:
        kind, tok, _ = toks[i]
        i += 1
        if kind != "group" or tok[1:].lower() == "end":
            continue                           # text outside a group
        gname = tok[1:].lower()
        entries: dict[str, Any] = {}
        closed = False
        while i < n:
            kind, tok, line = toks[i]
            if kind == "slash" or (kind == "group" and tok[1:].lower() == "end"):
                i += 1
                closed = True
                break
            if kind == "group":
                raise NamelistError(f"{where}:{line}: &{gname} is not closed with '/' before "
                                    f"{tok}")
            if kind != "word" or i + 1 >= n or toks[i + 1][0] != "eq":
                raise NamelistError(f"{where}:{line}: &{gname}: expected 'name = value', "
                                    f"found {tok!r}")
            name = tok.lower()
            i += 2
            values: list[Any] = []
            pending = True                     # a value may follow (start, or after a comma)
            while i < n:
                kind, tok, line = toks[i]
                if kind in ("slash", "group"):
                    break
                if kind == "word" and i + 1 < n and toks[i + 1][0] == "eq":
                    break                      # the next 'name ='
                if kind == "comma":
                    if pending:
                        values.append(None)    # null value
                    pending = True
                    i += 1
                    continue
                if kind == "eq":
                    raise NamelistError(f"{where}:{line}: &{gname}: unexpected '='")
                rep = re.fullmatch(r"(\d+)\*(.*)", tok) if kind == "word" else None
                if rep:
                    count = int(rep.group(1))
                    if rep.group(2):
                        val = _convert("word", rep.group(2))
                    elif i + 1 < n and toks[i + 1][0] in ("str1", "str2"):
                        i += 1
                        val = _convert(toks[i][0], toks[i][1])
                    else:
                        val = None
                    values.extend([val] * count)
                else:
                    values.append(_convert(kind, tok))
                pending = False
                i += 1
            _assign(entries, name, values)
        if not closed:
            raise NamelistError(f"{where}: &{gname} is not closed with '/'")
        groups.setdefault(gname, []).append(entries)
    return groups


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
