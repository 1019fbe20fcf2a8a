"""``shroud compare BASE NEW``: every number of NEW's results.json held against BASE's.

A number agrees when |new - base| <= atol + rtol |base|. A number present in
one run and missing in the other (or null there: NaN or infinity) is a
drift. Strings (paths, dates, versions, the git revision, statuses) are never
compared; numbers whose dotted path matches a pattern of ``DEFAULT_IGNORE``
(wall and CPU times, which vary from run to run, and where and how the run
was made) or of ``--ignore`` are skipped. Paths are those of gates
(workbench.gates): lists of tables are named by their elements' label, name
or model (``results.modal.rows.flap1.reduced``), other lists by index.

On campaign folders each scene's results.json is compared; paths start with
the scene's name (``fig8/results.fig8.rpm``) and patterns match with or
without it.
"""

from __future__ import annotations

import fnmatch
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from workbench import junit
from workbench.gates import children, is_number
from shroud.base.errors import InputError

DEFAULT_RTOL = 1e-6
DEFAULT_ATOL = 1e-12
DEFAULT_IGNORE = (
    # wall and CPU times of this machine (s), and ratios of them: they vary from run to run
    "*elapsed_s", "*cpu_s", "*build_s", "*run_s", "*solve_s", "*compile_s", "*draw_s", "*total_s",
    "*time_s", "*transient_s", "*time_ratio*",
    # where and how the run was made
    "host.*", "versions.*", "command.*", "scene", "finished", "overrides.*", "incomplete_files.*",
    # gate records: their bounds are the scene's, their values are compared at their own paths
    "gates.*",
)
_ABSENT = object()


@dataclass(frozen=True)
class Drift:
    """A number that differs beyond tolerance; ``base``/``new`` None when null or absent."""

    path: str
    base: float | None
    new: float | None
    note: str = ""                   # "missing in NEW", "null in BASE", ...

    @property
    def relative(self) -> float:
        if self.base is None or self.new is None:
            return math.inf
        if self.base == 0:
            return 0.0 if self.new == 0 else math.inf
        return abs(self.new - self.base) / abs(self.base)

    def describe(self) -> str:
        if self.note:
            return self.note
        return f"{self.base:.10g} -> {self.new:.10g} (relative change {self.relative:.3g})"


@dataclass(frozen=True)
class Comparison:
    base: str
    new: str
    rtol: float
    atol: float
    ignore: tuple[str, ...]
    campaign: bool                   # paths start with "<scene>/"
    compared: list[str]              # paths held (in BASE order, then NEW's own)
    ignored: int
    drifts: list[Drift]              # largest relative change first

    def to_json(self) -> dict:
        return {"base": self.base, "new": self.new, "rtol": self.rtol, "atol": self.atol,
                "ignore": list(self.ignore), "compared": len(self.compared), "ignored": self.ignored,
                "drifted": [{"path": d.path, "base": d.base, "new": d.new,
                             "relative_change": None if math.isinf(d.relative) else d.relative,
                             "note": d.note} for d in self.drifts]}


def numbers(document: Any, prefix: str = "") -> dict[str, float | None]:
    """Every number (and null) of a results.json document by dotted path."""
    out: dict[str, float | None] = {}
    for segment, value in children(document):
        path = f"{prefix}.{segment}" if prefix else segment
        if value is None or is_number(value):
            out[path] = value
        else:
            out.update(numbers(value, path))
    return out


def _read(path: Path, key: str) -> dict:
    try:
        document = json.loads(path.read_text())
    except FileNotFoundError:
        raise InputError(key, f"no {path.name} in {str(path.parent)!r}; allowed: an output folder "
                         "of shroud run (a scene's or a campaign's)") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(key, f"{str(path)!r} is not readable JSON ({exc})") from None
    if not isinstance(document, dict):
        raise InputError(key, f"{str(path)!r} is not a results.json of shroud run (not a JSON object)")
    return document


def run_numbers(folder: str | Path, key: str) -> tuple[bool, dict[str, float | None]]:
    """(is a campaign, numbers) of an output folder; a campaign's scenes prefixed ``<scene>/``."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(key, f"{str(folder)!r} is not a folder; allowed: an output folder of shroud run")
    document = _read(folder / "results.json", key)
    if "campaign" not in document:
        return False, numbers(document)
    found: dict[str, float | None] = {}
    for scene in document.get("scenes", []):
        record = folder / scene["results"]
        if record.is_file():          # a scene that never ran has no numbers: each of BASE's drifts
            found.update({f"{scene['name']}/{p}": v for p, v in numbers(_read(record, key)).items()})
    return True, found


def _ignored(path: str, patterns: Sequence[str], campaign: bool) -> bool:
    local = path.partition("/")[2] if campaign else path
    return any(fnmatch.fnmatchcase(path, p) or fnmatch.fnmatchcase(local, p) for p in patterns)


def _drift(path: str, base: Any, new: Any, rtol: float, atol: float) -> Drift | None:
    for value, where in ((base, "BASE"), (new, "NEW")):
        if value is _ABSENT:
            return Drift(path, None if base is _ABSENT else base, None if new is _ABSENT else new,
                         f"missing in {where}")
    if base is None and new is None:
        return None
    if base is None or new is None:
        return Drift(path, base, new, f"null (NaN or infinity) in {'BASE' if base is None else 'NEW'}")
    if abs(new - base) <= atol + rtol * abs(base):
        return None
    return Drift(path, float(base), float(new))


def compare(base: str | Path, new: str | Path, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL,
            ignore: Sequence[str] = (), junit_path: str | Path | None = None) -> Comparison:
    """Hold NEW's numbers against BASE's; write ``junit_path`` (one test case per number) if given."""
    target = Path(junit_path) if junit_path else None
    if target is not None and target.is_dir():
        raise InputError("--junit", f"{str(target)!r} is a folder; allowed: a file path")
    base_campaign, base_numbers = run_numbers(base, "BASE")
    new_campaign, new_numbers = run_numbers(new, "NEW")
    if base_campaign != new_campaign:
        raise InputError("NEW", "one folder holds a campaign, the other a scene; allowed: two scene "
                         "folders or two campaign folders")
    patterns = DEFAULT_IGNORE + tuple(ignore)
    paths = list(base_numbers) + [p for p in new_numbers if p not in base_numbers]
    held = [p for p in paths if not _ignored(p, patterns, new_campaign)]
    drifts = [d for p in held if (d := _drift(p, base_numbers.get(p, _ABSENT), new_numbers.get(p, _ABSENT),
                                             rtol, atol)) is not None]
    drifts.sort(key=lambda d: (-d.relative, d.path))
    comparison = Comparison(str(base), str(new), rtol, atol, patterns, new_campaign, held,
                            len(paths) - len(held), drifts)
    if target is not None:
        target.parent.mkdir(parents=True, exist_ok=True)
        junit.write(target, f"shroud compare {base} {new}", _suites(comparison))
    return comparison


def _suites(comparison: Comparison) -> list[tuple[str, list[junit.Case]]]:
    """One suite per scene (one in all for a scene folder), one case per number held."""
    drifted = {d.path: d for d in comparison.drifts}
    suites: dict[str, list[junit.Case]] = {}
    for path in comparison.compared:
        scene, _, local = path.partition("/") if comparison.campaign else ("results", "", path)
        drift = drifted.get(path)
        detail = (drift.describe() if drift else "within tolerance") + \
            f" (rtol {comparison.rtol:g}, atol {comparison.atol:g})"
        suites.setdefault(scene, []).append(
            junit.Case(local, drift.describe() if drift else None, detail, kind="drift"))
    return list(suites.items())


def markdown(comparison: Comparison) -> str:
    """The verdict and the drifted numbers, largest relative change first, as a Markdown table."""
    head = (f"Compared {len(comparison.compared)} numbers of {comparison.new} against {comparison.base} "
            f"(rtol {comparison.rtol:g}, atol {comparison.atol:g}; {comparison.ignored} ignored by pattern).")
    if not comparison.drifts:
        return head + "\nAll within tolerance."
    rows = ["| path | BASE | NEW | relative change | note |", "|---|---|---|---|---|"]
    for d in comparison.drifts:
        rows.append(f"| `{d.path}` | {_cell(d.base)} | {_cell(d.new)} | "
                    f"{'inf' if math.isinf(d.relative) else f'{d.relative:.3g}'} | {d.note or '-'} |")
    return f"{head}\n**{len(comparison.drifts)} drifted:**\n\n" + "\n".join(rows)


def _cell(value: float | None) -> str:
    return "-" if value is None else f"{value:.10g}"
