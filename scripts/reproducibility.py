"""Reproducibility of the quick scenes: two identical runs, and runs under ``mpirun -n P``, held
against a serial run with ``shroud compare`` at its default tolerance (issue 24).

For each scene: a serial ``shroud run SCENE --quick`` (BASE), then, with ``--identical``, a second
serial run compared against BASE, and for each P of ``--ranks`` a run under ``mpirun -n P`` compared
against BASE. Exit 0 of ``shroud compare`` means every number agrees to 1e-6 relative (timings
skipped), 3 that some drifted (the first drift is shown). One JSON line per scene is appended to
``--log`` as it finishes, and a Markdown table is printed at the end::

    OMP_NUM_THREADS=1 python scripts/reproducibility.py --identical table1 fig4
    OMP_NUM_THREADS=1 python scripts/reproducibility.py --ranks 1,2,3 fig8 fig10

Runs are made one at a time (the machine is shared); their folders are kept under ``--work``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


@dataclass
class Outcome:
    """One run of a scene and, unless it is the baseline, its compare against the baseline."""

    label: str                       # "serial", "identical", "n=2", ...
    run_exit: int
    seconds: float                   # wall time of the run
    compare_exit: int | None = None  # None for the baseline
    first_drift: str = ""


@dataclass
class SceneRow:
    scene: str
    outcomes: list[Outcome] = field(default_factory=list)


def run_scene(scene: str, out: Path, ranks: int | None, timeout: float) -> Outcome:
    """``shroud run scenes/SCENE.toml --quick --out OUT``, serially (ranks None) or under mpirun."""
    shutil.rmtree(out, ignore_errors=True)
    command = [str(BIN / "shroud"), "run", str(ROOT / "scenes" / f"{scene}.toml"), "--quick", "--out", str(out)]
    if ranks is not None:
        command = [str(BIN / "mpirun"), "-n", str(ranks), *command]
    start = time.perf_counter()
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
        code = done.returncode
        if code != 0:
            print(f"  {scene} {'serial' if ranks is None else f'n={ranks}'}: exit {code}: "
                  f"{done.stderr.strip().splitlines()[-1:] }", file=sys.stderr)
    except subprocess.TimeoutExpired:
        code = -1
    label = "serial" if ranks is None else f"n={ranks}"
    return Outcome(label, code, time.perf_counter() - start)


def compare(base: Path, new: Path, outcome: Outcome) -> Outcome:
    """``shroud compare BASE NEW --json``: its exit status and the largest drift, if any."""
    done = subprocess.run([str(BIN / "shroud"), "compare", str(base), str(new), "--json"],
                          capture_output=True, text=True)
    outcome.compare_exit = done.returncode
    try:
        drifted = json.loads(done.stdout)["drifted"]
    except (json.JSONDecodeError, KeyError):
        drifted = [{"path": done.stderr.strip()[:200], "base": None, "new": None, "relative_change": None}]
    if drifted:
        d = drifted[0]
        outcome.first_drift = (f"{d['path']}: {d['base']!r} -> {d['new']!r}"
                               + (f" ({d['relative_change']:.2g})" if d.get("relative_change") else "")
                               + (f" and {len(drifted) - 1} more" if len(drifted) > 1 else ""))
    return outcome


def check_scene(scene: str, work: Path, identical: bool, ranks: list[int], timeout: float, reuse: bool) -> SceneRow:
    row = SceneRow(scene)
    base = work / scene / "serial"
    if reuse and (base / "results.json").is_file():      # the serial run of an earlier call of this script
        row.outcomes.append(Outcome("serial", 0, math.nan))
    else:
        row.outcomes.append(run_scene(scene, base, None, timeout))
    if row.outcomes[0].run_exit not in (0, 3):      # 3: a gate of the scene failed; its numbers still compare
        return row
    if identical:
        again = run_scene(scene, work / scene / "identical", None, timeout)
        again.label = "identical"
        row.outcomes.append(compare(base, work / scene / "identical", again) if again.run_exit in (0, 3) else again)
    for n in ranks:
        folder = work / scene / f"n{n}"
        outcome = run_scene(scene, folder, n, timeout)
        row.outcomes.append(compare(base, folder, outcome) if outcome.run_exit in (0, 3) else outcome)
    return row


def table(rows: list[SceneRow]) -> str:
    """Markdown: per scene and run, the compare exit (or the run's failure) and the wall time."""
    labels = list(dict.fromkeys(o.label for row in rows for o in row.outcomes))
    lines = ["| scene | " + " | ".join(labels) + " | first drift |",
             "|---" * (len(labels) + 2) + "|"]
    for row in rows:
        cells, drifts = [], []
        by_label = {o.label: o for o in row.outcomes}
        for label in labels:
            o = by_label.get(label)
            if o is None:
                cells.append("")
            elif o.run_exit not in (0, 3):
                cells.append(f"run exit {o.run_exit} ({o.seconds:.0f} s)" if o.run_exit >= 0
                             else f"timeout ({o.seconds:.0f} s)")
            elif o.compare_exit is None:
                cells.append("(earlier run)" if math.isnan(o.seconds) else f"{o.seconds:.0f} s")
            else:
                cells.append(f"{o.compare_exit} ({o.seconds:.0f} s)")
                if o.first_drift:
                    drifts.append(f"{label}: {o.first_drift}")
        lines.append(f"| {row.scene} | " + " | ".join(cells) + " | " + "; ".join(drifts) + " |")
    return "\n".join(lines)


def logged(log: Path) -> list[SceneRow]:
    """The scenes of a log, in first-seen order, each with its outcomes by label (a later line's replace
    an earlier's, a reused baseline never replaces a measured one)."""
    rows: dict[str, dict[str, Outcome]] = {}
    for line in log.read_text().splitlines():
        entry = json.loads(line)
        mine = rows.setdefault(entry["scene"], {})
        for o in entry["outcomes"]:
            outcome = Outcome(**o)
            if not (math.isnan(outcome.seconds) and outcome.label in mine):
                mine[outcome.label] = outcome
    return [SceneRow(scene, list(outcomes.values())) for scene, outcomes in rows.items()]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="*", help="scene names (scenes/NAME.toml)")
    parser.add_argument("--identical", action="store_true", help="a second serial run against the first")
    parser.add_argument("--ranks", default="", help="comma-separated rank counts for mpirun, e.g. 1,2,3")
    parser.add_argument("--work", type=Path, default=Path("out/reproducibility"), help="run folders")
    parser.add_argument("--log", type=Path, default=None, help="append one JSON line per scene (default WORK/log.jsonl)")
    parser.add_argument("--timeout", type=float, default=1800.0, help="per run (s)")
    parser.add_argument("--reuse", action="store_true",
                        help="keep a serial run WORK/SCENE/serial of an earlier call as the baseline")
    parser.add_argument("--table", action="store_true",
                        help="only print the table of the log's lines (a scene's later lines add to its earlier)")
    args = parser.parse_args(argv)
    ranks = [int(n) for n in args.ranks.split(",") if n]
    log = args.log or args.work / "log.jsonl"
    if args.table:
        print(table(logged(log)))
        return 0
    log.parent.mkdir(parents=True, exist_ok=True)
    rows = []
    for scene in args.scenes:
        row = check_scene(scene, args.work, args.identical, ranks, args.timeout, args.reuse)
        rows.append(row)
        with log.open("a") as stream:
            stream.write(json.dumps(asdict(row)) + "\n")
        print(table([row]).splitlines()[-1], file=sys.stderr, flush=True)
    print(table(rows))
    return 0 if all(o.compare_exit in (None, 0) and o.run_exit in (0, 3) for r in rows for o in r.outcomes) else 1


if __name__ == "__main__":
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    sys.exit(main())
