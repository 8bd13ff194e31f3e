#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Every link of the manual leads somewhere: each relative Markdown link of README.md,
docs/**/*.md and plots/README.md names an existing file, and its #anchor a heading of that file
(GitHub's slugs: lower case, punctuation dropped, spaces to hyphens) or an `<a id="...">`
anchor; and every
`docs/<file>.md#<anchor>` that the code prints (warnings and errors in src/) is one too.

    python3 -m tests.test_doc_links [SCRATCH]
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

from tests.pycheck import Checks

ROOT = Path(__file__).resolve().parent.parent

T = Checks("test_doc_links")
LINK = re.compile(r"\]\(([^)\s]+)\)")
CODE_REF = re.compile(r"docs/([A-Za-z0-9_/.-]+\.md)#([A-Za-z0-9_-]+)")


def slug(heading: str) -> str:
    """GitHub's anchor of a heading."""
    s = heading.strip().lower()
    s = re.sub(r"[`*_]", "", s)
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    out: set[str] = set()
    fence = False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            fence = not fence
        if not fence:
            out.update(re.findall(r'<a id="([^"]+)"></a>', line))
        if not fence and line.startswith("#"):
            base = slug(line.lstrip("#"))
            k, name = 1, base
            while name in out:
                name = f"{base}-{k}"
                k += 1
            out.add(name)
    return out


def main() -> int:
    files = [ROOT / "README.md", ROOT / "plots" / "README.md",
             *sorted((ROOT / "docs").rglob("*.md"))]
    cache: dict[Path, set[str]] = {}
    n = 0
    for f in files:
        text = f.read_text(encoding="utf-8")
        text = re.sub(r"```.*?```", "", text, flags=re.S)
        for m in LINK.finditer(text):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue                              # http:, https:, mailto:
            path_part, _, anchor = target.partition("#")
            dest = (f.parent / path_part).resolve() if path_part else f
            n += 1
            if not T.check(dest.exists(), f"{f.relative_to(ROOT)}: link {target} names a "
                                          f"missing file"):
                continue
            if anchor and dest.suffix == ".md":
                cache.setdefault(dest, anchors(dest))
                T.check(anchor in cache[dest], f"{f.relative_to(ROOT)}: link {target}: no "
                                               f"heading #{anchor} in {dest.name}")
    for src in sorted((ROOT / "src").rglob("*.f90")):
        for m in CODE_REF.finditer(src.read_text(encoding="utf-8")):
            dest = ROOT / "docs" / m.group(1)
            n += 1
            if T.check(dest.is_file(), f"{src.relative_to(ROOT)}: prints docs/{m.group(1)}, "
                                       f"which does not exist"):
                cache.setdefault(dest, anchors(dest))
                T.check(m.group(2) in cache[dest], f"{src.relative_to(ROOT)}: prints "
                                                   f"{m.group(0)}: no such heading")
    print(f"  {n} links checked")
    return T.summary()


if __name__ == "__main__":
    sys.exit(main())
