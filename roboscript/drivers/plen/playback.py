"""How long a stored motion plays on PLEN2 firmware 1.4.2: the host's model of its timing.

The firmware never says when a motion has ended, so the driver predicts it from the motion's
frames. The motion controller moves every joint towards the next frame in equal steps, one
every 32 ms (``UPDATE_INTERVAL_MS``), and a frame of ``transition_time_ms`` takes
``transition_time_ms // 32`` of them. With a loop code ``[begin, end, count]`` it plays frames
``0..end``, jumps back to ``begin`` after ``end`` as many times as asked, then plays on to the
last frame. ``$SM`` only clears the loop (and jump) flags: the frame in progress and every
frame after it, up to the last, still play.

Played by ``$PM``, a loop code with count ``c`` repeats the section ``c`` more times (``c + 1``
passes; 0 and 255 mean "until stopped"). Played by the interpreter (``#PU slot n`` then
``#PO``), the section plays ``n`` times in all. A jump code (another motion after this one) is
not followed: the schedule ends with this motion's last frame.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

__all__ = ["UPDATE_INTERVAL_MS", "Schedule"]

UPDATE_INTERVAL_MS = 32
"""The firmware's interpolation step, milliseconds."""


@dataclass(frozen=True)
class Schedule:
    """The order and length of the frames a motion plays.

    Attributes:
        cycles: Updates per frame (``transition_time_ms // 32``, at least 1), by frame index.
        loop: ``(begin, end)`` frame indices of the loop section, or ``None``.
        passes: How many times the loop section plays, or ``None`` for "until stopped".
    """

    cycles: tuple[int, ...]
    loop: tuple[int, int] | None = None
    passes: int | None = 1

    @classmethod
    def of(
        cls,
        transition_times_ms: Sequence[int],
        loop: tuple[int, int] | None = None,
        passes: int | None = 1,
    ) -> Schedule:
        """Build a schedule from frame transition times.

        Args:
            transition_times_ms: Each frame's transition time, milliseconds, in index order.
            loop: ``(begin, end)`` of the loop section, or ``None``.
            passes: Plays of the loop section (at least 1), or ``None`` for "until stopped".

        Raises:
            ValueError: No frames, a loop outside the frames, or fewer than one pass.
        """
        if not transition_times_ms:
            raise ValueError("a motion has at least one frame")
        if loop is not None and not 0 <= loop[0] <= loop[1] < len(transition_times_ms):
            raise ValueError(f"loop {loop} is outside frames 0..{len(transition_times_ms) - 1}")
        if passes is not None and passes < 1:
            raise ValueError(f"a loop plays at least once, not {passes} times")
        # A transition under 32 ms would divide by zero in the firmware; count it as one step.
        cycles = tuple(max(1, time // UPDATE_INTERVAL_MS) for time in transition_times_ms)
        return cls(cycles, loop, passes if loop is not None else 1)

    def _frames(self) -> Iterator[int]:
        """Frame indices in playing order (endless when the loop plays until stopped)."""
        last = len(self.cycles) - 1
        if self.loop is None:
            yield from range(last + 1)
            return
        begin, end = self.loop
        yield from range(end + 1)
        repeats = itertools.count() if self.passes is None else range(self.passes - 1)
        for _ in repeats:
            yield from range(begin, end + 1)
        yield from range(end + 1, last + 1)

    def duration_s(self, period_s: float = UPDATE_INTERVAL_MS / 1000.0) -> float | None:
        """Seconds from start to end, or ``None`` when the motion loops until stopped.

        Args:
            period_s: Length of one update, seconds.
        """
        if self.passes is None:
            return None
        return sum(self.cycles[index] for index in self._frames()) * period_s

    def stopped_at_s(self, stop_s: float, period_s: float = UPDATE_INTERVAL_MS / 1000.0) -> float:
        """When playback ends if ``$SM`` arrives ``stop_s`` seconds after the start.

        The frame in progress finishes, then every later frame up to the last plays once.

        Args:
            stop_s: Seconds from the start of playback to the ``$SM``.
            period_s: Length of one update, seconds.

        Returns:
            Seconds from the start of playback to its end.
        """
        elapsed = 0
        for index in self._frames():
            elapsed += self.cycles[index]
            if elapsed * period_s > stop_s:
                return (elapsed + sum(self.cycles[index + 1 :])) * period_s
        return elapsed * period_s
