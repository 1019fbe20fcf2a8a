"""Verdicts: a yes/no or a word drawn from a measured number, with the line it was drawn at.

A study's conclusion ("friction has no effect at large gaps", "the reduced
solid is cheaper than the full beam", "this orbit is stable") is a
measurement like any other. A :class:`Verdict` keeps

* ``value``: the number measured (a spread, a ratio, a multiplier's modulus);
* ``threshold``: where the answer changes side;
* ``margin``: the number's own uncertainty (mesh, time step, sampling of a
  speed grid, settling, timing noise); within ``threshold +- margin`` the
  verdict reads :data:`NOT_DECIDED` instead of taking a side;
* ``reason``: why the threshold and the margin are what they are, in words a
  reviewer can check.

``answer`` is ``below`` when ``value < threshold - margin``, ``above`` when
``value > threshold + margin`` and :data:`NOT_DECIDED` between. The answers
may be words or booleans; both serialize as JSON scalars, so ``shroud
compare`` and ``[gates] ... = {equals = ...}`` hold them for equality.

>>> v = Verdict.of(0.0356, threshold=0.05, margin=0.01, below="no effect", above="effect",
...                reason="resonance read on a 250 r/min grid: 1 % of the peak")
>>> v.answer
'no effect'
>>> Verdict.of(0.045, threshold=0.05, margin=0.01, below=True, above=False, reason="").answer
'not decided'
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

NOT_DECIDED = "not decided"
KEYS = ("answer", "value", "kind", "threshold", "margin", "unit", "reason")   # a verdict's JSON, in this order
# How a verdict's JSON reads its threshold and margin (its "kind"): "difference" value against threshold +- margin
# (Verdict); "band" |value| against the band +-threshold, +- margin at either edge (BandVerdict); "ratio" the
# ratio a/b against a band of x threshold, margin a factor >= 1 at either edge (RatioVerdict).
DIFFERENCE, BAND, RATIO = "difference", "band", "ratio"
TIME_RATIO = "time ratio"   # the unit of a number or verdict drawn from run times: a timing, whatever its answer
MEMORY_MB = "MB of memory"  # the unit of a memory size the run allocated (a factor's, a buffer's), 1e6 bytes
MEMORY_RATIO = "memory ratio"   # ... of a ratio or a fit of memory sizes
# The units of costs: what the run's machine, load and rank count set (run time, memory), not the blade;
# by unit, the resource each measures.
COSTS = {TIME_RATIO: "run_time", MEMORY_MB: "memory", MEMORY_RATIO: "memory"}
ROUNDING = "rounding"       # the key under which a JSON object declares its values' round-off (with_rounding)


@dataclass(frozen=True)
class Verdict:
    """One conclusion: the measured ``value``, the ``threshold`` and ``margin`` it was read against."""

    value: float
    threshold: float
    margin: float
    below: Any          # the answer when value < threshold - margin
    above: Any          # the answer when value > threshold + margin
    reason: str
    unit: str = ""

    @classmethod
    def of(cls, value: float, threshold: float, margin: float, below: Any, above: Any, reason: str,
           unit: str = "") -> "Verdict":
        if not margin >= 0.0:
            raise ValueError(f"a verdict's margin is >= 0 (got {margin})")
        return cls(float(value), float(threshold), float(margin), below, above, reason, unit)

    @property
    def decided(self) -> bool:
        """Whether the value lies outside ``threshold +- margin`` (a NaN value decides nothing)."""
        return math.isfinite(self.value) and abs(self.value - self.threshold) > self.margin

    @property
    def answer(self) -> Any:
        if not self.decided:
            return NOT_DECIDED
        return self.below if self.value < self.threshold else self.above

    @property
    def distance(self) -> float:
        """How far the value lies beyond the margin, in units of the margin (< 1: within it; inf: margin 0)."""
        gap = abs(self.value - self.threshold)
        return gap / self.margin if self.margin > 0 else math.inf

    def sentence(self, fmt: str = "{:.4g}") -> str:
        """``answer (value V against T +- M unit: reason)`` for reports."""
        unit = f" {self.unit}" if self.unit else ""
        return (f"{_word(self.answer)} ({fmt.format(self.value)}{unit} against {fmt.format(self.threshold)}"
                f" +- {fmt.format(self.margin)}{unit}: {self.reason})")

    def to_json(self) -> dict:
        return {"answer": self.answer, "value": _finite_or_none(self.value), "kind": DIFFERENCE,
                "threshold": self.threshold, "margin": self.margin, "unit": self.unit, "reason": self.reason}


def _word(answer: Any) -> str:
    """An answer as a sentence starts: yes/no for booleans."""
    return {True: "yes", False: "no"}.get(answer, str(answer)) if isinstance(answer, bool) else str(answer)


def _factor(noise: float) -> str:
    """A margin factor as a reader takes it in: a share below x1.5 ("0.2 %"), a factor above ("x2")."""
    if not math.isfinite(noise):
        return "an unmeasured margin"
    return f"{100 * (noise - 1):.2g} %" if noise < 1.5 else f"x{noise:.3g}"


def _finite_or_none(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


@dataclass(frozen=True)
class RatioVerdict:
    """How ``a`` compares with ``b`` (both > 0): three answers with a dead band, on a log scale.

    ``above`` when a > factor b, ``below`` when a < b / factor, ``between``
    when they lie within the factor of each other. ``noise`` (a factor >= 1,
    e.g. 1.5 for run times that vary by 50 % between identical runs) is the
    margin around either edge of the band, inside which the answer is
    :data:`NOT_DECIDED`.
    """

    a: float
    b: float
    factor: float
    noise: float
    above: Any
    below: Any
    between: Any
    reason: str
    unit: str = RATIO       # records made before verdicts wrote their kind tell a ratio by it (kind_of)

    def __post_init__(self):
        if not (self.a > 0 and self.b > 0 and self.factor >= 1 and self.noise >= 1):
            raise ValueError(f"a ratio verdict needs a, b > 0 and factor, noise >= 1 "
                             f"(got {self.a}, {self.b}, {self.factor}, {self.noise})")

    @property
    def ratio(self) -> float:
        return self.a / self.b

    @property
    def answer(self) -> Any:
        return _three_way(math.log(self.ratio), math.log(self.factor), math.log(self.noise),
                          self.above, self.below, self.between)

    def sentence(self, fmt: str = "{:.4g}") -> str:
        return (f"{_word(self.answer)} (ratio {fmt.format(self.ratio)} against a band of x{self.factor:.4g}"
                f" +- {_factor(self.noise)}: {self.reason})")

    def to_json(self) -> dict:
        return {"answer": self.answer, "value": self.ratio, "kind": RATIO, "threshold": self.factor,
                "margin": self.noise, "unit": self.unit, "reason": self.reason}


@dataclass(frozen=True)
class BandVerdict:
    """How a signed difference ``value`` lies against a band ``+- band`` around zero, with a ``margin``.

    ``above`` when value > band, ``below`` when value < -band, ``between``
    inside; :data:`NOT_DECIDED` within ``margin`` of either edge (e.g. a
    frequency "higher", "lower" or "the same" as the solid's, the band the
    solid mesh's own error).

    >>> BandVerdict(0.8, band=0.5, margin=0.1, above="higher", below="lower", between="the same",
    ...             reason="mesh", unit="%").answer
    'higher'
    """

    value: float
    band: float
    margin: float
    above: Any
    below: Any
    between: Any
    reason: str
    unit: str = ""

    def __post_init__(self):
        if not (self.band >= 0 and self.margin >= 0):
            raise ValueError(f"a band verdict needs band, margin >= 0 (got {self.band}, {self.margin})")

    @property
    def answer(self) -> Any:
        if not math.isfinite(self.value):
            return NOT_DECIDED
        return _three_way(self.value, self.band, self.margin, self.above, self.below, self.between)

    def sentence(self, fmt: str = "{:.4g}") -> str:
        unit = f" {self.unit}" if self.unit else ""
        band = f"a band of +-{fmt.format(self.band)}" if self.band > 0 else "0"
        return (f"{_word(self.answer)} ({fmt.format(self.value)}{unit} against {band}"
                f" +- {fmt.format(self.margin)}{unit}: {self.reason})")

    def to_json(self) -> dict:
        return {"answer": self.answer, "value": _finite_or_none(self.value), "kind": BAND,
                "threshold": self.band, "margin": self.margin, "unit": self.unit, "reason": self.reason}


def _three_way(x: float, edge: float, margin: float, above: Any, below: Any, between: Any) -> Any:
    """``above`` for x > edge, ``below`` for x < -edge, ``between`` inside; not decided within the margin."""
    if abs(abs(x) - edge) <= margin:
        return NOT_DECIDED
    if abs(x) < edge:
        return between
    return above if x > 0 else below


def is_verdict(document: Any) -> bool:
    """Whether a JSON value is a verdict's record (the keys of :meth:`Verdict.to_json`, in any order: a JSON
    object is unordered, and records are written with sorted keys), its round-off declared or not
    (:func:`with_rounding`), its ``kind`` written or not (records made before verdicts named their kind)."""
    return isinstance(document, dict) and set(document) - {ROUNDING} in (set(KEYS), set(KEYS) - {"kind"})


def kind_of(document: dict) -> str | None:
    """How a verdict's record reads its threshold and margin (:data:`DIFFERENCE`, :data:`BAND`,
    :data:`RATIO`). A record made before verdicts wrote their kind tells a ratio by its unit (only
    RatioVerdicts wrote "ratio" or :data:`TIME_RATIO`); a difference and a band wrote alike there, so for
    those it is None.

    >>> kind_of({"unit": "ratio"}), kind_of({"unit": "%"}), kind_of({"kind": BAND, "unit": "%"})
    ('ratio', None, 'band')
    """
    if "kind" in document:
        return document["kind"]
    return RATIO if document.get("unit") in (RATIO, TIME_RATIO) else None


def cost(value: Any, unit: str) -> dict:
    """A value the run's resources set, not the physics (a fit of run times, the points a time axis ranks,
    a factor's memory, which the rank count changes: anything the machine, its load and the partition
    decide), as a results.json holds it, its unit (one of :data:`COSTS`) declared:
    ``{"value": value, "unit": unit}``. ``shroud compare`` skips such values and counts them by resource.

    >>> cost(1.86, TIME_RATIO), cost(["reduced nr = 4"], TIME_RATIO)
    ({'value': 1.86, 'unit': 'time ratio'}, {'value': ['reduced nr = 4'], 'unit': 'time ratio'})
    >>> cost(87.8, MEMORY_MB), resource(cost(87.8, MEMORY_MB))
    ({'value': 87.8, 'unit': 'MB of memory'}, 'memory')
    """
    if unit not in COSTS:
        raise ValueError(f"a cost's unit is one of {sorted(COSTS)} (got {unit!r})")
    return {"value": value, "unit": unit}


def timing(value: Any) -> dict:
    """A value drawn from run times: :func:`cost` in :data:`TIME_RATIO`.

    >>> timing(1.86)
    {'value': 1.86, 'unit': 'time ratio'}
    """
    return cost(value, TIME_RATIO)


def with_rounding(record: dict, reason: str, **spreads: float) -> dict:
    """``record`` (a JSON object: a table's row, a verdict's record) with the round-off of some of its
    values declared: ``{**record, "rounding": {key: spread, ..., "reason": reason}}``.

    Some numbers are set in their last digits by the solver's rounding: a
    factorization of an ill-conditioned operator, whose fill-reducing
    ordering (and with it the rounding) changes with the rank count; a
    residual that Newton drove below its tolerance. Runs that differ only in
    that differ in those digits. ``spread`` (>= 0, absolute, in the value's
    own units) is how far, measured, with ``reason`` saying how; ``shroud
    compare`` holds the value (every number in it, for a table or a record)
    to it instead of its default tolerance, and says so. A verdict drawn
    from such a number has a margin that covers its spread.

    A record declared before keeps its declarations, the reasons joined.

    >>> with_rounding({"tip": 5.2208e-3, "case": "thin"}, "orderings", tip=5e-7)
    {'tip': 0.0052208, 'case': 'thin', 'rounding': {'tip': 5e-07, 'reason': 'orderings'}}
    """
    for key, spread in spreads.items():
        if key not in record:
            raise ValueError(f"a rounding declared for {key!r}, which the record lacks ({sorted(record)})")
        if not (math.isfinite(spread) and spread >= 0.0):
            raise ValueError(f"the rounding of {key!r} is a finite spread >= 0 (got {spread})")
    earlier = record.get(ROUNDING, {})              # a record declared before keeps its spreads and reason
    reasons = "; ".join(r for r in (earlier.get("reason", ""), reason) if r)
    return {**record, ROUNDING: {**declared_rounding(record), **{k: float(v) for k, v in spreads.items()},
                                 "reason": reasons}}


def declared_rounding(document: Any) -> dict[str, float]:
    """The spreads a JSON object declares for its own values (:func:`with_rounding`), by key; {} if none."""
    found = document.get(ROUNDING) if isinstance(document, dict) else None
    if not isinstance(found, dict):
        return {}
    return {k: v for k, v in found.items() if k != "reason" and isinstance(v, (int, float))
            and not isinstance(v, bool)}


def resource(document: Any) -> str | None:
    """The resource a JSON value measures by its declared unit (:data:`COSTS`: "run_time", "memory"), for
    an object (a verdict, or a value of :func:`cost`) whose ``unit`` is a cost's; None for anything else.
    ``shroud compare`` skips such values."""
    unit = document.get("unit") if isinstance(document, dict) else None
    return COSTS.get(unit) if isinstance(unit, str) else None


def is_cost_record(document: Any) -> bool:
    """Whether a JSON value was drawn from the run's resources (run time, memory) by its declared unit."""
    return resource(document) is not None


def answer_of(document: Any) -> Any:
    """A verdict record's answer; any other value as it is (conclusions stored before verdicts had margins)."""
    return document["answer"] if is_verdict(document) else document


def contradicts(a: Any, b: Any) -> bool:
    """Whether two runs' answers (records or plain values) take different sides.

    An answer :data:`NOT_DECIDED` contradicts nothing: a coarser run that
    cannot decide within its margin does not disagree with a finer one that can.

    >>> contradicts("larger", NOT_DECIDED), contradicts(True, False), contradicts("same", "same")
    (False, True, False)
    """
    a, b = answer_of(a), answer_of(b)
    return a != NOT_DECIDED and b != NOT_DECIDED and a != b
