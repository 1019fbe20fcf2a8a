"""On-disk cache of expensive artefacts (meshes, FE matrices, reduction bases).

An artefact is keyed by a hash of exactly the inputs that shape it, so a
scene that needs what an earlier run built reuses it, and a changed input
builds anew. The log says which, and why.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Any, Callable, Mapping

from shroud.base.log import info

# Bump when a builder's output format or meaning changes: old entries are then unused.
CACHE_VERSION = 1


def cache_root() -> Path:
    """``$SHROUD_CACHE`` or the project's ``.cache/`` folder."""
    env = os.environ.get("SHROUD_CACHE")
    root = Path(env) if env else Path(__file__).resolve().parents[1] / ".cache"
    root.mkdir(parents=True, exist_ok=True)
    return root


def key_of(kind: str, inputs: Mapping[str, Any]) -> str:
    text = json.dumps({"kind": kind, "v": CACHE_VERSION, **inputs}, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def cached(kind: str, inputs: Mapping[str, Any], suffix: str,
           build: Callable[[Path], None], what: str = "") -> Path:
    """Path of the artefact for ``inputs``; ``build(tmp_path)`` writes it if missing.

    Writes go to a temporary name first, so an interrupted build leaves no
    half-written entry behind.
    """
    key = key_of(kind, inputs)
    folder = cache_root() / kind
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{key}{suffix}"
    label = what or kind
    if path.exists():
        info(f"reused {label} {path.name} (same inputs: {_short(inputs)})")
        return path
    info(f"building {label} {path.name} (no cached entry for {_short(inputs)})")
    tmp = folder / f".{key}.{os.getpid()}.tmp{suffix}"
    build(tmp)
    os.replace(tmp, path)
    (folder / f"{key}.json").write_text(json.dumps(dict(inputs), sort_keys=True, default=repr, indent=1))
    return path


def _short(inputs: Mapping[str, Any]) -> str:
    text = ", ".join(f"{k}={v}" for k, v in sorted(inputs.items()))
    return text if len(text) < 160 else text[:157] + "..."
