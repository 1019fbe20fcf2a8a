"""Run one scene: validate everything, then let its study write into DIR.

Each study module (``comparisons/<study>.py``) has ``OPTIONS`` (defaults of
its own options) and ``run(scene, out) -> dict`` returning every number its
figures show; it writes its figures, CSVs and ``report.md`` into ``out``.
The runner adds ``results.json``: those numbers plus the parameters, options,
versions, cost and status (``complete``, ``diverged (<models>)`` when a study reports runs that
left the bounded regime in its ``diverged`` entry, ``partial`` or ``failed``).

Gates (the scene's ``[gates]`` table merged with those of the command line
or campaign; workbench.gates) are held against that results.json once it is
assembled: it gains a ``gates`` list, ``report.md`` opens with the gate
table and ``junit.xml`` holds one test case per gate.

Nothing is written before the whole input is checked. An interrupted run
(Ctrl-C, or SIGTERM from a batch system at its time limit) leaves a marked
partial result: ``results.json`` says ``partial``, every CSV the run wrote
starts with a ``# status: incomplete`` line, and ``report.md`` says so at the top.
Under ``mpirun`` all ranks run the study together and only rank 0 writes.
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime
import json
import os
import platform
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np

from shroud.base.errors import InputError
from shroud.base.log import info, warn
from shroud.base.outputs import FolderLock, check_writable, write_text
from shroud.base.parallel import mpi_rank, mpi_size, on_rank_zero
from workbench import junit
from workbench.compare import check_timings
from workbench.gates import Gate, hold, merged
from workbench.report import open_with_gates
from workbench.scene import Scene, load_scene, study_module

INCOMPLETE_MARK = "# status: incomplete"


def versions() -> dict[str, str]:
    """Versions of what produced a result (FE stack only if it was loaded)."""
    out = {"python": platform.python_version(), "numpy": np.__version__}
    for name in ("scipy", "numba", "matplotlib", "dolfinx", "petsc4py", "slepc4py", "gmsh", "pyvista"):
        module = sys.modules.get(name)
        if module is not None:
            out[name] = str(getattr(module, "__version__", "?"))
    revision = _git_revision()
    if revision:
        out["workbench"] = revision
    return out


def _git_revision() -> str:
    root = Path(__file__).resolve().parents[1]
    try:
        head = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, timeout=10)
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.TimeoutExpired):
        return ""
    if head.returncode != 0:
        return ""
    return head.stdout.strip() + ("+local changes" if dirty.stdout.strip() else "")


def jsonable(value: Any) -> Any:
    """``value`` in plain JSON types (NaN and inf become null)."""
    if hasattr(value, "to_json"):
        return jsonable(value.to_json())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return jsonable(dataclasses.asdict(value))
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, (np.floating, float)):
        return None if not np.isfinite(value) else float(value)
    if isinstance(value, (np.integer, np.bool_)):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    return value


def write_results(out: Path, scene: Scene, status: str, elapsed: float, results: dict,
                  overrides=(), extra: dict | None = None, gates: tuple[Gate, ...] = ()) -> list[dict]:
    """``out/results.json``: the study's numbers and everything that produced them.

    Each of ``gates`` is held against that payload; their records (returned)
    are stored in it as ``gates``, in ``out/junit.xml`` and atop ``out/report.md``.
    """
    path = out / "results.json"
    payload = jsonable({
        "study": scene.study, "title": scene.title, "status": status, "quick": scene.quick,
        "elapsed_s": round(elapsed, 3),
        "finished": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
        "scene": str(scene.path) if scene.path else None, "overrides": list(overrides),
        "command": sys.argv,
        "host": {"cores": len(os.sched_getaffinity(0)), "mpi_ranks": mpi_size(), "mpi_rank": mpi_rank()},
        "parameters": scene.params.as_tables(), "options": scene.options,
        "versions": versions(), **(extra or {}), "results": results,
    })
    records = hold(gates, payload)
    if gates:
        payload["gates"] = records
    write_text(path, json.dumps(payload, indent=1))
    _report_gates(out, scene.path.stem if scene.path else scene.study, records)
    return records


def _report_gates(out: Path, name: str, records: list[dict]) -> None:
    """``out/junit.xml`` (one test case per gate) and the gate table atop ``out/report.md``.

    A folder run again without gates loses the junit.xml of its earlier run.
    """
    if not records:
        (out / "junit.xml").unlink(missing_ok=True)
        return
    junit.write(out / "junit.xml", f"shroud gates: {name}", [(name, junit.gate_cases(records))])
    open_with_gates(out / "report.md", records)


def output_folder(scene_path: str | Path, out: str | Path | None) -> Path:
    """``out`` or ``out/<scene name>``; refused if it names an existing file."""
    folder = Path(out) if out else Path("out") / Path(scene_path).stem
    if folder.exists() and not folder.is_dir():
        raise InputError("--out", f"{str(folder)!r} is an existing file; allowed: a folder path")
    check_writable(folder, "--out")
    return folder


@contextlib.contextmanager
def signal_handlers(handlers: dict):
    """``handlers`` (signal -> handler) in force for the block, the previous ones after it; a no-op
    outside the main thread, where Python cannot set them."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {sig: signal.signal(sig, handler) for sig, handler in handlers.items()}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def shielded_from_interrupts():
    """SIGINT and SIGTERM ignored for the block: a second Ctrl-C (a user's,
    or a batch system's repeat) must not cut the partial result half-written."""
    return signal_handlers({signal.SIGINT: signal.SIG_IGN, signal.SIGTERM: signal.SIG_IGN})


def _raise_interrupt(signum, frame):
    raise KeyboardInterrupt(f"signal {signum}")


def sigterm_as_interrupt():
    """A batch system's SIGTERM ends the run like Ctrl-C: with a marked partial result."""
    return signal_handlers({signal.SIGTERM: _raise_interrupt})


def run_scene(path: str | Path, out: str | Path | None = None, overrides=(), quick: bool = False,
              writer: bool | None = None, gates: tuple[Gate, ...] = ()) -> dict:
    """Validate scene ``path`` with ``overrides``, run its study into ``out``.

    A study may define ``check(scene)`` for cross-checks of its options; it
    runs before anything is written. A study that solves the ring of
    ``ring.blades`` declares ``RING = True``; the others refuse a ring
    (shroud.analysis.systems: no path drops it). ``writer`` (default: rank 0) says
    whether this process writes files; the other ranks of an MPI job run the same study into a scratch folder that
    is removed afterwards. ``gates`` replace the scene's own bound by bound.
    Returns a summary: study, out, status, elapsed_s, gates (their records).
    """
    scene = load_scene(path, list(overrides), quick=quick)
    gates = merged(scene.gates, tuple(gates))
    if not scene.study:
        raise InputError("study", f"scene {path} names no study; allowed: study = \"<name>\"")
    module = study_module(scene.study)
    if scene.params.ring.blades and not getattr(module, "RING", False):
        raise InputError("ring.blades", f"study {scene.study} solves the blade between fixed neighbours and would "
                                        "drop the ring; allowed: ring.blades = 0 with it (the studies that solve "
                                        "the ring of ring.blades declare RING = True, docs/ring.md)")
    check = getattr(module, "check", None)
    if check is not None:
        check(scene)                 # a study's own cross-checks of its options, before any write
    out = output_folder(path, out)
    writer = mpi_rank() == 0 if writer is None else writer
    with holding(out, writer):
        return _run_study(scene, module, path, out, writer, quick, overrides, gates)


@contextlib.contextmanager
def holding(out: Path, writer: bool):
    """``out`` held by this run's writer (shroud.base.outputs.FolderLock) for the block.

    Another run's hold is refused (InputError) on every MPI rank, before
    anything is written; a folder the block made is removed again when its
    input turns out bad (InputError) after all.
    """
    fresh = not out.exists()
    lock = FolderLock(out)
    on_rank_zero(lambda: lock.acquire() if writer else None)
    try:
        yield
    except InputError:
        if fresh and writer:
            shutil.rmtree(out, ignore_errors=True)   # bad input found late: leave nothing behind
        raise
    finally:
        lock.release()


def _run_study(scene: Scene, module, path, out: Path, writer: bool, quick: bool, overrides,
               gates: tuple[Gate, ...]) -> dict:
    target = out if writer else Path(tempfile.mkdtemp(prefix=f"shroud-rank{mpi_rank()}-"))
    target.mkdir(parents=True, exist_ok=True)
    info(f"scene {path}: study {scene.study}{' (quick)' if quick else ''} -> {out}")
    started = time.time()
    t0 = time.perf_counter()
    status = "complete"
    try:
        with sigterm_as_interrupt():
            results = module.run(scene, target) or {}
            check_timings(jsonable(results), "results")   # run times named as such, so compare skips them
    except KeyboardInterrupt:
        elapsed = time.perf_counter() - t0
        with shielded_from_interrupts():
            marked = mark_incomplete(target, started, f"run interrupted after {elapsed:.1f} s")
            write_results(target, scene, "partial (interrupted)", elapsed, {}, overrides,
                          {"incomplete_files": [str(p.relative_to(target)) for p in marked]}, gates)
        warn(f"interrupted: partial result in {out} (results.json says partial; "
             f"{len(marked)} file(s) marked incomplete)")
        raise
    except InputError:
        raise
    except Exception as exc:
        elapsed = time.perf_counter() - t0
        marked = mark_incomplete(target, started, f"run failed: {type(exc).__name__}")
        write_results(target, scene, f"failed ({type(exc).__name__}: {exc})", elapsed, {}, overrides,
                      {"incomplete_files": [str(p.relative_to(target)) for p in marked]}, gates)
        raise
    finally:
        if not writer:
            shutil.rmtree(target, ignore_errors=True)
    elapsed = time.perf_counter() - t0
    diverged = results.get("diverged") or {}        # a study's runs that left the bounded regime, by model
    if diverged:
        status = f"diverged ({', '.join(diverged)})"
        warn(f"{', '.join(diverged)} diverged: the run failed (results.json says {status!r})")
    records = write_results(target, scene, status, elapsed, results, overrides, gates=gates) if writer else []
    info(f"scene {scene.study} done in {elapsed:.1f} s")
    return {"study": scene.study, "title": scene.title, "out": str(out),
            "elapsed_s": round(elapsed, 3), "status": status, "gates": records}


def mark_incomplete(folder: Path, since: float, why: str) -> list[Path]:
    """Mark every CSV and report written since ``since`` (epoch s) as incomplete.

    A CSV's first line becomes ``# status: incomplete: <why>`` (replacing a
    ``# status:`` line a writer put there, as shroud.analysis.transient does);
    comment-aware readers such as numpy.loadtxt skip it, a person sees it first.
    """
    marked = []
    mark = f"{INCOMPLETE_MARK}: {why}; the run's other results are missing and this file may stop short"
    for csv in sorted(folder.rglob("*.csv")):
        if csv.stat().st_mtime >= since - 1.0:
            first, _, rest = csv.read_text().partition("\n")
            if not first.startswith(INCOMPLETE_MARK):
                body = rest if first.startswith("# status:") else f"{first}\n{rest}"
                write_text(csv, f"{mark}\n{body}")
            marked.append(csv)
    report = folder / "report.md"
    note = f"> **Partial result** ({why}): figures and tables below may be missing or cut short.\n\n"
    if report.exists() and report.stat().st_mtime >= since - 1.0:
        write_text(report, note + report.read_text())
    else:
        write_text(report, f"# Partial result\n\n{note}")
    marked.append(report)
    return marked
