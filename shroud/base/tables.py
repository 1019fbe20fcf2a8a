"""CSV tables of records: one row per dict, columns in the first record's key order."""

from __future__ import annotations

import csv
from pathlib import Path

from shroud.base.outputs import open_replacing


def write_records(path: Path, rows: list[dict]) -> Path | None:
    """``rows`` as a CSV at ``path`` (nothing is written for no rows); returns the path written.

    >>> import tempfile, pathlib
    >>> p = write_records(pathlib.Path(tempfile.mkdtemp()) / "t.csv", [{"rpm": 1, "a": 2.5}])
    >>> p.read_text().splitlines()
    ['rpm,a', '1,2.5']
    """
    if not rows:
        return None
    with open_replacing(path) as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return Path(path)
