"""The wire log: every byte in both directions with a timestamp, one chunk per line.

Format (UTF-8 text, one record per line)::

    # roboscript wire log v1
    0.000000 < "!Mirtle2017 running on ATmega328P with Services: I M B R T S D L P \\n"
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

from roboscript.transport.output_file import OutputFile

__all__ = ["WireLog", "read_wire_log"]

_HEADER = "# roboscript wire log v1\n"


class WireLog:
    """Appends wire records to a file, flushed at least once a second.

    A write that fails (a full disk, a file-size limit, a path that cannot be opened) never
    reaches the link: the log closes, keeps what was written, and says why in :attr:`error`,
    for the program to tell once the robot is stopped
    (:class:`~roboscript.transport.output_file.OutputFile`).

    Args:
        path: The file to write (replaced if it exists).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._out = OutputFile(path, "the wire log")
        self._out.write(_HEADER)
        self._out.flush()

    @property
    def error(self) -> str | None:
        """``"cannot write the wire log PATH: why"``, or ``None`` while all is well."""
        return self._out.error

    def record(self, time_s: float, direction: str, data: bytes) -> None:
        """Write one chunk; ``direction`` is ``">"`` (sent) or ``"<"`` (received)."""
        if data:
            self._out.write(f"{time_s:.6f} {direction} {json.dumps(data.decode('latin-1'))}\n")

    def flush(self) -> None:
        """Push buffered records to the file."""
        self._out.flush()

    def close(self) -> None:
        """Flush and close; later records are ignored."""
        self._out.close()


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
