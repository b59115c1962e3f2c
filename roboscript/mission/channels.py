"""The student's own values: ``log(name=value)`` records named channels beside the sensors.

A behaviour or a condition calls :func:`log` while the mission runs; the running mission keeps
the last value of each name, and the recording writes them each tick (frame key ``log``), so
the live view and the replay plot them beside the sensors, ``roboscript view --csv`` exports
them and ``roboscript.run()`` returns them as columns. A YAML mission plots any condition
value with ``plot: [range.distance_cm, ...]``. What the mission prints is stamped with the
mission time, on the terminal and in the record (:func:`stamped_prints`).
"""

from __future__ import annotations

import io
import math
import sys
from collections.abc import Callable, Iterator
from contextlib import AbstractContextManager, contextmanager
from contextvars import ContextVar
from typing import TextIO

__all__ = [
    "MAX_CHANNELS",
    "MAX_PRINTED_LINES",
    "PRINTED_LINE_CHARS",
    "Channels",
    "StampedPrints",
    "copied_prints",
    "log",
    "logging_to",
    "printed_line",
    "stamped_prints",
]

MAX_CHANNELS = 16
"""Names one mission may log: enough to debug with, few enough to plot and record each tick."""

Channels = dict[str, float | bool | None]
"""The last value of each logged name (``None``: not a number, such as NaN)."""

_CURRENT: ContextVar[Channels | None] = ContextVar("roboscript_log_channels", default=None)


def log(**values: float | bool) -> None:
    """Record named values at this moment of the run: ``log(gap_cm=gap, turning=True)``.

    Call it from a behaviour's ``update()`` or from a condition method; each name becomes a
    channel plotted beside the sensors (live and in the replay). Outside a running mission
    it does nothing, so a file that logs can still be imported and tested on its own.

    Args:
        values: Numbers or ``True``/``False`` by name; put the unit in the name
            (``gap_cm``), as roboscript does.

    Raises:
        TypeError: A value that is not a number or true/false.
        ValueError: More than :data:`MAX_CHANNELS` different names in one mission.
    """
    channels = _CURRENT.get()
    for name, value in values.items():
        if not isinstance(value, int | float):  # bool is an int
            raise TypeError(
                f"log() records numbers and True/False, not {type(value).__name__} "
                f"(for '{name}'): put a number in, e.g. log({name}=len(...))"
            )
        if channels is None:
            continue
        if name not in channels and len(channels) >= MAX_CHANNELS:
            raise ValueError(
                f"log() keeps at most {MAX_CHANNELS} names in one mission; '{name}' would be "
                f"one more (log fewer things, or reuse a name)"
            )
        number = value if isinstance(value, bool) else float(value)
        channels[name] = None if isinstance(number, float) and not math.isfinite(number) else number


@contextmanager
def logging_to(channels: Channels) -> Iterator[None]:
    """Send :func:`log` calls to ``channels`` for the duration (one mission tick)."""
    token = _CURRENT.set(channels)
    try:
        yield
    finally:
        _CURRENT.reset(token)


MAX_PRINTED_LINES = 2000
"""Lines a run's record keeps of what the mission printed; later ones are counted only."""

PRINTED_LINE_CHARS = 500
"""Characters of one printed line a record keeps (the terminal shows it whole)."""

_CUT_MARK = "…"


def printed_line(line: str) -> str:
    """A line the mission printed, as every record keeps it (``run --record``, ``grade``).

    Made printable (a tab, a terminal's escape or any other control character becomes a
    space, so a replay page or a table shows what a terminal would not hide), and cut at
    :data:`PRINTED_LINE_CHARS` characters: a longer line ends with ``…``. Only the first
    ``PRINTED_LINE_CHARS + 1`` characters are read, so a huge line costs no more.
    """
    head = line[: PRINTED_LINE_CHARS + 1]
    clean = head if head.isprintable() else "".join(c if c.isprintable() else " " for c in head)
    return clean[:PRINTED_LINE_CHARS] + _CUT_MARK if len(clean) > PRINTED_LINE_CHARS else clean


class StampedPrints(io.TextIOBase):
    """What the mission prints, line by line, stamped with the mission time.

    Installed as ``sys.stdout`` while a mission runs: each line goes on to the terminal as
    ``    3.21 s  > text`` (so prints line up with the states above them) and to ``record``
    (the recording writes it as the frame key ``print``).

    Args:
        out: Where the stamped lines go (the stdout it replaces).
        clock: The mission time, s; ``None`` before the mission has one (while it loads):
            the lines go on as they were printed.
        record: Called with each whole line, or ``None``.
    """

    def __init__(
        self,
        out: TextIO,
        clock: Callable[[], float] | None,
        record: Callable[[str], None] | None,
    ) -> None:
        super().__init__()
        self._out = out
        self._clock = clock
        self._record = record
        self._partial = ""

    def writable(self) -> bool:
        return True

    def write(self, text: str) -> int:
        lines = (self._partial + text).split("\n")
        self._partial = lines.pop()
        for line in lines:
            self._emit(line)
        return len(text)

    def _emit(self, line: str) -> None:
        clock = self._clock
        self._out.write(f"{line}\n" if clock is None else f"{clock():8.2f} s  > {line}\n")
        if self._record is not None:
            self._record(line)

    def flush(self) -> None:
        self._out.flush()

    def finish(self) -> None:
        """Write a last line left without its newline."""
        if self._partial:
            line, self._partial = self._partial, ""
            self._emit(line)
        self.flush()


@contextmanager
def stamped_prints(
    clock: Callable[[], float] | None, record: Callable[[str], None] | None = None
) -> Iterator[None]:
    """Stamp what is printed with ``clock`` while the block runs (see :class:`StampedPrints`)."""
    out = sys.stdout
    stamped = StampedPrints(out, clock, record)
    sys.stdout = stamped
    try:
        yield
    finally:
        sys.stdout = out
        stamped.finish()


def copied_prints(record: Callable[[str], None]) -> AbstractContextManager[None]:
    """Hand ``record`` each line printed while the block runs, the lines going on to the
    terminal unchanged: what a Python mission prints while it loads (a ``print`` at the top
    of its file or in its class body), before it has a mission time."""
    return stamped_prints(None, record)
