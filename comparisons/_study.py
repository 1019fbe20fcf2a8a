"""The shape every study has: compute -> results object -> plot -> report.

* ``compute(scene)`` runs the models and returns a typed, frozen results
  object whose ``to_json()`` is the study's results.json (its conclusions
  included); studies whose computation itself writes files into the run's
  folder as it goes (time series, solver decks) take ``compute(scene, out)``;
* ``plot(result, scene, out)`` draws the figures and writes the data tables
  into ``out``, returning the file names the report shows;
* ``report(result, scene, files)`` is the markdown report.

``run(scene, out)`` only glues them: ``run = study(compute, plot, report)``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Protocol

from shroud.base.outputs import write_text


class Result(Protocol):
    """What compute returns: a results object that is results.json when asked."""

    def to_json(self) -> dict: ...


def study(compute: Callable[..., Result], plot: Callable[[Result, object, Path], list[str]],
          report: Callable[[Result, object, list[str]], str], writes: bool = False) -> Callable[[object, Path], dict]:
    """The study's ``run(scene, out)``: compute (``writes``: it is handed ``out``), plot, report into
    out/report.md (written whole or not at all, shroud.base.outputs); the results as JSON."""

    def run(scene, out: Path) -> dict:
        result = compute(scene, out) if writes else compute(scene)
        files = plot(result, scene, out)
        write_text(out / "report.md", report(result, scene, files))
        return result.to_json()

    run.__doc__ = f"compute -> plot -> report ({compute.__module__}); the results as JSON."
    return run
