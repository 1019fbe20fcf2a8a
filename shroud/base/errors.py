"""The one error a user can cause: bad input, reported on one line, exit 2."""

from __future__ import annotations


class InputError(ValueError):
    """Bad input named by its key: ``error: <key>: <what is wrong; what is allowed>``."""

    def __init__(self, key: str, message: str):
        super().__init__(f"{key}: {message}")
        self.key = key
        self.message = message

    def __reduce__(self):              # pickles whole (an error raised on one MPI rank reaches all)
        return (InputError, (self.key, self.message))

    def line(self) -> str:
        return f"error: {self.key}: {self.message}"


class RunDiverged(RuntimeError):
    """A time integration left the bounded regime (named cause in the message)."""
