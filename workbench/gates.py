"""Gates: bounds on the numbers of a run's own ``results.json``, held after the run.

A scene's ``[gates]`` table names numbers by their dotted path in
``results.json`` and bounds them::

    [gates]
    "results.fig8.versus_reference.reduced.nrmse.v_L" = { max = 0.08 }
    "results.modal.rows.flap1.reduced_vs_fe_percent" = { min = -0.5, max = 0.5 }
    "results.fig8.amplitude.reduced.v_L" = { max = 0.04, relative_to = "results.fig8.amplitude.fe-reduced.v_L" }

A yes/no or a word (a verdict's answer) is required with ``equals``::

    "results.conclusions.large_gaps_no_effect" = { equals = "no effect" }
    "results.conclusions.settled.fe" = { equals = true }

A path that ends at a verdict record (shroud.core.verdict: answer, value,
threshold, margin, unit, reason) gates its ``answer`` with ``equals`` and its
``value`` with ``max``/``min``.

``shroud run --gate 'PATH<=VALUE'`` / ``'PATH>=VALUE'`` / ``'PATH==VALUE'``
adds a bound (or replaces the scene's bound of the same kind on the same
path); after ``==`` the value is ``true``, ``false``, a number or a word. A path walks
tables by key and lists by index (``rows.0``) or by the ``label``, ``name``
or ``model`` of their elements (``rows.flap1``). With ``relative_to`` the
gated number is the relative difference |x / x_ref - 1| to the number at that
other path.

Every gate becomes a record ``{path, value, max, min, margin, passed,
message}`` (and ``equals``); a path that is not in the results, a bounded
value that is not a number (NaN and infinity are stored as null) or a run
that did not complete (or whose record has no ``status``) is a failed gate
that says so, never a pass. ``margin`` is the distance to the
nearest bound, negative when a bound is broken.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from typing import Any, Iterator, Mapping

from shroud.base.errors import InputError
from shroud.core.verdict import is_verdict

BOUNDS = ("max", "min")
KEYS = BOUNDS + ("equals", "relative_to")
# Fields that name the elements of a list of tables (rows.flap1, table3.reduced).
ELEMENT_NAMES = ("label", "name", "model")
_OPTION = re.compile(r"^(?P<path>[^<>=]*?)\s*(?P<op><=|>=|==)\s*(?P<value>.*)$")


@dataclass(frozen=True)
class Gate:
    """Bounds on the number at ``path`` (or on its relative difference to ``relative_to``), or the
    yes/no, word or number it ``equals``."""

    path: str
    max: float | None = None
    min: float | None = None
    relative_to: str | None = None
    equals: bool | str | float | None = None


def dotted_path(path: Any, key: str) -> str:
    """``path`` if it is dotted text: segments of text joined by dots, none empty."""
    if not isinstance(path, str) or not path.strip() or any(
            not s or s != s.strip() for s in path.split(".")):
        raise InputError(key, f"{path!r} is not a dotted path; allowed: keys of results.json joined "
                         "by dots, e.g. \"results.fig8.versus_reference.reduced.nrmse.v_L\"")
    return path


def _number(value: Any, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(key, f"{value!r} is not a number; allowed: a finite number")
    return float(value)


def _gate(path: str, spec: Mapping[str, Any], key: str) -> Gate:
    """A gate from a table of bounds ``spec`` found at ``key`` of the scene."""
    for name in spec:
        if name not in KEYS:
            raise InputError(f"{key}.{name}", f"unknown bound {name!r}; allowed: {', '.join(KEYS)}")
    bounds = {b: _number(spec[b], f"{key}.{b}") for b in BOUNDS if b in spec}
    reference = spec.get("relative_to")
    if reference is not None:
        reference = dotted_path(reference, f"{key}.relative_to")
    equals = spec.get("equals")
    if equals is not None and not (isinstance(equals, (bool, str)) or is_number(equals)):
        raise InputError(f"{key}.equals", f"{equals!r} is not a yes/no, word or number; allowed: "
                         "true, false, \"a word\" or a number")
    return _checked(Gate(path, relative_to=reference, equals=equals, **bounds), key)


def _checked(gate: Gate, key: str) -> Gate:
    if gate.max is None and gate.min is None and gate.equals is None:
        raise InputError(key, "no bound; allowed: { max = X }, { min = Y }, both, or { equals = V }")
    if gate.equals is not None and (gate.max is not None or gate.min is not None or gate.relative_to):
        raise InputError(key, "equals with a bound or relative_to; allowed: { equals = V } alone, or bounds")
    if gate.max is not None and gate.min is not None and gate.min > gate.max:
        raise InputError(key, f"min {gate.min:g} is above max {gate.max:g}; allowed: min <= max")
    return gate


def from_table(table: Any, key: str = "gates") -> tuple[Gate, ...]:
    """The gates of a ``[gates]`` table.

    Paths are best quoted (``"results.fig8.rpm" = {...}``); TOML reads an
    unquoted dotted key as nested tables, which are joined back into the path.
    """
    if not isinstance(table, dict):
        raise InputError(key, f"{table!r} is not a table; allowed: a [{key}] table of "
                         "\"dotted.path\" = { max = X, min = Y }")
    gates = []
    for path, spec in _leaves(table, ""):
        where = f"{key}.{path}" if path else key
        if not isinstance(spec, dict):
            raise InputError(where, f"{spec!r} is not a table of bounds; allowed: {{ max = X, min = Y }}")
        gates.append(_gate(dotted_path(path, key), spec, where))
    return tuple(gates)


def _leaves(table: dict, prefix: str) -> Iterator[tuple[str, Any]]:
    """(path, bounds) pairs: a table whose values are all tables is one more level of the path."""
    for name, value in table.items():
        path = f"{prefix}.{name}" if prefix else name
        if isinstance(value, dict) and value and all(isinstance(v, dict) for v in value.values()):
            yield from _leaves(value, path)
        else:
            yield path, value


def from_option(text: str) -> Gate:
    """The gate of one ``--gate 'PATH<=VALUE'``, ``'PATH>=VALUE'`` or ``'PATH==VALUE'``."""
    match = _OPTION.match(text.strip()) if isinstance(text, str) else None
    if not match or not match["path"] or not match["value"].strip():
        raise InputError("--gate", f"{text!r} is not PATH<=VALUE, PATH>=VALUE or PATH==VALUE; allowed: e.g. "
                         "--gate 'results.fig8.versus_reference.reduced.nrmse.v_L<=0.08'")
    path = dotted_path(match["path"], "--gate")
    if match["op"] == "==":
        return Gate(path, equals=_word(match["value"].strip()))
    if any(c in match["value"] for c in "<>="):
        raise InputError("--gate", f"{text!r} has more than one bound; allowed: one per --gate "
                         "(give --gate twice for both)")
    try:
        value = float(match["value"])
    except ValueError:
        raise InputError("--gate", f"{match['value'].strip()!r} in {text!r} is not a number; "
                         "allowed: a finite number") from None
    value = _number(value, "--gate")
    return Gate(path, **{("max" if match["op"] == "<=" else "min"): value})


def _word(text: str) -> bool | str | float:
    """The value after ``==``: true/false, a number, or the word itself (quotes around it dropped)."""
    if text in ("true", "false"):
        return text == "true"
    try:
        return _number(float(text), "--gate")
    except (ValueError, InputError):
        return text[1:-1] if len(text) > 1 and text[0] == text[-1] and text[0] in "'\"" else text


def merged(*groups: tuple[Gate, ...]) -> tuple[Gate, ...]:
    """One gate per path; a later group's bounds replace an earlier group's, bound by bound."""
    by_path: dict[str, Gate] = {}
    for group in groups:
        for gate in group:
            old = by_path.get(gate.path)
            if old is not None:
                gate = dataclasses.replace(old, **{f.name: getattr(gate, f.name)
                                                   for f in dataclasses.fields(gate)
                                                   if getattr(gate, f.name) is not None})
            by_path[gate.path] = _checked(gate, f"gates.{gate.path}")
    return tuple(by_path.values())


# --- walking results.json ------------------------------------------------------

def element_names(items: list) -> list[str] | None:
    """Names of a list's elements (their label, name or model) when these name each one once."""
    for field in ELEMENT_NAMES:
        names = [item.get(field) if isinstance(item, dict) else None for item in items]
        if items and all(isinstance(n, str) for n in names) and len(set(names)) == len(names):
            return names
    return None


def children(value: Any) -> list[tuple[str, Any]]:
    """(segment, child) of a table or list of results.json, as paths name them."""
    if isinstance(value, dict):
        return [(str(k), v) for k, v in value.items()]
    if isinstance(value, list):
        names = element_names(value) or [str(i) for i in range(len(value))]
        return list(zip(names, value))
    return []


class Missing(LookupError):
    """A path that is not in the results (the message says where it stops)."""


def lookup(document: Any, path: str) -> Any:
    """The value at dotted ``path`` of ``document``; lists by index or element name."""
    value, walked = document, []
    for segment in path.split("."):
        found = dict(children(value))
        if isinstance(value, list) and segment.isdigit() and int(segment) < len(value):
            found[segment] = value[int(segment)]
        if segment not in found:
            where = ".".join(walked) or "results.json"
            has = ", ".join(list(found)[:12]) + (", ..." if len(found) > 12 else "")
            raise Missing(f"{where} has no {segment!r}" + (f" (it has: {has})" if has else
                                                            " (it is not a table or list)"))
        value = found[segment]
        walked.append(segment)
    return value


def is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


# --- holding the gates ---------------------------------------------------------

def _fmt(x: float) -> str:
    return f"{x:.6g}"


def _gated_value(gate: Gate, document: Any) -> tuple[float, str]:
    """The gated number and how it was formed; ``Missing`` when it cannot be."""
    value = lookup(document, gate.path)
    if is_verdict(value):
        value = value["value"]
    if not is_number(value):
        raise Missing(f"{gate.path} is {'null (NaN or infinity)' if value is None else repr(value)}, "
                      "not a number")
    if gate.relative_to is None:
        return float(value), _fmt(value)
    reference = lookup(document, gate.relative_to)
    if not is_number(reference) or reference == 0:
        raise Missing(f"{gate.relative_to} is {reference!r}, not a nonzero number to compare against")
    difference = abs(value / reference - 1)
    return difference, f"|{_fmt(value)} / {_fmt(reference)} - 1| = {_fmt(difference)}"


def hold(gates: tuple[Gate, ...], document: Mapping[str, Any]) -> list[dict]:
    """Each gate held against ``document`` (a results.json payload): its record."""
    status = document.get("status", "missing")          # a record without a status is not a complete run
    return [_record(gate, document, status) for gate in gates]


def same(a: Any, b: Any) -> bool:
    """Equal as JSON values: a yes/no equals only a yes/no (never 1 or 0), numbers by value."""
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    return a == b


def _record(gate: Gate, document: Mapping[str, Any], status: str) -> dict:
    record = {"path": gate.path, "value": None, "max": gate.max, "min": gate.min}
    if gate.relative_to is not None:
        record["relative_to"] = gate.relative_to
    if gate.equals is not None:
        record["equals"] = gate.equals
    if status != "complete":
        return {**record, "margin": None, "passed": False, "message": f"not evaluated (run status: {status})"}
    if gate.equals is not None:
        return {**record, "margin": None, **_equality(gate, document)}
    try:
        value, shown = _gated_value(gate, document)
    except Missing as exc:
        return {**record, "margin": None, "passed": False, "message": f"missing: {exc}"}
    margins = []
    if gate.max is not None:
        margins.append(gate.max - value)
    if gate.min is not None:
        margins.append(value - gate.min)
    margin = min(margins)
    passed = margin >= 0
    if passed:
        low = f"{_fmt(gate.min)} <= " if gate.min is not None else ""
        high = f" <= {_fmt(gate.max)}" if gate.max is not None else ""
        message = f"{low}{shown}{high} (margin {_fmt(margin)})"
    elif gate.max is not None and value > gate.max:
        message = f"{shown} > max {_fmt(gate.max)} (over by {_fmt(value - gate.max)})"
    else:
        message = f"{shown} < min {_fmt(gate.min)} (under by {_fmt(gate.min - value)})"
    return {**record, "value": value, "margin": margin, "passed": passed, "message": message}


def _equality(gate: Gate, document: Any) -> dict:
    """value, passed and message of an ``equals`` gate (a verdict record gives its answer)."""
    try:
        value = lookup(document, gate.path)
    except Missing as exc:
        return {"value": None, "passed": False, "message": f"missing: {exc}"}
    if is_verdict(value):
        value = value["answer"]
    if isinstance(value, (dict, list)):
        return {"value": None, "passed": False, "message": f"{gate.path} is a table or list, not a value"}
    if same(value, gate.equals):
        return {"value": value, "passed": True, "message": f"{value!r} as required"}
    return {"value": value, "passed": False, "message": f"{value!r}, not {gate.equals!r}"}


def not_held(records: list[dict]) -> list[dict]:
    return [r for r in records if not r["passed"]]
