"""The wire log: every byte in both directions with a timestamp, one chunk per line.

Format (UTF-8 text, one record per line)::

    # roboscript wire log v1
    0.000000 < "!mirto2017 running on ATmega328P with Services: I M B R D T L \\n"
    0.020000 > "#,?\\n"

* the scheduler time in seconds with six decimals;
* ``>`` for bytes the host sent, ``<`` for bytes the host received;
* the bytes as a JSON string of their Latin-1 decoding, so any byte value round-trips
  exactly (``"\\u00ff"`` is the byte 0xFF).

:func:`read_wire_log` returns the records, and a test can feed the ``<`` chunks to a host codec
to replay what the robot said.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import IO

__all__ = ["FLUSH_EVERY_S", "WireLog", "read_wire_log"]

_HEADER = "# roboscript wire log v1\n"
FLUSH_EVERY_S = 1.0
"""Most wall seconds a record waits in memory before it reaches the file, so a program
killed outright leaves every record up to its last second."""


class WireLog:
    """Appends wire records to a file, flushed at least once a second.

    A write that fails (a full disk, a file-size limit, a path that cannot be opened) never
    reaches the link: the log closes, keeps what was written, and says why in :attr:`error`,
    for the program to tell once the robot is stopped.

    Args:
        path: The file to write (replaced if it exists).

    Attributes:
        error: ``"cannot write the wire log PATH: why"``, or ``None`` while all is well.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.error: str | None = None
        self._file: IO[str] | None = None
        self._next_flush_s = time.monotonic() + FLUSH_EVERY_S
        try:
            self._file = self.path.open("w", encoding="utf-8", newline="\n")
            self._file.write(_HEADER)
            self._file.flush()
        except OSError as exc:
            self._fail(exc)

    def record(self, time_s: float, direction: str, data: bytes) -> None:
        """Write one chunk; ``direction`` is ``">"`` (sent) or ``"<"`` (received)."""
        if self._file is not None and data:
            try:
                self._file.write(
                    f"{time_s:.6f} {direction} {json.dumps(data.decode('latin-1'))}\n"
                )
                if time.monotonic() >= self._next_flush_s:
                    self._file.flush()
                    self._next_flush_s = time.monotonic() + FLUSH_EVERY_S
            except OSError as exc:
                self._fail(exc)

    def flush(self) -> None:
        """Push buffered records to the file."""
        if self._file is not None:
            try:
                self._file.flush()
            except OSError as exc:
                self._fail(exc)

    def close(self) -> None:
        """Flush and close; later records are ignored."""
        if self._file is not None:
            try:
                self._file.close()
            except OSError as exc:
                self._fail(exc)
            self._file = None

    def _fail(self, exc: OSError) -> None:
        if self.error is None:
            self.error = f"cannot write the wire log {self.path}: {exc.strerror or exc}"
        file, self._file = self._file, None
        if file is not None:
            try:
                file.close()
            except OSError:  # the buffer that failed to go out fails again: already said
                pass


def read_wire_log(path: str | Path) -> list[tuple[float, str, bytes]]:
    """Read a wire log into ``(time_s, direction, bytes)`` records."""
    records = []
    lines = Path(path).read_text(encoding="utf-8").split("\n")
    for line in lines[:-1]:  # the text after the last newline is a record cut short
        if not line or line.startswith("#"):
            continue
        stamp, direction, payload = line.split(" ", 2)
        records.append((float(stamp), direction, json.loads(payload).encode("latin-1")))
    return records
