"""Every study has the shape of comparisons/_study.py: compute -> results object -> plot -> report.

Read off the modules without running them: each study module exposes
``compute``, ``plot``, ``report`` and ``run``; ``compute`` is annotated to
return a frozen dataclass with ``to_json`` (results.json) and ``conclusions``
(in to_json or as a method); ``plot`` and ``report`` take the results object.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import typing

import pytest

from workbench.scene import available_studies


@pytest.mark.parametrize("name", available_studies())
def test_study_is_compute_plot_report(name):
    module = importlib.import_module(f"comparisons.{name}")
    for part in ("compute", "plot", "report", "run"):
        assert callable(getattr(module, part, None)), f"comparisons.{name} has no {part}()"
    result = typing.get_type_hints(module.compute)["return"]
    assert dataclasses.is_dataclass(result) and result.__dataclass_params__.frozen, \
        f"{name}.compute returns {result!r}, not a frozen dataclass"
    assert callable(getattr(result, "to_json", None)), f"{result.__name__} has no to_json()"
    for part in ("plot", "report"):
        first = next(iter(inspect.signature(getattr(module, part)).parameters.values()))
        hint = typing.get_type_hints(getattr(module, part)).get(first.name)
        assert hint is result, f"{name}.{part} takes {hint!r} first, not the results object {result.__name__}"


def test_the_list_of_studies_is_the_one_the_runner_uses():
    """The parametrization is not empty and holds studies the runner knows (a renamed study would drop out)."""
    names = set(available_studies())
    assert {"table1", "fig3", "fig4", "fig7", "fig8", "default", "campbell", "convergence", "error_vs_time",
            "gap_preload", "stiffness_ratio", "calculix", "friction", "stability"} <= names
    assert {"hb_fig4", "hb_fig7", "hb_friction", "hb_gap_preload", "hb_optimal_preload", "hb_stiffness_ratio",
            "interference", "ring_mistuning", "ring_tuned", "shell_benchmarks", "periodicity"} <= names
