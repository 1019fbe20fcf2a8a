"""Run one scene: validate everything, then let its study write into DIR.

Each study module (``comparisons/<study>.py``) has ``OPTIONS`` (defaults of
its own options) and ``run(scene, out) -> dict`` returning every number its
figures show; it writes its figures, CSVs and ``report.md`` into ``out``.
The runner adds ``results.json``: those numbers plus the parameters, options,
versions, cost and status (``complete`` or ``partial``).
"""

from __future__ import annotations

import json
import platform
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from shroud.errors import InputError
from shroud.log import info
from shroud.scene import load_scene, study_module


def versions() -> dict[str, str]:
    """Versions of what produced a result (FE stack only if it was loaded)."""
    out = {"python": platform.python_version(), "numpy": np.__version__}
    for name in ("scipy", "numba", "matplotlib", "dolfinx", "petsc4py", "slepc4py", "gmsh"):
        module = sys.modules.get(name)
        if module is not None:
            out[name] = str(getattr(module, "__version__", "?"))
    return out


def _jsonable(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, (np.floating, float)):
        return None if not np.isfinite(value) else float(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, Path):
        return str(value)
    return value


def write_results(out: Path, scene, status: str, elapsed: float, results: dict) -> Path:
    path = out / "results.json"
    payload = {
        "study": scene.study, "title": scene.title, "status": status, "quick": scene.quick,
        "elapsed_s": round(elapsed, 3), "parameters": scene.params.as_tables(),
        "options": scene.options, "versions": versions(), "results": results,
    }
    path.write_text(json.dumps(_jsonable(payload), indent=1))
    return path


def run_scene(path: str | Path, out: str | Path | None = None, overrides=(), quick: bool = False) -> dict:
    scene = load_scene(path, list(overrides), quick=quick)
    if not scene.study:
        raise InputError("study", f"scene {path} names no study; allowed: study = \"<name>\"")
    module = study_module(scene.study)
    out = Path(out) if out else Path("out") / Path(path).stem
    out.mkdir(parents=True, exist_ok=True)
    info(f"scene {path}: study {scene.study}{' (quick)' if quick else ''} -> {out}")
    t0 = time.perf_counter()
    try:
        results = module.run(scene, out)
    except KeyboardInterrupt:
        write_results(out, scene, "partial (interrupted)", time.perf_counter() - t0, {})
        raise
    elapsed = time.perf_counter() - t0
    write_results(out, scene, "complete", elapsed, results or {})
    info(f"scene {scene.study} done in {elapsed:.1f} s")
    return {"study": scene.study, "out": str(out), "elapsed_s": round(elapsed, 3), "status": "complete"}
