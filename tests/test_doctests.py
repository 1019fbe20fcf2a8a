"""The runnable examples in the docstrings (numpydoc ``Examples``, ``>>>``) run and give what they show.

Every module of the project's packages that holds one is collected; those
that need the DOLFINx stack are marked ``fe``.
"""

from __future__ import annotations

import doctest
import importlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("shroud", "reduced_model", "meshes", "reference_fe", "comparisons")
NEEDS_FE = ("reference_fe",)


def modules_with_examples() -> list[str]:
    found = []
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            if ">>>" in path.read_text():
                parts = path.relative_to(ROOT).with_suffix("").parts
                found.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return found


def _param(name: str):
    marks = [pytest.mark.fe] if name.split(".")[0] in NEEDS_FE else []
    return pytest.param(name, marks=marks, id=name)


def test_the_core_carries_examples():
    assert {"shroud.core.modes", "shroud.core.damping", "shroud.core.signals"} <= set(modules_with_examples())


@pytest.mark.parametrize("name", [_param(n) for n in modules_with_examples()])
def test_docstring_examples(name):
    if name.split(".")[0] in NEEDS_FE:
        import dolfinx_solver  # noqa: F401  (before petsc4py / slepc4py)
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples in {name} failed (see above)"
