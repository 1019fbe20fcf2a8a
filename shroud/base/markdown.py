"""Markdown for reports: tables, run times, links and headings of nested reports."""

from __future__ import annotations

import re
from typing import Sequence

# [text](target) and ![alt](target); the target is rewritten when relative.
_LINK = re.compile(r"(!?\[[^\]]*\]\()([^)\s]+)(\))")
_HEADING = re.compile(r"^(#{1,5}) ", flags=re.MULTILINE)


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[object]]) -> str:
    """A Markdown table; floats are printed with 4 significant digits."""
    def cell(v: object) -> str:
        if v is None:
            return "-"
        if isinstance(v, float):
            return f"{v:.4g}"
        return str(v).replace("|", "\\|")
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(cell(v) for v in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def seconds(t: float | None) -> str:
    """A wall time for a report: 0.042 s, 12.3 s, 4 min 05 s."""
    if t is None:
        return "-"
    if t < 1:
        return f"{t:.3f} s"
    if t < 120:
        return f"{t:.1f} s"
    return f"{int(t // 60)} min {int(t % 60):02d} s"


def relink(markdown: str, prefix: str) -> str:
    """Prefix every relative link and image target with ``prefix/``."""
    def fix(m: re.Match) -> str:
        target = m.group(2)
        if re.match(r"^([a-z]+:|/|#)", target):
            return m.group(0)
        return f"{m.group(1)}{prefix}/{target}{m.group(3)}"
    return _LINK.sub(fix, markdown)


def demote(markdown: str) -> str:
    """Every heading one level deeper, so a scene's report nests under its own section."""
    return _HEADING.sub(lambda m: "#" + m.group(1) + " ", markdown)
