"""Logging and progress on stderr (stdout is kept for --json).

Under mpirun the ranks running one study together say the same things:
rank 0 speaks for them. Ranks running separate items of a spread sweep or
campaign (shroud.base.parallel.map_parallel) each speak for themselves.
"""

from __future__ import annotations

import sys
import time

from shroud.base.parallel import in_task, mpi_rank


def _speaks() -> bool:
    return in_task() or mpi_rank() == 0


def _say(line: str) -> None:
    if _speaks():
        print(line, file=sys.stderr, flush=True)


def info(message: str) -> None:
    """One log line on stderr: what was built, reused, and why."""
    _say(f"[shroud] {message}")


def warn(message: str) -> None:
    _say(f"[shroud] warning: {message}")


class Progress:
    """Progress of a long loop (sweeps, time stepping, eigen-solves) on stderr.

    Prints at most every ``every_s`` seconds, and only once the task has run
    for ``after_s`` (quick work stays quiet).
    """

    def __init__(self, label: str, total: int, every_s: float = 2.0, after_s: float = 2.0):
        self.label, self.total = label, max(int(total), 1)
        self.every_s, self.after_s = every_s, after_s
        self.t0 = self.last = time.perf_counter()

    def update(self, done: float, detail: str = "") -> None:
        """``done`` of ``total``; ``detail`` (where the work is, in its own terms) replaces the count."""
        now = time.perf_counter()
        if now - self.t0 < self.after_s or now - self.last < self.every_s:
            return
        self.last = now
        frac = min(max(done / self.total, 0.0), 1.0)
        left = f", ~{(now - self.t0) * (1 - frac) / frac:.0f} s left" if frac > 0 else ""
        where = detail or f"{done:g}/{self.total}"
        _say(f"[shroud] {self.label}: {where} ({100 * frac:.0f} %), {now - self.t0:.1f} s{left}")

    def done(self) -> float:
        elapsed = time.perf_counter() - self.t0
        if elapsed >= self.after_s:
            _say(f"[shroud] {self.label}: done in {elapsed:.1f} s")
        return elapsed
