"""An output file written while the robot runs: flushed at least once a second, never raising.

The wire log and a run's recording are written from inside the tick loop. A write there must
neither slow the loop (lines wait in a buffer, pushed out at most once a second) nor stop it: a
full disk or a file-size limit closes the file, keeps what reached it, and is kept as one
sentence in :attr:`OutputFile.error`, for the program to say once the robot is stopped.
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path
from typing import IO

__all__ = ["FLUSH_EVERY_S", "OutputFile"]

FLUSH_EVERY_S = 1.0
"""Most wall seconds a written line waits in memory before it reaches the file, so a program
killed outright (SIGKILL) leaves every line up to its last second."""


class OutputFile:
    """A text file (UTF-8, ``\\n`` line ends) whose write errors are kept, not raised.

    Args:
        path: The file (replaced if it exists).
        what: What it holds, for the error (``"the wire log"``).

    Attributes:
        error: ``"cannot write WHAT PATH: why"`` once a write failed, else ``None``; later
            writes are dropped.
    """

    def __init__(self, path: str | Path, what: str) -> None:
        self.path = Path(path)
        self.what = what
        self.error: str | None = None
        self._file: IO[str] | None = None
        self._next_flush_s = time.monotonic() + FLUSH_EVERY_S
        try:
            self._file = self.path.open("w", encoding="utf-8", newline="\n")
        except OSError as exc:
            self.fail(exc)

    def write(self, text: str) -> None:
        """Write ``text``; flush if the last flush was a second ago or more."""
        if self._file is None:
            return
        try:
            self._file.write(text)
            if time.monotonic() >= self._next_flush_s:
                self._file.flush()
                self._next_flush_s = time.monotonic() + FLUSH_EVERY_S
        except OSError as exc:
            self.fail(exc)

    def flush(self) -> None:
        """Push what was written so far to the file."""
        if self._file is None:
            return
        try:
            self._file.flush()
        except OSError as exc:
            self.fail(exc)
        self._next_flush_s = time.monotonic() + FLUSH_EVERY_S

    def close(self) -> None:
        """Flush and close; later writes are dropped."""
        if self._file is None:
            return
        try:
            self._file.close()
        except OSError as exc:
            self.fail(exc)
        self._file = None

    def fail(self, exc: Exception) -> None:
        """Stop writing because of ``exc``; the first reason given is the one kept."""
        if self.error is None:
            reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
            self.error = f"cannot write {self.what} {self.path}: {reason}"
        file, self._file = self._file, None
        if file is not None:
            # the buffer that failed to go out fails again on close: already said
            with contextlib.suppress(OSError):
                file.close()
