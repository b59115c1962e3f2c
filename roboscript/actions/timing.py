"""Actions that wait or make sound: ``wait``, ``wait_until`` and ``play_tone``."""

from __future__ import annotations

from typing import Any

from roboscript import capabilities as cap
from roboscript.actions.base import FROM_INIT, Action, ActionContext, Param, Result

__all__ = ["PlayTone", "Wait", "WaitUntil"]


class Wait(Action):
    """Do nothing for a while.

    Args:
        duration_s: How long, seconds.

    Outcome: ``done`` after ``duration_s``.
    """

    name = "wait"
    summary = "Do nothing for a while."
    params = (Param("duration", "duration_s", "time", "how long"),)
    guessed_params = dict.fromkeys(
        ("time", "seconds", "secs", "s", "length", "delay", "for"),
        "how long a wait lasts is its duration, with its unit: duration: 2 s, or duration_s=2"
        " in Python",
    )

    def __init__(self, duration_s: float) -> None:
        if duration_s < 0:
            raise ValueError("a wait cannot be negative")
        self.duration_s = duration_s
        self._start_s = 0.0

    def start(self, ctx: ActionContext) -> None:
        self._start_s = ctx.now_s

    def update(self, ctx: ActionContext) -> Result | None:
        waited = ctx.now_s - self._start_s
        self.feedback = f"waiting {waited:.1f}/{self.duration_s:.1f} s"
        return Result.done() if ctx.has_passed(self._start_s, self.duration_s) else None


class PlayTone(Action):
    """Play a tone and wait until it has finished.

    Args:
        frequency_hz: Pitch, hertz (e.g. 440 for A4).
        duration_s: Length, seconds.

    Outcome: ``done`` when the tone has finished.
    """

    name = "play_tone"
    summary = "Play a tone and wait until it ends."
    params = (
        Param("frequency", "frequency_hz", "frequency", "pitch"),
        Param("duration", "duration_s", "time", "length", FROM_INIT),
    )
    requires = frozenset({cap.SPEAKER})

    def __init__(self, frequency_hz: float, duration_s: float = 0.2) -> None:
        if not 20 <= frequency_hz <= 20000:
            raise ValueError("a tone's frequency must be between 20 Hz and 20 kHz")
        if duration_s <= 0:
            raise ValueError("a tone's duration must be positive")
        self.frequency_hz = frequency_hz
        self.duration_s = duration_s
        self._start_s = 0.0

    def start(self, ctx: ActionContext) -> None:
        self._start_s = ctx.now_s
        ctx.speaker.beep(self.frequency_hz, self.duration_s)

    def update(self, ctx: ActionContext) -> Result | None:
        self.feedback = f"tone {self.frequency_hz:.0f} Hz"
        return Result.done() if ctx.has_passed(self._start_s, self.duration_s) else None


class WaitUntil(Action):
    """Wait until a condition holds, for at most a time bound.

    Args:
        condition: The condition (a guard such as ``"range.distance_cm < 20"``).
        timeout_s: The most it waits, seconds. Every wait has a bound.

    Outcomes: ``done`` when the condition holds; ``timeout`` when the bound passes first.
    """

    name = "wait_until"
    summary = "Wait until a condition holds (with a time bound)."
    params = (
        Param("condition", "condition", "guard", "what to wait for"),
        Param(
            "timeout",
            "timeout_s",
            "time",
            "the most it waits (every wait has a bound)",
            example="10 s",
        ),
    )
    can_time_out = True

    def __init__(self, condition: Any, timeout_s: float) -> None:
        if timeout_s <= 0:
            raise type(self).needs("wait_until needs a positive timeout", "timeout")
        self.condition = condition
        self.timeout_s = timeout_s
        self._start_s = 0.0

    def start(self, ctx: ActionContext) -> None:
        self._start_s = ctx.now_s

    def update(self, ctx: ActionContext) -> Result | None:
        if ctx.holds(self.condition):
            return Result.done()
        waited = ctx.now_s - self._start_s
        self.feedback = f"waiting {waited:.1f}/{self.timeout_s:.1f} s"
        if ctx.has_passed(self._start_s, self.timeout_s):
            text = getattr(self.condition, "source", "the condition")
            return Result.timeout(f"'{text}' did not hold within {self.timeout_s:g} s")
        return None
