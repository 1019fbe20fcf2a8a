"""The README is a door: short, its commands real, its links alive."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from workbench.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def test_the_two_commands_open_it():
    first_block = README.split("```bash\n", 1)[1].split("```", 1)[0]
    assert first_block.splitlines()[0].startswith("bash scripts/main.sh")
    assert first_block.splitlines()[1].startswith("bash scripts/test.sh")
    assert README.index("bash scripts/main.sh") < README.index("\n## ")


def test_it_reads_in_five_minutes():
    words = len(re.sub(r"```.*?```", "", README, flags=re.S).split())
    assert words < 1200, f"{words} words: about 200 a minute is five minutes' reading"


@pytest.mark.parametrize("line", [l.split("#")[0].strip() for l in README.splitlines()
                                  if l.startswith("shroud ")])
def test_every_shroud_command_shown_parses(line):
    args = build_parser().parse_args(shlex.split(line)[1:])
    assert args.command


def test_every_link_leads_somewhere():
    for target in re.findall(r"\]\(([^)#]+)\)", README):
        assert (ROOT / target).exists(), target
    for scene in re.findall(r"`([a-z0-9_]+)`", README.split("## The scenes", 1)[1].split("## ", 1)[0]):
        assert (ROOT / "scenes" / f"{scene}.toml").exists(), scene
