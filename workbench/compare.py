"""``shroud compare BASE NEW``: every number, yes/no and word of NEW's results.json held against BASE's.

A number agrees when |new - base| <= atol + rtol |base|; a boolean or a word
(a verdict's answer: "stable", "larger", "separate > slip > stick") agrees
when it is equal, so a flipped verdict is a drift. A value present in one run
and missing in the other (or null there: NaN or infinity) is a drift.

Costs (what the run's machine, load and rank count set: run time and
memory) are recognised by what they are, not by a list of names
(:func:`cost_paths`): a key ending in ``_s`` holds wall or CPU times of the
run's machine (the runner refuses anything but numbers under such a key,
:func:`check_timings`), a key ending in ``_time_ratio`` a ratio of them, and
an object whose unit is a cost's (``shroud.core.verdict.COSTS``: a verdict of
unit ``TIME_RATIO``, or a value the study declared with
``shroud.core.verdict.cost``: a fit of run times, a factor's memory, which the
rank count changes) was drawn from them; these vary from run to run and are
skipped, counted by resource, with the paths matching a
pattern of ``DEFAULT_IGNORE`` (where and how the run was made) or of
``--ignore``. Physical times (a time step) are named otherwise
(``time_step``). Paths are those of gates (workbench.gates): lists of
tables are named by their elements' label, name or model
(``results.modal.rows.flap1.reduced``), other lists by index.

Numbers whose last digits the solver's rounding sets are declared so by the
study (``shroud.core.verdict.with_rounding``: an object's ``rounding`` gives
a measured spread per key, absolute, with its reason, e.g. a thin shell's
deflection under another factor ordering, or a residual below Newton's
tolerance): such a number is held to |new - base| <= its spread (the larger
of BASE's and NEW's declarations, never less than the default tolerance)
instead, and the output says how many were and to what.

A verdict's ``kind`` (how its threshold and margin read: difference, band,
ratio) is held like a word. A run made before verdicts wrote their kind is
read with the kind its unit tells (``shroud.core.verdict.kind_of``: a ratio);
where it cannot tell (a difference and a band wrote alike) the kind is not
compared, counted with the ignored values.

A results.json without a ``status``, or two runs of different studies, are
refused in one line. On campaign folders each scene's results.json is
compared; paths start with the scene's name (``fig8/results.fig8.rpm``) and
patterns match with or without it.
"""

from __future__ import annotations

import fnmatch
import json
import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

from workbench import junit
from workbench.gates import children, is_number
from shroud.base.errors import InputError
from shroud.core.verdict import COSTS, ROUNDING, TIME_RATIO, declared_rounding, is_verdict, kind_of, resource

DEFAULT_RTOL = 1e-6
DEFAULT_ATOL = 1e-12
DEFAULT_IGNORE = (
    # where and how the run was made
    "host.*", "versions.*", "command.*", "scene", "finished", "overrides.*", "incomplete_files.*",
    # gate records: their bounds are the scene's, their values are compared at their own paths
    "gates.*",
)
TIMING_SUFFIXES = ("_s", "_time_ratio")    # keys whose values are run times (s), or ratios of them
_ABSENT = object()


@dataclass(frozen=True)
class Drift:
    """A value that differs (a number beyond tolerance, a yes/no or word at all); ``base``/``new`` None
    when null or absent."""

    path: str
    base: Any
    new: Any
    note: str = ""                   # "missing in NEW", "null in BASE", ...

    @property
    def relative(self) -> float:
        if not (is_number(self.base) and is_number(self.new)):
            return math.inf
        if self.base == 0:
            return 0.0 if self.new == 0 else math.inf
        return abs(self.new - self.base) / abs(self.base)

    def describe(self) -> str:
        if self.note:
            return self.note
        if not (is_number(self.base) and is_number(self.new)):
            return f"{self.base!r} -> {self.new!r} (a verdict or word changed)"
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
    ignored: int                     # by pattern or as costs
    skipped: dict[str, int]          # resource ("run_time", "memory") -> how many values skipped as its cost
    drifts: list[Drift]              # changed words and yes/no first, then largest relative change
    rounded: dict[str, float]        # path -> declared rounding spread it was held to instead of rtol/atol

    def tolerance(self, path: str) -> str:
        """How a path was held, in words."""
        if path in self.rounded:
            return f"declared rounding {self.rounded[path]:.3g}"
        return f"rtol {self.rtol:g}, atol {self.atol:g}"

    def to_json(self) -> dict:
        return {"base": self.base, "new": self.new, "rtol": self.rtol, "atol": self.atol,
                "ignore": list(self.ignore), "compared": len(self.compared), "ignored": self.ignored,
                "skipped": self.skipped, "rounded": self.rounded,
                "drifted": [{"path": d.path, "base": d.base, "new": d.new,
                             "relative_change": None if math.isinf(d.relative) else d.relative,
                             "note": d.note} for d in self.drifts]}


def scalars(document: Any, prefix: str = "") -> dict[str, Any]:
    """Every number, yes/no, word and null of a results.json document by dotted path."""
    out: dict[str, Any] = {}
    for segment, value in children(document):
        path = f"{prefix}.{segment}" if prefix else segment
        if isinstance(value, (dict, list)):
            out.update(scalars(value, path))
        else:
            out[path] = value
    return out


def is_timing(path: str) -> bool:
    """Whether a dotted path names a run time: one of its keys ends in ``TIMING_SUFFIXES``."""
    return any(segment.endswith(TIMING_SUFFIXES) for segment in path.split("."))


def cost_paths(document: Any, prefix: str = "") -> dict[str, str]:
    """Path -> resource ("run_time", "memory") of every value drawn from the run's resources: under a timing
    key, or in an object whose unit is a cost's (``shroud.core.verdict.resource``; its unit itself is held:
    a value declared a cost in one run and not in the other drifts)."""
    found: dict[str, str] = {}
    for segment, value in children(document):
        path = f"{prefix}.{segment}" if prefix else segment
        if is_timing(segment):
            found.update(dict.fromkeys(scalars(value, path) if isinstance(value, (dict, list)) else [path],
                                       COSTS[TIME_RATIO]))
        elif (kind := resource(value)) is not None:
            found.update(dict.fromkeys((p for p in scalars(value, path) if p != f"{path}.unit"), kind))
        elif isinstance(value, (dict, list)):
            found.update(cost_paths(value, path))
    return found


def rounding_spreads(document: Any, prefix: str = "") -> dict[str, float]:
    """Path -> declared spread of every number an object declares rounded (``shroud.core.verdict.with_rounding``):
    the numbers under a declared key, and the declaration's own spreads (held to themselves)."""
    found: dict[str, float] = {}
    declared = declared_rounding(document)
    for segment, value in children(document):
        path = f"{prefix}.{segment}" if prefix else segment
        if segment in declared:
            spread = declared[segment]
            found.update({p: spread for p in (scalars(value, path) if isinstance(value, (dict, list)) else [path])})
        elif isinstance(value, (dict, list)):
            found.update(rounding_spreads(value, path))
    found.update({f"{prefix}.{ROUNDING}.{k}" if prefix else f"{ROUNDING}.{k}": v for k, v in declared.items()})
    return found


def check_timings(document: Any, prefix: str = "") -> None:
    """Refuse (ValueError) a value under a timing key that is not a number or null: a verdict or a word
    named like a time would never be compared."""
    for path, value in scalars(document, prefix).items():
        if is_timing(path) and value is not None and not is_number(value):
            raise ValueError(f"{path} is {value!r}: keys ending in {' or '.join(TIMING_SUFFIXES)} hold run "
                             "times (numbers), which shroud compare skips; name it otherwise")


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


@dataclass(frozen=True)
class RunValues:
    """What an output folder holds for compare; a campaign's paths prefixed ``<scene>/``."""

    campaign: bool
    values: dict[str, Any]           # path -> number, yes/no, word or null
    costs: dict[str, str]            # path -> resource, of the values drawn from run time or memory
    rounded: dict[str, float]        # path -> declared rounding spread
    name: str                        # study or campaign title
    untold: frozenset[str]           # paths of verdicts' kinds a run made before kinds cannot tell


def kinds_of_old_verdicts(document: Any, prefix: str = "") -> dict[str, str | None]:
    """Path of the ``kind`` -> kind as :func:`shroud.core.verdict.kind_of` tells it (None where it cannot)
    of every verdict recorded before verdicts wrote their kind."""
    found: dict[str, str | None] = {}
    for segment, value in children(document):
        path = f"{prefix}.{segment}" if prefix else segment
        if is_verdict(value):
            if "kind" not in value:
                found[f"{path}.kind"] = kind_of(value)
        elif isinstance(value, (dict, list)):
            found.update(kinds_of_old_verdicts(value, path))
    return found


def _values(document: dict, prefix: str = "") -> tuple[dict[str, Any], set[str]]:
    """Every scalar of ``document`` by path (a verdict made before kinds with the kind its unit tells), and
    the paths of the kinds it cannot tell."""
    old = {prefix + p: k for p, k in kinds_of_old_verdicts(document).items()}
    values = {prefix + p: v for p, v in scalars(document).items()}
    values.update({p: k for p, k in old.items() if k is not None})
    return values, {p for p, k in old.items() if k is None}


def run_values(folder: str | Path, key: str) -> RunValues:
    """The values of an output folder's results.json (a campaign's: of each scene's)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(key, f"{str(folder)!r} is not a folder; allowed: an output folder of shroud run")
    document = _record(folder / "results.json", key)
    if "campaign" not in document:
        values, untold = _values(document)
        return RunValues(False, values, cost_paths(document), rounding_spreads(document),
                         str(document.get("study")), frozenset(untold))
    found: dict[str, Any] = {}
    costs: dict[str, str] = {}
    rounded: dict[str, float] = {}
    untold: set[str] = set()
    for scene in document.get("scenes", []):
        record = folder / scene["results"]
        if record.is_file():          # a scene that never ran has no numbers: each of BASE's drifts
            run = _record(record, key)
            values, unknown = _values(run, f"{scene['name']}/")
            found.update(values)
            untold |= unknown
            costs.update({f"{scene['name']}/{p}": v for p, v in cost_paths(run).items()})
            rounded.update({f"{scene['name']}/{p}": v for p, v in rounding_spreads(run).items()})
    return RunValues(True, found, costs, rounded, str(document["campaign"]), frozenset(untold))


def _record(path: Path, key: str) -> dict:
    """A results.json that says how its run ended: one without ``status`` is refused, never read as complete."""
    document = _read(path, key)
    if "status" not in document:
        raise InputError(key, f"{str(path)!r} has no status (a run that never finished writing, or not a "
                         "results.json of shroud run); allowed: a record with its status")
    return document


def _ignored(path: str, patterns: Sequence[str], campaign: bool) -> bool:
    local = path.partition("/")[2] if campaign else path
    return any(fnmatch.fnmatchcase(path, p) or fnmatch.fnmatchcase(local, p) for p in patterns)


def _drift(path: str, base: Any, new: Any, rtol: float, atol: float, spread: float = 0.0) -> Drift | None:
    for value, where in ((base, "BASE"), (new, "NEW")):
        if value is _ABSENT:
            return Drift(path, None if base is _ABSENT else base, None if new is _ABSENT else new,
                         f"missing in {where}")
    if base is None and new is None:
        return None
    if base is None or new is None:
        return Drift(path, base, new, f"null (NaN or infinity) in {'BASE' if base is None else 'NEW'}")
    if is_number(base) and is_number(new):
        within = abs(new - base) <= max(atol + rtol * abs(base), spread)
        return None if within else Drift(path, float(base), float(new),
                                         f"beyond its declared rounding {spread:.3g}" if spread else "")
    return None if base == new and type(base) is type(new) else Drift(path, base, new)


def compare(base: str | Path, new: str | Path, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL,
            ignore: Sequence[str] = (), junit_path: str | Path | None = None) -> Comparison:
    """Hold NEW's values against BASE's; write ``junit_path`` (one test case per value) if given."""
    target = Path(junit_path) if junit_path else None
    if target is not None and target.is_dir():
        raise InputError("--junit", f"{str(target)!r} is a folder; allowed: a file path")
    b, n = run_values(base, "BASE"), run_values(new, "NEW")
    if b.campaign != n.campaign:
        raise InputError("NEW", "one folder holds a campaign, the other a scene; allowed: two scene "
                         "folders or two campaign folders")
    if b.name != n.name:
        kind = "campaign" if n.campaign else "study"
        raise InputError("NEW", f"BASE is a run of {kind} {b.name!r}, NEW of {kind} {n.name!r}; "
                         f"allowed: two runs of one {kind}")
    patterns = DEFAULT_IGNORE + tuple(ignore)
    costs = {**b.costs, **n.costs}
    paths = list(b.values) + [p for p in n.values if p not in b.values]
    untold = b.untold | n.untold          # kinds of verdicts one run recorded before kinds were written
    held = [p for p in paths if p not in costs and p not in untold and not _ignored(p, patterns, n.campaign)]
    skipped = dict(Counter(costs[p] for p in paths if p in costs))
    rounded = {p: max(b.rounded.get(p, 0.0), n.rounded.get(p, 0.0)) for p in held
               if p in b.rounded or p in n.rounded}
    drifts = [d for p in held if (d := _drift(p, b.values.get(p, _ABSENT), n.values.get(p, _ABSENT),
                                             rtol, atol, rounded.get(p, 0.0))) is not None]
    drifts.sort(key=lambda d: (-d.relative, d.path))
    comparison = Comparison(str(base), str(new), rtol, atol, patterns, n.campaign, held,
                            len(paths) - len(held), skipped, drifts, rounded)
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
        detail = (drift.describe() if drift else "within tolerance") + f" ({comparison.tolerance(path)})"
        suites.setdefault(scene, []).append(
            junit.Case(local, drift.describe() if drift else None, detail, kind="drift"))
    return list(suites.items())


def markdown(comparison: Comparison) -> str:
    """The verdict and the drifted numbers, largest relative change first, as a Markdown table."""
    head = (f"Compared {len(comparison.compared)} values of {comparison.new} against {comparison.base} "
            f"(numbers within rtol {comparison.rtol:g}, atol {comparison.atol:g}; yes/no and words equal; "
            f"{_skipped_words(comparison)})." + _rounded_sentence(comparison))
    if not comparison.drifts:
        return head + "\nAll within tolerance."
    rows = ["| path | BASE | NEW | relative change | note |", "|---|---|---|---|---|"]
    for d in comparison.drifts:
        rows.append(f"| `{d.path}` | {_cell(d.base)} | {_cell(d.new)} | "
                    f"{_change(d)} | {d.note or '-'} |")
    return f"{head}\n**{len(comparison.drifts)} drifted:**\n\n" + "\n".join(rows)


def _skipped_words(comparison: Comparison) -> str:
    """What was not compared: the costs by resource, then the paths ignored by pattern."""
    costs = sum(comparison.skipped.values())
    words = [f"{n} of {kind.replace('_', ' ')}" for kind, n in sorted(comparison.skipped.items())]
    skipped = (f"skipped as costs of the machine and rank count: {', '.join(words)}; " if words else "")
    return (f"{skipped}{comparison.ignored - costs} ignored by pattern or as the kind of a verdict recorded "
            "before verdicts wrote their kind")


def _rounded_sentence(comparison: Comparison) -> str:
    """Which numbers were held to their declared rounding instead of the default tolerance, if any."""
    if not comparison.rounded:
        return ""
    spreads = comparison.rounded.values()
    return (f"\n{len(comparison.rounded)} of them held to the rounding their study declares instead (spreads "
            f"{min(spreads):.3g} to {max(spreads):.3g}, absolute, in each number's units; each declaration's "
            "reason is in results.json beside it under `rounding`).")


def _change(d: Drift) -> str:
    if not (is_number(d.base) and is_number(d.new)):
        return "changed" if not d.note else "-"
    return "inf" if math.isinf(d.relative) else f"{d.relative:.3g}"


def _cell(value: Any) -> str:
    return "-" if value is None else f"{value:.10g}" if is_number(value) else f"`{value!r}`"
