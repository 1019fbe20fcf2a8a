"""Output folders: one writer at a time, and every file in place whole or not at all.

A run holds its output folder with an advisory lock (``fcntl.flock`` on the
folder's ``.shroud-lock`` file); a second run into the same folder is refused
at once with one line naming the run that holds it. The lock belongs to the
open file, so a killed run leaves none behind; the file itself stays (removing
it would let a third run lock a file the second already holds open).

Every file is written under a hidden temporary name beside its place and
renamed over it (``os.replace``, atomic on one file system), so neither a
reader nor a run killed mid-write ever leaves half a file.
"""

from __future__ import annotations

import contextlib
import datetime
import fcntl
import os
import socket
import tempfile
from pathlib import Path
from typing import IO, Iterator

from shroud.base.errors import InputError

LOCK_NAME = ".shroud-lock"


class FolderLock:
    """This process's hold on an output folder (made if missing), released by ``release`` or on exit.

    ``acquire`` raises InputError(``key``) when another run holds the folder.
    A context manager too: ``with FolderLock(out): ...``.
    """

    def __init__(self, folder: Path, key: str = "--out"):
        self.folder, self.key = Path(folder), key
        self._fh: IO | None = None

    def acquire(self) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        fh = open(self.folder / LOCK_NAME, "a+")
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            fh.seek(0)
            holder = fh.read().strip() or "another run"
            fh.close()
            raise InputError(self.key, f"{str(self.folder)!r} is being written by another run ({holder}); "
                                       "allowed: a different folder, or this one once that run has ended") from None
        fh.seek(0)
        fh.truncate()
        started = datetime.datetime.now().astimezone().isoformat(timespec="seconds")
        fh.write(f"pid {os.getpid()} on {socket.gethostname()}, since {started}\n")
        fh.flush()
        self._fh = fh

    def release(self) -> None:
        if self._fh is not None:
            self._fh.close()                # closing the file releases the lock
            self._fh = None

    def __enter__(self) -> Path:
        self.acquire()
        return self.folder

    def __exit__(self, *exc) -> None:
        self.release()


def check_writable(folder: Path, key: str) -> None:
    """Refuse (InputError ``key``) a folder that cannot be made or written into (probed in its nearest
    existing folder, which is left as it was)."""
    folder = Path(folder)
    existing = folder.absolute()
    while not existing.exists():
        existing = existing.parent
    allowed = "allowed: a folder that exists or can be made, in a place this user may write"
    if not existing.is_dir():
        raise InputError(key, f"{str(folder)!r} cannot be made: {str(existing)!r} is a file; {allowed}")
    try:
        tempfile.TemporaryDirectory(dir=existing, prefix=".shroud-probe-").cleanup()
    except OSError as exc:
        raise InputError(key, f"{str(folder)!r} cannot be written: {exc.strerror} in "
                         f"{str(existing)!r}; {allowed}") from None


def _temporary(path: Path) -> Path:
    # same folder (one file system, so the rename is atomic), same suffix (savefig and savetxt read it)
    return path.with_name(f".{path.stem}.{os.getpid()}.tmp{path.suffix}")


@contextlib.contextmanager
def replacing(path: Path) -> Iterator[Path]:
    """A temporary path to write ``path``'s content to; renamed over ``path`` if the block succeeds."""
    path = Path(path)
    tmp = _temporary(path)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


@contextlib.contextmanager
def open_replacing(path: Path, mode: str = "w", newline: str | None = "") -> Iterator[IO]:
    """``open(path, mode)`` that puts the file in place only when the block has written all of it."""
    with replacing(path) as tmp, open(tmp, mode, newline=None if "b" in mode else newline) as fh:
        yield fh


def write_text(path: Path, text: str) -> Path:
    """``Path(path).write_text(text)``, whole or not at all."""
    with replacing(path) as tmp:
        tmp.write_text(text)
    return Path(path)
