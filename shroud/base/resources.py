"""What the machine can hold: its physical memory, and sizes in words.

Model builders and analyses estimate what a run will need before they start
(a mesh before gmsh runs, the records of a time integration before they are
allocated) and refuse, naming the estimate, what this machine cannot hold.
"""

from __future__ import annotations

import os


def physical_memory() -> int:
    """Bytes of RAM of this machine (the ceiling of any one run, whatever else is running)."""
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def in_words(n_bytes: float) -> str:
    """A byte count for people: ``in_words(3 * 2**30) == '3.0 GiB'``.

    >>> in_words(1536), in_words(381 * 2**30), in_words(2**50), in_words(1e30)
    ('1.5 KiB', '381.0 GiB', '1.0 PiB', '8.7e+11 EiB')
    """
    value = float(n_bytes)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(value) < 1024.0:
            return f"{value:.1f} {unit}" if unit != "B" else f"{value:.0f} B"
        value /= 1024.0
    return f"{value:.2g} EiB" if value >= 1024.0 else f"{value:.1f} EiB"
