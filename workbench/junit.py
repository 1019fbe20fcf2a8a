"""JUnit XML, the test report every common CI system displays (GitLab, GitHub
Actions reporters, Jenkins, Azure Pipelines, CircleCI).

One ``<testsuites>`` root; one ``<testsuite>`` per scene; one ``<testcase>``
per check, with a ``<failure message=... type=...>`` when it did not hold and
its details in the element text (passing cases carry them in ``<system-out>``).
"""

from __future__ import annotations

import datetime
import socket
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from shroud.base.outputs import replacing


@dataclass(frozen=True)
class Case:
    """One check: ``failure`` is None when it held; ``detail`` is shown either way."""

    name: str
    failure: str | None
    detail: str
    kind: str = "gate"


def write(path: Path, title: str, suites: Sequence[tuple[str, Sequence[Case]]]) -> Path:
    """``path``: a JUnit report of ``suites`` (name, cases), written whole or not at all."""
    stamp = datetime.datetime.now().astimezone().isoformat(timespec="seconds")
    total = sum(len(cases) for _, cases in suites)
    failed = sum(c.failure is not None for _, cases in suites for c in cases)
    root = ET.Element("testsuites", name=title, tests=str(total), failures=str(failed),
                      errors="0", time="0")
    for number, (name, cases) in enumerate(suites):
        suite = ET.SubElement(root, "testsuite", name=name, id=str(number), tests=str(len(cases)),
                              failures=str(sum(c.failure is not None for c in cases)), errors="0",
                              skipped="0", time="0", timestamp=stamp, hostname=socket.gethostname())
        for case in cases:
            element = ET.SubElement(suite, "testcase", classname=name, name=case.name, time="0")
            if case.failure is None:
                ET.SubElement(element, "system-out").text = case.detail
            else:
                ET.SubElement(element, "failure", message=case.failure, type=case.kind).text = case.detail
    ET.indent(root)
    with replacing(path) as tmp:
        ET.ElementTree(root).write(tmp, encoding="UTF-8", xml_declaration=True)
    return path


def gate_cases(records: Sequence[dict]) -> list[Case]:
    """One case per gate record (workbench.gates.hold)."""
    return [Case(r["path"], None if r["passed"] else r["message"], _gate_detail(r)) for r in records]


def _gate_detail(record: dict) -> str:
    fields = ("path", "relative_to", "value", "equals", "min", "max", "margin")
    lines = [f"{f.replace('_', ' ')}: {record[f]}" for f in fields if record.get(f) is not None]
    return "\n".join(lines + [record["message"]])
