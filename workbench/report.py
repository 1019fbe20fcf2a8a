"""Markdown reports: tables for the studies, and one campaign report stitched
from the per-scene ``report.md`` files with their figures linked."""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from shroud.base.markdown import demote, markdown_table, relink, seconds
from shroud.base.outputs import write_text

@dataclass(frozen=True)
class SceneOutcome:
    """One scene of a campaign as its results.json records it."""

    name: str
    study: str
    title: str
    status: str
    elapsed_s: float | None
    folder: Path
    gates: tuple[dict, ...] = ()          # gate records (workbench.gates.hold)


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
    write_text(path, "".join(parts))
    return path


def gate_table(records: Sequence[dict]) -> str:
    """A Markdown table of gate records: what held, what broke and by how much."""
    rows = [("held" if r["passed"] else "**FAILED**", f"`{r['path']}`", _cell(r["value"]), r["min"], r["max"],
             _cell(r.get("equals")), r["margin"], r["message"]) for r in records]
    return markdown_table(("gate", "path", "value", "min", "max", "equals", "margin", "detail"), rows)


def _cell(value):
    """A gated value as the table shows it: a number as a number, a yes/no or word as JSON writes it."""
    return json.dumps(value) if isinstance(value, (bool, str)) else value


def open_with_gates(report: Path, records: Sequence[dict]) -> None:
    """Put the gate table at the top of ``report`` (under its title), or start a report with it."""
    failed = sum(not r["passed"] for r in records)
    section = (f"## Gates: {len(records) - failed} of {len(records)} held"
               + (f", {failed} failed" if failed else "") + "\n\n" + gate_table(records) + "\n")
    text = report.read_text() if report.exists() else ""
    title = re.match(r"\A# [^\n]*\n+", text)
    head, body = (title.group(0), text[title.end():]) if title else ("# Gates\n\n", text)
    write_text(report, head + section + body)


def campaign_gate_summary(outcomes: Sequence[SceneOutcome]) -> str:
    """Per gated scene: how many gates held, and each failed one."""
    gated = [o for o in outcomes if o.gates]
    if not gated:
        return ""
    rows = []
    for o in gated:
        broken = [r for r in o.gates if not r["passed"]]
        rows.append((o.name, f"{len(o.gates) - len(broken)} of {len(o.gates)}",
                     "; ".join(f"`{r['path']}`: {r['message']}" for r in broken) or "-"))
    failed = sum(not r["passed"] for o in gated for r in o.gates)
    return (f"**Gates: {'all held' if not failed else f'{failed} failed'}** "
            f"(details in [junit.xml](junit.xml) and each scene's report)\n\n"
            + markdown_table(("scene", "gates held", "failed gates"), rows) + "\n")


def _anchor(name: str) -> str:
    return re.sub(r"[^a-z0-9_ -]", "", name.lower()).replace(" ", "-")
