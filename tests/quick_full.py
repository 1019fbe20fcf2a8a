"""How a quick scene's conclusions are held against its full scene's record (tests/test_quick_conclusions*.py).

A verdict (shroud.core.verdict: answer, value, kind, threshold, margin, unit, reason) is held by its
answer: a quick run that cannot decide within its margin ("not decided") does not contradict a full run
that can; only a quick answer that takes the other side does (shroud.core.verdict.contradicts). Verdicts
drawn from run times or memory are never held: the machine decides them, not the blade.

Because "not decided" contradicts nothing, a comparison whose verdicts are all undecided on one side or
the other, or whose tables share no keys, would pass having held nothing. :class:`Held` counts the
verdict pairs decided on both sides that a test held; the ``held`` fixture (tests/conftest.py) fails the
test when it held none, and prints how many it held (``pytest -rA`` shows it).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from shroud.core.verdict import NOT_DECIDED, answer_of, contradicts, is_cost_record, is_verdict

SCENES = Path(__file__).resolve().parents[1] / "scenes"
_QUICK_RUNS: dict[str, Path] = {}      # study -> the folder its quick run wrote, this test session


def quick_run(study: str, tmp_path: Path) -> tuple[dict, Path]:
    """The results.json of the quick version of scenes/<study>.toml run as a user would
    (workbench.runner.run_scene), and the folder it wrote: run once a test session, by the first test that
    asks (into its ``tmp_path``), and read by the others (hb_gap_preload, table1, interference and
    ring_mistuning each serve two tests)."""
    if study not in _QUICK_RUNS:
        from workbench.runner import run_scene
        run_scene(SCENES / f"{study}.toml", tmp_path / study, quick=True)
        _QUICK_RUNS[study] = tmp_path / study
    folder = _QUICK_RUNS[study]
    return json.loads((folder / "results.json").read_text()), folder


class Held:
    """The verdict pairs one quick-against-full test held, counted: decided on both sides, or not."""

    def __init__(self, test: str):
        self.test = test
        self.decided = 0          # verdict pairs whose answers both sides decided (and that agreed)
        self.undecided = 0        # verdict pairs "not decided" on at least one side (they hold nothing)

    def count(self, got: Any, full: Any) -> None:
        """Count a verdict pair a test held by a rule of its own (not :meth:`agrees`)."""
        if is_verdict(got) and is_verdict(full):
            if NOT_DECIDED in (answer_of(got), answer_of(full)):
                self.undecided += 1
            else:
                self.decided += 1

    def agrees(self, got: Any, full: Any) -> bool:
        """Whether a quick conclusion agrees with the full one: verdicts and plain values by their answers
        (contradicts), tables entry by entry where both have it. A verdict drawn from run times or memory
        (the machine and the rank count set them) handed over is refused, not passed."""
        assert not (is_cost_record(got) or is_cost_record(full)), f"a verdict drawn from run time or memory: {got}"
        if isinstance(got, dict) and not is_verdict(got) and isinstance(full, dict) and not is_verdict(full):
            return all([self.agrees(got[k], full[k]) for k in got.keys() & full.keys()])
        if isinstance(got, list) and isinstance(full, list):
            return len(got) == len(full) and all([self.agrees(a, b) for a, b in zip(got, full)])
        self.count(got, full)
        return not contradicts(got, full)

    def same(self, got: dict, full: dict) -> bool:
        """Whether two verdicts' answers are equal, "not decided" included (the HB studies hold both)."""
        self.count(got, full)
        return answer_of(got) == answer_of(full)

    def same_where_shared(self, got: dict, full: dict, keys) -> None:
        """Every entry of got[key] that full[key] also has agrees, and each key shares at least one."""
        for key in keys:
            shared = got[key].keys() & full[key].keys()
            assert shared, key
            for entry in shared:
                assert self.agrees(got[key][entry], full[key][entry]), (key, entry, got[key][entry],
                                                                        full[key][entry])

    def summary(self) -> str:
        return (f"{self.test}: held {self.decided} verdict pairs decided on both sides "
                f"({self.undecided} more not decided on one side or both)")

    def check(self) -> None:
        """Fail when the test held no verdict decided on both sides: it compared nothing."""
        assert self.decided > 0, f"compared no decided verdict: {self.summary()}"
