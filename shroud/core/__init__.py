"""Physics core: the linear structure plus contact elements, the one contact
law, the time integrator, signals and result types.

Imports nothing of the project above :mod:`shroud.base`; model builders
register with :mod:`shroud.core.registry`.
"""

import hashlib as _hashlib
import os as _os
from pathlib import Path as _Path


def _numba_cache_dir() -> str:
    """Folder of numba's compiled-kernel cache, named by a hash of the compiled sources.

    numba keys a cached function on its own file's time stamp only: a kernel
    compiled with an older contact law (contact.py) would be reused after a
    change to contact.py alone, and run the old law silently. Keying the
    folder on every compiled source of the core rebuilds instead.
    """
    here = _Path(__file__).resolve().parent
    digest = _hashlib.sha256()
    for path in sorted(here.glob("*.py")):
        digest.update(path.read_bytes())
    # The user's cache folder, never the source tree (which may be read-only, or a clone in CI).
    user = _os.environ.get("XDG_CACHE_HOME") or _os.path.join(_os.path.expanduser("~"), ".cache")
    return _os.path.join(user, "shroud", f"numba-{digest.hexdigest()[:12]}")


_os.environ.setdefault("NUMBA_CACHE_DIR", _numba_cache_dir())
