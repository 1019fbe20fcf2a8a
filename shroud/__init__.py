"""Shared core of the shrouded-blade workbench: parameters, the contact law,
the Newmark integrator, signals, scenes and the ``shroud`` command."""

import hashlib as _hashlib
import os as _os
from pathlib import Path as _Path


def _numba_cache_dir() -> str:
    """Folder of numba's compiled-kernel cache, named by a hash of the compiled sources.

    numba keys a cached function on its own file's time stamp only: the
    Newmark kernel (newmark.py) compiled with an older contact law
    (contact.py) would be reused after a change to contact.py alone, and run
    the old law silently. Keying the folder on both sources rebuilds instead.
    """
    here = _Path(__file__).resolve().parent
    digest = _hashlib.sha256()
    for name in ("contact.py", "newmark.py"):
        digest.update((here / name).read_bytes())
    return str(here / "__pycache__" / f"numba-{digest.hexdigest()[:12]}")


_os.environ.setdefault("NUMBA_CACHE_DIR", _numba_cache_dir())
