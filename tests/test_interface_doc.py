"""docs/interface.md against the commands: every parameter key, option and JSON key the commands have is
documented there, and every one documented there exists.
The JSON keys are read off real runs of each command; every option has --help text, speeds with r/min."""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

import pytest

from workbench.cli import build_parser, main
from shroud.params import all_keys

ROOT = Path(__file__).resolve().parents[1]
DOC = (ROOT / "docs/interface.md").read_text()

# Documented, implementation under way (marked "(pending)" in the page). Each must be marked so there,
# and once it exists the test asks for its documentation like any other's.
PENDING_KEYS: set[str] = set()
PENDING_OPTIONS: dict[str, set[str]] = {}
# Printed only with ring.blades = N or --interface, which the runs below do not use; compare's count of
# skipped memory only when a study declares memory (convergence).
CONDITIONAL_JSON = {"nodal_diameters", "nd", "blades", "N", "Ff", "blades_amplitude_v_L", "blades_amplitude_w_L",
                    "interface", "memory", "turn_rad", "kind"}      # turn_rad, kind: a branch's corners and folds


def _section(command: str) -> str:
    match = re.search(rf"^### shroud {command}\n(.*?)(?=^##)", DOC, re.S | re.M)
    assert match, f"docs/interface.md has no section '### shroud {command}'"
    return match.group(1)


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


# --- parameter keys ----------------------------------------------------------------------------------
def _documented_keys() -> dict[str, str]:
    table = DOC.split("## Parameter keys", 1)[1].split("\n## ", 1)[0]
    out = {}
    for row in table.splitlines():
        cells = [c.strip() for c in row.strip().strip("|").split("|")]
        if row.startswith("| `"):
            for key in re.findall(r"`([a-z_]+\.[A-Za-z0-9_]+)`", cells[0]):
                out[key] = row
    return out


def test_every_parameter_key_is_documented_and_every_documented_key_exists():
    documented, real = _documented_keys(), set(all_keys())
    assert real - set(documented) == set(), "keys missing from docs/interface.md"
    assert set(documented) - real - PENDING_KEYS == set(), "documented keys that do not exist"
    for key in set(documented) - real:
        assert "(pending)" in documented[key], key


def test_every_parameter_row_names_a_unit():
    for key, row in _documented_keys().items():
        unit = [c.strip() for c in row.strip().strip("|").split("|")][1]
        assert unit, f"{key}: no unit column"
        if key.endswith("_deg"):
            assert unit == "deg"
        if key.endswith("rpm"):
            assert unit == "r/min"


# --- options -----------------------------------------------------------------------------------------
def _options(parser: argparse.ArgumentParser) -> set[str]:
    return {s for a in parser._actions for s in a.option_strings if s.startswith("--") and s != "--help"}


@pytest.mark.parametrize("command", sorted(_subparsers()))
def test_every_option_is_documented_in_its_command_section(command):
    documented = set(re.findall(r"(--[a-z][a-z-]*)", _section(command)))
    real = _options(_subparsers()[command])
    assert real - documented == set(), f"shroud {command}: options missing from docs/interface.md"
    assert documented - real - PENDING_OPTIONS.get(command, set()) == set(), \
        f"shroud {command}: documented options that do not exist"


def test_pending_commands_are_marked_and_documented():
    for command in set(PENDING_OPTIONS) - set(_subparsers()):
        assert "(pending)" in _section(command)


@pytest.mark.parametrize("command", sorted(_subparsers()))
def test_every_option_has_help_and_speeds_their_unit(command):
    for action in _subparsers()[command]._actions:
        if not action.option_strings or "--help" in action.option_strings:
            continue
        assert action.help, f"shroud {command} {action.option_strings[0]}: no --help text"
        if ("rpm" in action.dest and "count" not in action.dest) or action.dest == "checkpoints":
            assert "r/min" in action.help, f"shroud {command} {action.option_strings[0]}: no unit"


# --- JSON keys, read off real runs -------------------------------------------------------------------
def _keys(value) -> set[str]:
    """Every key of a JSON object, nested ones too (a list of objects: its elements'); data-named keys
    (digits) aside."""
    out: set[str] = set()
    if isinstance(value, dict):
        for k, v in value.items():
            if not k.isdigit():
                out.add(k)
            out |= _keys(v)
    elif isinstance(value, list):
        for v in value:
            out |= _keys(v)
    return out


def _documented_json(text: str) -> set[str]:
    """The quoted keys of the JSON descriptions in ``text`` (a quoted word after ': ' is a value)."""
    return set(re.findall(r'(?<!: )"([A-Za-z_][A-Za-z0-9_]*)"', text))


def _json_of(capsys, argv: list[str]) -> dict:
    code = main(argv)
    captured = capsys.readouterr()
    assert code == 0, captured.err
    return json.loads(captured.out)


def _check(section: str, payload: dict, part: str | None = None):
    text = section if part is None else section.split(part, 1)[1].split("\n\n", 1)[0]
    documented, real = _documented_json(text), _keys(payload)
    assert real - documented == set(), "JSON keys missing from docs/interface.md"
    assert documented - real - CONDITIONAL_JSON == set(), "documented JSON keys the command does not print"


def test_modal_json(capsys):
    _check(_section("modal"), _json_of(capsys, ["modal", "--json", "--modes", "3"]))


def test_static_json(capsys):
    _check(_section("static"), _json_of(capsys, ["static", "--json", "--tip-force", "0", "100", "0"]))


def test_transient_json(capsys, tmp_path):
    _check(_section("transient"), _json_of(capsys, ["transient", "--json", "--set", "time.periods=12",
                                                    "--out", str(tmp_path / "tr")]))


def test_sweep_json(capsys):
    section = _section("sweep")
    time_domain = _json_of(capsys, ["sweep", "--json", "--rpm-from", "9000", "--rpm-to", "10000",
                                    "--rpm-count", "2", "--set", "time.periods=20"])
    _check(section, time_domain, "Time domain, JSON:")
    hb = _json_of(capsys, ["sweep", "--json", "--method", "hb", "--rpm-from", "8000", "--rpm-to", "9000",
                           "--harmonics", "5", "--samples", "128"])
    _check(section, hb, "Harmonic balance (`--method hb`), JSON:")
    checkpoints = _json_of(capsys, ["sweep", "--json", "--method", "hb", "--checkpoints", "9000",
                                    "--harmonics", "5", "--samples", "128"])
    _check(section, checkpoints, "Checkpoints (`--method hb --checkpoints`), JSON:")


@pytest.mark.parametrize("section", ["rectangle", "naca4"])
def test_section_json(capsys, section):
    _check(_section("section"), _json_of(capsys, ["section", "--json", "--set", f"blade.section={section}"]), "JSON:")


def test_run_and_compare_json(capsys, tmp_path):
    out = tmp_path / "fig3"
    summary = _json_of(capsys, ["run", str(ROOT / "scenes/fig3.toml"), "--quick", "--json", "--out", str(out)])
    section = _section("run")
    campaign = {"campaign": None}                 # a campaign's summary names it instead of study and title
    _check(section, {k: v for k, v in summary.items() if k != "gates"} | {"gates": []} | campaign,
           "JSON (the summary):")
    record = json.loads((out / "results.json").read_text())
    top = {k: (v if k == "host" else None) for k, v in record.items()}
    documented = _documented_json(section.split("`results.json`:", 1)[1].split("\n\n", 1)[0])
    assert _keys(top) <= documented
    assert documented - _keys(top) == {"gates", "incomplete_files"}      # only with gates, only if partial
    _check(_section("compare"), _json_of(capsys, ["compare", str(out), str(out), "--json"]))
