"""Markdown reports: tables for the studies, and one campaign report stitched
from the per-scene ``report.md`` files with their figures linked."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
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


@dataclass(frozen=True)
class SceneOutcome:
    """One scene of a campaign as its results.json records it."""

    name: str
    study: str
    title: str
    status: str
    elapsed_s: float | None
    folder: Path


def stitch(out: Path, title: str, outcomes: Sequence[SceneOutcome], preamble: str = "") -> Path:
    """``out/report.md``: a summary table, then each scene's report with its figures."""
    rows = [(f"[{o.name}](#{_anchor(o.name)})", o.study, o.status, seconds(o.elapsed_s),
             f"[report]({o.name}/report.md)" if (o.folder / "report.md").exists() else "-")
            for o in outcomes]
    parts = [f"# {title}\n\n", preamble,
             markdown_table(("scene", "study", "status", "wall time", "files"), rows), "\n"]
    for o in outcomes:
        parts.append(f"## {o.name}\n\n*{o.title}* - {o.status}, {seconds(o.elapsed_s)}\n\n")
        report = o.folder / "report.md"
        if report.exists():
            body = report.read_text()
            body = re.sub(r"\A# [^\n]*\n", "", body)      # the section heading replaces its title
            parts.append(relink(demote(body), o.name).strip() + "\n\n")
        else:
            parts.append("(no report written)\n\n")
    path = out / "report.md"
    path.write_text("".join(parts))
    return path


def _anchor(name: str) -> str:
    return re.sub(r"[^a-z0-9_ -]", "", name.lower()).replace(" ", "-")
