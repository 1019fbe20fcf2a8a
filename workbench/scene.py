"""Scenes: TOML files that name a study, its parameters and its options.

Layout of a scene file::

    study = "table1"              # runs comparisons/table1.py
    title = "Table 1: ..."
    [speed]                       # any parameter section (shroud.params)
    rpm = 8500
    [options]                     # the study's own options (its OPTIONS dict)
    N_values = [4, 5, 6, 7]
    [quick.options]               # applied by --quick: a coarse, minute-scale run
    N_values = [4, 6]
    [quick.time]
    periods = 20
    [gates]                       # bounds on numbers of the run's results.json (workbench.gates)
    "results.fig8.versus_reference.reduced.nrmse.v_L" = { max = 0.08 }

``--set key=value`` overrides either a parameter (``speed.rpm=9000``) or an
option (``options.N_values=[4,6]``; values are read as TOML).
Everything is validated before any output is written.
"""

from __future__ import annotations

import importlib
import importlib.util
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

from workbench.gates import Gate, from_table
from shroud.base.errors import InputError
from shroud.params import SECTIONS, Parameters, parse_value, unknown_key

_TOP_KEYS = {"study", "title", "description", "options", "quick", "gates"}


@dataclass(frozen=True)
class Scene:
    study: str
    title: str
    params: Parameters
    options: dict[str, Any] = field(default_factory=dict)
    quick: bool = False
    path: Path | None = None
    description: str = ""
    gates: tuple[Gate, ...] = ()


def read_toml(path: Path) -> dict[str, Any]:
    """The tables of a scene or campaign file; InputError naming the file for anything else."""
    allowed = "allowed: a TOML text file (UTF-8), e.g. scenes/fig8.toml"
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise InputError(str(path), f"no such scene file; {allowed}") from None
    except IsADirectoryError:
        raise InputError(str(path), f"is a folder, not a scene file; {allowed}") from None
    except PermissionError:
        raise InputError(str(path), f"cannot be read (permission denied); {allowed}") from None
    except UnicodeDecodeError as exc:
        raise InputError(str(path), f"is not UTF-8 text (byte {exc.start}); {allowed}") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(str(path), f"does not parse as TOML ({exc})") from None


def study_module(name: str):
    """The module ``comparisons.<name>`` that runs study ``name``."""
    if not isinstance(name, str) or not name.replace("_", "").isalnum():
        raise InputError("study", f"{name!r} is not a study name")
    module = None
    if importlib.util.find_spec(f"comparisons.{name}") is not None:
        module = importlib.import_module(f"comparisons.{name}")
    if not callable(getattr(module, "run", None)):   # helper modules (paper data, plots) are not studies
        raise InputError("study", f"unknown study {name!r}; allowed: " + ", ".join(available_studies()))
    return module


def available_studies() -> list[str]:
    """Modules of comparisons/ that define a study (an ``OPTIONS`` dict and ``run``)."""
    folder = Path(importlib.util.find_spec("comparisons").origin).parent
    return sorted(p.stem for p in folder.glob("*.py")
                  if not p.stem.startswith("_") and "OPTIONS" in p.read_text())


def _check_options(given: Mapping[str, Any], defaults: Mapping[str, Any],
                   prefix: str = "options") -> dict[str, Any]:
    """The study's defaults updated by ``given``; each value of its default's kind."""
    out = dict(defaults)
    for key, value in given.items():
        if key not in defaults:
            raise unknown_key(f"{prefix}.{key}", [f"{prefix}.{k}" for k in defaults]
                              or ["(study takes no options)"])
        want = defaults[key]
        if want is not None and not _same_kind(value, want):
            raise InputError(f"{prefix}.{key}", f"{value!r} has the wrong type; allowed: "
                             f"{type(want).__name__} like {want!r}")
        out[key] = value
    return out


def _same_kind(value: Any, want: Any) -> bool:
    if isinstance(want, bool) or isinstance(value, bool):
        return isinstance(value, bool) and isinstance(want, bool)
    if isinstance(want, (int, float)):
        return isinstance(value, (int, float))
    if isinstance(want, list):
        return isinstance(value, list) and all(
            not want or _same_kind(v, want[0]) for v in value)
    return isinstance(value, type(want))


def load_scene(path: str | Path | None, overrides: list[str] = (), quick: bool = False,
               study: str | None = None, profile: bool = False, step: bool = False,
               disk: bool = False) -> Scene:
    """Read, merge and validate a scene (or the bare defaults when ``path`` is None).

    The blade keys the path at hand cannot honour are refused here, before
    anything is written (shroud.params.Blade.check_modelled; ``profile`` lets
    a NACA section and tapers through, for ``shroud section``, the beams, the
    solid and the shell models, and for a study that declares ``PROFILE = True``; ``step`` a STEP file, for
    the beams and the solid's modes), and so is
    a flexible disk unless ``disk`` says the command builds one
    (shroud.params.Disk.check_rigid).

    The ``[quick]`` table is checked whether or not ``quick`` is asked for, so
    a typo in it fails on the first run, not on the first quick run.
    """
    data = read_toml(Path(path)) if path else {}
    for key in data:
        if key not in _TOP_KEYS and key not in SECTIONS:
            raise unknown_key(key, sorted(_TOP_KEYS | set(SECTIONS)))
    name = study or data.get("study")
    if name is not None and not isinstance(name, str):
        raise InputError("study", f"{name!r} is not a study name; allowed: study = \"<name>\"")
    params = Parameters.from_mapping({k: v for k, v in data.items() if k in SECTIONS})
    gates = from_table(data.get("gates", {}))
    options_given = _table(data, "options")
    quick_table = _table(data, "quick")
    for key in quick_table:
        if key != "options" and key not in SECTIONS:
            raise unknown_key(f"quick.{key}", ["quick.options"] + [f"quick.{s}" for s in SECTIONS])
    try:
        quick_params = Parameters.from_mapping(
            {k: v for k, v in quick_table.items() if k != "options"}, base=params)
    except InputError as exc:
        raise InputError(f"quick.{exc.key}", exc.message) from None
    quick_options = _table(quick_table, "options", "quick.options")
    if quick:
        params = quick_params
        options_given.update(quick_options)
    param_sets = []
    for text in overrides:
        key, sep, value = text.partition("=")
        if not sep or not key.strip():
            raise InputError("--set", f"{text!r} is not key=value; allowed: e.g. --set speed.rpm=8500 "
                             "or --set options.periods=20")
        if key.strip().startswith("options."):
            options_given[key.strip()[len("options."):]] = parse_value(value.strip())
        else:
            param_sets.append(text)
    params = params.with_overrides(param_sets)
    # a study that declares PROFILE = True runs every model on the airfoil (comparisons.airfoil)
    params.blade.check_modelled(profile or bool(name and getattr(study_module(name), "PROFILE", False)), step)
    # a study that declares DISK = True builds the flexible disk's FE sector itself (comparisons.interference)
    if not (disk or bool(name and getattr(study_module(name), "DISK", False))):
        params.disk.check_rigid()
    options: dict[str, Any] = {}
    if name:
        defaults = getattr(study_module(name), "OPTIONS", {})
        _check_options(quick_options, defaults, prefix="quick.options")
        options = _check_options(options_given, defaults)
    elif options_given or quick_options:
        raise InputError("options", "options need a study (scene key 'study')")
    return Scene(study=name or "", title=str(data.get("title", name or "")), params=params,
                 options=options, quick=quick, path=Path(path) if path else None,
                 description=str(data.get("description", "")), gates=gates)


def _table(data: Mapping[str, Any], key: str, name: str | None = None) -> dict[str, Any]:
    value = data.get(key, {})
    if not isinstance(value, dict):
        raise InputError(name or key, f"{value!r} is not a table; allowed: a [{name or key}] table")
    return dict(value)
