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
from pathlib import Path
from typing import IO

__all__ = ["WireLog", "read_wire_log"]

_HEADER = "# roboscript wire log v1\n"


class WireLog:
    """Appends wire records to a file.

    Args:
        path: The file to write (replaced if it exists).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._file: IO[str] | None = self.path.open("w", encoding="utf-8")
        self._file.write(_HEADER)

    def record(self, time_s: float, direction: str, data: bytes) -> None:
        """Write one chunk; ``direction`` is ``">"`` (sent) or ``"<"`` (received)."""
        if self._file is not None and data:
            self._file.write(f"{time_s:.6f} {direction} {json.dumps(data.decode('latin-1'))}\n")

    def flush(self) -> None:
        """Push buffered records to the file."""
        if self._file is not None:
            self._file.flush()

    def close(self) -> None:
        """Flush and close; later records are ignored."""
        if self._file is not None:
            self._file.close()
            self._file = None


def read_wire_log(path: str | Path) -> list[tuple[float, str, bytes]]:
    """Read a wire log into ``(time_s, direction, bytes)`` records."""
    records = []
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        if not line or line.startswith("#"):
            continue
        stamp, direction, payload = line.split(" ", 2)
        records.append((float(stamp), direction, json.loads(payload).encode("latin-1")))
    return records
