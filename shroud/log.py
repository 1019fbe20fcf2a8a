"""Logging and progress on stderr (stdout is kept for --json)."""

from __future__ import annotations

import sys
import time


def info(message: str) -> None:
    """One log line on stderr: what was built, reused, and why."""
    print(f"[shroud] {message}", file=sys.stderr, flush=True)


def warn(message: str) -> None:
    print(f"[shroud] warning: {message}", file=sys.stderr, flush=True)


class Progress:
    """Progress of a long loop (sweeps, time stepping, eigen-solves) on stderr.

    Prints at most every ``every_s`` seconds, and only once the task has run
    for ``after_s`` (quick work stays quiet).
    """

    def __init__(self, label: str, total: int, every_s: float = 2.0, after_s: float = 2.0):
        self.label, self.total = label, max(int(total), 1)
        self.every_s, self.after_s = every_s, after_s
        self.t0 = self.last = time.perf_counter()

    def update(self, done: int) -> None:
        now = time.perf_counter()
        if now - self.t0 < self.after_s or now - self.last < self.every_s:
            return
        self.last = now
        frac = done / self.total
        eta = (now - self.t0) * (1 - frac) / frac if frac > 0 else float("nan")
        print(f"[shroud] {self.label}: {done}/{self.total} ({100 * frac:.0f} %), "
              f"{now - self.t0:.1f} s, ~{eta:.0f} s left", file=sys.stderr, flush=True)

    def done(self) -> float:
        elapsed = time.perf_counter() - self.t0
        if elapsed >= self.after_s:
            print(f"[shroud] {self.label}: done in {elapsed:.1f} s", file=sys.stderr, flush=True)
        return elapsed
