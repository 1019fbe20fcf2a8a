"""``--set key=value`` reads the value as TOML (README, docs/interface.md): ``time.contact="explicit"``
is the string explicit, as the bare word is; the same for every string key of the schema."""

from __future__ import annotations

import dataclasses
import json

import pytest

from workbench.cli import main
from shroud.params import SECTIONS, Parameters

# A value other than the default for each string key (the schema's own defaults are the other).
OTHER = {"time.contact": "explicit", "reduced.shroud": "rigid", "fe.cell": "tet", "blade.section": "naca4"}
# String keys whose value is a file's path, not a word from a set (blade.step: its refusals are the hostile
# STEP files of tests/test_airfoil_solid.py and tests/test_cli_errors.py)
PATHS = {"blade.step"}
STRING_KEYS = sorted(f"{s}.{f.name}" for s, cls in SECTIONS.items() for f in dataclasses.fields(cls)
                     if f.type == "str" and f"{s}.{f.name}" not in PATHS)


def test_every_string_key_has_a_second_value_here():
    assert STRING_KEYS == sorted(OTHER)


@pytest.mark.parametrize("key", STRING_KEYS)
@pytest.mark.parametrize("spelling", ['"{}"', "'{}'", "{}"])
def test_a_toml_string_and_a_bare_word_set_the_same_value(key, spelling, capsys):
    value = OTHER[key]
    code = main(["modal", "--modes", "1", "--json", "--set", f"{key}={spelling.format(value)}"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert json.loads(captured.out)["modes"]
    assert Parameters().with_overrides([f"{key}={spelling.format(value)}"]).flat()[key] == value


@pytest.mark.parametrize("key", STRING_KEYS)
def test_a_quoted_value_out_of_range_is_named_without_its_quotes(key, capsys):
    assert main(["modal", "--set", f'{key}="banana"']) == 2
    line = capsys.readouterr().err.strip()
    assert line.startswith(f"error: {key}: 'banana' is out of range") and "allowed:" in line
