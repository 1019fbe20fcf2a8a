"""Markdown reports: tables for the studies, and one campaign report stitched
from the per-scene ``report.md`` files with their figures linked."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from shroud.base.markdown import demote, markdown_table, relink, seconds

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
