"""Records of full scenes: what each study's full version concludes, regenerable by one command.

The full scenes take minutes to an hour, too long for CI, so
``tests/test_quick_conclusions*.py`` hold each quick version against a
record of its full version. A record is only worth holding against if
anyone can make it again and tell that it is current, so each one names

* ``commit``: the clean git revision it was made at (a tree with changes is
  refused: its conclusions could not be made again);
* ``sources``: the files the study's conclusions depend on directly, each
  with its SHA-256: the scene, the study module and the study helpers it
  imports (comparisons/_*.py, paper.py, and the two public in the analysis
  layer: shroud/analysis/agreement.py, coexistence.py). A record whose
  sources have changed since is stale; physics below the studies is held by
  the quick run itself;
* ``physics``: the files of the physics below the study that its sources
  import, transitively within the project (shroud/, reduced_model/,
  reference_fe/, meshes/: the integrator, the contact law, the models), each
  with its SHA-256. A physics change does not make a record stale (the quick
  run holds the physics), but ``shroud record --check`` lists the records it
  has left behind, to be made again before the change lands. Records made
  before records carried it lack it;
* ``digest``: the SHA-256 of its conclusions, sources, physics (where it has
  it) and commit, so a record edited by hand reads as such;
* the command that made it, and (not compared) its run time and date.

``shroud record [SCENE ...]`` runs the named full scenes (default: every
recorded one) and writes ``tests/data/records/<scene>.json``, one file per
scene, so that one study's record can be made again without the others.
Everything but ``elapsed_s`` and ``finished`` is the same byte for byte when
the same commit makes it again.
"""

from __future__ import annotations

import ast
import datetime
import functools
import hashlib
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from shroud.base.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
RECORDS = ROOT / "tests" / "data" / "records"
SCENES = ROOT / "scenes"
TIMINGS = ("elapsed_s", "finished")       # the only fields a remake may change

# The scenes whose full versions are recorded (those a quick-against-full test holds).
RECORDED = ("airfoil", "calculix", "campbell", "convergence", "default", "error_vs_time", "fig3", "fig4", "fig7",
            "fig8", "fig10", "friction", "gap_preload", "hb_fig4", "hb_fig7", "hb_friction", "hb_gap_preload",
            "hb_optimal_preload", "hb_stiffness_ratio", "interference", "periodicity", "ring_mistuning",
            "ring_tuned", "shell_benchmarks", "stability", "stability_fe", "stiffness_ratio", "table1")


def study_of(scene: str) -> str:
    """The study module a scene runs (its ``study = "..."`` line)."""
    import tomllib
    return tomllib.loads((SCENES / f"{scene}.toml").read_text())["study"]


# Study helpers public in the analysis layer (moved out of comparisons/): a study importing one depends on
# it as on its private helpers. Their own imports are physics below the studies, not followed.
ANALYSIS_HELPERS = ("shroud/analysis/agreement.py", "shroud/analysis/coexistence.py")


def _study_imports(path: Path) -> tuple[set[str], set[str]]:
    """Modules of the comparisons package, and files of ANALYSIS_HELPERS, that ``path`` imports (anywhere in it)."""
    found, helpers = set(), set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        for name in names:
            parts = name.split(".")
            if parts[0] == "comparisons" and len(parts) == 2 and (ROOT / "comparisons" / f"{parts[1]}.py").is_file():
                found.add(parts[1])
            elif "/".join(parts) + ".py" in ANALYSIS_HELPERS:
                helpers.add("/".join(parts) + ".py")
    return found, helpers


def sources_of(scene: str) -> list[str]:
    """Paths (relative to the project) of the files ``scene``'s conclusions depend on directly."""
    todo, seen, helpers = [study_of(scene)], set(), set()
    while todo:
        module = todo.pop()
        if module not in seen:
            seen.add(module)
            modules, used = _study_imports(ROOT / "comparisons" / f"{module}.py")
            todo.extend(modules - seen)
            helpers |= used
    return [f"scenes/{scene}.toml"] + sorted(f"comparisons/{m}.py" for m in seen) + sorted(helpers)


# The packages of the physics below the studies; and the studies' own (already sources), since a physics
# module never imports one (layers).
PHYSICS_PACKAGES = ("shroud", "reduced_model", "reference_fe", "meshes", "comparisons")
NO_PHYSICS = "shroud/base/"     # errors, logging, cache, MPI helpers, Markdown: no physics (CONTRIBUTING.md)
# A module named in a string, as the registry's lazy loaders, shroud.analysis.systems' SOLVERS and entry points
# name them ("reduced_model.system", "reference_fe.transient:simulate"): imported at run time.
_MODULE_NAMED = re.compile(r"[A-Za-z_]\w*(\.[A-Za-z_]\w*)+(:\w+)?")


def _module_file(name: str) -> str | None:
    """The project file (relative path) of the module ``name`` of a physics package; None for any other."""
    parts = name.split(".")
    if parts[0] not in PHYSICS_PACKAGES:
        return None
    base = ROOT.joinpath(*parts)
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file() and not (found := path.relative_to(ROOT).as_posix()).startswith(NO_PHYSICS):
            return found
    return None


def _entry_point_modules() -> set[str]:
    """The modules the builders declare their models in (pyproject.toml, the registry's entry points)."""
    import tomllib
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    return {v.split(":")[0] for v in project.get("entry-points", {}).get("shroud.models", {}).values()}


@functools.lru_cache(maxsize=None)
def _imported_files(path: str) -> frozenset[str]:
    """Project files the module at ``path`` imports: by import statements anywhere in it (relative ones
    resolved), by name in a string (importlib, lazy loaders), the builders' entry points for the registry,
    and the packages whose ``__init__`` each of these imports runs."""
    tree = ast.parse((ROOT / path).read_text(), filename=path)
    package = path.split("/")[:-1]          # where a relative import starts (level 1: this module's package)
    names = _entry_point_modules() if path == "shroud/core/registry.py" else set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            above = package[:len(package) - node.level + 1] if node.level else []
            module = ".".join(above + ([node.module] if node.module else []))
            names |= {module} | {f"{module}.{a.name}" for a in node.names}
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and _MODULE_NAMED.fullmatch(node.value):
            names.add(node.value.split(":")[0])
    files = set()
    for name in names:
        parts = name.split(".")
        files |= {f for i in range(1, len(parts) + 1) if (f := _module_file(".".join(parts[:i])))}
    return frozenset(files - {path})


def physics_of(scene: str) -> list[str]:
    """Paths of the project files below ``scene``'s sources that they import, transitively (the physics)."""
    sources = sources_of(scene)
    todo, seen = [p for p in sources if p.endswith(".py")], set()
    while todo:
        path = todo.pop()
        if path not in seen:
            seen.add(path)
            todo.extend(_imported_files(path) - seen)
    return sorted(seen - set(sources))


def file_hashes(paths: list[str]) -> dict[str, str]:
    return {p: hashlib.sha256((ROOT / p).read_bytes()).hexdigest() for p in paths}


def digest(record: dict) -> str:
    """SHA-256 of what a record asserts: its conclusions, sources, physics (records made before records
    carried it have none, and keep the digest they were made with) and commit."""
    body = {k: record[k] for k in ("scene", "commit", "sources", "conclusions", "physics") if k in record}
    return hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()


def _git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()


def clean_commit() -> str:
    """HEAD's hash when the tree has no changes to tracked files; InputError otherwise."""
    if _git("status", "--porcelain", "--untracked-files=no"):
        raise InputError("record", "the work tree has uncommitted changes; a record names the commit that "
                                   "makes it, so commit (or stash) first")
    return _git("rev-parse", "HEAD")


@dataclass(frozen=True)
class Staleness:
    """Why a record cannot be held against (empty: it can)."""

    problems: tuple[str, ...]

    @property
    def current(self) -> bool:
        return not self.problems


def check(record: dict) -> Staleness:
    """Whether ``record`` is whole, unedited and as new as its study's sources."""
    problems = []
    scene = record.get("scene", "?")
    for key in ("scene", "commit", "sources", "conclusions", "digest", "command"):
        if key not in record:
            problems.append(f"no {key!r}")
    if problems:
        return Staleness(tuple(problems))
    if len(record["commit"]) != 40 or not all(c in "0123456789abcdef" for c in record["commit"]):
        problems.append(f"commit {record['commit']!r} is not a clean git revision")
    if digest(record) != record["digest"]:
        problems.append("its digest does not match its contents (edited by hand?)")
    expected = sources_of(scene)
    if sorted(record["sources"]) != sorted(expected):
        problems.append(f"its sources {sorted(record['sources'])} are not the study's {sorted(expected)}")
    else:
        changed = [p for p, h in file_hashes(expected).items() if record["sources"][p] != h]
        if changed:
            problems.append(f"{', '.join(changed)} changed since it was made")
    return Staleness(tuple(problems))


def physics_changes(record: dict) -> tuple[str, ...] | None:
    """The physics files (:func:`physics_of`) changed, added or gone since ``record`` was made; None for a
    record made before records carried them."""
    if "physics" not in record:
        return None
    now, then = file_hashes(physics_of(record["scene"])), record["physics"]
    return tuple(sorted(p for p in now.keys() | then.keys() if now.get(p) != then.get(p)))


UNDECIDED_SHARE = 0.10      # issue 33: a full scene decides what it asks, at most this share left not decided


@dataclass(frozen=True)
class Decided:
    """How many verdicts a record's conclusions draw and how many of them stay not decided (those drawn
    from run times or memory counted apart: the machine decides them, not the blade)."""

    verdicts: int
    undecided: int
    undecided_costs: int

    @property
    def over(self) -> bool:
        """More than UNDECIDED_SHARE of the verdicts not decided."""
        return self.undecided > UNDECIDED_SHARE * self.verdicts

    def __str__(self) -> str:
        costs = f", {self.undecided_costs} of them run time or memory" if self.undecided_costs else ""
        flag = f", over {UNDECIDED_SHARE:.0%}" if self.over else ""
        return f"{self.verdicts} verdict{'' if self.verdicts == 1 else 's'}, {self.undecided} not decided{costs}{flag}"


def decided(conclusions) -> Decided:
    """The verdicts (shroud.core.verdict records) anywhere in ``conclusions`` and those not decided."""
    from shroud.core.verdict import NOT_DECIDED, is_cost_record, is_verdict
    from workbench.gates import children

    def verdicts(node) -> list[dict]:
        return [node] if is_verdict(node) else [v for _, child in children(node) for v in verdicts(child)]
    found = verdicts(conclusions)
    open_ = [v for v in found if v["answer"] == NOT_DECIDED]
    return Decided(len(found), len(open_), sum(map(is_cost_record, open_)))


def load(scene: str, folder: Path | None = None) -> dict:
    return json.loads(((folder or RECORDS) / f"{scene}.json").read_text())


def make(scene: str, commit: str, folder: Path = RECORDS) -> Path:
    """Run ``scene`` in full and write its record into ``folder``."""
    command = ["shroud", "run", f"scenes/{scene}.toml"]
    with tempfile.TemporaryDirectory(prefix=f"record-{scene}-") as tmp:
        env = {**os.environ, "OMP_NUM_THREADS": "1"}
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "workbench.cli", *command[1:], "--out", tmp],
                              cwd=ROOT, env=env, capture_output=True, text=True)
        elapsed = time.perf_counter() - t0
        if proc.returncode != 0:
            raise RuntimeError(f"{scene}: `{' '.join(command)}` exited {proc.returncode}:\n{proc.stderr[-2000:]}")
        result = json.loads((Path(tmp) / "results.json").read_text())
    if result.get("status") != "complete":
        raise RuntimeError(f"{scene}: the run ended {result.get('status')!r}, not complete")
    record = {"scene": scene, "study": study_of(scene), "command": "OMP_NUM_THREADS=1 " + " ".join(command),
              "commit": commit, "sources": file_hashes(sources_of(scene)),
              "physics": file_hashes(physics_of(scene)), "conclusions": result["results"]["conclusions"]}
    record["digest"] = digest(record)
    record["elapsed_s"] = round(elapsed, 1)
    record["finished"] = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{scene}.json"
    tmp_path = path.with_suffix(".json.tmp")
    tmp_path.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
    os.replace(tmp_path, path)
    return path


def record(scenes: list[str] | None = None, stale_only: bool = False, jobs: int = 1) -> list[Path]:
    """Make the records of ``scenes`` (default: every recorded scene; ``stale_only``: those :func:`due`)."""
    unknown = [s for s in scenes or () if s not in RECORDED]
    if unknown:
        raise InputError("record", f"{', '.join(unknown)} has no record; recorded scenes: {', '.join(RECORDED)}")
    commit = clean_commit()
    todo = list(scenes or RECORDED)
    if stale_only:
        todo = [s for s in todo if due(s)]
    from concurrent.futures import ThreadPoolExecutor      # each scene is its own process: threads only wait
    # longest first (by the last record's run time), so that side by side the last to finish is not a long
    # scene started late: hb_fig7, 40 min, is fourteenth of 28 in name order
    order = sorted(range(len(todo)), key=lambda i: -_last_elapsed(todo[i]))
    with ThreadPoolExecutor(max(jobs, 1)) as pool:
        ran = dict(zip(order, pool.map(lambda i: _made(todo[i], commit), order)))
    outcomes = [ran[i] for i in range(len(todo))]
    failed = [f"{scene}: {o}" for scene, o in zip(todo, outcomes) if isinstance(o, Exception)]
    if failed:                     # every other scene's record is made all the same
        raise RuntimeError("records not made:\n" + "\n".join(failed))
    return outcomes


def due(scene: str) -> bool:
    """Whether the record of ``scene`` must be made again: missing, not current (its sources changed), or left
    behind by a change of the physics it imports (its conclusions may no longer be what the code gives)."""
    if not (RECORDS / f"{scene}.json").is_file():
        return True
    record = load(scene)
    return not check(record).current or physics_changes(record) != ()


def _last_elapsed(scene: str) -> float:
    """The run time (s) of the scene's last record, 0 where it has none."""
    path = RECORDS / f"{scene}.json"
    return float(json.loads(path.read_text()).get("elapsed_s") or 0.0) if path.is_file() else 0.0


def _made(scene: str, commit: str) -> Path | Exception:
    """The record of ``scene``, or the error that stopped it (one scene's failure stops no other)."""
    t0 = time.perf_counter()
    print(f"[record] {scene}: running the full scene", file=sys.stderr, flush=True)
    try:
        path = make(scene, commit)
    except RuntimeError as exc:
        print(f"[record] {scene}: FAILED after {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
        return exc
    print(f"[record] {scene}: {path.relative_to(ROOT)} in {time.perf_counter() - t0:.0f} s", file=sys.stderr,
          flush=True)
    return path
