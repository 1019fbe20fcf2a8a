"""On-disk cache of expensive artefacts (meshes, FE matrices, reduction bases).

An artefact is keyed by a hash of exactly the inputs that shape it and of
the source files of the code that builds it, so a scene that needs what an
earlier run built reuses it, and a changed input or an edited builder builds
anew. The log says which, and why.

Entries are written to a temporary name and renamed into place, so a run
killed while writing leaves no entry behind; an entry that cannot be read
all the same (a full disk, a copy cut short) is rebuilt with a warning.

A cost measurement can tell a cold build (one that built entries) from a
warm one (that read them): :func:`builds` collects the wall time spent
building entries inside a block, so a build cached on disk is counted once
and said so.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import json
import os
import time
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

from shroud.base.log import info, warn
from shroud.base.outputs import check_writable, replacing


def cache_folder() -> Path:
    """``$SHROUD_CACHE`` or the project's ``.cache/`` folder (not made)."""
    env = os.environ.get("SHROUD_CACHE")
    return Path(env) if env else Path(__file__).resolve().parents[2] / ".cache"


def check_cache() -> None:
    """Refuse (InputError on SHROUD_CACHE) a cache folder that cannot be made or written, before any work."""
    check_writable(cache_folder(), "SHROUD_CACHE" if os.environ.get("SHROUD_CACHE") else "cache folder")


_LISTENERS: list[list[tuple[str, float]]] = []
_DEPTH = [0]          # entries being built now: an entry built inside another counts in the outer one


@contextlib.contextmanager
def builds():
    """The entries built (not read) inside the block, as a list of (what, wall seconds) filled as they are.

    An entry built while building another (a mesh inside a reduction basis) counts in the outer one only.
    """
    record: list[tuple[str, float]] = []
    _LISTENERS.append(record)
    try:
        yield record
    finally:
        _LISTENERS.remove(record)


def cache_root() -> Path:
    """The cache folder, made if missing (InputError if it cannot be)."""
    root = cache_folder()
    try:
        root.mkdir(parents=True, exist_ok=True)
    except OSError:
        check_cache()                   # names the cause in one line
        raise
    return root


def source_digest(modules: Iterable[str]) -> dict[str, str]:
    """``{module: hash of its file's bytes}`` of the named modules (dotted names), this one included.

    The cache's own layout is part of every entry; the named modules are the
    code whose output the entry holds.
    """
    out = {}
    for name in sorted({__name__, *modules}):
        spec = importlib.util.find_spec(name)
        if spec is None or not spec.origin:
            raise ModuleNotFoundError(f"cache source {name!r} is not an importable module")
        out[name] = hashlib.sha256(Path(spec.origin).read_bytes()).hexdigest()[:16]
    return out


def key_of(kind: str, inputs: Mapping[str, Any], sources: Iterable[str] = ()) -> str:
    text = json.dumps({"kind": kind, "code": source_digest(sources), **inputs}, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def cached(kind: str, inputs: Mapping[str, Any], suffix: str, build: Callable[[Path], None],
           what: str = "", sources: Iterable[str] = (),
           check: Callable[[Path], None] | None = None) -> Path:
    """Path of the artefact for ``inputs`` and ``sources``; ``build(tmp_path)`` writes it if missing.

    ``sources``: dotted names of the modules whose code shapes the artefact
    (their file bytes join the key: editing one builds anew). ``check(path)``
    raises if an existing entry cannot be read; such an entry is rebuilt.
    """
    sources = tuple(sources)
    key = key_of(kind, inputs, sources)
    folder = cache_root() / kind
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{key}{suffix}"
    label = what or kind
    if path.exists():
        problem = _unreadable(path, check)
        if problem is None:
            info(f"reused {label} {path.name} (same inputs: {_short(inputs)})")
            return path
        warn(f"cached {label} {path} cannot be read ({problem}): building it again")
    else:
        info(f"building {label} {path.name} (no cached entry for {_short(inputs)})")
    t0 = time.perf_counter()
    _DEPTH[0] += 1
    try:
        _write_atomic(path, build)
    finally:
        _DEPTH[0] -= 1
    if _DEPTH[0] == 0:
        for record in _LISTENERS:
            record.append((label, time.perf_counter() - t0))
    record = {"inputs": dict(inputs), "code": source_digest(sources)}
    _write_atomic(folder / f"{key}.json",
                  lambda tmp: tmp.write_text(json.dumps(record, sort_keys=True, default=repr, indent=1)))
    return path


def _unreadable(path: Path, check: Callable[[Path], None] | None) -> str | None:
    """Why the entry at ``path`` cannot be used, or None."""
    if path.stat().st_size == 0:
        return "empty file"
    if check is None:
        return None
    try:
        check(path)
    except Exception as exc:        # noqa: BLE001 - any failure to read means: rebuild
        return f"{type(exc).__name__}: {exc}"
    return None


def _write_atomic(path: Path, write: Callable[[Path], None]) -> None:
    """``write(tmp)`` to a temporary name beside ``path``, then rename it into place."""
    with replacing(path) as tmp:
        write(tmp)


def _short(inputs: Mapping[str, Any]) -> str:
    text = ", ".join(f"{k}={v}" for k, v in sorted(inputs.items()))
    return text if len(text) < 160 else text[:157] + "..."
